"""tswm.run against the command line: the same table as `lanes.parquet`
for sweep files, dicts, TOML text and lane tables (files, pandas, polars,
pyarrow), and the same folder with out=."""

import tomllib

import pyarrow as pa
import pyarrow.parquet as pq
import pytest

import tswm


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
        assert got.equals(want), sweep.name


def test_a_path_as_text_or_as_pathlib_is_the_same_sweep(root):
    a = tswm.run(root / "sweeps/paper.toml", backend="cpu", progress=False)
    b = tswm.run(str(root / "sweeps/paper.toml"), backend="cpu", progress=False)
    assert a.equals(b)


def test_a_dict_and_toml_text_are_the_sweep_file(cli, root, tmp_path):
    path = root / "sweeps/efficiency_map.toml"
    text = path.read_text()
    as_dict = tomllib.loads(text)
    want = cli_table(cli, tmp_path, path)
    assert tswm.run(as_dict, backend="cpu", progress=False).equals(want)
    assert tswm.run(text, backend="cpu", progress=False).equals(want)


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
    assert tswm.run(lanes=df, backend="cpu", progress=False).equals(want)
    # The same table as a file, from polars and from pyarrow.
    assert tswm.run(lanes=csv, backend="cpu", progress=False).equals(want)
    import polars as pl

    assert tswm.run(lanes=pl.from_pandas(df), backend="cpu", progress=False).equals(want)
    assert tswm.run(lanes=pa.Table.from_pandas(df), backend="cpu", progress=False).equals(want)


def test_a_lane_table_over_a_sweeps_base(cli, tmp_path):
    df = lane_frame()[["gamma_deg", "f2"]]
    csv = tmp_path / "lanes.csv"
    df.to_csv(csv, index=False)
    base = tmp_path / "base.toml"
    base.write_text('[base]\nfriction = "coulomb"\nmu = 0.04\n')
    want = cli_table(cli, tmp_path, base, "--lanes", csv)
    got = tswm.run({"base": {"friction": "coulomb", "mu": 0.04}}, lanes=df, backend="cpu", progress=False)
    assert got.equals(want)


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
    assert pq.read_table(tmp_path / "py/lanes.parquet").equals(got)
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
    c = tswm.check(root / "sweeps/paper.toml", progress=False)
    assert c.lanes == 2 and c.passed, str(c)
