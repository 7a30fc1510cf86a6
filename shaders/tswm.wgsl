// tswm: the TSWM hybrid integrator, one lane per invocation, in f32.
//
// Why one file of over 400 lines: WGSL has no modules or includes, and a
// pipeline is made from one source; the sections below keep it readable.
//
// The same algorithm as the f64 CPU path, in the same parts and order,
// each section headed by the Rust file it mirrors:
//   src/model/ (mod.rs, friction.rs)  motor_force, tan_small, agma_mu, agma_upper,
//                                 mu_sliding, phi, side_of, Mode, motion, stick_test
//   src/integrator/result.rs      status codes
//   src/integrator/stepper.rs     tableau, rhs (src/integrator/rhs.rs), stage*_v,
//                                 increment, error_term, error_scale, dense_coeffs,
//                                 dense_r5, try_step
//   src/integrator/events.rs      dense_v, event_value, locate_root, earliest_event
//   src/integrator/flow.rs        dense_slope, split, dense_w, step_flow
//   src/integrator/automaton.rs   State, init, set_side, check_mode, come_to_rest,
//                                 depart, cut_motor, horizon, reach_time_event
//   src/integrator/step.rs        prepare, step_factor (src/integrator/control.rs),
//                                 finish_step, add_flow,
//                                 step_to_event, attempt
//   src/integrator/batch.rs       Globals, bindings, the entry point
// Structs and constants shared with the host are mirrored in
// src/backend/gpu/layout.rs and src/model/; tests read them from this file with
// naga and compare.
//
// Differences forced by f32: x1, the works and the time are compensated
// (Kahan) sums; the per-step tolerance is 1e-6 rather than 1e-8 (Globals);
// event roots are located to a relative step fraction of 1e-6 rather than
// 1e-13 s; a step below 1e-7·max(t, 1) s, not 1e-15·max(t, 1), is an
// underflow; tan_small's series stops at x^9, exact in f32; "never" is
// 3e38 rather than infinity. The f64 path computes x^y and the step
// factor's err^(-1/5) with its own straight-line kernels (so that they
// run as vector code, src/model/vmath.rs and src/integrator/control.rs);
// here WGSL's pow does. Where p changes sign inside a step, the f64 path
// finds the zero by the Illinois method, here by 24 halvings.

// ==== src/model/ (mod.rs, friction.rs) ====

// Keep in sync with `GpuLane` in src/backend/gpu/layout.rs.
struct Lane {
    m1: f32, m2: f32, tan_g: f32, sin_g: f32,
    cos_g: f32, inv_cos_g: f32, f2: f32, motor: u32,
    v_sync: f32, sigma_k: f32, f_crit: f32, f1: f32,
    motor_off: f32, friction: u32, fric_a: f32, fric_b: f32,
    fric_c: f32, mu: f32, mu_s: f32, x1_0: f32,
    v1_0: f32, t_end: f32, t_max: f32, table: u32,
    inv_cos_an: f32, pad0: u32,
}

// Law codes: keep in sync with src/model/mod.rs.
const MOTOR_KLOSS: u32 = 0u;
const MOTOR_CONSTANT: u32 = 1u;
const FRICTION_PAPER: u32 = 0u;
const FRICTION_COULOMB: u32 = 1u;
const FRICTION_TABLE: u32 = 2u;
const FRICTION_AGMA: u32 = 3u;

// The agma law: keep in sync with src/model/friction.rs.
const FT_PER_MIN_PER_M_PER_S: f32 = 196.8503937007874;
const AGMA_LOW_A: f32 = 0.124;
const AGMA_LOW_B: f32 = 0.074;
const AGMA_LOW_E: f32 = 0.645;
const AGMA_HIGH_A: f32 = 0.103;
const AGMA_HIGH_B: f32 = 0.110;
const AGMA_HIGH_E: f32 = 0.450;
const AGMA_HIGH_C: f32 = 0.012;
const AGMA_JUMP_M_S: f32 = 0.0508;

const PI: f32 = 3.14159265358979;

fn motor_force(l: Lane, v1: f32, motor_on: bool) -> f32 {
    if (!motor_on) { return 0.0; }
    if (l.motor == MOTOR_CONSTANT) { return l.f1; }
    let sigma = (l.v_sync - v1) / l.v_sync;
    let sk = l.sigma_k;
    return 2.0 * l.f_crit * sigma * sk / (sigma * sigma + sk * sk);
}

fn tan_small(x: f32) -> f32 {
    if (abs(x) > 0.15) { return tan(x); }
    let x2 = x * x;
    var p = 62.0 / 2835.0;
    p = p * x2 + 17.0 / 315.0;
    p = p * x2 + 2.0 / 15.0;
    p = p * x2 + 1.0 / 3.0;
    return x + x * x2 * p;
}

// Point i of table t (see `GpuGlobals`).
fn table_at(t: u32, i: u32) -> vec2<f32> {
    let k = t * TABLE_VEC4S + i / 4u;
    return vec2<f32>(g.table_vs[k][i % 4u], g.table_mu[k][i % 4u]);
}

