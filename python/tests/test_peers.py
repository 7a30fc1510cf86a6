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
