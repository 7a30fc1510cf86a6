"""Independent check of sensitivity.csv with SALib.

Usage: salib_sobol.py LANES_CSV SENSITIVITY_CSV N INPUT [INPUT ...]

Reads the lanes of a tswm sensitivity sweep (N base samples over the
given inputs, one or more grid points of N*(D+2) lanes each, in lane
order), checks that the sample is a Saltelli design in SALib's order (in
each row group A, AB_1 .. AB_D, B: AB_i is A with input i from B), builds
each result's outputs as tswm defines them (a row group used only when
every lane of it is ok and has the value; status=ok uses every row group),
hands them to SALib.analyze.sobol.analyze (first and total order) and
compares its S1 and ST with tswm's to 1e-9. Prints the worst difference;
exits 1 on a mismatch.
"""

import sys

import numpy as np
import pandas as pd
from SALib.analyze import sobol

TOL = 1e-9


def main():
    lanes_csv, sens_csv, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
    inputs = sys.argv[4:]
    d = len(inputs)
    step = d + 2
    lanes = pd.read_csv(lanes_csv, keep_default_na=False, na_values=[""])
    sens = pd.read_csv(sens_csv, keep_default_na=False, na_values=[""])
    per_group = n * step
    assert len(lanes) % per_group == 0, "lanes are not whole grid points"
    groups = len(lanes) // per_group
    x = lanes[inputs].to_numpy(float)
    # The design: AB_i differs from A in input i only, where it is B's.
    xs = x.reshape(groups * n, step, d)
    for i in range(d):
        others = [k for k in range(d) if k != i]
        assert np.array_equal(xs[:, 1 + i, others], xs[:, 0, others]), f"AB_{i} is not A"
        assert np.array_equal(xs[:, 1 + i, i], xs[:, d + 1, i]), f"AB_{i} has not B's {inputs[i]}"
    ok = (lanes["status"] == "ok").to_numpy().reshape(groups, n, step).all(axis=2)
    problem = {"num_vars": d, "names": inputs, "bounds": [[0.0, 1.0]] * d}
    worst, compared, mismatches = 0.0, 0, 0
    for (g, result), rows in sens.groupby(["group", "result"], sort=False):
        if "=" in result:
            col, word = result.split("=")
            y = (lanes[col] == word).to_numpy(float)
        else:
            y = lanes[result].to_numpy(float)
        y = y[g * per_group:(g + 1) * per_group].reshape(n, step)
        use = np.ones(n, bool) if result == "status=ok" else ok[g] & np.isfinite(y).all(axis=1)
        assert (rows["samples"] == use.sum()).all(), f"group {g} {result}: samples"
        yy = y[use]
        ab = np.r_[yy[:, 0], yy[:, -1]]
        if use.sum() < 2 or np.ptp(ab) == 0 or np.ptp(yy) == 0:
            # No variance over A and B: tswm leaves the indices empty.
            assert rows[["s1", "st"]].isna().all().all(), f"group {g} {result}: not empty"
            continue
        si = sobol.analyze(problem, yy.reshape(-1), calc_second_order=False,
                           num_resamples=10, print_to_console=False, seed=1)
        for i, name in enumerate(inputs):
            row = rows[rows["input"] == name].iloc[0]
            for ours, theirs in ((row["s1"], si["S1"][i]), (row["st"], si["ST"][i])):
                diff = abs(ours - theirs)
                worst = max(worst, diff)
                compared += 1
                if not diff <= TOL:
                    mismatches += 1
                    print(f"group {g} {result} {name}: tswm {ours!r}, SALib {theirs!r}")
    print(f"compared {compared} indices with SALib; worst difference {worst:.3e}")
    sys.exit(1 if mismatches or compared == 0 else 0)


if __name__ == "__main__":
    main()
