// Mirrors src/integrator/events.rs: the events inside a step and their roots.

// Root finding ends when the bracket is ROOT_THETA_TOL narrow (the
// prelude, from src/backend/gpu/shader.rs), a fraction of the step (the
// f64 path locates roots to `T_ROOT_TOL` = 1e-13 s).

fn dense_v(r: array<real, 5>, th: real) -> real {
    let th1 = 1.0 - th;
    return r[0] + th * (r[1] + th1 * (r[2] + th * (r[3] + th1 * r[4])));
}

// Event functions (EV_*): generated into the prelude from `EventFn` in
// src/integrator/events.rs.

fn event_value(l: Lane, m: Mode, which: u32, v: real) -> real {
    if (which == EV_SWITCH) {
        // No load: phi = F1/m1 changes sign only at synchronous speed, a
        // fixed point of the motion, never crossed (`switch_value`).
        if (load_term(l.f2, l.m2, l.tan_g) == 0.0) { return 1.0; }
        return real(m.side) * phi(l, v, m.motor_on);
    }
    if (which == EV_REST) { return real(m.dir) * v; }
    if (which == EV_BRANCH) {
        return branch_value(real(m.dir), v, l.inv_cos_g, branch_edges(l, m.branch));
    }
    // The speeding event: -s x1'' D, the sign of -s x1'' without its pole
    // where a jamming wedge takes D through 0 (`speeding_value`).
    let mo = motion(l, m, v);
    return -real(m.dir) * mo.acc * mo.d;
}

// The branch event's function: the sliding speed's distance from the
// nearer of the edges e (x: lo, y: hi).
fn branch_value(dir: real, v: real, inv_cos_g: real, e: vec2<real>) -> real {
    let vs = sliding_speed(dir, v, inv_cos_g);
    return min(vs - e.x, e.y - vs);
}

// Whether a lane that left its branch (edges e) at speed v left it
// upwards: the nearer edge is the one crossed.
fn left_upwards(dir: real, v: real, inv_cos_g: real, e: vec2<real>) -> bool {
    let vs = sliding_speed(dir, v, inv_cos_g);
    return e.y - vs <= vs - e.x;
}

// `crossed_edge`: the edge of the mode's branch a step ending at speed
// v_end crossed, the other one "never".
fn crossed_edge(l: Lane, m: Mode, v_end: real) -> vec2<real> {
    let e = branch_edges(l, m.branch);
    if (e.y - sliding_speed(real(m.dir), v_end, l.inv_cos_g) < 0.0) {
        return vec2<real>(-3.0e38, e.y);
    }
    return vec2<real>(e.x, 3.0e38);
}

// The event function `locate_root` seeks a root of: a branch event's on
// the edge crossed alone (see `crossed_edge` in src/integrator/events.rs).
fn root_value(l: Lane, m: Mode, which: u32, edge: vec2<real>, v: real) -> real {
    if (which == EV_BRANCH) { return branch_value(real(m.dir), v, l.inv_cos_g, edge); }
    return event_value(l, m, which, v);
}

fn locate_root(l: Lane, m: Mode, which: u32, r: array<real, 5>, g_end: real) -> real {
    // A branch event's edge, found once for the whole search.
    var edge = vec2<real>(-3.0e38, 3.0e38);
    if (which == EV_BRANCH) { edge = crossed_edge(l, m, dense_v(r, 1.0)); }
    var a: real = 0.0;
    var fa = root_value(l, m, which, edge, r[0]);
    var b: real = 1.0;
    var fb = g_end;
    if (fa <= 0.0) { return 0.0; }
    var side = 0;
    for (var it = 0; it < 100; it++) {
        if (b - a <= ROOT_THETA_TOL) { break; }
        var c = (a * fb - b * fa) / (fb - fa);
        if (!(c > a && c < b)) { c = 0.5 * (a + b); }
        let fc = root_value(l, m, which, edge, dense_v(r, c));
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
fn earliest_event(l: Lane, m: Mode, tr: Trial, running_on: bool) -> vec2<real> {
    let g_rest = event_value(l, m, EV_REST, tr.y1[1]);
    let g_switch = event_value(l, m, EV_SWITCH, tr.y1[1]);
    var theta: real = 2.0;
    var which = EV_REST;
    if (g_rest < 0.0) { theta = locate_root(l, m, EV_REST, tr.dense, g_rest); }
    if (g_switch < 0.0) {
        let th = locate_root(l, m, EV_SWITCH, tr.dense, g_switch);
        if (th < theta) { theta = th; which = EV_SWITCH; }
    }
    let g_speeding = -real(m.dir) * tr.k7[1] * tr.d_end;
    if (running_on && g_speeding < 0.0) {
        let th = locate_root(l, m, EV_SPEEDING, tr.dense, g_speeding);
        if (th < theta) { theta = th; which = EV_SPEEDING; }
    }
    let e = branch_edges(l, m.branch);
    if (e.x > -1.0e38 || e.y < 1.0e38) {
        let g_branch = branch_value(real(m.dir), tr.y1[1], l.inv_cos_g, e);
        if (g_branch < 0.0) {
            let th = locate_root(l, m, EV_BRANCH, tr.dense, g_branch);
            if (th < theta) { theta = th; which = EV_BRANCH; }
        }
    }
    return vec2<real>(theta, real(which));
}
