"""Random user lanes drawn in Python, independently of tswm's own
generator but with the same recipe (src/testmodels.rs, random_user_lanes):
lead angle 2 to 25 deg, load -9 to +9 kN, masses 0.5 to 1.5 times the
paper's, t_end 1 to 4 s, the motor cut in 35 % of lanes, and Coulomb
friction (mu 0.02 to 0.12, static up to 30 % above) in half of them.

    python3 random_lanes.py N SEED OUT.csv
"""
import csv
import random
import sys

n, seed, out = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
rng = random.Random(seed)
cols = ["gamma_deg", "f2", "m1", "m2", "t_end", "motor_off", "friction", "mu", "mu_static"]
with open(out, "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(cols)
    for _ in range(n):
        t_end = 1.0 + 3.0 * rng.random()
        row = {
            "gamma_deg": 2.0 + 23.0 * rng.random(),
            "f2": -9000.0 + 18000.0 * rng.random(),
            "m1": 586.0 * (0.5 + rng.random()),
            "m2": 10275.0 * (0.5 + rng.random()),
            "t_end": t_end,
            "motor_off": t_end * rng.random() if rng.random() < 0.35 else "",
            "friction": "paper",
            "mu": "",
            "mu_static": "",
        }
        if rng.random() < 0.5:
            mu = 0.02 + 0.1 * rng.random()
            row.update(friction="coulomb", mu=mu, mu_static=mu * (1.0 + 0.3 * rng.random()))
        w.writerow([row[c] for c in cols])
