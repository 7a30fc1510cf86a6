"""A peer for tswm's CPU throughput: heyoka's Taylor integrator in batch mode
(LLVM-compiled at run time, SIMD lanes stepped together, events located per
lane), written as an expert would for lanes that tswm integrates too.

    python3 benches/peers/heyoka_peer.py --make-lanes lanes.csv [--distinct 150 --copies 1000]
    tswm run --lanes lanes.csv --out o --threads 1           # tswm's rows of the same lanes
    python3 benches/peers/heyoka_peer.py lanes.csv --check o/lanes.csv [--tol 1e-7]

The lanes (docs/model.md sections 2, 3, 5): the paper's drive with its
Kloss motor and friction law, from rest, with the lead angle, the load, the
worm's mass and the horizon varied; lanes that start at once and never
stick nor reverse (`--make-lanes` keeps only those, by the model's start
test at rest: a Kloss motor at rest pulls F1(0) = 2 f_crit s_k / (1 + s_k^2)).

What it integrates: x1, v1 and the works w_motor, w_load and w_friction;
psi = -tan(gamma + c rho(Vs)) with the contact side c a runtime parameter
of each lane, flipped by a terminal event on phi = F1/m1 - F2/(m2 tan gamma)
(scaled by f_crit/m1) whose callback goes on integrating; the works scaled
by f_crit v_sync t_end. Vs^b has no derivative at Vs = 0, which a Taylor
method needs, so each lane starts 1e-7 m/s after rest on its first-order
motion. Batch width heyoka.recommended_simd_size(), fast_math, Taylor order
from the tolerance.

It prints lanes/s of the integration alone (after the one compile, which
it times apart), the mean steps a lane, and with --check the largest
difference of x1_end, v1_end and the works from tswm's rows, relative to
max(1, |value|) (the bound tswm holds its CPU rows to is 1e-6).
"""

import argparse
import csv
import math
import time

import numpy as np

M1, M2, GAMMA_DEG = 586.0, 10275.0, math.degrees(math.atan(0.1))
V_SYNC, V_CRIT, F_CRIT = 3.35, 2.07, 4375.0
FA, FB, FC = 0.174, 0.612, 0.14
SK = (V_SYNC - V_CRIT) / V_SYNC
V_START = 1e-7
COLUMNS = ["m1", "m2", "gamma_deg", "f2", "t_end"]


def f1_of(v1):
    sigma = (V_SYNC - v1) / V_SYNC
    return 2.0 * F_CRIT * sigma * SK / (sigma * sigma + SK * SK)


def make_lanes(path, distinct, copies, seed):
    """`distinct` lanes that start at once and run without sticking, each
    written `copies` times."""
    rng = np.random.default_rng(seed)
    rows = []
    while len(rows) < distinct:
        m1 = rng.uniform(400.0, 800.0)
        m2 = rng.uniform(8000.0, 12000.0)
        g = rng.uniform(4.0, 9.0)
        f2 = rng.uniform(-5000.0, 5000.0)
        t_end = rng.uniform(1.0, 3.0)
        tg = math.tan(math.radians(g))
        rho0 = math.radians(1.0 / FC)
        # Starts at once: the motor at rest beats the load through the
        # wedge with its friction at rest, on the side it pushes.
        if f1_of(0.0) <= abs(f2) * math.tan(math.radians(g) + rho0) * 1.05:
            continue
        rows.append((m1, m2, g, f2, t_end))
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(COLUMNS)
        for _ in range(copies):
            for r in rows:
                w.writerow([repr(x) for x in r])


def system():
    import heyoka as hy

    x1, v1, wm, wl, wf = hy.make_vars("x1", "v1", "wm", "wl", "wf")
    c, f2, tg, m1, m2, wscale = (hy.par[i] for i in range(6))
    sigma = (V_SYNC - v1) / V_SYNC
    f1 = 2.0 * F_CRIT * sigma * SK / (sigma * sigma + SK * SK)
    cos_g = 1.0 / hy.sqrt(1.0 + tg * tg)
    vs = v1 / cos_g
    rho = (math.pi / 180.0) / (FA * vs**FB + FC)
    psi = -hy.tan(hy.atan(tg) + c * rho)
    a1 = (f1 - psi * f2) / (m1 - psi * m2 * tg)
    s1 = f1 - m1 * a1
    s2 = f2 - m2 * tg * a1
    v2 = v1 * tg
    sys = [
        (x1, v1),
        (v1, a1),
        (wm, f1 * v1 / wscale),
        (wl, f2 * v2 / wscale),
        (wf, (s1 * v1 + s2 * v2) / wscale),
    ]
    phi = (f1 / m1 - f2 / (m2 * tg)) * m1 / F_CRIT
    return sys, phi


