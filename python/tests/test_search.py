"""A search in Python: the same drives, brackets and critical values as
the command line's run of the same sweep, and the search's columns read
back from its folder."""

import pyarrow.csv as pacsv

import tswm


def test_a_search_gives_the_command_lines_table(root, cli, tmp_path):
    sweep = root / "sweeps" / "start_load.toml"
    cli("run", str(sweep), "--out", str(tmp_path / "cli"), "--backend", "cpu", "--no-report")
    lanes = tswm.run(str(sweep), backend="cpu", progress=False)
    want = tswm.read(tmp_path / "cli")
    assert lanes.column_names == want.column_names
    for name in ["lane", "gamma_deg", "f2", "critical", "search_lo", "search_hi", "search_status", "search_meets", "search_lanes"]:
        assert lanes.column(name).to_pylist() == want.column(name).to_pylist(), name
    # The folder's table is lanes.csv as written, search columns included.
    raw = pacsv.read_csv(tmp_path / "cli" / "lanes.csv")
    assert raw.column("critical").to_pylist() == want.column("critical").to_pylist()
    assert set(lanes.column("search_status").to_pylist()) == {"found"}


def test_a_share_boundary_from_python_is_in_its_summary(root, tmp_path):
    sweep = {
        "base": {"friction": "coulomb", "mu": 0.05, "mu_static": 0.1, "f2": 5000.0, "motor_off": 0.0, "t_end": 0.5},
        "search": {"param": "gamma_deg", "from": 1.0, "to": 15.0, "require": "hold = held", "tol": 1e-4, "at_least": 0.9},
        "sampling": {"method": "monte_carlo", "n": 200, "seed": 11},
        "tolerance": [{"param": "mu_static", "dist": "uniform", "tol_rel": 0.3}],
    }
    tswm.run(sweep, out=tmp_path / "o", progress=False)
    rows = tswm.summary(tmp_path / "o").to_pylist()
    b = next(r for r in rows if r["kind"] == "boundary")
    assert b["share"] == 0.9
    assert b["ci95_low"] <= b["p50"] <= b["ci95_high"]
    bound = next(r for r in rows if r["kind"] == "bound")
    assert bound["p50"] <= b["p50"]
