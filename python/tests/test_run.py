"""tswm.run against the command line: the same table as `lanes.parquet`
for sweep files, dicts, TOML text and lane tables (files, pandas, polars,
pyarrow), and the same folder with out=."""

import tomllib

import pyarrow as pa
import pyarrow.parquet as pq
import pytest

import tswm


def as_words(t):
    """`t` with each word (dictionary) column as its strings: pyarrow keys
    a Parquet file's words by the file's own dictionary pages, the engine
    by each word's code, so two tables of the same words can differ in
    their keys."""
    cols = [c.cast(c.type.value_type) if pa.types.is_dictionary(c.type) else c for c in t.columns]
    return pa.table(cols, names=t.column_names)


def same(a, b):
    """The same columns, types and values (words compared as words)."""
    return a.schema == b.schema and as_words(a).equals(as_words(b))


def cli_table(cli, tmp_path, *args):
    """The command line's lanes.parquet of `tswm run ARGS`."""
    out = tmp_path / "cli"
    cli("run", *args, "--backend", "cpu", "--format", "parquet", "--no-report", "--out", out)
    return pq.read_table(out / "lanes.parquet")


def test_every_shipped_sweep_gives_the_command_lines_table(cli, shipped, tmp_path):
    for sweep in shipped:
        got = tswm.run(sweep, backend="cpu", progress=False)
        want = cli_table(cli, tmp_path / sweep.stem, sweep)
        assert got.schema == want.schema, sweep.name
        assert same(got, want), sweep.name


def test_word_columns_are_keyed_by_their_codes(root):
    """A word column holds every word its column can take, in one order in
    every batch (the status words in the order the model lists them), so a
    key is a word's code; pandas sees a category."""
    t = tswm.run(root / "sweeps/heterogeneous.toml", backend="cpu", progress=False)
    status = ["ok", "inconsistent", "nonfinite", "max_steps", "max_events", "step_underflow"]
    for chunk in t.column("status").chunks:
        assert chunk.dictionary.to_pylist() == status
    contact = t.column("contact_end").combine_chunks()
    assert contact.dictionary.to_pylist() == ["aa", "bb", "stick"]
    words = contact.to_pylist()
    assert [contact.dictionary.to_pylist()[i] for i in contact.indices.to_pylist()] == words
    assert {"aa", "bb", "stick"} == set(words)
    df = t.select(["status", "drive"]).to_pandas()
    assert str(df.status.dtype) == "category" and (df.status == "ok").all()


def test_a_path_as_text_or_as_pathlib_is_the_same_sweep(root):
    a = tswm.run(root / "sweeps/paper.toml", backend="cpu", progress=False)
    b = tswm.run(str(root / "sweeps/paper.toml"), backend="cpu", progress=False)
    assert a.equals(b)


def test_a_dict_and_toml_text_are_the_sweep_file(cli, root, tmp_path):
    path = root / "sweeps/efficiency_map.toml"
    text = path.read_text()
    as_dict = tomllib.loads(text)
    want = cli_table(cli, tmp_path, path)
    assert same(tswm.run(as_dict, backend="cpu", progress=False), want)
    assert same(tswm.run(text, backend="cpu", progress=False), want)


def lane_frame():
    """A lane table in pandas: floats, integers, words and missing cells."""
    import pandas as pd

    return pd.DataFrame(
        {
            "gamma_deg": [5.710593137499643, 8.0, 12.5, 20.0],
            "f2": [4774.0, -4774.0, 1000, -30000.0],
            "friction": ["paper", "coulomb", "coulomb", None],
            "mu": [None, 0.05, 0.08, None],
            "motor_off": [None, 1.0, None, 0.5],
            "t_end": [2, 2, 1, 1],
        }
    )


def test_a_pandas_lane_table_gives_the_table_of_its_csv(cli, tmp_path):
    df = lane_frame()
    csv = tmp_path / "lanes.csv"
    df.to_csv(csv, index=False)
    want = cli_table(cli, tmp_path, "--lanes", csv)
    assert same(tswm.run(lanes=df, backend="cpu", progress=False), want)
    # The same table as a file, from polars and from pyarrow.
    assert same(tswm.run(lanes=csv, backend="cpu", progress=False), want)
    import polars as pl

    assert same(tswm.run(lanes=pl.from_pandas(df), backend="cpu", progress=False), want)
    assert same(tswm.run(lanes=pa.Table.from_pandas(df), backend="cpu", progress=False), want)