def starts(lanes):
    """Each lane's state 1e-7 m/s after rest on its first-order motion, its
    parameters (contact side, f2, tan gamma, m1, m2, work scale), its time
    then and its horizon, as arrays (component-major)."""
    m1, m2, g, f2, t_end = (np.array(c) for c in zip(*lanes))
    tg = np.tan(np.radians(g))
    f1 = f1_of(0.0)
    c = np.where(f1 / m1 - f2 / (m2 * tg) > 0, 1.0, -1.0)
    psi = -np.tan(np.radians(g) + c * math.radians(1.0 / FC))
    a0 = (f1 - psi * f2) / (m1 - psi * m2 * tg)
    t0 = V_START / a0
    x = 0.5 * a0 * t0 * t0
    s1 = f1 - m1 * a0
    s2 = f2 - m2 * tg * a0
    wscale = F_CRIT * V_SYNC * t_end
    state = np.array([x, np.full_like(x, V_START), f1 * x, f2 * tg * x, (s1 + s2 * tg) * x])
    state[2:] /= wscale
    pars = np.array([c, f2, tg, m1, m2, wscale])
    return state, pars, t0, t_end


def integrate(lanes, tol):
    """Every lane's (x1, v1, w_motor, w_load, w_friction) at its t_end, the
    seconds the integration took, the compile's seconds, and the mean
    steps a lane (counted on a second pass over the first 1000 lanes,
    outside the timing)."""
    import heyoka as hy

    sys, phi = system()
    b = hy.recommended_simd_size()
    ev = hy.t_event_batch(phi, callback=flip)
    t = time.perf_counter()
    ta = hy.taylor_adaptive_batch(
        sys,
        np.zeros((5, b)),
        pars=np.zeros((6, b)),
        tol=tol,
        fast_math=True,
        t_events=[ev],
    )
    compile_s = time.perf_counter() - t
    n = len(lanes)
    pad = (-n) % b
    lanes = lanes + [lanes[-1]] * pad
    state, pars, t0, t_end = starts(lanes)
    out = np.empty_like(state)

    def run(count_steps):
        steps = 0
        for k in range(0, len(lanes), b):
            ta.state[:] = state[:, k : k + b]
            ta.pars[:] = pars[:, k : k + b]
            ta.set_time(t0[k : k + b])
            ta.propagate_until(t_end[k : k + b])
            out[:, k : k + b] = ta.state
            if count_steps:
                steps += sum(int(r[3]) for r in ta.propagate_res)
                if k + b >= 1000:
                    return steps / (k + b)
        return steps

    t = time.perf_counter()
    run(False)
    secs = time.perf_counter() - t
    ys = out[:, :n].T.copy()
    ys[:, 2:] *= pars[5, :n, None]
    return ys, secs, compile_s, run(True)


def flip(ta, d_sgn, i):
    """The event's callback: lane i's contact side flips, and it goes on."""
    ta.pars[0, i] = -ta.pars[0, i]
    return True


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("lanes", nargs="?", help="lane table (m1, m2, gamma_deg, f2, t_end)")
    ap.add_argument("--make-lanes", help="write a lane table here and stop")
    ap.add_argument("--distinct", type=int, default=150)
    ap.add_argument("--copies", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=20261126)
    ap.add_argument("--tol", type=float, default=1e-7)
    ap.add_argument("--check", help="tswm's lanes.csv of the same table")
    a = ap.parse_args()
    if a.make_lanes:
        make_lanes(a.make_lanes, a.distinct, a.copies, a.seed)
        return
    import heyoka as hy

    with open(a.lanes) as fh:
        lanes = [tuple(float(r[c]) for c in COLUMNS) for r in csv.DictReader(fh)]
    out, secs, compile_s, steps = integrate(lanes, a.tol)
    line = (
        f"heyoka {hy.__version__} batch x{hy.recommended_simd_size()}, tol {a.tol:g}: "
        f"{len(lanes)} lanes in {secs:.3f} s ({len(lanes) / secs:.0f} lanes/s; compile "
        f"{compile_s:.2f} s apart), {steps:.1f} steps a lane"
    )
    if a.check:
        with open(a.check) as fh:
            rows = list(csv.DictReader(fh))
        worst = 0.0
        for k, col in enumerate(["x1_end", "v1_end", "w_motor", "w_load", "w_friction"]):
            ref = np.array([float(r[col]) for r in rows])
            d = np.abs(out[:, k] - ref) / np.maximum(1.0, np.abs(ref))
            worst = max(worst, float(d.max()))
        line += f"; worst difference from tswm {worst:.2e} (relative to max(1, |value|))"
    print(line, flush=True)


if __name__ == "__main__":
    main()
