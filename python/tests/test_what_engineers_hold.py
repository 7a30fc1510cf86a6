"""What engineers hold, handed to tswm as they hold it (issue 36): each
is either taken as the docs promise or refused with the command line's
one line as tswm.InputError, never a stray ArrowInvalid, OverflowError,
AttributeError, RecursionError or a TypeError about the package's
internals."""

import csv
import decimal
import os
import pathlib

import pyarrow as pa
import pytest

import tswm

# A base every lane table below completes: Coulomb friction, a load.
BASE = {"base": {"friction": "coulomb", "mu": 0.05, "f2": 1000.0}}


def run(lanes, sweep=BASE, **kw):
    return tswm.run(sweep, lanes=lanes, backend="cpu", progress=False, **kw)


def input_error(call):
    with pytest.raises(tswm.InputError) as e:
        call()
    msg = str(e.value)
    assert "\n" not in msg and "\r" not in msg, msg
    return msg


def cli_error(cli, *args):
    p = cli(*args, check=False)
    assert p.returncode == 2, p.stderr
    (line,) = p.stderr.strip().splitlines()
    return line.removeprefix("tswm: error: ")


# --- summary.csv and sensitivity.csv: declared columns, never guessed ---

WORD_TABLES = ["NA", "null", "true", "nan", "None", "FALSE"]


def words_sweep():
    """A grid over friction tables whose names pyarrow's defaults read as
    nulls, booleans or NaN."""
    sweep = {
        "base": {"friction": "table", "f2": 1000.0, "gamma_deg": 8.0},
        "grid": [{"param": "friction_table", "values": WORD_TABLES}],
        "sampling": {"method": "monte_carlo", "n": 3, "seed": 7},
        "tolerance": [{"param": "f2", "dist": "uniform", "tol": 100.0}],
        "friction_table": {},
    }
    for i, name in enumerate(WORD_TABLES):
        mu = 0.04 + 0.01 * i
        sweep["friction_table"][name] = {"vs": [0.0, 1.0], "mu": [mu, mu / 2]}
    return sweep


def csv_rows(path):
    with open(path, newline="") as f:
        return list(csv.reader(f))


def assert_same_cells(table, path):
    """Every cell of the table is the file's cell: a word as written, a
    number as the float or integer written, an empty cell a null."""
    rows = csv_rows(path)
    assert table.column_names == rows[0]
    assert table.num_rows == len(rows) - 1
    for j, name in enumerate(rows[0]):
        col = table.column(name).to_pylist()
        t = table.schema.field(name).type
        for i, row in enumerate(rows[1:]):
            cell = row[j]
            if cell == "":
                assert col[i] is None, (name, i)
            elif t == pa.string():
                assert col[i] == cell, (name, i)
            elif t == pa.int64():
                assert col[i] == int(cell), (name, i)
            else:
                assert t == pa.float64() and col[i] == float(cell), (name, i)


def test_summary_reads_words_as_words_and_empty_cells_as_nulls(tmp_path):
    out = tmp_path / "out"
    tswm.run(words_sweep(), backend="cpu", out=out, report=False, progress=False)
    s = tswm.summary(out)
    types = {f.name: f.type for f in s.schema}
    assert types["group"] == pa.int64() and types["count"] == pa.int64()
    for name in ["friction_table", "kind", "name", "input", "quantiles"]:
        assert types[name] == pa.string(), name
    for name in ["mean", "std", "min", "p1", "p50", "p99", "max", "share", "ci95_low", "rho"]:
        assert types[name] == pa.float64(), name
    # Each grid group keeps its own table's name: six groups, six words.
    groups = {}
    for g, t in zip(s.column("group").to_pylist(), s.column("friction_table").to_pylist()):
        groups.setdefault(g, set()).add(t)
    assert groups == {i: {w} for i, w in enumerate(WORD_TABLES)}
    assert_same_cells(s, out / "summary.csv")


def test_sensitivity_reads_its_declared_columns(root, tmp_path):
    out = tmp_path / "out"
    tswm.run(root / "sweeps/which_tolerance.toml", backend="cpu", out=out, report=False, progress=False)
    s = tswm.sensitivity(out)
    assert [(f.name, f.type) for f in s.schema] == [
        ("group", pa.int64()),
        ("result", pa.string()),
        ("input", pa.string()),
        *[(n, pa.float64()) for n in ["s1", "s1_low", "s1_high", "st", "st_low", "st_high"]],
        ("samples", pa.int64()),
    ]
    assert_same_cells(s, out / "sensitivity.csv")
    (out / "sensitivity.csv").write_text("")
    assert input_error(lambda: tswm.sensitivity(out)) == (
        f"{out}/sensitivity.csv: is empty; allowed: the sensitivity.csv tswm writes (a header line: "
        "group,result,input,s1,s1_low,s1_high,st,st_low,st_high,samples)"
    )