fn agma_mu(vs: f32, upper: bool) -> f32 {
    let v = max(vs, 0.0) * FT_PER_MIN_PER_M_PER_S;
    // pow(0, e) is not defined in WGSL: Vs^e = 0 at rest.
    let e = select(AGMA_LOW_E, AGMA_HIGH_E, upper);
    var pw = 0.0;
    if (v > 0.0) { pw = pow(v, e); }
    if (upper) { return AGMA_HIGH_A * exp(-AGMA_HIGH_B * pw) + AGMA_HIGH_C; }
    return AGMA_LOW_A * exp(-AGMA_LOW_B * pw);
}

fn agma_upper(vs: f32) -> bool {
    return vs > AGMA_JUMP_M_S;
}

fn mu_sliding(l: Lane, vs: f32, upper: bool) -> f32 {
    if (l.friction == FRICTION_PAPER) {
        var pw = 0.0;
        if (vs > 0.0) { pw = pow(vs, l.fric_b); }
        let rho = (PI / 180.0) / (l.fric_a * pw + l.fric_c);
        return tan_small(rho);
    }
    if (l.friction == FRICTION_COULOMB) { return l.mu; }
    if (l.friction == FRICTION_AGMA) { return agma_mu(vs, upper) * l.inv_cos_an; }
    if (l.friction != FRICTION_TABLE || l.table >= g.n_tables) {
        // No such law or table: NaN makes the lane `nonfinite`, never a number.
        return bitcast<f32>(0x7fc00000u);
    }
    // table: linear between points, flat past the ends
    let t = l.table;
    let n = g.table_n[t / 4u][t % 4u];
    var prev = table_at(t, 0u);
    if (vs <= prev.x) { return prev.y * l.inv_cos_an; }
    for (var i = 1u; i < n; i++) {
        let cur = table_at(t, i);
        if (vs < cur.x) {
            let w = (vs - prev.x) / (cur.x - prev.x);
            return (prev.y + w * (cur.y - prev.y)) * l.inv_cos_an;
        }
        prev = cur;
    }
    return prev.y * l.inv_cos_an;
}

fn phi(l: Lane, v1: f32, motor_on: bool) -> f32 {
    return motor_force(l, v1, motor_on) / l.m1 - l.f2 / (l.m2 * l.tan_g);
}

fn side_of(p: f32) -> i32 {
    if (p >= 0.0) { return 1; }
    return -1;
}

// Keep in sync with `Mode` in src/model/mod.rs.
struct Mode { side: i32, dir: i32, motor_on: bool, upper: bool }

struct Motion { acc: f32, d: f32, f1: f32, s1: f32, s2: f32 }

fn motion(l: Lane, m: Mode, v1: f32) -> Motion {
    let f1 = motor_force(l, v1, m.motor_on);
    let vs = max(f32(m.dir) * v1, 0.0) * l.inv_cos_g;
    let t = f32(m.side * m.dir) * mu_sliding(l, vs, m.upper);
    let p = l.tan_g + t;
    let q = 1.0 - l.tan_g * t;
    let dq = l.m1 * q + p * l.m2 * l.tan_g;
    let acc = (f1 * q + p * l.f2) / dq;
    return Motion(acc, dq / q, f1, f1 - l.m1 * acc, l.f2 - l.m2 * l.tan_g * acc);
}

// x: sticks, y: T
fn stick_test(l: Lane, motor_on: bool) -> vec2<f32> {
    let f1 = motor_force(l, 0.0, motor_on);
    let n = abs(l.f2 * l.cos_g - f1 * l.sin_g);
    let t = f1 * l.cos_g + l.f2 * l.sin_g;
    return vec2<f32>(select(0.0, 1.0, abs(t) <= l.mu_s * n), t);
}

// ==== src/integrator/result.rs ====

// Status codes: keep in sync with `Status` in src/integrator/result.rs.
const S_OK: u32 = 0u;
const S_INCONSISTENT: u32 = 1u;
const S_NONFINITE: u32 = 2u;
const S_MAX_STEPS: u32 = 3u;
const S_MAX_EVENTS: u32 = 4u;
const S_STEP_UNDERFLOW: u32 = 5u;

// ==== src/integrator/stepper.rs ====

