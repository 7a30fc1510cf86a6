"""Shared fixtures: the repository, its shipped sweeps, and the `tswm`
command line the package is compared against."""

import os
import pathlib
import shutil
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


def _cli():
    """The command line: $TSWM_BIN, `tswm` on PATH, or the repository's
    release build."""
    for c in (os.environ.get("TSWM_BIN"), shutil.which("tswm"), ROOT / "target/release/tswm"):
        if c and pathlib.Path(c).is_file():
            return str(c)
    return None


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def cli():
    """Runs the command line; its CompletedProcess (text)."""
    exe = _cli()
    if exe is None:
        if os.environ.get("CI"):
            pytest.fail("CI: the tswm command line is required (cargo install --path .)")
        pytest.skip("no tswm command line (set TSWM_BIN, or build it: cargo build --release)")

    def run(*args, cwd=None, check=True):
        p = subprocess.run([exe, *map(str, args)], capture_output=True, text=True, cwd=cwd)
        if check and p.returncode != 0:
            raise AssertionError(f"tswm {' '.join(map(str, args))}: {p.stderr}")
        return p

    return run


@pytest.fixture(scope="session")
def shipped():
    """The shipped sweeps a test can run in seconds (million.toml is 10^6 lanes)."""
    return sorted(p for p in (ROOT / "sweeps").glob("*.toml") if p.name != "million.toml")
