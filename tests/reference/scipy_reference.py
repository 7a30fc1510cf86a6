"""An independent high-accuracy integration of the TSWM model (docs/model.md),
written from the model's text and not from tswm's code: scipy's DOP853 at
rtol = atol = 1e-12 with located events, for checking tswm's results.

    python3 scipy_reference.py LANES.csv OUT.csv [TABLES.toml]

LANES.csv holds lanes.csv's parameter columns (tswm's own lanes.csv will
do); TABLES.toml, a tswm sweep file (a run's sweep.resolved.toml will do),
holds the friction tables ([friction_table.NAME], arrays vs and mu) that
lanes with friction = table name in their friction_table column. OUT.csv
gets lane, status, contact_end, x1_end, v1_end, the works and the four
mesh energies, then hold, t_stop, branches (changes of the law's piece:
crossings of the agma law's 10 ft/min or of a table's speeds), and the
counts switches (changes of contact side; a stick phase has none of its
own, and a lane that starts at rest starts on the side of phi at t = 0),
reversals (changes of the direction of motion) and sticks (stick phases)
("Does it hold?": a lane whose motor is cut and that still slides,
slowing down, at t_end runs on to t_max until it comes to rest (held, or
it departs: runs away) or its acceleration turns to driving it (runs
away)).

Friction laws: the paper's fit, a constant mu, a table mu(Vs) (linear
between its points and flat past its ends, mu at Vs = 0 its static
value), AGMA's steel-on-bronze curve (docs/model.md section 5, in
ft/min) and the Stribeck curve mu = mu_c + (mu_s - mu_c)
exp(-(Vs/v_st)^delta) + kv Vs; the laws that give a coefficient take the
flank's pressure angle: tan rho = mu / cos(alpha_n). The agma law's jump
at 10 ft/min and a table's kinks at its speeds split mu(Vs) into pieces:
each integration segment stays on one piece, its formula kept smooth
(extended) past the piece's ends, and the sliding speed leaving the piece
is located as an event, after which the next piece takes over.
"""
import bisect
import csv
import math
import sys

from scipy.integrate import solve_ivp

RTOL = ATOL = 1e-12
FT_MIN = 60.0 / 0.3048  # ft/min in 1 m/s (1 ft = 0.3048 m exactly)
AGMA_JUMP = 10.0 / FT_MIN  # m/s


def agma(vs, upper):
    """AGMA's mu at vs (m/s) on the given branch (Shigley's fit)."""
    v = max(vs, 0.0) * FT_MIN
    if upper:
        return 0.103 * math.exp(-0.110 * v ** 0.450) + 0.012
    return 0.124 * math.exp(-0.074 * v ** 0.645)


def num(row, key, default=float("nan")):
    v = row.get(key, "")
    return float(v) if v not in ("", None) else default