// Dormand-Prince 5(4): keep in sync with src/integrator/stepper.rs.
const A21: f32 = 1.0 / 5.0;
const A31: f32 = 3.0 / 40.0;
const A32: f32 = 9.0 / 40.0;
const A41: f32 = 44.0 / 45.0;
const A42: f32 = -56.0 / 15.0;
const A43: f32 = 32.0 / 9.0;
const A51: f32 = 19372.0 / 6561.0;
const A52: f32 = -25360.0 / 2187.0;
const A53: f32 = 64448.0 / 6561.0;
const A54: f32 = -212.0 / 729.0;
const A61: f32 = 9017.0 / 3168.0;
const A62: f32 = -355.0 / 33.0;
const A63: f32 = 46732.0 / 5247.0;
const A64: f32 = 49.0 / 176.0;
const A65: f32 = -5103.0 / 18656.0;
const A71: f32 = 35.0 / 384.0;
const A73: f32 = 500.0 / 1113.0;
const A74: f32 = 125.0 / 192.0;
const A75: f32 = -2187.0 / 6784.0;
const A76: f32 = 11.0 / 84.0;
const E1: f32 = 71.0 / 57600.0;
const E3: f32 = -71.0 / 16695.0;
const E4: f32 = 71.0 / 1920.0;
const E5: f32 = -17253.0 / 339200.0;
const E6: f32 = 22.0 / 525.0;
const E7: f32 = -1.0 / 40.0;
const D1: f32 = -12715105075.0 / 11282082432.0;
const D3: f32 = 87487479700.0 / 32700410799.0;
const D4: f32 = -10690763975.0 / 1880347072.0;
const D5: f32 = 701980252875.0 / 199316789632.0;
const D6: f32 = -1453857185.0 / 822651844.0;
const D7: f32 = 69997945.0 / 29380423.0;

// Components of the integrated state: keep in sync with `NY` in
// src/integrator/mod.rs (x1, v1, w_motor, w_load, w_friction, w_p1).
const NY: u32 = 6u;

struct Deriv { k: array<f32, NY>, d: f32 }

fn rhs(l: Lane, m: Mode, v: f32) -> Deriv {
    let mo = motion(l, m, v);
    let v2 = v * l.tan_g;
    let p1 = mo.s1 * v;
    let p2 = mo.s2 * v2;
    return Deriv(array<f32, NY>(v, mo.acc, mo.f1 * v, l.f2 * v2, p1 + p2, p1), mo.d);
}

fn stage2_v(v0: f32, h: f32, k1: f32) -> f32 {
    return v0 + h * (A21 * k1);
}
fn stage3_v(v0: f32, h: f32, k1: f32, k2: f32) -> f32 {
    return v0 + h * (A31 * k1 + A32 * k2);
}
fn stage4_v(v0: f32, h: f32, k1: f32, k2: f32, k3: f32) -> f32 {
    return v0 + h * (A41 * k1 + A42 * k2 + A43 * k3);
}
fn stage5_v(v0: f32, h: f32, k1: f32, k2: f32, k3: f32, k4: f32) -> f32 {
    return v0 + h * (A51 * k1 + A52 * k2 + A53 * k3 + A54 * k4);
}
fn stage6_v(v0: f32, h: f32, k1: f32, k2: f32, k3: f32, k4: f32, k5: f32) -> f32 {
    return v0 + h * (A61 * k1 + A62 * k2 + A63 * k3 + A64 * k4 + A65 * k5);
}

fn increment(h: f32, k1: f32, k3: f32, k4: f32, k5: f32, k6: f32) -> f32 {
    return h * (A71 * k1 + A73 * k3 + A74 * k4 + A75 * k5 + A76 * k6);
}

fn error_term(h: f32, k1: f32, k3: f32, k4: f32, k5: f32, k6: f32, k7: f32) -> f32 {
    return h * (E1 * k1 + E3 * k3 + E4 * k4 + E5 * k5 + E6 * k6 + E7 * k7);
}

fn error_scale(tol: f32, y0: f32, y1: f32) -> f32 {
    return tol * (1.0 + max(abs(y0), abs(y1)));
}

fn dense_coeffs(v0: f32, v1: f32, h: f32, k1: f32, k3: f32, k4: f32, k5: f32, k6: f32, k7: f32) -> array<f32, 5> {
    let r2 = v1 - v0;
    let r3 = h * k1 - r2;
    let r4 = r2 - h * k7 - r3;
    return array<f32, 5>(v0, r2, r3, r4, dense_r5(h, k1, k3, k4, k5, k6, k7));
}

fn dense_r5(h: f32, k1: f32, k3: f32, k4: f32, k5: f32, k6: f32, k7: f32) -> f32 {
    return h * (D1 * k1 + D3 * k3 + D4 * k4 + D5 * k5 + D6 * k6 + D7 * k7);
}

struct Trial {
    y1: array<f32, NY>,
    y1c: array<f32, NY>,
    k7: array<f32, NY>,
    err: f32,
    dense: array<f32, 5>,
    // increments of the integrals of p1 and p2, and the last coefficient
    // of their dense outputs, for `step_flow`
    dw: vec2<f32>,
    dw_r4: vec2<f32>,
}

// Compensated (Kahan) y1 = y + dy of component i; the value is y1 - y1c.
fn step_component(tr: ptr<function, Trial>, i: u32, dy: f32, y: f32, yc: f32) {
    let yy = dy - yc;
    let s = y + yy;
    (*tr).y1c[i] = (s - y) - yy;
    (*tr).y1[i] = s;
}

