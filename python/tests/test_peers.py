"""The heyoka peer (benches/peers/heyoka_peer.py) integrates the lanes it
writes as tswm does: its rows agree with a reference-grade tswm run of the
same lane table (--tol 1e-12) within the 1e-6 bound tswm holds its own rows
to, at the tolerance its figure in docs/performance.md is measured at."""

import os
import subprocess
import sys

import pytest


def test_the_heyoka_peer_agrees_with_tswm(root, cli, tmp_path):
    if os.environ.get("CI") is None:
        pytest.importorskip("heyoka", reason="the peer needs heyoka (pip install heyoka)")
    peer = root / "benches/peers/heyoka_peer.py"
    lanes = tmp_path / "lanes.csv"
    subprocess.run(
        [sys.executable, peer, "--make-lanes", lanes, "--distinct", "150", "--copies", "1"],
        check=True,
    )
    cli("run", "--lanes", lanes, "--out", tmp_path / "ref", "--tol", "1e-12", "--no-report")
    for tol in ("1e-7", "1e-6"):
        p = subprocess.run(
            [sys.executable, peer, lanes, "--check", tmp_path / "ref/lanes.csv", "--tol", tol],
            capture_output=True,
            text=True,
            check=True,
        )
        worst = float(p.stdout.split("worst difference from tswm ")[1].split(" ")[0])
        assert worst < 1e-6, p.stdout
        assert "150 lanes" in p.stdout, p.stdout


def twenty_peer_lanes(root, tmp_path):
    """The first 20 distinct lanes of the heyoka peer's table, once each."""
    lanes = tmp_path / "lanes.csv"
    subprocess.run(
        [sys.executable, root / "benches/peers/heyoka_peer.py", "--make-lanes", lanes,
         "--distinct", "20", "--copies", "1"],
        check=True,
    )
    return lanes


def test_the_pairs_comparison_runs_on_the_peers_lanes(root, tmp_path):
    """benches/peers/pairs_scipy.py (docs/performance.md): each pair's
    accuracy follows its tolerance, and the figure's claim holds on a few
    lanes: at a tolerance where both pairs are within 1e-7, Dormand-Prince
    5(4) takes fewer evaluations than DOP853."""
    lanes = twenty_peer_lanes(root, tmp_path)
    p = subprocess.run(
        [sys.executable, root / "benches/peers/pairs_scipy.py", lanes, "--lanes", "20"],
        capture_output=True, text=True, check=True,
    )
    rows = {}
    for line in p.stdout.splitlines()[2:]:
        _, pair, tol, evals, _, worst, _ = line.split("|")
        rows[(pair.strip(), float(tol))] = (float(evals), float(worst))
    for (pair, tol), (_, worst) in rows.items():
        assert worst < 30 * tol, (pair, tol, worst)
    assert rows[("RK45", 1e-8)][1] < 1e-7 and rows[("DOP853", 1e-8)][1] < 1e-7
    assert rows[("RK45", 1e-8)][0] < rows[("DOP853", 1e-8)][0], p.stdout


def test_the_multistep_residual_overstates_the_local_error_far_more_than_the_embedded_estimate(
    root, tmp_path
):
    """benches/peers/estimate_multistep.py (docs/performance.md): on the
    peer's lanes at tol 1e-6, the embedded estimates summed are 5 to 15
    times the actual local errors summed for every component, and the
    multistep residual's median ratio to the local error is over 100 times
    the embedded estimate's."""
    lanes = twenty_peer_lanes(root, tmp_path)
    p = subprocess.run(
        [sys.executable, root / "benches/peers/estimate_multistep.py", lanes, "--lanes", "20"],
        capture_output=True, text=True, check=True,
    )
    median = {}
    sums = {}
    for line in p.stdout.splitlines():
        cells = [c.strip() for c in line.split("|")[1:-1]]
        if len(cells) == 4 and cells[0] in ("embedded 4th-order", "multistep, 6 points"):
            median[cells[0]] = float(cells[2])
        if len(cells) == 3 and cells[0] in ("x1", "v1", "w_motor", "w_load", "w_friction"):
            sums[cells[0]] = (float(cells[1]), float(cells[2]))
    assert len(median) == 2 and len(sums) == 5, p.stdout
    assert median["multistep, 6 points"] > 100 * median["embedded 4th-order"], p.stdout
    for name, (actual, embedded) in sums.items():
        assert 5 * actual < embedded < 15 * actual, (name, p.stdout)


def test_the_cost_split_files_each_location_under_its_part(root):
    """benches/cost_split.py files callgrind's file:function locations
    under the parts docs/performance.md names; standard-library code under
    the tswm function it was inlined into."""
    sys.path.insert(0, str(root / "benches"))
    try:
        import cost_split
    finally:
        sys.path.pop(0)
    lib = "/rustc/0123/library/core/src/num/f64.rs"
    for loc, part in [
        ("/x/src/model/vmath.rs:tswm::integrator::batch::on_avx2", "right-hand side"),
        ("/x/src/integrator/stepper.rs:tswm::integrator::batch::on_avx2",
         "stages and step control"),
        ("/x/src/integrator/accuracy.rs:tswm::integrator::batch::on_avx2",
         "step verdicts and error budget"),
        ("/x/src/integrator/events.rs:tswm::integrator::events::locate_root",
         "events and the automaton"),
        ("/x/src/integrator/lockstep.rs:tswm::integrator::batch::on_avx2",
         "lockstep bookkeeping"),
        (f"{lib}:tswm::integrator::batch::on_avx2", "lockstep bookkeeping"),
        ("/x/src/params/check.rs:tswm::params::check::check", "reading and checking lanes"),
        (f"{lib}:core::num::dec2flt::parse::parse_number", "reading and checking lanes"),
        ("/x/src/output/float_text.rs:tswm::output::float_text::push_f64", "writing"),
        ("/y/zmij-1.0.23/src/lib.rs:<f64 as zmij::private::Sealed>::write", "writing"),
        ("./malloc/./malloc/malloc.c:_int_free", "other"),
    ]:
        assert cost_split.part_of(loc) == part, loc