def test_an_empty_or_bad_summary_is_bad_input_naming_the_file(root, tmp_path):
    out = tmp_path / "out"
    tswm.run(root / "sweeps/paper.toml", backend="cpu", out=out, report=False, progress=False)
    f = out / "summary.csv"
    text = f.read_text()
    f.write_text("")
    assert input_error(lambda: tswm.summary(out)) == (
        f"{f}: is empty; allowed: the summary.csv tswm writes (a header line: group, the grid's "
        "parameters, then kind,name,input,count,mean,std,min,p1,p5,p50,p95,p99,max,quantiles,share,"
        "ci95_low,ci95_high,rho)"
    )
    # Its header alone: no rows, the declared types.
    f.write_text(text.splitlines()[0] + "\n")
    s = tswm.summary(out)
    assert s.num_rows == 0 and s.schema.field("count").type == pa.int64()
    assert s.schema.field("kind").type == pa.string()
    # A cell that is not of its column's kind: the line and the column.
    lines = text.splitlines()
    cells = lines[2].split(",")
    cells[lines[0].split(",").index("mean")] = "abc"
    f.write_text("\n".join(lines[:2] + [",".join(cells)] + lines[3:]) + "\n")
    assert input_error(lambda: tswm.summary(out)) == (
        f"{f}: line 3: mean: `abc` is not a number; allowed: a number, or empty"
    )
    allowed = (
        "group, the grid's parameters, then kind,name,input,count,mean,std,min,p1,p5,p50,p95,p99,"
        "max,quantiles,share,ci95_low,ci95_high,rho"
    )
    f.write_text("group,kind,colour\n0,number,red\n")
    assert input_error(lambda: tswm.summary(out)) == f"{f}: line 1: header: allowed: {allowed}"
    f.write_text(lines[0].replace("group,", "group,colour,") + "\n")
    assert input_error(lambda: tswm.summary(out)) == (
        f"{f}: line 1: colour: is not a parameter of the grid (or is named twice); allowed: {allowed}"
    )


# --- lane tables: every type the docs promise ---


def reference(tmp_path, text, sweep=BASE):
    """The table of a CSV lane table `text`, the form whose meaning is fixed."""
    f = tmp_path / "lanes.csv"
    f.write_text(text)
    return run(f, sweep)


def test_every_integer_and_float_dtype(tmp_path):
    import numpy as np
    import pandas as pd
    import polars as pl

    want = reference(tmp_path, "gamma_deg,t_end\n4,1\n8,2\n12,1\n")
    dtypes = ["int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64"]
    dtypes += ["float16", "float32", "float64", np.longdouble]
    dtypes += ["Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32", "Int64", "UInt64", "Float32", "Float64"]
    for dt in dtypes:
        df = pd.DataFrame({"gamma_deg": [4, 8, 12], "t_end": [1, 2, 1]}).astype(dt)
        assert run(df).equals(want), dt
    for dt in [pl.Int8, pl.UInt8, pl.Int16, pl.UInt16, pl.Int32, pl.UInt32, pl.Int64, pl.UInt64, pl.Float32, pl.Float64]:
        df = pl.DataFrame({"gamma_deg": [4, 8, 12], "t_end": [1, 2, 1]}, schema={"gamma_deg": dt, "t_end": dt})
        assert run(df).equals(want), dt
    for t in [pa.float16(), pa.int8(), pa.uint64()]:
        table = pa.table({"gamma_deg": pa.array([4, 8, 12]).cast(t), "t_end": pa.array([1, 2, 1]).cast(t)})
        assert run(table).equals(want), t
    dec = [decimal.Decimal(x) for x in ["4", "8.00", "12.0"]]
    table = pa.table({"gamma_deg": pa.array(dec, pa.decimal128(5, 2)), "t_end": pa.array([1, 2, 1], pa.decimal128(3, 0))})
    assert run(table).equals(want)
    # A decimal as DuckDB gives it (0.05 is DECIMAL(3,2)).
    mu = pa.table({"gamma_deg": [4.0], "mu": pa.array([decimal.Decimal("0.05")], pa.decimal128(3, 2))})
    assert run(mu).equals(reference(tmp_path, "gamma_deg,mu\n4,0.05\n"))