fn try_step(l: Lane, m: Mode, y: array<f32, NY>, yc: array<f32, NY>, k1: array<f32, NY>, h: f32, tol: f32) -> Trial {
    let v0 = y[1];
    let k2 = rhs(l, m, stage2_v(v0, h, k1[1])).k;
    let k3 = rhs(l, m, stage3_v(v0, h, k1[1], k2[1])).k;
    let k4 = rhs(l, m, stage4_v(v0, h, k1[1], k2[1], k3[1])).k;
    let k5 = rhs(l, m, stage5_v(v0, h, k1[1], k2[1], k3[1], k4[1])).k;
    let k6 = rhs(l, m, stage6_v(v0, h, k1[1], k2[1], k3[1], k4[1], k5[1])).k;
    var tr: Trial;
    // Written out component by component (constant indices): with a loop
    // over the components lavapipe's compiler keeps these arrays in
    // memory and runs ten times slower.
    step_component(&tr, 0u, increment(h, k1[0], k3[0], k4[0], k5[0], k6[0]), y[0], yc[0]);
    step_component(&tr, 1u, increment(h, k1[1], k3[1], k4[1], k5[1], k6[1]), y[1], yc[1]);
    step_component(&tr, 2u, increment(h, k1[2], k3[2], k4[2], k5[2], k6[2]), y[2], yc[2]);
    step_component(&tr, 3u, increment(h, k1[3], k3[3], k4[3], k5[3], k6[3]), y[3], yc[3]);
    step_component(&tr, 4u, increment(h, k1[4], k3[4], k4[4], k5[4], k6[4]), y[4], yc[4]);
    step_component(&tr, 5u, increment(h, k1[5], k3[5], k4[5], k5[5], k6[5]), y[5], yc[5]);
    tr.k7 = rhs(l, m, tr.y1[1]).k;
    var err = 0.0;
    err = max(err, abs(error_term(h, k1[0], k3[0], k4[0], k5[0], k6[0], tr.k7[0])) / error_scale(tol, y[0], tr.y1[0]));
    err = max(err, abs(error_term(h, k1[1], k3[1], k4[1], k5[1], k6[1], tr.k7[1])) / error_scale(tol, y[1], tr.y1[1]));
    err = max(err, abs(error_term(h, k1[2], k3[2], k4[2], k5[2], k6[2], tr.k7[2])) / error_scale(tol, y[2], tr.y1[2]));
    err = max(err, abs(error_term(h, k1[3], k3[3], k4[3], k5[3], k6[3], tr.k7[3])) / error_scale(tol, y[3], tr.y1[3]));
    err = max(err, abs(error_term(h, k1[4], k3[4], k4[4], k5[4], k6[4], tr.k7[4])) / error_scale(tol, y[4], tr.y1[4]));
    err = max(err, abs(error_term(h, k1[5], k3[5], k4[5], k5[5], k6[5], tr.k7[5])) / error_scale(tol, y[5], tr.y1[5]));
    // NaN and infinity fail this test: the step is rejected.
    if (!(err <= 3.0e38)) { err = 3.0e38; }
    tr.err = err;
    tr.dense = dense_coeffs(v0, tr.y1[1], h, k1[1], k3[1], k4[1], k5[1], k6[1], tr.k7[1]);
    // The integral of p1 is component 5; that of p2 the difference of 4 and 5.
    let k7 = tr.k7;
    let q1 = k1[4] - k1[5];
    let q3 = k3[4] - k3[5];
    let q4 = k4[4] - k4[5];
    let q5 = k5[4] - k5[5];
    let q6 = k6[4] - k6[5];
    tr.dw = vec2<f32>(increment(h, k1[5], k3[5], k4[5], k5[5], k6[5]), increment(h, q1, q3, q4, q5, q6));
    tr.dw_r4 = vec2<f32>(dense_r5(h, k1[5], k3[5], k4[5], k5[5], k6[5], k7[5]),
        dense_r5(h, q1, q3, q4, q5, q6, k7[4] - k7[5]));
    return tr;
}

// ==== src/integrator/events.rs ====

const THETA_TOL: f32 = 1e-6;

fn dense_v(r: array<f32, 5>, th: f32) -> f32 {
    let th1 = 1.0 - th;
    return r[0] + th * (r[1] + th1 * (r[2] + th * (r[3] + th1 * r[4])));
}

// Event functions: keep in sync with `EventFn` in src/integrator/events.rs.
const EV_SWITCH: u32 = 0u;
const EV_REST: u32 = 1u;
const EV_SPEEDING: u32 = 2u;
const EV_BRANCH: u32 = 3u;

fn event_value(l: Lane, m: Mode, which: u32, v: f32) -> f32 {
    if (which == EV_SWITCH) { return f32(m.side) * phi(l, v, m.motor_on); }
    if (which == EV_REST) { return f32(m.dir) * v; }
    if (which == EV_BRANCH) {
        let vs = max(f32(m.dir) * v, 0.0) * l.inv_cos_g;
        return select(AGMA_JUMP_M_S - vs, vs - AGMA_JUMP_M_S, m.upper);
    }
    return -f32(m.dir) * motion(l, m, v).acc;
}

