"""A refusal writes nothing (issue 36): over randomised folder states and
calls that are refused, the folder (and the folder around it) is exactly
as it was, names, kinds, sizes, contents, modes and modification times,
and the refusal is a tswm.InputError.

Each (state, call) pair is one test, run on a few randomly drawn
variants of the state (names, contents, how many files); the draw is
seeded by TSWM_PROPERTY_SEED (default 36) and the pair, so a failure
reproduces with the same seed."""

import os
import random
import shutil
import stat
import zlib

import pytest

import tswm

SEED = int(os.environ.get("TSWM_PROPERTY_SEED", "36"))
#: Variants of a state drawn for each pair.
DRAWS = 3

# --- folder states: each makes `d` (which does not exist yet) ---

ODD_NAMES = [
    "with space.txt",
    "-starts-with-dash",
    "line\nbreak",
    "tab\there",
    "ünïcödé.csv",
    os.fsdecode(b"not-utf8-\xff\xfe"),
    ".hidden",
    "report.html",
    "lanes.csv",
    ".tswm.files.bak",
    "x" * 200,
]


def user_files(rng, d, names):
    """A few files of the user's, of random sizes and bytes."""
    for name in rng.sample(names, rng.randint(1, min(4, len(names)))):
        (d / name).write_bytes(rng.randbytes(rng.choice([0, 1, 17, 4096, 70_000])))


def state_missing(rng, d, earlier):
    pass


def state_empty(rng, d, earlier):
    d.mkdir()


def state_users_file(rng, d, earlier):
    d.mkdir()
    user_files(rng, d, ["notes.txt", "report.html", "data.csv", "summary.csv", "plot.png"])


def state_earlier_run(rng, d, earlier):
    # copy2 keeps the files' modification times; the copies are a run's.
    shutil.copytree(earlier, d, copy_function=shutil.copy2)


def state_not_a_run(rng, d, earlier):
    """The files of a run without its marker, a user's lanes.csv among them."""
    d.mkdir()
    for name in rng.sample(["summary.csv", "sweep.resolved.toml", "traces.csv", "report.html"], 2):
        shutil.copy2(earlier / name, d / name)
    (d / "lanes.csv").write_text("my own table\n1,2,3\n")


def state_odd_names(rng, d, earlier):
    d.mkdir()
    user_files(rng, d, ODD_NAMES)
    if rng.random() < 0.5:
        (d / "sub dir").mkdir()
        (d / "sub dir" / "deep\nname").write_bytes(rng.randbytes(33))


def state_a_file(rng, d, earlier):
    """Not a folder: a file where the folder would be."""
    d.write_bytes(rng.randbytes(rng.choice([0, 5, 1000])))


STATES = {
    "missing": state_missing,
    "empty": state_empty,
    "users_file": state_users_file,
    "earlier_run": state_earlier_run,
    "not_a_run": state_not_a_run,
    "odd_names": state_odd_names,
    "a_file": state_a_file,
}

# --- refused calls: (which states refuse them, the call) ---

EVERY = set(STATES)
#: States whose folder a run refuses: it holds what tswm did not write.
FOREIGN = {"users_file", "not_a_run", "odd_names", "a_file"}
#: States that are no run's folder.
NOT_A_RUN = {"missing", "empty", "users_file", "not_a_run", "odd_names", "a_file"}


def bad_lane_frame(rng):
    import pandas as pd

    rows = rng.randint(1, 5)
    gammas = [rng.uniform(2.0, 30.0) for _ in range(rows)]
    gammas[rng.randrange(rows)] = rng.choice([100.0, 0.1, -5.0])
    return pd.DataFrame({"gamma_deg": gammas, "f2": [1000.0] * rows})


def call_bad_sweep_text(rng, d, paper, tmp):
    text = rng.choice(['[base]\ngamma_deg = 100.0\n', '[base\n', '[base]\nfriction = "teflon"\n'])
    tswm.run(text, out=d, progress=False)


def call_bad_sweep_dict(rng, d, paper, tmp):
    tswm.run({"base": {"gamma_deg": rng.choice([100.0, 0.0, -1.0])}}, out=d, progress=False)


def call_bad_lane_frame(rng, d, paper, tmp):
    tswm.run({"base": {"friction": "coulomb", "mu": 0.05}}, lanes=bad_lane_frame(rng), out=d, progress=False)


def call_bad_lane_csv(rng, d, paper, tmp):
    f = tmp / "bad-lanes.csv"
    f.write_text(rng.choice(["gamma_deg,f2\n5,1\n100,2\n", "gama_deg\n5\n", "f2\nheavy\n"]))
    tswm.run(lanes=f, out=d, progress=False)


def call_bad_threads(rng, d, paper, tmp):
    tswm.run(paper, out=d, threads=rng.choice([-1, 0, 10**30]), progress=False)