def test_categorical_words(tmp_path):
    import pandas as pd
    import polars as pl

    want = reference(
        tmp_path, "gamma_deg,friction,mu,motor,f1\n4,coulomb,0.05,kloss,\n8,paper,,constant,40\n12,coulomb,0.08,kloss,\n",
        {"base": {"f2": 1000.0}},
    )
    cols = {
        "gamma_deg": [4.0, 8.0, 12.0],
        "friction": ["coulomb", "paper", "coulomb"],
        "mu": [0.05, None, 0.08],
        "motor": ["kloss", "constant", "kloss"],
        "f1": [None, 40.0, None],
    }
    sweep = {"base": {"f2": 1000.0}}
    df = pd.DataFrame(cols).astype({"friction": "category", "motor": "category"})
    assert run(df, sweep).equals(want)
    for kind in [pl.Categorical, pl.Enum(["paper", "coulomb", "table", "agma", "kloss", "constant"])]:
        pdf = pl.DataFrame(cols, schema_overrides={"friction": kind, "motor": kind})
        assert run(pdf, sweep).equals(want), kind
    # A dictionary column of numbers is its numbers.
    t = pa.table({"gamma_deg": pa.array([4.0, 8.0, 12.0]).dictionary_encode(), "friction": cols["friction"],
                  "mu": cols["mu"], "motor": pa.array(cols["motor"]).dictionary_encode(), "f1": cols["f1"]})
    assert run(t, sweep).equals(want)


def test_a_column_of_nothing_sets_nothing(tmp_path):
    import pandas as pd
    import polars as pl

    want = reference(tmp_path, "gamma_deg\n4\n8\n")
    for lanes in [
        pd.DataFrame({"gamma_deg": [4.0, 8.0], "mu_static": [None, None], "friction_table": [None, None]}),
        pl.DataFrame({"gamma_deg": [4.0, 8.0], "mu_static": [None, None]}),
        pa.table({"gamma_deg": [4.0, 8.0], "mu_static": pa.nulls(2)}),
    ]:
        assert run(lanes).equals(want), type(lanes)


def test_numbers_and_words_mixed_read_as_a_csv_cell(tmp_path):
    import pandas as pd

    want = reference(tmp_path, "gamma_deg,f2\n4,1000\n8.5,\n12,-2000.25\n")
    df = pd.DataFrame({"gamma_deg": [4, "8.5", 12.0], "f2": [1000, None, "-2000.25"]})
    assert run(df).equals(want)
    bad = pd.DataFrame({"gamma_deg": [4.0, "heavy"]})
    assert input_error(lambda: run(bad)) == "lanes: lane 1: gamma_deg: `heavy` is not a number"
    assert input_error(lambda: run(pd.DataFrame({"gamma_deg": [4.0, True, "x"]}))).startswith(
        "lanes: lane 1: gamma_deg: `True` is a boolean; allowed: numbers"
    )
    assert input_error(lambda: run(pd.DataFrame({"gamma_deg": [4.0, {"a": 1}]}))).startswith(
        "lanes: lane 1: gamma_deg: holds a dict (`{'a': 1}`); allowed: numbers"
    )
    assert input_error(lambda: run(pd.DataFrame({"gamma_deg": [4 + 1j]}))).startswith(
        "lanes: gamma_deg: holds complex128; allowed: numbers (any integer or float type) or words"
    )


def test_a_column_named_twice(cli, tmp_path):
    import pandas as pd

    df = pd.DataFrame([[4.0, 1.0, 8.0]], columns=["gamma_deg", "f2", "gamma_deg"])
    f = tmp_path / "lanes.csv"
    f.write_text("gamma_deg,f2,gamma_deg\n4,1,8\n")
    # The command line names the header's line; a table in memory has none.
    assert cli_error(cli, "run", "--lanes", f, "--out", tmp_path / "o") == f"{f}: line 1: gamma_deg: column appears twice"
    assert input_error(lambda: run(df)) == "lanes: gamma_deg: column appears twice"
    t = pa.Table.from_arrays([pa.array([4.0]), pa.array([1.0]), pa.array([8.0])], names=["gamma_deg", "f2", "gamma_deg"])
    assert input_error(lambda: run(t)) == "lanes: gamma_deg: column appears twice"


