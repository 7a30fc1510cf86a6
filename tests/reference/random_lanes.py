"""Random user lanes drawn in Python, independently of tswm's own
generator but with the same recipe (src/input/testmodels.rs, random_user_lanes):
lead angle 2 to 25 deg, load -9 to +9 kN, masses 0.5 to 1.5 times the
paper's, t_end 1 to 4 s, the motor cut in 35 % of lanes, and Coulomb
friction (mu 0.02 to 0.12, static up to 30 % above) in half of them.

    python3 random_lanes.py N SEED OUT.csv [wide|hold|agma|stribeck|viscous|jam|noload|extreme|table]

`wide` draws from a wider recipe instead: lead angle 2 to 30 deg, load
-12 to +12 kN, masses 0.3 to 1.8 times the paper's, t_end 0.5 to 6 s,
constant motors (500 to 6,500 N) in 30 % of lanes and Kloss motors of
other synchronous speeds, slips and peaks in the rest, initial speeds
(-3 to 3 m/s) in 30 % and positions in 20 %, Coulomb friction (mu 0.01
to 0.16, static up to 40 % above) in 40 % and the paper law with its
three parameters within +-20 % in the rest.

`hold` draws lanes that answer "does it hold?": the motor cut in every
lane (0.1 to 0.9 of t_end, 0.5 to 3 s), lead angle 2 to 12 deg, load -9
to +9 kN, masses 0.5 to 1.5 times the paper's, Coulomb friction (mu 0.02
to 0.12, static up to 50 % above) in half and the paper law in the rest,
and t_max (t_end + 2 to 30 s) in 70 % of them.

`agma` draws lanes under AGMA's steel-on-bronze curve with a flank angle:
alpha_n 5 to 30 deg, lead angle 2 to 25 deg, load -9 to +9 kN, masses 0.5
to 1.5 times the paper's, t_end 0.5 to 4 s, the motor cut in 50 % of
lanes (with t_max, t_end + 2 to 20 s, in half of those), constant motors
(500 to 6,500 N) in 20 %, initial speeds (-3 to 3 m/s) in 25 %: lanes
that start, stop, reverse and cross 10 ft/min both ways.

`stribeck` draws lanes under the Stribeck curve, as `agma` does otherwise:
mu_c 0.02 to 0.08, static 1 to 2.5 times it, v_st 0.02 to 0.5 m/s, the
exponent 0.5 to 2 (below 1 in a third of the lanes: a slope unbounded at
rest), a viscous term 0 to 0.01 s/m in 60 %, a flank angle 0 to 30 deg in
half, lead angle 2 to 15 deg (static friction often above it: lanes that
hold), load -9 to +9 kN, the motor cut in 50 % (with t_max in half of
those), constant motors in 20 %, initial speeds in 25 %.

`viscous` draws lanes under the Stribeck curve as `stribeck` does, but
with a viscous term of 0.1 to 10 s/m (log-uniform) in every lane, where
friction soon grows past any real drive's and gamma + rho can reach 90
degrees (the mode is inconsistent there), and the motor never cut (a
back-driven lane may settle at a terminal speed, where `hold` has no
decided word: docs/model.md).

`jam` draws lanes whose wedge can jam: a light worm side (m1 5 to 60 kg)
and a heavy wheel side (m2 5,000 to 15,000 kg), lead angle 2 to 6 deg, a
load of 1 to 20 kN either way with the lane started in its direction
(0.02 to 1 m/s), the motor cut at 0 in 75 % of lanes (half of them with
t_max, t_end + 0.5 to 5 s, running on while they slow), and the paper law
or a Stribeck curve without viscous term (mu_c 0.02 to 0.06, static 0.02
to 0.15 above it, v_st 0.05 to 0.5 m/s, exponent 0.5 to 2) in half each.
The overhauling load drives the wedge in b-b (a-a backwards), where the
friction angle grows as the lane slows: when it passes the lead angle by
atan(m1 / (m2 tan gamma)), D reaches 0 and the mode is inconsistent; a
quarter of the lanes or so get there.

`noload` draws lanes with no load (f2 = 0), a motor running up: Kloss
motors of synchronous speed 0.3 to 5 m/s (peak at 0.3 to 0.95 of it,
peak force 1 to 40 kN) in 80 % of lanes, constant motors (100 to 5,000
N) in the rest, started from rest or (30 %) at -0.5 to 1.2 times the
synchronous speed, lead angle 2 to 25 deg, masses 0.3 to 3 times the
paper's, t_end 0.5 to 10 s, the motor cut in 20 %, and the paper law,
Coulomb friction or a Stribeck curve in a third each. As a Kloss motor
nears synchronous speed its force, S1, S2 and both mesh powers tend to
0, and the in and out parts of the flow must stay as the mode says (with
no load the contact never switches: phi = F1/m1 changes sign only at
synchronous speed, a fixed point of the motion).

`extreme` draws lanes over wide ranges, log-uniform where a range spans
decades: lead angle 0.5 to 60 deg, load 10 N to 100 kN either way (0 in
5 %), m1 1 to 10^4 kg and m2 10 to 10^6 kg (every mass ratio a drive in
gear terms can reduce to), t_end 0.05 to 8 s, the motor cut in 40 %
(t_max in half of those), constant motors (10 N to 100 kN either way, 0
in 5 %) in 30 %, Kloss motors of other speeds and peaks in 35 %, the
paper law (its own parameters in half), Coulomb friction (0.005 to 0.6),
a Stribeck curve (with a viscous term in 40 %) or AGMA's curve in a
quarter each, a flank angle in half of the coefficient laws, initial
speeds (1 mm/s to 10 m/s either way) in 40 % and positions in 20 %.

`table` draws lanes under friction tables, as `agma` does otherwise
(lead angle 2 to 15 deg), and writes the tables to OUT.toml (a sweep
file holding only them, for `tswm run --lanes OUT.csv OUT.toml` and
`scipy_reference.py`): six tables of 2 to 16 points, the first speed 0
in two tables of three (else up to 0.05 m/s), each next one 0.01 to 2
m/s above the last (log-uniform), mu 0.02 to 0.15 in a random walk that
may rise or fall; each lane names one of them, with a flank angle 0 to
30 deg in half of the lanes.
"""
import csv
import random
import sys

