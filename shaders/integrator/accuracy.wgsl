// Mirrors src/integrator/accuracy.rs: a lane's own estimate of the error
// in its results, kept in f64 only (KEEP_BUDGET), so that an f64 lane
// whose estimate is over the bound is run again on the CPU at tighter
// settings, as a CPU lane is.

// Rates of the results at derivative k: x1, v1, w_motor, w_load,
// w_friction, and the in and out parts of p1 and p2 (`parts`). add_step
// reads the same rates in place, as the CPU's does; only the mirrored
// tests call it.
fn rates(k: array<real, NY>) -> array<real, RESULTS> {
    let q = parts(k[4], k[5]);
    return array<real, RESULTS>(k[0], k[1], k[2], k[3], k[4], q.x, q.y, q.z, q.w);
}

// The in and out parts of p1 and p2 (the rates of w1_in, w1_out, w2_in,
// w2_out) from one lane's rates of w_friction (k4) and the integral of
// p1 (k5).
fn parts(k4: real, k5: real) -> vec4<real> {
    let p = powers(k4, k5);
    return vec4<real>(max(p.x, 0.0), max(-p.x, 0.0), max(p.y, 0.0), max(-p.y, 0.0));
}

// Adds an accepted step from derivative k0 to tr (its k7 the derivative
// at the end, its est the error estimates) whose flow `d` says which
// parts of p1 and p2 it fed: each result's phase term grows by the
// change of its rate times the lag so far, its local term by its own
// estimate, and the lag by v1's estimate over the acceleration.
fn add_step(st: ptr<function, State>, k0: array<real, NY>, tr: Trial, d: vec4<real>) {
    let lag = (*st).lag;
    // The change of each rate over the step, as `rates` gives them: the
    // first five are k's own components, the rest `parts`.
    for (var i = 0u; i < 5u; i++) {
        (*st).phase[i] += abs(tr.k7[i] - k0[i]) * lag;
    }
    let change = abs(parts(tr.k7[4], tr.k7[5]) - parts(k0[4], k0[5]));
    for (var q = 0u; q < 4u; q++) {
        (*st).phase[5u + q] += change[q] * lag;
    }
    for (var i = 0u; i < 5u; i++) {
        (*st).local[i] += tr.est[i];
    }
    // The integral of p1's estimate to the p1 parts the step fed, p2's to p2's.
    if (d.x != 0.0) { (*st).local[5] += tr.est[5]; }
    if (d.y != 0.0) { (*st).local[6] += tr.est[5]; }
    if (d.z != 0.0) { (*st).local[7] += tr.est[NY]; }
    if (d.w != 0.0) { (*st).local[8] += tr.est[NY]; }
    let a = max(abs(k0[1]), abs(tr.k7[1]));
    if (a > 0.0) { (*st).lag = lag + tr.est[1] / a; }
}

// Adds a step's split errors of the integrals of p1 and p2 to the local
// terms of their in and out parts.
fn add_split(st: ptr<function, State>, err: vec2<real>) {
    (*st).local[5] += err.x;
    (*st).local[6] += err.x;
    (*st).local[7] += err.y;
    (*st).local[8] += err.y;
}

// The room a result's estimate has left below BUDGET_AIM of its size, at
// value v, rate `rate` and estimate so far `used`: its size is the
// largest of 1, |v| and the value it would reach going on at its rate
// for the `left` seconds to t_end.
fn room(v: real, rate: real, used: real, left: real) -> real {
    let ahead = abs(v + rate * left);
    let aim = BUDGET_AIM * max(max(abs(v), ahead), 1.0);
    return max(aim - used, 0.0);
}

fn used(st: ptr<function, State>, r: u32) -> real { return (*st).phase[r] + (*st).local[r]; }

// The largest error estimate a step of size h may make in each component
// (absolute): each result's room shared over the rest of the horizon in
// proportion to the step. The integral of p1's cap is that of the part
// of p1 the step starts feeding; w_friction's also that of p2's part.
// Without the budget (f32), or at a tolerance the budget does not steer
// (STEER_ABOVE), no cap.
fn caps(l: Lane, st: ptr<function, State>, h: real) -> array<real, NY> {
    if (!KEEP_BUDGET || !(g.tol > STEER_ABOVE)) {
        return array<real, NY>(3.0e38, 3.0e38, 3.0e38, 3.0e38, 3.0e38, 3.0e38);
    }
    let left = max(l.t_end - time_of(st), 0.0);
    let share = h / max(left, h);
    let y = (*st).y;
    let k = (*st).k1;
    let f = (*st).flow;
    let p = powers(k[4], k[5]);
    // The part of p1 (of p2) the step starts feeding, in or out.
    let part1 = select(room(f.x, p.x, used(st, 5u), left), room(f.y, -p.x, used(st, 6u), left), p.x < 0.0);
    let part2 = select(room(f.z, p.y, used(st, 7u), left), room(f.w, -p.y, used(st, 8u), left), p.y < 0.0);
    // No cap below REFINE_FACTOR times the component's error scale at its
    // tolerance or CAP_FLOOR_TOL, whichever is tighter: finer than that,
    // the budget's limit is left to refinement.
    let lo = REFINE_FACTOR * min(g.tol, CAP_FLOOR_TOL);
    let lo_traj = REFINE_FACTOR * min(g.tol_traj, CAP_FLOOR_TOL);
    return array<real, NY>(
        max(room(y[0], k[0], used(st, 0u), left) * share, error_scale(lo_traj, y[0], y[0])),
        max(room(y[1], k[1], used(st, 1u), left) * share, error_scale(lo_traj, y[1], y[1])),
        max(room(y[2], k[2], used(st, 2u), left) * share, error_scale(lo, y[2], y[2])),
        max(room(y[3], k[3], used(st, 3u), left) * share, error_scale(lo, y[3], y[3])),
        max(min(room(y[4], k[4], used(st, 4u), left), part2) * share, error_scale(lo, y[4], y[4])),
        max(part1 * share, error_scale(lo, y[5], y[5])));
}