def test_lazy_frames_and_series(tmp_path):
    import pandas as pd
    import polars as pl

    want = reference(tmp_path, "gamma_deg\n4\n8\n")
    assert run(pl.DataFrame({"gamma_deg": [4.0, 8.0]}).lazy()).equals(want)
    assert run(pl.LazyFrame({"gamma_deg": [4, 8]}).with_columns(pl.col("gamma_deg") * 1.0)).equals(want)
    assert run(pd.Series([4.0, 8.0], name="gamma_deg")).equals(want)
    assert run(pl.Series("gamma_deg", [4.0, 8.0])).equals(want)
    for lanes, why in [
        (pd.Series([4.0, 8.0]), "it has no name"),
        (pd.DataFrame({"gamma_deg": [4.0], "f2": [1.0]}).iloc[0], "its index holds names"),
        (pl.Series([4.0, 8.0]), "a polars Series without a name is not a lane table"),
    ]:
        with pytest.raises(TypeError) as e:
            run(lanes)
        assert str(e.value).startswith("lanes: ") and why in str(e.value), str(e.value)
        assert "allowed: a CSV path, a pandas or polars DataFrame" in str(e.value)


def test_text_that_is_not_text(tmp_path):
    import pandas as pd

    # A lone surrogate (what a bad decode leaves in a str) is no law's or
    # parameter's name: shown as U+FFFD, refused with the lane.
    df = pd.DataFrame({"gamma_deg": [4.0, 8.0], "friction": pd.Series(["coulomb", "cou\ud800"], dtype=object)})
    assert input_error(lambda: run(df)) == (
        "lanes: lane 1: friction: `cou\ufffd` is not a friction law; allowed: paper, coulomb, table, agma, stribeck"
    )
    df = pd.DataFrame([[4.0]], columns=pd.Index(["gamma\ud800"], dtype=object))
    assert input_error(lambda: run(df)).startswith("lanes: gamma\ufffd: unknown column; allowed: m1, m2")
    assert input_error(lambda: tswm.run('[base]\nfriction = "co\ud800"\n', progress=False)) == (
        "sweep: line 2: U+D800 (a lone surrogate) is not UTF-8 text; a sweep is TOML, UTF-8 encoded"
    )
    assert input_error(lambda: tswm.run({"base": {"f2": 1.0, "friction": "co\udcff"}}, progress=False)) == (
        "sweep: sweep['base']['friction']: byte 0xff is not UTF-8 text; a sweep is TOML, UTF-8 encoded"
    )
    f = tmp_path / "bad.toml"
    f.write_bytes(b'[base]\nfriction = "co\xff"\n')
    assert "line 2: byte 0xff is not UTF-8 text; a sweep file is TOML, UTF-8 encoded" in input_error(
        lambda: tswm.run(f, progress=False)
    )
    assert input_error(lambda: tswm.run(pathlib.Path("no\ud800.toml"), progress=False)) == (
        "sweep: `no\ufffd.toml` holds a lone surrogate (U+D800), which no file name holds; allowed: "
        "a sweep file's path, its TOML text or a dict"
    )


def test_a_dict_nested_past_any_sweep():
    deep = {}
    d = deep
    for _ in range(3000):
        d["a"] = {}
        d = d["a"]
    msg = input_error(lambda: tswm.run({"base": deep}, progress=False))
    assert msg == (
        "sweep['base']" + "['a']" * 13 + "['...: nested more than 16 deep; allowed: a sweep file's "
        "tables and lists (docs/guide.md)"
    )
    lists = [1.0]
    for _ in range(3000):
        lists = [lists]
    msg = input_error(lambda: tswm.run({"grid": [{"param": "f2", "values": lists}]}, progress=False))
    assert msg.startswith("sweep['grid'][0]['values'][0][0][0]") and "nested more than 16 deep" in msg
    cycle = {}
    cycle["base"] = cycle
    assert "nested more than 16 deep" in input_error(lambda: tswm.run(cycle, progress=False))


# --- arguments ---


