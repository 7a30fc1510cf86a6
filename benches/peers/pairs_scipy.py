"""Which embedded Runge-Kutta pair costs least for tswm's lanes: scipy's
Dormand-Prince 5(4) (RK45, the pair tswm integrates with) against its
Dormand-Prince 8(5,3) (DOP853), each at several tolerances, on the same
lanes, as right-hand-side evaluations a lane against the accuracy reached.

    python3 benches/peers/pairs_scipy.py lanes.csv [--lanes 60]

lanes.csv: a table of paper-law lanes from rest (m1, m2, gamma_deg, f2,
t_end), as `benches/peers/heyoka_peer.py --make-lanes` writes it. Each lane
is integrated in its first mode up to its first switch (the switch is a
terminal event) or its end, from rest, with the model's equation of motion
(docs/model.md sections 2, 3, 5) written out here; the reference is DOP853
at rtol = atol = 1e-13. Accuracy: the largest difference of x1, v1 and the
works at the end, relative to max(1, |value|).
"""
import argparse
import csv
import math

import numpy as np
from scipy.integrate import solve_ivp

V_SYNC, V_CRIT, F_CRIT = 3.35, 2.07, 4375.0
FA, FB, FC = 0.174, 0.612, 0.14


def lane(row):
    """The right-hand side, the switch event and the horizon of a row."""
    m1, m2 = float(row["m1"]), float(row["m2"])
    g = math.radians(float(row["gamma_deg"]))
    tg, cg = math.tan(g), math.cos(g)
    f2 = float(row["f2"])
    sk = (V_SYNC - V_CRIT) / V_SYNC

    def f1(v):
        s = (V_SYNC - v) / V_SYNC
        return 2 * F_CRIT * s * sk / (s * s + sk * sk)

    side = 1 if f1(0.0) / m1 - f2 / (m2 * tg) >= 0 else -1

    def rhs(_, z):
        v = z[1]
        rho = math.radians(1 / (FA * (max(v, 0.0) / cg) ** FB + FC))
        force = f1(v)
        psi = -math.tan(g + side * rho)
        acc = (force - psi * f2) / (m1 - psi * m2 * tg)
        s1, s2 = force - m1 * acc, f2 - m2 * tg * acc
        return [v, acc, force * v, f2 * v * tg, s1 * v + s2 * v * tg]

    def switch(_, z):
        return side * (f1(z[1]) / m1 - f2 / (m2 * tg))

    switch.terminal, switch.direction = True, -1
    return rhs, switch, float(row["t_end"])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("lanes")
    ap.add_argument("--lanes", dest="n", type=int, default=60)
    a = ap.parse_args()
    rows = list(csv.DictReader(open(a.lanes)))[: a.n]
    cases = [lane(r) for r in rows]
    refs = [solve_ivp(f, (0, t), [0.0] * 5, method="DOP853", rtol=1e-13, atol=1e-13,
                      events=e, first_step=1e-8).y[:, -1] for f, e, t in cases]
    print("| pair | tol | evaluations a lane | steps a lane | worst difference |")
    print("|---|---|---|---|---|")
    for method in ["RK45", "DOP853"]:
        for tol in [1e-6, 1e-7, 1e-8, 1e-9]:
            nfev = steps = 0
            worst = 0.0
            for (f, e, t), ref in zip(cases, refs):
                s = solve_ivp(f, (0, t), [0.0] * 5, method=method, rtol=tol, atol=tol,
                              events=e, first_step=1e-6)
                nfev += s.nfev
                steps += len(s.t) - 1
                d = np.abs(s.y[:, -1] - ref) / np.maximum(1.0, np.abs(ref))
                worst = max(worst, float(d.max()))
            n = len(cases)
            print(f"| {method} | {tol:g} | {nfev / n:.0f} | {steps / n:.1f} | {worst:.1e} |")


if __name__ == "__main__":
    main()
