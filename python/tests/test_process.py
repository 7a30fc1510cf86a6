"""tswm in a Python process: the interpreter released while lanes
integrate, Ctrl-C stopping a run, the progress bar, the report inline."""

import os
import subprocess
import sys
import textwrap
import threading
import time

import tswm


def test_another_thread_runs_while_lanes_integrate():
    count = 0
    stop = threading.Event()

    def spin():
        nonlocal count
        while not stop.is_set():
            count += 1

    th = threading.Thread(target=spin)
    th.start()
    t0 = time.monotonic()
    try:
        t = tswm.run(
            {"grid": [{"param": "f2", "from": -6000.0, "to": 6000.0, "n": 400000}]},
            threads=1,
            backend="cpu",
            progress=False,
        )
    finally:
        stop.set()
        th.join()
    seconds = time.monotonic() - t0
    assert t.num_rows == 400000
    # Held by the run, the interpreter would let the other thread count
    # only between the run's wake-ups; released, it counts all along (a
    # loop of a Python thread counts millions a second).
    assert seconds > 0.5 and count > 200_000 * seconds, (seconds, count)


CTRL_C = textwrap.dedent(
    """
    import os, signal, sys, threading, time
    import tswm

    # Ctrl-C in an interactive session reaches Python's own handler. A
    # Python started with SIGINT ignored (a background job of a
    # non-interactive shell, as some test runners start their tests) keeps
    # it ignored, and the run would never hear it: install the handler an
    # interactive session has.
    signal.signal(signal.SIGINT, signal.default_int_handler)
    out = sys.argv[1]
    sent = {}

    def interrupt():
        time.sleep(float(sys.argv[2]))
        sent["at"] = time.monotonic()
        os.kill(os.getpid(), signal.SIGINT)

    threading.Thread(target=interrupt, daemon=True).start()
    sweep = {"base": {"t_end": 1e-4}, "grid": [{"param": "f2", "from": -5000.0, "to": 5000.0, "n": 50_000_000}]}
    try:
        tswm.run(sweep, out=out, progress=False)
        print("finished")
    except KeyboardInterrupt:
        print(f"stopped {time.monotonic() - sent['at']:.3f}")
    """
)


def test_ctrl_c_stops_a_run_and_leaves_no_folder(tmp_path):
    # One second in (the run still checks its 5x10^7 lanes), and later (a
    # shorter sweep is running its lanes by then: see the second run).
    for delay, n in [("1.0", None), ("3.0", 3_000_000)]:
        script = CTRL_C if n is None else CTRL_C.replace("50_000_000", str(n))
        out = tmp_path / f"out-{delay}"
        p = subprocess.run(
            [sys.executable, "-c", script, str(out), delay],
            capture_output=True,
            text=True,
            timeout=120,
        )
        assert p.returncode == 0, p.stderr
        said = p.stdout.split()
        if said[0] == "finished":
            # The shorter sweep may finish before the signal on a fast machine.
            assert n is not None
            continue
        assert said[0] == "stopped" and float(said[1]) < 2.0, p.stdout
        assert not out.exists()


def test_a_progress_bar_for_runs_over_a_second(capsys):
    sweep = {"grid": [{"param": "f2", "from": -6000.0, "to": 6000.0, "n": 200000}]}
    tswm.run(sweep, threads=1, backend="cpu", progress=True)
    err = capsys.readouterr().err
    assert "lanes" in err and "%" in err, err
    tswm.run(sweep, threads=1, backend="cpu", progress=False)
    assert capsys.readouterr().err == ""


def test_the_report_shows_inline(root, tmp_path):
    tswm.run(root / "sweeps/efficiency_map.toml", backend="cpu", out=tmp_path, progress=False)
    os.remove(tmp_path / "report.html")
    r = tswm.report(tmp_path)
    assert r.path == str(tmp_path / "report.html") and os.path.isfile(r.path)
    page = r.html()
    assert page.startswith("<!DOCTYPE html>") and "</html>" in page
    shown = r._repr_html_()
    assert shown.startswith("<iframe") and 'srcdoc="&lt;!DOCTYPE html&gt;' in shown
    # The page inside, escaped once: no raw quote breaks the attribute.
    inner = shown.split('srcdoc="', 1)[1].rsplit('"></iframe>', 1)[0]
    assert '"' not in inner