def test_threads_out_of_range(root):
    paper = root / "sweeps/paper.toml"
    most = tswm._tswm.MAX_THREADS
    for n in [-1, 0, most + 1, 10**30]:
        msg = input_error(lambda: tswm.run(paper, threads=n, progress=False))
        assert msg.startswith(f"threads: {n} is not allowed; allowed: 1 to {most} ("), msg
        msg = input_error(lambda: tswm.bench(paper, threads=n, progress=False))
        assert msg.startswith(f"threads: {n} is not allowed"), msg
    for n in [1.5, True, "2"]:
        with pytest.raises(TypeError) as e:
            tswm.run(paper, threads=n, progress=False)
        assert str(e.value).startswith("threads: "), str(e.value)
    import numpy as np

    assert tswm.run(paper, threads=np.int64(2), backend="cpu", progress=False).num_rows == 2
    msg = input_error(lambda: tswm.run(paper, tol=10**400, progress=False))
    assert msg.startswith("--tol: inf is not allowed; allowed: 1e-13 to 1e-4"), msg


def test_an_empty_or_unnameable_path(root, tmp_path, monkeypatch):
    paper = root / "sweeps/paper.toml"
    monkeypatch.chdir(tmp_path)
    assert input_error(lambda: tswm.run(paper, out="", progress=False)) == (
        "out: the path is empty; allowed: a folder's path: a new or empty folder, or the folder of "
        "an earlier tswm run"
    )
    assert input_error(lambda: tswm.run(paper, out=b"", progress=False)).startswith("out: the path is empty")
    assert input_error(lambda: tswm.run(paper, out="o\0ut", progress=False)).startswith(
        "out: `o\\u{0}ut` holds a NUL character"
    )
    assert input_error(lambda: tswm.run(paper, lanes="", progress=False)).startswith("lanes: the path is empty")
    assert input_error(lambda: tswm.read("")).startswith("dir: the path is empty")
    assert input_error(lambda: tswm.summary("")).startswith("dir: the path is empty")
    assert input_error(lambda: tswm.report("")).startswith("dir: the path is empty")
    assert os.listdir(tmp_path) == []


def test_a_folder_whose_name_is_not_utf8(root, tmp_path):
    raw = os.fsencode(tmp_path) + b"/run-\xff\xfe"
    name = os.fsdecode(raw)
    got = tswm.run(root / "sweeps/paper.toml", backend="cpu", out=name, progress=False)
    assert os.path.isfile(raw + b"/lanes.csv")
    assert tswm.read(raw).equals(got) and tswm.read(name).equals(got)
    r = tswm.report(name)
    assert isinstance(r.path, str) and os.fsencode(r.path) == raw + b"/report.html"
    assert os.path.isfile(r.path) and r.html().startswith("<!DOCTYPE html>")
    r = tswm.report(raw)
    assert r.path == raw + b"/report.html" and r.html().startswith("<!DOCTYPE html>")
    assert tswm.summary(raw).equals(tswm.summary(name))


def test_a_line_break_in_a_path_stays_one_line(cli, tmp_path):
    odd = tmp_path / "a\nb"
    want = cli_error(cli, "run", odd / "sweep.toml", "--out", tmp_path / "o")
    assert input_error(lambda: tswm.run(odd / "sweep.toml", progress=False)) == want
    assert want == f"{tmp_path}/a\\nb/sweep.toml: cannot read the sweep file: No such file or directory (os error 2)"
    for call in [tswm.read, tswm.summary, tswm.sensitivity, tswm.report]:
        msg = input_error(lambda: call(odd))
        assert msg.startswith(f"{tmp_path}/a\\nb"), msg
    odd.mkdir()
    assert input_error(lambda: tswm.summary(odd)) == (
        f"{tmp_path}/a\\nb: holds no summary.csv; every tswm run writes one (a shard does not)"
    )
    f = tmp_path / "tab\there.csv"
    f.write_text("gamma_deg\n100\n")
    assert input_error(lambda: run(f)).startswith(f"{tmp_path}/tab\\there.csv: row 1 (line 2): gamma_deg:")


def test_a_sweep_past_one_run_says_what_a_python_caller_can_do():
    sweep = {
        "grid": [
            {"param": "f2", "from": -1.0, "to": 1.0, "n": 100000},
            {"param": "gamma_deg", "from": 2.0, "to": 30.0, "n": 20000},
        ]
    }
    assert input_error(lambda: tswm.run(sweep, progress=False)) == (
        "sweep: 2000000000 lanes are more than one run takes (at most 1e9); run them as at least 2 "
        "parts of at most 1e9 lanes: from the command line as 2 shards (tswm run SWEEP --shard K/2, "
        "docs/cluster.md), or in Python each a tswm.run of its own (split a grid axis's values, or "
        "a lane table's rows: docs/python.md)"
    )