class Lane:
    def __init__(self, row, table=None):
        """table: a friction table's (vs, mu) for friction = table."""
        self.m1, self.m2 = num(row, "m1"), num(row, "m2")
        g = math.radians(num(row, "gamma_deg"))
        self.tg, self.sg, self.cg = math.tan(g), math.sin(g), math.cos(g)
        self.f2 = num(row, "f2")
        self.motor = row["motor"]
        self.v_sync, self.v_crit, self.f_crit = num(row, "v_sync"), num(row, "v_crit"), num(row, "f_crit")
        self.f1c = num(row, "f1")
        self.motor_off = num(row, "motor_off", math.inf)
        self.friction = row["friction"]
        self.a, self.b, self.c = num(row, "fric_a"), num(row, "fric_b"), num(row, "fric_c")
        self.mu_c = num(row, "mu")
        self.mu_static = num(row, "mu_static", self.mu_c)
        self.v_st = num(row, "v_stribeck")
        self.delta = num(row, "stribeck_exp", 2.0)
        self.kv = num(row, "mu_viscous", 0.0)
        self.x0, self.v0, self.t_end = num(row, "x1_0"), num(row, "v1_0"), num(row, "t_end")
        self.t_max = num(row, "t_max", self.t_end)
        self.k = 1.0 / math.cos(math.radians(num(row, "alpha_n_deg", 0.0) or 0.0))
        # The sliding speeds that split mu(Vs) into pieces: piece p lies
        # between speeds[p - 1] and speeds[p] (-inf and +inf past the ends).
        if self.friction == "table":
            self.speeds, self.mus = list(table[0]), list(table[1])
        else:
            self.speeds = [AGMA_JUMP] if self.friction == "agma" else []

    def piece(self, vs):
        """The piece of mu holding sliding speed vs >= 0: for agma 0 (the
        lower branch, up to and at 10 ft/min) or 1; for a table the p with
        speeds[p - 1] <= vs < speeds[p], so that a speed rising from rest
        enters the piece that starts at 0 when the table does."""
        if self.friction == "agma":
            return int(vs > AGMA_JUMP)
        return bisect.bisect_right(self.speeds, vs)

    def bounds(self, p):
        """The ends of piece p, lo and hi; an end at 0 or below is -inf, as
        the sliding speed leaves it only by coming to rest (an event of its
        own)."""
        sp = self.speeds
        lo = sp[p - 1] if p > 0 and sp[p - 1] > 0 else -math.inf
        hi = sp[p] if p < len(sp) else math.inf
        return lo, hi

    def mu(self, vs, p=None):
        """tan rho at sliding speed vs >= 0 on piece p of the law, its
        formula extended past the piece's ends (None: the piece of vs)."""
        if p is None:
            p = self.piece(vs)
        if self.friction == "paper":
            return math.tan(math.radians(1.0 / (self.a * vs ** self.b + self.c)))
        if self.friction == "agma":
            return agma(vs, p == 1) * self.k
        if self.friction == "table":
            v, m = self.speeds, self.mus
            if p == 0:
                return m[0] * self.k
            if p == len(v):
                return m[-1] * self.k
            slope = (m[p] - m[p - 1]) / (v[p] - v[p - 1])
            return (m[p - 1] + slope * (vs - v[p - 1])) * self.k
        if self.friction == "stribeck":
            drop = math.exp(-((vs / self.v_st) ** self.delta))
            return (self.mu_c + (self.mu_static - self.mu_c) * drop + self.kv * vs) * self.k
        return self.mu_c * self.k

    def mu_s(self):
        if self.friction in ("coulomb", "stribeck"):
            return self.mu_static * self.k
        if self.friction == "agma":
            return 0.150 * self.k
        return self.mu(0.0)

    def f1(self, v, on):
        if not on:
            return 0.0
        if self.motor == "constant":
            return self.f1c
        s = (self.v_sync - v) / self.v_sync
        sk = (self.v_sync - self.v_crit) / self.v_sync
        return 2 * self.f_crit * s * sk / (s * s + sk * sk)

    def phi(self, v, on):
        return self.f1(v, on) / self.m1 - self.f2 / (self.m2 * self.tg)

    def forces(self, v, c, s, on, p=None):
        """Acceleration, D and the reactions S1, S2 in mode (c, s), on
        piece p of the friction law."""
        f1 = self.f1(v, on)
        rho = math.atan(self.mu(max(s * v, 0.0) / self.cg, p))
        psi = -math.tan(math.atan(self.tg) + c * s * rho)
        d = self.m1 - psi * self.m2 * self.tg
        acc = (f1 - psi * self.f2) / d
        return acc, d, f1 - self.m1 * acc, self.f2 - self.m2 * self.tg * acc, f1


BRANCHES = [0]  # the friction law's changes of piece in the lane being run
COUNTS = {}  # switches, reversals, sticks of the lane being run