def call_bad_tol(rng, d, paper, tmp):
    tswm.run(paper, out=d, tol=rng.choice([1.0, 0.0, -1e-8]), progress=False)


def call_bad_backend(rng, d, paper, tmp):
    tswm.run(paper, out=d, backend=rng.choice(["tpu", "CPU", ""]), progress=False)


def call_bad_format(rng, d, paper, tmp):
    tswm.run(paper, out=d, format=rng.choice(["xlsx", "json"]), progress=False)


def call_sweep_too_big(rng, d, paper, tmp):
    grid = [{"param": "f2", "from": -1.0, "to": 1.0, "n": 100_000}, {"param": "gamma_deg", "values": [5.0] * 20_000}]
    tswm.run({"grid": grid}, out=d, progress=False)


def call_run_into_foreign(rng, d, paper, tmp):
    tswm.run(paper, out=d, backend="cpu", format=rng.choice(["csv", "parquet"]), progress=False)


def call_report(rng, d, paper, tmp):
    tswm.report(d)


def call_read(rng, d, paper, tmp):
    rng.choice([tswm.read, tswm.sensitivity])(d)


CALLS = {
    "bad_sweep_text": (EVERY, call_bad_sweep_text),
    "bad_sweep_dict": (EVERY, call_bad_sweep_dict),
    "bad_lane_frame": (EVERY, call_bad_lane_frame),
    "bad_lane_csv": (EVERY, call_bad_lane_csv),
    "bad_threads": (EVERY, call_bad_threads),
    "bad_tol": (EVERY, call_bad_tol),
    "bad_backend": (EVERY, call_bad_backend),
    "bad_format": (EVERY, call_bad_format),
    "sweep_too_big": (EVERY, call_sweep_too_big),
    "run_into_a_foreign_folder": (FOREIGN, call_run_into_foreign),
    "report_of_no_run": (NOT_A_RUN, call_report),
    "read_of_no_run": (NOT_A_RUN - {"not_a_run"}, call_read),
}

PAIRS = [(s, c) for c, (states, _) in CALLS.items() for s in STATES if s in states]


def snapshot(root):
    """Everything about the tree under `root` (itself included): each
    entry's name (bytes, as the OS holds it), kind, mode, size,
    modification time and, for a file, its contents."""
    out = {}
    broot = os.fsencode(root)
    for top, dirs, files in os.walk(broot):
        # Each folder once as `top` (None), its files by name.
        for name in [*files, None]:
            path = top if name is None else os.path.join(top, name)
            st = os.lstat(path)
            entry = (stat.S_IFMT(st.st_mode), stat.S_IMODE(st.st_mode), st.st_size, st.st_mtime_ns)
            if stat.S_ISREG(st.st_mode):
                with open(path, "rb") as f:
                    entry += (f.read(),)
            out[os.path.relpath(path, broot)] = entry
    return out


def differences(before, after):
    """What changed, in words (names as the OS holds them)."""
    said = []
    for k in sorted(set(before) | set(after)):
        if k not in after:
            said.append(f"{k!r} removed")
        elif k not in before:
            said.append(f"{k!r} appeared")
        elif before[k] != after[k]:
            what = ["kind", "mode", "size", "mtime", "contents"]
            changed = [w for w, a, b in zip(what, before[k], after[k]) if a != b]
            said.append(f"{k!r}: {', '.join(changed)} changed")
    return said


@pytest.fixture(scope="module")
def earlier(root, tmp_path_factory):
    """The folder of an earlier run (paper.toml: traces, summary, report)."""
    d = tmp_path_factory.mktemp("earlier") / "run"
    tswm.run(root / "sweeps/paper.toml", backend="cpu", out=d, progress=False)
    return d


@pytest.mark.parametrize("state,call", PAIRS, ids=[f"{s}-{c}" for s, c in PAIRS])
def test_a_refusal_leaves_the_folder_as_it_was(root, tmp_path, earlier, state, call):
    _, do = CALLS[call]
    for draw in range(DRAWS):
        seed = zlib.crc32(f"{SEED}/{state}/{call}/{draw}".encode())
        rng = random.Random(seed)
        # The folder sits alone in `around`, which is watched too: a folder
        # made and removed again changes its modification time.
        around = tmp_path / f"draw{draw}" / "around"
        around.mkdir(parents=True)
        d = around / rng.choice(["out", "run 1", "ü-dir", os.fsdecode(b"dir-\xff")])
        STATES[state](rng, d, earlier)
        before = snapshot(around)
        with pytest.raises(tswm.InputError) as e:
            do(rng, d, root / "sweeps/paper.toml", tmp_path)
        assert "\n" not in str(e.value)
        changed = differences(before, snapshot(around))
        assert not changed, f"seed {SEED}, draw {draw} ({state}, {call}): {e.value}: {changed}"