fn locate_root(l: Lane, m: Mode, which: u32, r: array<f32, 5>, g_end: f32) -> f32 {
    var a = 0.0;
    var fa = event_value(l, m, which, r[0]);
    var b = 1.0;
    var fb = g_end;
    if (fa <= 0.0) { return 0.0; }
    var side = 0;
    for (var it = 0; it < 100; it++) {
        if (b - a <= THETA_TOL) { break; }
        var c = (a * fb - b * fa) / (fb - fa);
        if (!(c > a && c < b)) { c = 0.5 * (a + b); }
        let fc = event_value(l, m, which, dense_v(r, c));
        if (fc >= 0.0) {
            a = c; fa = fc;
            if (side == -1) { fb *= 0.5; }
            side = -1;
        } else {
            b = c; fb = fc;
            if (side == 1) { fa *= 0.5; }
            side = 1;
        }
    }
    return a;
}

// x: θ of the earliest event (> 1: none), y: which (EV_*)
fn earliest_event(l: Lane, m: Mode, tr: Trial, running_on: bool) -> vec2<f32> {
    let g_rest = event_value(l, m, EV_REST, tr.y1[1]);
    let g_switch = event_value(l, m, EV_SWITCH, tr.y1[1]);
    var theta = 2.0;
    var which = EV_REST;
    if (g_rest < 0.0) { theta = locate_root(l, m, EV_REST, tr.dense, g_rest); }
    if (g_switch < 0.0) {
        let th = locate_root(l, m, EV_SWITCH, tr.dense, g_switch);
        if (th < theta) { theta = th; which = EV_SWITCH; }
    }
    let g_speeding = -f32(m.dir) * tr.k7[1];
    if (running_on && g_speeding < 0.0) {
        let th = locate_root(l, m, EV_SPEEDING, tr.dense, g_speeding);
        if (th < theta) { theta = th; which = EV_SPEEDING; }
    }
    if (l.friction == FRICTION_AGMA) {
        let g_branch = event_value(l, m, EV_BRANCH, tr.y1[1]);
        if (g_branch < 0.0) {
            let th = locate_root(l, m, EV_BRANCH, tr.dense, g_branch);
            if (th < theta) { theta = th; which = EV_BRANCH; }
        }
    }
    return vec2<f32>(theta, f32(which));
}

// ==== src/integrator/flow.rs ====

// Bisection ends when the bracket is this narrow: 2^-24, the resolution of
// f32 on [0, 1] (2^-52 in f64, see `THETA_TOL` in src/integrator/flow.rs).
const THETA_TOL_FLOW: f32 = 5.9604645e-8;

fn dense_slope(r: array<f32, 5>, th: f32) -> f32 {
    let th1 = 1.0 - th;
    return r[1] + (th1 - th) * r[2] + th * (2.0 - 3.0 * th) * r[3] + 2.0 * th * th1 * (th1 - th) * r[4];
}

// [in, out] parts of a step's increment r[1] of the integral of p, from
// its dense output r (r0 = 0) and p at the step's start and end.
fn split(r: array<f32, 5>, p0: f32, p_end: f32) -> vec2<f32> {
    let total = r[1];
    if (!(p0 * p_end < 0.0)) {
        let positive = p0 + p_end > 0.0 || (p0 + p_end == 0.0 && total >= 0.0);
        return select(vec2<f32>(0.0, -total), vec2<f32>(total, 0.0), positive);
    }
    let sign = select(-1.0, 1.0, p0 > 0.0);
    var a = 0.0;
    var b = 1.0;
    // A trip count the compiler cannot see: a constant one is unrolled,
    // and that code, run only at a crossing, halved lavapipe's throughput.
    var it = 0u;
    while (b - a > THETA_TOL_FLOW && it < 64u) {
        it++;
        let c = 0.5 * (a + b);
        if (sign * dense_slope(r, c) > 0.0) { a = c; } else { b = c; }
    }
    let first = dense_v(r, 0.5 * (a + b));
    let rest = total - first;
    return select(vec2<f32>(rest, -first), vec2<f32>(first, -rest), sign > 0.0);
}

fn dense_w(dw: f32, h: f32, q0: f32, q_end: f32, r4: f32) -> array<f32, 5> {
    let r2 = h * q0 - dw;
    return array<f32, 5>(0.0, dw, r2, dw - h * q_end - r2, r4);
}