def simulate(L):
    """status, y, c, stuck, hold, t_stop"""
    y = [L.x0, L.v0] + [0.0] * 7
    t, on = 0.0, not (L.motor_off <= 0.0)
    end, running_on = L.t_end, False
    c = 1 if L.phi(L.v0, on) >= 0 else -1
    s, stuck = (1 if L.v0 > 0 else -1 if L.v0 < 0 else 0), False
    piece = L.piece(abs(L.v0) / L.cg)

    COUNTS.update(switches=0, reversals=0, sticks=0)

    def rest():
        nonlocal s, c, stuck, piece
        y[1] = 0.0
        piece = L.piece(0.0)
        f1 = L.f1(0.0, on)
        n = abs(L.f2 * L.cg - f1 * L.sg)
        T = f1 * L.cg + L.f2 * L.sg
        if abs(T) <= L.mu_s() * n:
            if not stuck:  # a new stick phase (a stuck lane re-tested stays in its own)
                COUNTS["sticks"] += 1
            stuck = True
            return
        new_s = 1 if T > 0 else -1
        if s != 0 and new_s != s:
            COUNTS["reversals"] += 1
        stuck, s = False, new_s
        new_c = 1 if L.phi(0.0, on) >= 0 else -1
        if new_c != c:
            COUNTS["switches"] += 1
        c = new_c

    if L.v0 == 0.0:
        rest()
    last_kink, after_kink = 0.0, False
    def hold(stuck, c, s, speeding):
        if not L.motor_off < L.t_end:
            return ""
        if stuck:
            return "held"
        if speeding or s * L.forces(y[1], c, s, on)[0] >= 0:
            return "runs_away"
        return "coasting"

    for _ in range(100000):
        t_stop = L.motor_off if on and L.motor_off < end else end
        # Stuck, or an event found at the stop time itself (a switch that
        # chatters at an equilibrium where phi tends to 0): nothing to
        # integrate before the stop.
        if stuck or t >= t_stop:
            t = t_stop
        else:
            def rhs(_, z, c=c, s=s, on=on, u=piece):
                v = z[1]
                acc, _, s1, s2, f1 = L.forces(v, c, s, on, u)
                p1, p2 = s1 * v, s2 * v * L.tg
                # The smooth integrals of p1 and p2; their in and out
                # parts are shared out after the segment (below).
                return [v, acc, f1 * v, L.f2 * v * L.tg, p1 + p2, p1, p2]

            def ev_rest(_, z, s=s):
                return s * z[1]

            # No load: phi = F1/m1. With no motor force (cut, or a
            # constant 0) it is 0 throughout, the contact stays where it is
            # (phi >= 0: a-a), and an event function that is 0 everywhere
            # would stop every segment where it starts. A constant motor's
            # phi keeps its sign, and a Kloss motor's changes sign only at
            # synchronous speed, a fixed point of the motion (x1'' = F1/D =
            # 0 there), which a lane approaches but never crosses: an event
            # located there is the integration's rounding, and the contact
            # stays where it is.
            no_phi = L.f2 == 0

            def ev_switch(_, z, c=c, on=on):
                return 1.0 if no_phi else c * L.phi(z[1], on)

            kink0 = L.mu(max(s * y[1], 0.0) / L.cg, piece) - L.tg if c * s == -1 else 0.0
            if c * s == -1 and after_kink:
                # At a located kink the state sits on the root; the gap's
                # sign there is rounding. The crossing is behind us: the
                # new side is the opposite of the old one.
                kink0 = -last_kink
            last_kink, after_kink = kink0, False

            def ev_kink(_, z, s=s, k=kink0, u=piece):
                return k * (L.mu(max(s * z[1], 0.0) / L.cg, u) - L.tg) if k else 1.0

            def ev_speeding(_, z, c=c, s=s, on=on, u=piece):
                return -s * L.forces(z[1], c, s, on, u)[0] if running_on else 1.0

            # Where gamma + rho reaches 90 degrees (c s = +1 and tan(gamma)
            # tan(rho) = 1; friction far beyond a real drive's), psi passes
            # through infinity and D from +infinity to below 0: the mode is
            # inconsistent from there on (docs/model.md section 2). With
            # c s = -1, D = m1 - tan(rho - gamma) m2 tan(gamma) is finite
            # and can fall to 0 (rho growing as the lane slows): the
            # acceleration m1 phi / D grows without bound, D falls as the
            # square root of the time left, and no step reaches D = 0;
            # the lane ends inconsistent where D is 1e-6 of m1.
            def ev_wedge(_, z, s=s, c=c, on=on, u=piece):
                if c * s == 1:
                    return 1.0 - L.tg * L.mu(max(s * z[1], 0.0) / L.cg, u)
                return L.forces(z[1], c, s, on, u)[1] / L.m1 - 1e-6

            lo, hi = L.bounds(piece)

            def ev_branch(_, z, s=s, lo=lo, hi=hi):
                # >= 0 on the piece; its ends are the agma law's jump or a
                # table's kinks.
                if lo == -math.inf and hi == math.inf:
                    return 1.0
                vs = max(s * z[1], 0.0) / L.cg
                return min(vs - lo, hi - vs)

            events = (ev_rest, ev_switch, ev_kink, ev_speeding, ev_branch, ev_wedge)
            for e in events:
                e.terminal, e.direction = True, -1
            if L.forces(y[1], c, s, on, piece)[1] <= 0:
                return "inconsistent", y, c, stuck, "", t
            # p1 = S1 x1' and p2 = S2 x2' change sign only where x1' = 0
            # (rest), S2 = 0 (phi = 0, a switch; or psi through infinity,
            # the wedge event, where the lane ends) or S1 = psi S2 = 0 (the
            # kink): all terminal events. So each segment's increments of
            # their integrals go whole to the in or the out part, by the
            # sign of the segment's integral, which is p's. (Not by p at
            # the segment's middle: where p tends to 0, a motor reaching
            # synchronous speed with no load, p there is rounding of
            # either sign.) (Integrating max(+-p, 0)
            # instead puts a kink at the rest event inside the step that
            # overshoots it, and the dense output at the event reads the
            # part past it: 1.8e-6 J of a w1_out that is 0.)
            z0 = y[:5] + [0.0, 0.0]
            sol = solve_ivp(rhs, (t, t_stop), z0, method="DOP853", rtol=RTOL, atol=ATOL,
                            events=events, first_step=min(1e-8, t_stop - t), dense_output=True)
            if sol.status == -1:
                # The integration could not go on. Where a wedge jams just
                # past a kink (D = m1 there, and 0 a hair further on for a
                # light worm side), the acceleration outgrows any step
                # before the wedge event's D = 1e-6 m1: inconsistent. Any
                # other failure is the reference's, said aloud.
                v_fail = sol.y[1, -1]
                if L.forces(v_fail, c, s, on, piece)[1] < 1e-3 * L.m1:
                    return "inconsistent", y, c, stuck, "", t
                raise RuntimeError(f"the integration failed at t = {sol.t[-1]}: {sol.message}")
            z = sol.y[:, -1]
            flow = y[5:9]
            flow[0 if z[5] > 0 else 1] += abs(z[5])
            flow[2 if z[6] > 0 else 3] += abs(z[6])
            y, t = list(z[:5]) + flow, sol.t[-1]
            hit = [len(te) > 0 and te[0] > sol.t[0] for te in sol.t_events]
            if sol.status == 1 and hit[0]:
                rest()
                if running_on:
                    # Answered: held, or departed and running away.
                    return "ok", y, c, stuck, hold(stuck, c, s, False), t
                continue
            if sol.status == 1 and hit[3]:
                return "ok", y, c, stuck, hold(stuck, c, s, True), t
            if sol.status == 1 and hit[1]:
                c = -c
                COUNTS["switches"] += 1
                continue
            if sol.status == 1 and hit[2]:
                after_kink = True
                continue
            if sol.status == 1 and hit[5]:
                return "inconsistent", y, c, stuck, "", t
            if sol.status == 1 and hit[4]:
                # Up to the next piece through hi, down through lo.
                vs = max(s * y[1], 0.0) / L.cg
                piece += 1 if hi - vs < vs - lo else -1
                BRANCHES[0] += 1
                continue
        if t >= end:
            coasting = not stuck and s * L.forces(y[1], c, s, on)[0] < 0
            if (not running_on and L.t_max > L.t_end and L.motor_off < L.t_end
                    and coasting):
                running_on, end = True, L.t_max
                continue
            return "ok", y, c, stuck, hold(stuck, c, s, False), t
        on = False  # the motor's cut-off
        if stuck:
            rest()
        else:
            new_c = 1 if L.phi(y[1], on) >= 0 else -1
            if new_c != c:
                COUNTS["switches"] += 1
            c = new_c
    return "max_events", y, c, stuck, "", t


