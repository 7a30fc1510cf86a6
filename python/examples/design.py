"""Two design questions answered with tswm in Python.

1. An efficiency map: the running efficiency of a worm drive in both
   directions of power flow over lead angle and friction, from one
   tswm.run, drawn with matplotlib.
2. An inverse question, answered by one search: the largest lead angle
   that still holds its load with the motor off in 99 % of manufactured
   drives, when the static friction of the mesh scatters by +-25 %
   (uniform). A sweep's [search] finds it in one tswm.run: each drive's
   critical lead angle is bracketed in rounds, only the drives that decide
   the 1 % boundary are refined, and the answer comes with a
   distribution-free 95 % interval and a one-sided bound. It is checked
   against the closed form tan(gamma) = the 1 % quantile of mu_static, and
   the lanes it integrated are counted.

Run it as a script (`python python/examples/design.py [OUT_DIR] [DRIVES]`);
it writes efficiency_map.png into OUT_DIR and prints the answer.
"""

import math
import os
import sys

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt
import numpy as np

import tswm


def efficiency_map(out_dir):
    """eta_direct_ss and eta_inverse_ss over lead angle and friction (a
    Coulomb mu), the paper's resisting load: a 29 x 15 grid, one run."""
    sweep = {
        "base": {"friction": "coulomb", "mu": 0.05, "f2": -4774.0},
        "grid": [
            {"param": "gamma_deg", "from": 2.0, "to": 30.0, "n": 29},
            {"param": "mu", "from": 0.01, "to": 0.15, "n": 15, "scale": "log"},
        ],
    }
    lanes = tswm.run(sweep, progress=False).to_pandas()
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.4), constrained_layout=True)
    stalled = lanes.pivot(index="mu", columns="gamma_deg", values="drive") == "stalled"
    for ax, col, title in [
        (axes[0], "eta_direct_ss", "running direct efficiency (worm drives)"),
        (axes[1], "eta_inverse_ss", "running inverse efficiency (wheel drives)"),
    ]:
        grid = lanes.pivot(index="mu", columns="gamma_deg", values=col)
        x, y = grid.columns, grid.index
        # A stalled drive's values are start-up values, not a running
        # point: drawn apart, as is an inverse efficiency <= 0 (the wheel
        # cannot drive the worm: self-locking).
        running = grid.where(~stalled & (grid > 0))
        m = ax.pcolormesh(x, y, running.values, shading="nearest", cmap="viridis", vmin=0, vmax=1)
        handles = []
        locking = (grid <= 0) & ~stalled
        if locking.values.any():
            ax.pcolormesh(x, y, np.where(locking, 1.0, np.nan), shading="nearest", cmap=ListedColormap(["#7f1d1d"]))
            handles.append(Patch(color="#7f1d1d", label="self-locking (<= 0)"))
        if stalled.values.any():
            ax.pcolormesh(x, y, np.where(stalled, 1.0, np.nan), shading="nearest", cmap=ListedColormap(["#bbbbbb"]))
            handles.append(Patch(color="#bbbbbb", label="stalled (motor cannot start)"))
        # The static self-locking limit: tan(gamma) = mu.
        g = np.linspace(2, 30, 200)
        (line,) = ax.plot(g, np.tan(np.radians(g)), color="#e11d48", ls="--", lw=1.2, label="tan(gamma) = mu")
        handles.append(line)
        ax.set_yscale("log")
        ax.set_ylim(y.min(), y.max())
        ax.set_xlabel("lead angle, gamma_deg (deg)")
        ax.set_ylabel("friction coefficient, mu")
        ax.set_title(title)
        fig.colorbar(m, ax=ax, label=col)
        ax.legend(handles=handles, loc="lower right", fontsize=8, framealpha=0.9)
    path = os.path.join(out_dir, "efficiency_map.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path, len(lanes)


#: The drive of the search: starting at rest with the motor off (the load
#: overhauls it), Coulomb friction with a static coefficient of 0.09.
BASE = {"friction": "coulomb", "mu": 0.06, "mu_static": 0.09, "f2": 6000.0, "motor_off": 0.0, "t_end": 1.0}
#: The static friction's manufacturing scatter: uniform, +-25 % of 0.09.
SCATTER = 0.25


def largest_self_locking_angle(out_dir, drives=2000, at_least=0.99, seed=20261126):
    """The largest lead angle at which at least `at_least` of `drives`
    manufactured drives hold, from one run with a [search]: the boundary,
    its 95 % interval, the one-sided 95 % bound (the angle is at least
    this), and the lanes the search integrated."""
    sweep = {
        "base": BASE,
        "search": {
            "param": "gamma_deg",
            "from": 2.0,
            "to": 8.0,
            "require": "hold = held",
            "tol": 1e-4,
            "at_least": at_least,
        },
        "sampling": {"method": "monte_carlo", "n": drives, "seed": seed},
        "tolerance": [{"param": "mu_static", "dist": "uniform", "tol_rel": SCATTER}],
    }
    folder = os.path.join(out_dir, "search")
    lanes = tswm.run(sweep, out=folder, progress=False)
    rows = tswm.summary(folder).to_pylist()
    boundary = next(r for r in rows if r["kind"] == "boundary")
    bound = next(r for r in rows if r["kind"] == "bound")
    integrated = sum(lanes.column("search_lanes").to_pylist())
    return (
        boundary["p50"],
        (boundary["ci95_low"], boundary["ci95_high"]),
        bound["p50"],
        integrated,
    )


def main(out_dir=".", drives=2000):
    path, n = efficiency_map(out_dir)
    print(f"efficiency map of {n} drives: {path}")
    gamma, (lo95, hi95), bound, lanes = largest_self_locking_angle(out_dir, drives)
    lo = BASE["mu_static"] * (1 - SCATTER)
    hi = BASE["mu_static"] * (1 + SCATTER)
    closed_form = math.degrees(math.atan(lo + 0.01 * (hi - lo)))
    print(
        f"the largest lead angle that holds in 99 % of drives is at least {bound:.3f} deg "
        f"with 95 % confidence (estimate {gamma:.3f} deg, 95 % interval {lo95:.3f} to {hi95:.3f} deg; "
        f"{lanes} lanes for {drives} drives; closed form atan(1 % quantile of mu_static) = {closed_form:.3f} deg)"
    )
    return gamma, (lo95, hi95), bound, closed_form, lanes


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else ".", int(sys.argv[2]) if len(sys.argv) > 2 else 2000)