// Increments of (w1_in, w1_out, w2_in, w2_out) over an accepted step.
fn step_flow(k1: array<f32, NY>, tr: Trial, h: f32) -> vec4<f32> {
    let p1_0 = k1[5];
    let p1_end = tr.k7[5];
    let p2_0 = k1[4] - k1[5];
    let p2_end = tr.k7[4] - tr.k7[5];
    let f1 = split(dense_w(tr.dw.x, h, p1_0, p1_end, tr.dw_r4.x), p1_0, p1_end);
    let f2 = split(dense_w(tr.dw.y, h, p2_0, p2_end, tr.dw_r4.y), p2_0, p2_end);
    return vec4<f32>(f1, f2);
}

// ==== src/integrator/automaton.rs ====

// Keep in sync with `GpuState` in src/backend/gpu/layout.rs.
struct State {
    t_hi: f32, t_lo: f32, h: f32, t_first_switch: f32,
    flow: vec4<f32>,    // w1_in, w1_out, w2_in, w2_out
    flow_c: vec4<f32>,  // their Kahan compensations
    y: array<f32, NY>,
    yc: array<f32, NY>,
    k1: array<f32, NY>,
    side: i32, dir: i32, flags: u32, status: u32,
    switches: u32, reversals: u32, sticks: u32, steps: u32,
    events: u32, pad0: u32, pad1: u32, pad2: u32,
    pad3: u32, pad4: u32,
}

// Flag bits of State.flags: keep in sync with `flags` in src/backend/gpu/layout.rs.
const F_STUCK: u32 = 1u;
const F_MOTOR_ON: u32 = 2u;
const F_DONE: u32 = 4u;
const F_K1_VALID: u32 = 8u;
const F_STARTED: u32 = 16u;
const F_RUNNING_ON: u32 = 32u;
const F_SPEEDING: u32 = 64u;
const F_UPPER: u32 = 128u;

const NO_FIRST_SWITCH: f32 = -1.0;

fn has(st: ptr<function, State>, f: u32) -> bool { return ((*st).flags & f) != 0u; }
fn set_flag(st: ptr<function, State>, f: u32, on: bool) {
    if (on) { (*st).flags |= f; } else { (*st).flags &= ~f; }
}

fn time_of(st: ptr<function, State>) -> f32 { return (*st).t_hi - (*st).t_lo; }

fn time_add(st: ptr<function, State>, h: f32) {
    let y = h - (*st).t_lo;
    let t = (*st).t_hi + y;
    (*st).t_lo = (t - (*st).t_hi) - y;
    (*st).t_hi = t;
}

fn time_set(st: ptr<function, State>, t: f32) {
    (*st).t_hi = t;
    (*st).t_lo = 0.0;
}

fn mode_of(st: ptr<function, State>) -> Mode {
    return Mode((*st).side, (*st).dir, has(st, F_MOTOR_ON), has(st, F_UPPER));
}

fn finish(st: ptr<function, State>, status: u32) {
    (*st).status = status;
    set_flag(st, F_DONE, true);
}

fn init(l: Lane, st: ptr<function, State>) {
    let motor_on = !(l.motor_off <= 0.0);
    let v = l.v1_0;
    (*st).t_hi = 0.0;
    (*st).t_lo = 0.0;
    (*st).y = array<f32, NY>(l.x1_0, v, 0.0, 0.0, 0.0, 0.0);
    (*st).yc = array<f32, NY>();
    (*st).flow = vec4<f32>();
    (*st).flow_c = vec4<f32>();
    (*st).h = min(g.h_initial, l.t_end);
    (*st).side = side_of(phi(l, v, motor_on));
    (*st).dir = select(select(0, -1, v < 0.0), 1, v > 0.0);
    (*st).flags = F_STARTED;
    set_flag(st, F_MOTOR_ON, motor_on);
    set_flag(st, F_UPPER, l.friction == FRICTION_AGMA && agma_upper(abs(v) * l.inv_cos_g));
    (*st).status = S_OK;
    (*st).switches = 0u;
    (*st).reversals = 0u;
    (*st).sticks = 0u;
    (*st).t_first_switch = NO_FIRST_SWITCH;
    (*st).steps = 0u;
    (*st).events = 0u;
    if (v == 0.0) { come_to_rest(l, st); } else { check_mode(l, st); }
}

fn set_side(st: ptr<function, State>, side: i32) {
    if (side != (*st).side) {
        (*st).switches += 1u;
        if ((*st).t_first_switch < 0.0) { (*st).t_first_switch = time_of(st); }
        (*st).side = side;
    }
}

fn check_mode(l: Lane, st: ptr<function, State>) {
    if (has(st, F_STUCK) || has(st, F_DONE)) { return; }
    let dv = rhs(l, mode_of(st), (*st).y[1]);
    if (!(dv.d > 0.0)) { finish(st, S_INCONSISTENT); }
    (*st).k1 = dv.k;
    set_flag(st, F_K1_VALID, true);
}

fn come_to_rest(l: Lane, st: ptr<function, State>) {
    (*st).y[1] = 0.0;
    (*st).yc[1] = 0.0;
    set_flag(st, F_UPPER, false);
    let s = stick_test(l, has(st, F_MOTOR_ON));
    if (s.x > 0.5) {
        set_flag(st, F_STUCK, true);
        (*st).sticks += 1u;
        set_flag(st, F_K1_VALID, false);
        return;
    }
    depart(l, st, s.y);
}