def load_tables(path):
    """The friction tables of a sweep file: name -> (vs, mu)."""
    import tomllib

    with open(path, "rb") as f:
        sections = tomllib.load(f).get("friction_table", {})
    tables = {}
    for name, t in sections.items():
        vs, mu = [float(v) for v in t.get("vs", [])], [float(m) for m in t.get("mu", [])]
        if not vs or len(vs) != len(mu):
            sys.exit(f"{path}: friction_table.{name}: vs and mu must be non-empty and of one length")
        if vs[0] < 0 or any(b <= a for a, b in zip(vs, vs[1:])) or min(mu) < 0:
            sys.exit(f"{path}: friction_table.{name}: vs must rise strictly from >= 0 and mu be >= 0")
        tables[name] = (vs, mu)
    return tables


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit("usage: scipy_reference.py LANES.csv OUT.csv [TABLES.toml]")
    src, dst = sys.argv[1], sys.argv[2]
    tables = load_tables(sys.argv[3]) if len(sys.argv) > 3 else {}
    rows = list(csv.DictReader(open(src)))
    for i, row in enumerate(rows):
        name = row.get("friction_table") or ""
        if row["friction"] == "table" and name not in tables:
            sys.exit(f"lane {row.get('lane', i)}: friction table {name!r} not given"
                     + ("" if len(sys.argv) > 3 else " (no TABLES.toml)"))
    with open(dst, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["lane", "status", "contact_end", "x1_end", "v1_end", "w_motor", "w_load",
                    "w_friction", "w1_in", "w1_out", "w2_in", "w2_out", "hold", "t_stop",
                    "branches", "switches", "reversals", "sticks"])
        for i, row in enumerate(rows):
            BRANCHES[0] = 0
            table = tables.get(row.get("friction_table") or "") if row["friction"] == "table" else None
            status, y, c, stuck, hold, t = simulate(Lane(row, table))
            contact = "stick" if stuck else ("aa" if c > 0 else "bb")
            w.writerow([row.get("lane", i), status, contact] + [repr(float(v)) for v in y]
                       + [hold, repr(float(t)), BRANCHES[0], COUNTS["switches"],
                          COUNTS["reversals"], COUNTS["sticks"]])


if __name__ == "__main__":
    main()
