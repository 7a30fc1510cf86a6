"""Whether the error of the solution tswm propagates could be estimated
from the steps it takes anyway: the local error of Dormand-Prince's
5th-order solution, step by step, against two estimates read off the
accepted steps: the embedded 4th-order estimate (what `accuracy` sums
today) and a multistep residual (the step's increment against the
integral of the polynomial through the derivatives at the last six
accepted points, as Adams-Moulton's 6th-order formula would take it).

    python3 benches/peers/estimate_multistep.py lanes.csv [--lanes 30] [--tol 1e-6]

lanes.csv as `benches/peers/heyoka_peer.py --make-lanes` writes it. Each
lane is integrated from rest to its first switch or its end (the
right-hand side of `pairs_scipy.py`) with Dormand-Prince 5(4), each
component's step error held to tol * max(1, |y|) as tswm does; each
step's actual local error is the 5th-order solution less DOP853's at
rtol 1e-14 from the same start. Prints, over the component-steps whose
local error is over 1e-3 tol, the estimate's ratio to it, and per
component the median over lanes of the summed local errors and summed
estimates, relative to max(1, |final value|).
"""
import argparse
import csv
import os
import sys
import warnings

import numpy as np
from scipy.integrate import solve_ivp

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pairs_scipy import lane  # noqa: E402

C = [0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1, 1]
A = [[], [1 / 5], [3 / 40, 9 / 40], [44 / 45, -56 / 15, 32 / 9],
     [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729],
     [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656],
     [35 / 384, 0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84]]
B5 = np.array([35 / 384, 0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84, 0])
B4 = np.array([5179 / 57600, 0, 7571 / 16695, 393 / 640, -92097 / 339200, 187 / 2100, 1 / 40])
NAMES = ["x1", "v1", "w_motor", "w_load", "w_friction"]
POINTS = 6


def dp_step(f, t, y, k1, h):
    k = [k1]
    for i in range(1, 7):
        k.append(np.array(f(t + C[i] * h, y + h * sum(a * kj for a, kj in zip(A[i], k)))))
    k = np.array(k)
    return y + h * B5 @ k, h * (B5 - B4) @ k, k[6]


def multistep(ts, fs, y0, y1):
    """y1 - y0 less the integral over the last interval of the polynomial
    through the derivatives fs at the times ts."""
    h = ts[-1] - ts[-2]
    x = (np.array(ts) - ts[-2]) / h
    w = np.linalg.solve(np.vander(x, len(x), increasing=True).T, 1.0 / np.arange(1, len(x) + 1))
    return y1 - y0 - h * (w @ np.array(fs))


def run(f, ev, t_end, tol):
    """Per accepted step: |e4|, |actual local error|, |multistep| (None
    without six points of history), and the lane's final state."""
    t, y, h = 0.0, np.zeros(5), 1e-6
    k1 = np.array(f(t, y))
    ts, fs, steps = [t], [k1], []
    while t < t_end - 1e-15:
        h = min(h, t_end - t)
        y5, e, k7 = dp_step(f, t, y, k1, h)
        err = np.max(np.abs(e) / (tol * np.maximum(1.0, np.maximum(np.abs(y), np.abs(y5)))))
        if err > 1:
            h *= max(0.2, 0.9 * err ** -0.2)
            continue
        if ev(t, y) >= 0 > ev(t + h, y5):
            break
        u = solve_ivp(f, (t, t + h), y, method="DOP853", rtol=1e-14, atol=1e-16).y[:, -1]
        ts.append(t + h)
        fs.append(k7)
        ms = multistep(ts[-POINTS:], fs[-POINTS:], y, y5) if len(ts) >= POINTS else None
        steps.append((np.abs(e), np.abs(y5 - u), None if ms is None else np.abs(ms)))
        t, y, k1 = t + h, y5, k7
        h *= min(5.0, 0.9 * max(err, 1e-10) ** -0.2)
    return steps, y


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("lanes")
    ap.add_argument("--lanes", dest="n", type=int, default=30)
    ap.add_argument("--tol", type=float, default=1e-6)
    a = ap.parse_args()
    warnings.filterwarnings("ignore", message="At least one element of `rtol`")
    rows = list(csv.DictReader(open(a.lanes)))[: a.n]
    ratios = {"embedded 4th-order": [], "multistep, 6 points": []}
    sums = []
    nsteps = 0
    for r in rows:
        f, ev, t_end = lane(r)
        steps, y = run(f, ev, t_end, a.tol)
        nsteps += len(steps)
        sc = np.maximum(1.0, np.abs(y))
        sums.append([sum(s[j] for s in steps) / sc for j in (1, 0)])
        for e4, le, ms in steps:
            if ms is None:
                continue
            big = le > 1e-3 * a.tol
            ratios["embedded 4th-order"].extend(e4[big] / le[big])
            ratios["multistep, 6 points"].extend(ms[big] / le[big])
    print(f"{len(rows)} lanes, tol {a.tol:g}, {nsteps / len(rows):.1f} steps a lane")
    print("| estimate / actual local error | 1st percentile | median | 99th percentile |")
    print("|---|---|---|---|")
    for name, q in ratios.items():
        q = np.array(q)
        print(f"| {name} | {np.percentile(q, 1):.3g} | {np.median(q):.3g} | {np.percentile(q, 99):.3g} |")
    print()
    print("| component | actual local errors, summed | embedded estimates, summed |")
    print("|---|---|---|")
    s = np.array(sums)
    for i, name in enumerate(NAMES):
        print(f"| {name} | {np.median(s[:, 0, i]):.2e} | {np.median(s[:, 1, i]):.2e} |")


if __name__ == "__main__":
    main()