fn depart(l: Lane, st: ptr<function, State>, tf: f32) {
    let dir = select(-1, 1, tf > 0.0);
    if ((*st).dir != 0 && dir != (*st).dir) { (*st).reversals += 1u; }
    (*st).dir = dir;
    set_flag(st, F_STUCK, false);
    (*st).h = g.h_initial;
    set_side(st, side_of(phi(l, 0.0, has(st, F_MOTOR_ON))));
    check_mode(l, st);
}

fn cut_motor(l: Lane, st: ptr<function, State>) {
    set_flag(st, F_MOTOR_ON, false);
    (*st).events += 1u;
    set_flag(st, F_K1_VALID, false);
    if (has(st, F_STUCK)) {
        let s = stick_test(l, false);
        if (s.x < 0.5) { depart(l, st, s.y); }
    } else {
        set_side(st, side_of(phi(l, (*st).y[1], false)));
        check_mode(l, st);
    }
}

fn horizon(l: Lane, st: ptr<function, State>) -> f32 {
    return select(l.t_end, l.t_max, has(st, F_RUNNING_ON));
}

fn reach_time_event(l: Lane, st: ptr<function, State>, t_stop: f32) {
    time_set(st, t_stop);
    if (t_stop < horizon(l, st)) {
        cut_motor(l, st);
    } else if (!has(st, F_RUNNING_ON) && l.t_max > l.t_end && l.motor_off < l.t_end
        && !has(st, F_STUCK) && has(st, F_K1_VALID) && f32((*st).dir) * (*st).k1[1] < 0.0) {
        set_flag(st, F_RUNNING_ON, true);
    } else {
        set_flag(st, F_DONE, true);
    }
}

// ==== src/integrator/step.rs ====

struct StepPlan { ok: bool, mode: Mode, h: f32, t_stop: f32, landing: bool }

fn prepare(l: Lane, st: ptr<function, State>) -> StepPlan {
    var plan: StepPlan;
    plan.ok = false;
    let end = horizon(l, st);
    var t_stop = end;
    if (has(st, F_MOTOR_ON) && l.motor_off < end) { t_stop = l.motor_off; }
    if (has(st, F_STUCK)) {
        reach_time_event(l, st, t_stop);
        return plan;
    }
    let m = mode_of(st);
    if (!has(st, F_K1_VALID)) {
        let dv = rhs(l, m, (*st).y[1]);
        if (!(dv.d > 0.0)) { finish(st, S_INCONSISTENT); return plan; }
        (*st).k1 = dv.k;
        set_flag(st, F_K1_VALID, true);
    }
    var h = (*st).h;
    let steep_at_rest = l.friction == FRICTION_PAPER || l.friction == FRICTION_AGMA;
    if (steep_at_rest && (*st).k1[1] * f32((*st).dir) < 0.0) {
        let t_rest = -(*st).y[1] / (*st).k1[1];
        h = min(h, max(0.5 * t_rest, g.h_initial));
    }
    let remaining = (t_stop - (*st).t_hi) + (*st).t_lo;
    let landing = h >= remaining;
    if (landing) { h = remaining; }
    return StepPlan(true, m, h, t_stop, landing);
}

fn step_factor(err: f32) -> f32 {
    if (err > 0.0) { return clamp(0.9 * pow(err, -0.2), 0.2, 5.0); }
    return 5.0;
}

fn finish_step(l: Lane, st: ptr<function, State>, plan: StepPlan, tr: Trial) {
    let h = plan.h;
    let fac = step_factor(tr.err);
    if (tr.err > 1.0) {
        (*st).h = h * min(fac, 1.0);
        if ((*st).h < 1e-7 * max(time_of(st), 1.0)) { finish(st, S_STEP_UNDERFLOW); }
        return;
    }
    let h_next = h * fac;
    (*st).steps += 1u;
    if ((*st).steps > g.max_steps) { finish(st, S_MAX_STEPS); return; }
    let ev = earliest_event(l, plan.mode, tr, has(st, F_RUNNING_ON));
    if (ev.x <= 1.0) {
        step_to_event(l, st, plan, ev.x, u32(ev.y), h_next);
    } else {
        add_flow(st, tr, h);
        (*st).y = tr.y1;
        (*st).yc = tr.y1c;
        (*st).k1 = tr.k7;
        (*st).h = h_next;
        if (plan.landing) {
            reach_time_event(l, st, plan.t_stop);
        } else {
            time_add(st, h);
        }
    }
    // One test per component with constant indices (see try_step); NaN
    // fails `<=` where max() might drop it.
    let y = (*st).y;
    if (!(abs(y[0]) <= 3.0e38 && abs(y[1]) <= 3.0e38 && abs(y[2]) <= 3.0e38
        && abs(y[3]) <= 3.0e38 && abs(y[4]) <= 3.0e38 && abs(y[5]) <= 3.0e38)) {
        finish(st, S_NONFINITE);
    }
}