n, seed, out = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
rng = random.Random(seed)
if sys.argv[4:] == ["wide"]:
    cols = ["gamma_deg", "f2", "m1", "m2", "t_end", "motor_off", "friction", "mu", "mu_static",
            "motor", "f1", "v1_0", "x1_0", "fric_a", "fric_b", "fric_c", "v_sync", "v_crit", "f_crit"]
    with open(out, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(cols)
        for _ in range(n):
            t_end = 0.5 + 5.5 * rng.random()
            row = {c: "" for c in cols}
            row.update(gamma_deg=2 + 28 * rng.random(), f2=-12000 + 24000 * rng.random(),
                       m1=586 * (0.3 + 1.5 * rng.random()), m2=10275 * (0.3 + 1.5 * rng.random()),
                       t_end=t_end, friction="paper")
            if rng.random() < 0.35:
                row["motor_off"] = t_end * rng.random()
            if rng.random() < 0.3:
                row["motor"] = "constant"
                row["f1"] = 500 + 6000 * rng.random()
            else:
                vs = 2.5 + 2 * rng.random()
                row.update(v_sync=vs, v_crit=vs * (0.4 + 0.5 * rng.random()), f_crit=2000 + 5000 * rng.random())
            if rng.random() < 0.3:
                row["v1_0"] = -3 + 6 * rng.random()
            if rng.random() < 0.2:
                row["x1_0"] = -5 + 10 * rng.random()
            if rng.random() < 0.4:
                mu = 0.01 + 0.15 * rng.random()
                row.update(friction="coulomb", mu=mu, mu_static=mu * (1 + 0.4 * rng.random()))
            else:
                row.update(fric_a=0.174 * (0.8 + 0.4 * rng.random()), fric_b=0.612 * (0.8 + 0.4 * rng.random()),
                           fric_c=0.14 * (0.8 + 0.4 * rng.random()))
            w.writerow([row[c] for c in cols])
    sys.exit(0)
if sys.argv[4:] == ["hold"]:
    cols = ["gamma_deg", "f2", "m1", "m2", "t_end", "motor_off", "t_max", "friction", "mu", "mu_static"]
    with open(out, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(cols)
        for _ in range(n):
            t_end = 0.5 + 2.5 * rng.random()
            row = {c: "" for c in cols}
            row.update(gamma_deg=2 + 10 * rng.random(), f2=-9000 + 18000 * rng.random(),
                       m1=586 * (0.5 + rng.random()), m2=10275 * (0.5 + rng.random()),
                       t_end=t_end, motor_off=t_end * (0.1 + 0.8 * rng.random()), friction="paper")
            if rng.random() < 0.7:
                row["t_max"] = t_end + 2 + 28 * rng.random()
            if rng.random() < 0.5:
                mu = 0.02 + 0.1 * rng.random()
                row.update(friction="coulomb", mu=mu, mu_static=mu * (1 + 0.5 * rng.random()))
            w.writerow([row[c] for c in cols])
    sys.exit(0)


def write_lanes(cols, draw):
    """Writes n lanes of columns cols to OUT.csv, each row drawn by
    draw(row) into a row of empty cells, and exits."""
    with open(out, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(cols)
        for _ in range(n):
            row = {c: "" for c in cols}
            draw(row)
            w.writerow([row[c] for c in cols])
    sys.exit(0)


def cut_motor_start(row, t_end):
    """The part of the agma, stribeck and table recipes after the law:
    the motor cut in 50 % of lanes (with t_max in half of those), constant
    motors in 20 %, initial speeds in 25 %."""
    if rng.random() < 0.5:
        row["motor_off"] = t_end * rng.random()
        if rng.random() < 0.5:
            row["t_max"] = t_end + 2 + 18 * rng.random()
    if rng.random() < 0.2:
        row.update(motor="constant", f1=500 + 6000 * rng.random())
    if rng.random() < 0.25:
        row["v1_0"] = -3 + 6 * rng.random()


if sys.argv[4:] == ["agma"]:
    cols = ["gamma_deg", "f2", "m1", "m2", "t_end", "motor_off", "t_max", "friction", "alpha_n_deg",
            "motor", "f1", "v1_0"]

    def draw(row):
        t_end = 0.5 + 3.5 * rng.random()
        row.update(gamma_deg=2 + 23 * rng.random(), f2=-9000 + 18000 * rng.random(),
                   m1=586 * (0.5 + rng.random()), m2=10275 * (0.5 + rng.random()),
                   t_end=t_end, friction="agma", alpha_n_deg=5 + 25 * rng.random())
        cut_motor_start(row, t_end)

    write_lanes(cols, draw)
if sys.argv[4:] == ["stribeck"]:
    cols = ["gamma_deg", "f2", "m1", "m2", "t_end", "motor_off", "t_max", "friction", "mu",
            "mu_static", "v_stribeck", "stribeck_exp", "mu_viscous", "alpha_n_deg", "motor", "f1",
            "v1_0"]

    def draw(row):
        t_end = 0.5 + 3.5 * rng.random()
        mu = 0.02 + 0.06 * rng.random()
        delta = 0.5 + 0.5 * rng.random() if rng.random() < 1 / 3 else 1 + rng.random()
        row.update(gamma_deg=2 + 13 * rng.random(), f2=-9000 + 18000 * rng.random(),
                   m1=586 * (0.5 + rng.random()), m2=10275 * (0.5 + rng.random()),
                   t_end=t_end, friction="stribeck", mu=mu, mu_static=mu * (1 + 1.5 * rng.random()),
                   v_stribeck=0.02 + 0.48 * rng.random(), stribeck_exp=delta)
        if rng.random() < 0.6:
            row["mu_viscous"] = 0.01 * rng.random()
        if rng.random() < 0.5:
            row["alpha_n_deg"] = 30 * rng.random()
        cut_motor_start(row, t_end)

    write_lanes(cols, draw)
if sys.argv[4:] == ["viscous"]:
    cols = ["gamma_deg", "f2", "m1", "m2", "t_end", "friction", "mu", "mu_static", "v_stribeck",
            "stribeck_exp", "mu_viscous", "alpha_n_deg", "motor", "f1", "v1_0"]

    def draw(row):
        mu = 0.02 + 0.06 * rng.random()
        delta = 0.5 + 0.5 * rng.random() if rng.random() < 1 / 3 else 1 + rng.random()
        row.update(gamma_deg=2 + 13 * rng.random(), f2=-9000 + 18000 * rng.random(),
                   m1=586 * (0.5 + rng.random()), m2=10275 * (0.5 + rng.random()),
                   t_end=0.5 + 3.5 * rng.random(), friction="stribeck", mu=mu,
                   mu_static=mu * (1 + 1.5 * rng.random()), v_stribeck=0.02 + 0.48 * rng.random(),
                   stribeck_exp=delta, mu_viscous=10 ** (-1 + 2 * rng.random()))
        if rng.random() < 0.5:
            row["alpha_n_deg"] = 30 * rng.random()
        if rng.random() < 0.2:
            row.update(motor="constant", f1=500 + 6000 * rng.random())
        if rng.random() < 0.25:
            row["v1_0"] = -3 + 6 * rng.random()

    write_lanes(cols, draw)
if sys.argv[4:] == ["jam"]:
    cols = ["gamma_deg", "f2", "m1", "m2", "t_end", "motor_off", "t_max", "friction", "mu",
            "mu_static", "v_stribeck", "stribeck_exp", "v1_0"]

    def draw(row):
        sign = rng.choice([1, -1])
        t_end = 0.2 + 1.8 * rng.random()
        row.update(gamma_deg=2 + 4 * rng.random(), f2=sign * (1000 + 19000 * rng.random()),
                   m1=5 + 55 * rng.random(), m2=5000 + 10000 * rng.random(),
                   t_end=t_end, v1_0=sign * (0.02 + 0.98 * rng.random()))
        if rng.random() < 0.75:
            row["motor_off"] = 0
            if rng.random() < 0.5:
                row["t_max"] = t_end + 0.5 + 4.5 * rng.random()
        if rng.random() < 0.5:
            row["friction"] = "paper"
        else:
            mu = 0.02 + 0.04 * rng.random()
            row.update(friction="stribeck", mu=mu, mu_static=mu + 0.02 + 0.13 * rng.random(),
                       v_stribeck=0.05 + 0.45 * rng.random(), stribeck_exp=0.5 + 1.5 * rng.random())

    write_lanes(cols, draw)
if sys.argv[4:] == ["noload"]:
    cols = ["gamma_deg", "f2", "m1", "m2", "t_end", "motor_off", "motor", "f1", "v_sync", "v_crit",
            "f_crit", "friction", "mu", "mu_static", "v_stribeck", "stribeck_exp", "v1_0"]

    def draw(row):
        t_end = 0.5 + 9.5 * rng.random()
        v_sync = 0.3 + 4.7 * rng.random()
        row.update(gamma_deg=2 + 23 * rng.random(), f2=0.0, m1=586 * (0.3 + 2.7 * rng.random()),
                   m2=10275 * (0.3 + 2.7 * rng.random()), t_end=t_end)
        if rng.random() < 0.8:
            row.update(v_sync=v_sync, v_crit=v_sync * (0.3 + 0.65 * rng.random()),
                       f_crit=1000 + 39000 * rng.random())
        else:
            row.update(motor="constant", f1=100 + 4900 * rng.random())
        if rng.random() < 0.3:
            row["v1_0"] = v_sync * (-0.5 + 1.7 * rng.random())
        if rng.random() < 0.2:
            row["motor_off"] = t_end * rng.random()
        law = rng.choice(["paper", "coulomb", "stribeck"])
        row["friction"] = law
        if law != "paper":
            mu = 0.02 + 0.08 * rng.random()
            row.update(mu=mu, mu_static=mu * (1 + rng.random()))
        if law == "stribeck":
            row.update(v_stribeck=0.02 + 0.48 * rng.random(), stribeck_exp=0.5 + 1.5 * rng.random())

    write_lanes(cols, draw)
if sys.argv[4:] == ["extreme"]:
    import math

    cols = ["gamma_deg", "f2", "m1", "m2", "t_end", "motor_off", "t_max", "motor", "f1", "v_sync",
            "v_crit", "f_crit", "friction", "mu", "mu_static", "v_stribeck", "stribeck_exp",
            "mu_viscous", "alpha_n_deg", "fric_a", "fric_b", "fric_c", "v1_0", "x1_0"]

    def lu(a, b):
        return math.exp(math.log(a) + (math.log(b) - math.log(a)) * rng.random())

    def draw(row):
        t_end = lu(0.05, 8)
        row.update(gamma_deg=lu(0.5, 60),
                   f2=rng.choice([1, -1]) * lu(10, 1e5) if rng.random() < 0.95 else 0.0,
                   m1=lu(1, 1e4), m2=lu(10, 1e6), t_end=t_end)
        if rng.random() < 0.4:
            row["motor_off"] = t_end * rng.random() * 1.2
        if row["motor_off"] != "" and rng.random() < 0.5:
            row["t_max"] = t_end + lu(0.5, 50)
        if rng.random() < 0.3:
            row.update(motor="constant",
                       f1=rng.choice([1, -1]) * lu(10, 1e5) if rng.random() < 0.95 else 0.0)
        elif rng.random() < 0.5:
            vs = lu(0.3, 20)
            row.update(v_sync=vs, v_crit=vs * rng.uniform(0, 0.95), f_crit=lu(100, 1e5))
        law = rng.choice(["paper", "coulomb", "stribeck", "agma"])
        row["friction"] = law
        if law == "paper":
            if rng.random() < 0.5:
                row.update(fric_a=lu(0.01, 2), fric_b=rng.uniform(0.2, 1.5), fric_c=lu(0.02, 2))
        elif law == "coulomb":
            mu = lu(0.005, 0.6)
            row.update(mu=mu, mu_static=mu * rng.uniform(1, 1.5))
        elif law == "stribeck":
            mu = lu(0.005, 0.3)
            row.update(mu=mu, mu_static=mu * rng.uniform(1, 3), v_stribeck=lu(0.005, 2),
                       stribeck_exp=rng.uniform(0.5, 2))
            if rng.random() < 0.4:
                row["mu_viscous"] = lu(1e-4, 0.3)
        if law != "paper" and rng.random() < 0.5:
            row["alpha_n_deg"] = rng.uniform(0, 40)
        if rng.random() < 0.4:
            row["v1_0"] = rng.choice([1, -1]) * lu(0.001, 10)
        if rng.random() < 0.2:
            row["x1_0"] = rng.uniform(-10, 10)

    write_lanes(cols, draw)
if sys.argv[4:] == ["table"]:
    names = [f"t{k}" for k in range(6)]
    with open(out.rsplit(".", 1)[0] + ".toml", "w") as f:
        for name in names:
            points = 2 + int(15 * rng.random())
            vs = [0.0 if rng.random() < 2 / 3 else 0.05 * rng.random()]
            mu = [0.02 + 0.13 * rng.random()]
            for _ in range(points - 1):
                vs.append(vs[-1] + 0.01 * 200 ** rng.random())
                mu.append(min(0.15, max(0.02, mu[-1] + 0.04 * (rng.random() - 0.5))))
            f.write(f"[friction_table.{name}]\nvs = {vs!r}\nmu = {mu!r}\n")
    cols = ["gamma_deg", "f2", "m1", "m2", "t_end", "motor_off", "t_max", "friction",
            "friction_table", "alpha_n_deg", "motor", "f1", "v1_0"]

    def draw(row):
        t_end = 0.5 + 3.5 * rng.random()
        row.update(gamma_deg=2 + 13 * rng.random(), f2=-9000 + 18000 * rng.random(),
                   m1=586 * (0.5 + rng.random()), m2=10275 * (0.5 + rng.random()),
                   t_end=t_end, friction="table", friction_table=rng.choice(names))
        if rng.random() < 0.5:
            row["alpha_n_deg"] = 30 * rng.random()
        cut_motor_start(row, t_end)

    write_lanes(cols, draw)
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
