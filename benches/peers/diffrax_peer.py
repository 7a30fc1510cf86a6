"""A peer for tswm's throughput: the same uniform lanes (sweeps/million.toml's:
the paper's design, load F2 from -6 to +6 kN, from rest, 2 s) integrated as a
vmapped JAX/diffrax ensemble with Dopri5, in float64 and float32, on JAX's
default device (the GPU where there is one).

    python3 benches/peers/diffrax_peer.py [N ...]          # default 100000 1000000

It prints lanes/s per size and precision (the jit compile excluded: one
warm-up solve first) and, with --check TSWM_LANES_CSV, the largest
difference of x1_end, v1_end and w_friction from tswm's rows of the same
lanes (a `tswm run` of the same grid).

What it integrates (docs/model.md sections 2, 3 and 5): x1, v1 and the works;
the Kloss motor, the paper's friction law, psi = -tan(gamma + c rho(Vs))
with the contact side c = sign(phi) read inside the right-hand side. It is
the peer a user would write first: the switch is not located as an event
(the step-size control absorbs the jump), and there is no rest or sticking
(these lanes start moving at once and never stop). Tolerances as tswm's:
rtol = atol = 1e-8 in float64 (tswm's f64 path), 1e-6 in float32 (its
GPU path).
"""

import argparse
import time

import jax
import jax.numpy as jnp
import diffrax

M1, M2 = 586.0, 10275.0
TAN_G = 0.1
V_SYNC, V_CRIT, F_CRIT = 3.35, 2.07, 4375.0
FA, FB, FC = 0.174, 0.612, 0.14
T_END = 2.0


def rhs(t, y, f2):
    x1, v1 = y[0], y[1]
    cos_g = 1.0 / jnp.sqrt(1.0 + TAN_G * TAN_G)
    sigma = (V_SYNC - v1) / V_SYNC
    sigma_k = (V_SYNC - V_CRIT) / V_SYNC
    f1 = 2.0 * F_CRIT * sigma * sigma_k / (sigma * sigma + sigma_k * sigma_k)
    vs = jnp.abs(v1) / cos_g
    rho = jnp.deg2rad(1.0 / (FA * jnp.power(vs, FB) + FC))
    phi = f1 / M1 - f2 / (M2 * TAN_G)
    c = jnp.where(phi > 0, 1.0, -1.0)
    gamma = jnp.arctan(TAN_G)
    psi = -jnp.tan(gamma + c * rho)
    d = M1 - psi * M2 * TAN_G
    a1 = (f1 - psi * f2) / d
    s1 = f1 - M1 * a1
    s2 = f2 - M2 * TAN_G * a1
    v2 = v1 * TAN_G
    return jnp.stack([v1, a1, f1 * v1, f2 * v2, s1 * v1 + s2 * v2])


def solve_one(f2, tol, dtype):
    y0 = jnp.zeros(5, dtype=dtype)
    sol = diffrax.diffeqsolve(
        diffrax.ODETerm(rhs),
        diffrax.Dopri5(),
        t0=0.0,
        t1=T_END,
        dt0=1e-4,
        y0=y0,
        args=f2,
        stepsize_controller=diffrax.PIDController(rtol=tol, atol=tol),
        max_steps=100_000,
        saveat=diffrax.SaveAt(t1=True),
    )
    return sol.ys[-1], sol.stats["num_accepted_steps"]


def ensemble(n, dtype):
    tol = 1e-8 if dtype == jnp.float64 else 1e-6
    f2 = jnp.linspace(-6000.0, 6000.0, n, dtype=dtype)
    run = jax.jit(jax.vmap(lambda f: solve_one(f, tol, dtype)))
    ys, steps = run(f2[:2])  # compile once for the batch shape below
    ys, steps = run(f2)
    jax.block_until_ready(ys)  # warm-up at the full size
    t = time.perf_counter()
    ys, steps = run(f2)
    jax.block_until_ready(ys)
    return n / (time.perf_counter() - t), ys, steps, f2


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("sizes", nargs="*", type=int, default=[100_000, 1_000_000])
    ap.add_argument("--check", help="tswm lanes.csv of the same grid (same N)")
    ap.add_argument("--precisions", default="float64,float32")
    a = ap.parse_args()
    jax.config.update("jax_enable_x64", True)
    print(f"JAX {jax.__version__}, diffrax {diffrax.__version__}, device {jax.devices()[0]}")
    for n in a.sizes:
        for name in a.precisions.split(","):
            dtype = {"float64": jnp.float64, "float32": jnp.float32}[name]
            rate, ys, steps, f2 = ensemble(n, dtype)
            line = f"diffrax Dopri5 {name}, vmap, {n} lanes: {rate:.0f} lanes/s, mean steps {float(jnp.mean(steps)):.1f}"
            if a.check:
                import csv

                with open(a.check) as fh:
                    rows = list(csv.DictReader(fh))
                if len(rows) == n:
                    worst = 0.0
                    for k, col in [(0, "x1_end"), (1, "v1_end"), (4, "w_friction")]:
                        ref = jnp.array([float(r[col]) for r in rows])
                        d = jnp.abs(ys[:, k] - ref) / jnp.maximum(1.0, jnp.abs(ref))
                        worst = max(worst, float(jnp.max(d)))
                    line += f"; worst difference from tswm {worst:.2e} (relative to max(1, |value|))"
            print(line, flush=True)


if __name__ == "__main__":
    main()