// Compensated (Kahan) sum of an accepted step's energy flow, before the
// state moves.
fn add_flow(st: ptr<function, State>, tr: Trial, h: f32) {
    let yy = step_flow((*st).k1, tr, h) - (*st).flow_c;
    let s = (*st).flow + yy;
    (*st).flow_c = (s - (*st).flow) - yy;
    (*st).flow = s;
}

fn step_to_event(l: Lane, st: ptr<function, State>, plan: StepPlan, theta: f32, which: u32, h_next: f32) {
    let h_ev = theta * plan.h;
    let ev = try_step(l, plan.mode, (*st).y, (*st).yc, (*st).k1, h_ev, g.tol);
    add_flow(st, ev, h_ev);
    time_add(st, h_ev);
    (*st).y = ev.y1;
    (*st).yc = ev.y1c;
    set_flag(st, F_K1_VALID, false);
    (*st).events += 1u;
    (*st).h = max(h_next, h_ev);
    if (which == EV_REST) {
        come_to_rest(l, st);
    } else if (which == EV_SWITCH) {
        set_side(st, -(*st).side);
        check_mode(l, st);
    } else if (which == EV_BRANCH) {
        set_flag(st, F_UPPER, !has(st, F_UPPER));
        check_mode(l, st);
    } else {
        set_flag(st, F_SPEEDING, true);
    }
    if (has(st, F_RUNNING_ON) && (which == EV_REST || which == EV_SPEEDING)) { set_flag(st, F_DONE, true); }
    if ((*st).events > g.max_events) { finish(st, S_MAX_EVENTS); }
}

// One step attempt (accepted or rejected). The Rust `advance` loops over
// it; here `main` does, refilling slots between attempts.
fn attempt(l: Lane, st: ptr<function, State>) {
    let plan = prepare(l, st);
    if (plan.ok) {
        let tr = try_step(l, plan.mode, (*st).y, (*st).yc, (*st).k1, plan.h, g.tol);
        finish_step(l, st, plan, tr);
    }
}

// ==== src/integrator/batch.rs ====

// Keep in sync with `GpuGlobals` in src/backend/gpu/layout.rs.
struct Globals {
    n_lanes: u32, budget: u32, max_steps: u32, max_events: u32,
    tol: f32, h_initial: f32, n_tables: u32, row_lanes: u32,
    n_slots: u32, pad0: u32, pad1: u32, pad2: u32,
    // Points per table; table t's point i is at [t * TABLE_VEC4S + i / 4][i % 4].
    table_n: array<vec4<u32>, 2>,
    table_vs: array<vec4<f32>, 64>,
    table_mu: array<vec4<f32>, 64>,
}

// Vec4s per table: keep in sync with src/backend/gpu/layout.rs.
const TABLE_VEC4S: u32 = 8u;

// Keep in sync with `GpuControl` in src/backend/gpu/layout.rs.
struct Control {
    // Slots that still hold an unfinished lane after this dispatch.
    n_active: atomic<u32>,
    // The next lane no slot has taken yet.
    next_lane: atomic<u32>,
}

@group(0) @binding(0) var<uniform> g: Globals;
@group(0) @binding(1) var<storage, read> lanes: array<Lane>;
@group(0) @binding(2) var<storage, read_write> states: array<State>;
@group(0) @binding(3) var<storage, read_write> ctl: Control;
@group(0) @binding(4) var<storage, read_write> slot_lane: array<u32>;

// One slot per invocation, each working through lanes: its lane's state
// stays in `states` between dispatches of at most `g.budget` step
// attempts, and when the lane finishes the slot takes the next lane not
// yet started, so an invocation stays busy until the chunk runs out of
// lanes rather than idling after its own lane ends. Each lane's result
// is in its own slot of `states`, whichever invocation ran it. The
// refill sits inside the one loop of attempts, so the invocations of a
// SIMD group keep stepping together; a second loop for the new lane would
// run it alone, the others masked.
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let slot = gid.x + gid.y * g.row_lanes;
    if (slot >= g.n_slots) { return; }
    var idx = slot_lane[slot];
    if (idx >= g.n_lanes) { return; }
    var st = states[idx];
    let l = lanes[idx];
    if ((st.flags & F_STARTED) == 0u) { init(l, &st); }
    var left = g.budget;
    loop {
        if (((st.flags & F_DONE) != 0u) || left == 0u) { break; }
        left -= 1u;
        attempt(l, &st);
    }
    states[idx] = st;
    if ((st.flags & F_DONE) != 0u) {
        idx = atomicAdd(&ctl.next_lane, 1u);
    }
    slot_lane[slot] = min(idx, g.n_lanes);
    if (idx < g.n_lanes) { atomicAdd(&ctl.n_active, 1u); }
}