def test_a_lane_table_over_a_sweeps_base(cli, tmp_path):
    df = lane_frame()[["gamma_deg", "f2"]]
    csv = tmp_path / "lanes.csv"
    df.to_csv(csv, index=False)
    base = tmp_path / "base.toml"
    base.write_text('[base]\nfriction = "coulomb"\nmu = 0.04\n')
    want = cli_table(cli, tmp_path, base, "--lanes", csv)
    got = tswm.run({"base": {"friction": "coulomb", "mu": 0.04}}, lanes=df, backend="cpu", progress=False)
    assert same(got, want)


def test_out_writes_the_command_lines_folder(cli, root, tmp_path):
    sweep = root / "sweeps/tolerance.toml"
    got = tswm.run(sweep, backend="cpu", out=tmp_path / "py", progress=False)
    cli("run", sweep, "--backend", "cpu", "--out", tmp_path / "cli")
    for name in ["lanes.csv", "summary.csv"]:
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    assert (tmp_path / "py/report.html").is_file()
    assert tswm.read(tmp_path / "py").equals(got)
    assert tswm.read(tmp_path / "cli").equals(got)
    s = tswm.summary(tmp_path / "py")
    assert s.num_rows > 0 and "mean" in s.column_names
    assert s.equals(tswm.summary(tmp_path / "cli"))


def test_out_in_parquet_and_the_sensitivity_table(cli, root, tmp_path):
    sweep = root / "sweeps/which_tolerance.toml"
    got = tswm.run(sweep, backend="cpu", out=tmp_path / "py", format="parquet", report=False, progress=False)
    assert not (tmp_path / "py/report.html").exists()
    assert same(pq.read_table(tmp_path / "py/lanes.parquet"), got)
    cli("run", sweep, "--backend", "cpu", "--out", tmp_path / "cli", "--no-report")
    sens = tswm.sensitivity(tmp_path / "py")
    assert sens.num_rows > 0
    assert sens.equals(tswm.sensitivity(tmp_path / "cli"))


def test_the_table_is_shared_not_copied(root):
    t = tswm.run(root / "sweeps/paper.toml", backend="cpu", progress=False)
    # The columns are the engine's buffers: one chunk a batch, read-only.
    col = t.column("x1_end").chunk(0)
    assert col.buffers()[1] is not None
    assert t.num_rows == 2 and t.num_columns == 70


def test_bench_check_and_devices(root):
    b = tswm.bench(root / "sweeps/paper.toml", backend="cpu", progress=False)
    assert b["lanes"] == 2 and b["lanes_per_second"] > 0 and b["backend"].startswith("cpu")
    d = tswm.devices()
    assert d["cpu"]["threads"] >= 1 and d["cpu"]["lanes"] >= 1
    if not d["adapters"]:
        pytest.skip("no GPU adapter for tswm.check (install mesa-vulkan-drivers)")
    # Whether an adapter's shaders have 64-bit floats: lavapipe's do.
    assert all(isinstance(a["shader_f64"], bool) for a in d["adapters"])
    assert all(a["shader_f64"] for a in d["adapters"] if a["name"].startswith("llvmpipe"))
    c = tswm.check(root / "sweeps/paper.toml", progress=False)
    assert c.lanes == 2 and c.passed, str(c)


def test_precision_f64_on_an_adapter_with_it(root):
    """`precision="f64"`: rows say `gpu64` (or `cpu:refined`, where the
    lane's error estimate sent it to the CPU at the tighter settings, as
    the CPU path refines the same lanes), and `tswm.check` holds them to
    the CPU path's bound (1e-6) on every lane; an adapter without 64-bit
    floats raises InputError naming it."""
    d = tswm.devices()
    if not d["adapters"]:
        pytest.skip("no GPU adapter (install mesa-vulkan-drivers)")
    sweep = root / "sweeps/friction_laws.toml"
    if not d["adapters"][0]["shader_f64"]:
        msg = str(pytest.raises(tswm.InputError, tswm.run, sweep, backend="gpu", precision="f64").value)
        assert d["adapters"][0]["name"] in msg and "no 64-bit floats" in msg, msg
        return
    t = tswm.run(sweep, backend="gpu", precision="f64", progress=False)
    cpu = tswm.run(sweep, backend="cpu", progress=False)
    paths = t.column("path").to_pylist()
    assert set(paths) == {"gpu64", "cpu:refined"}
    assert [p == "cpu:refined" for p in paths] == [p == "cpu:refined" for p in cpu.column("path").to_pylist()]
    c = tswm.check(sweep, precision="f64", progress=False)
    assert c.passed and c.disagreeing == 0 and c.lanes == t.num_rows, str(c)
    assert "gpu f64" in c.gpu
