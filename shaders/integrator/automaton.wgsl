// Mirrors src/integrator/automaton.rs: a lane's state and the switching
// automaton's moves between contact modes.

// Keep in sync with `GpuState` in src/backend/gpu/layout.rs. 32 reals
// and 16 words: a whole number of the struct's alignment in f32 (16
// bytes) and in f64 (32, a vec4<f64>'s), so neither has hidden padding.
struct State {
    t_hi: real, t_lo: real, h: real, t_first_switch: real,
    flow: vec4<real>,    // w1_in, w1_out, w2_in, w2_out
    flow_c: vec4<real>,  // their Kahan compensations
    y: array<real, NY>,
    yc: array<real, NY>,
    k1: array<real, NY>,
    // The error budget (src/integrator/accuracy.rs), kept in f64 only
    // (KEEP_BUDGET).
    lag: real,
    phase: array<real, RESULTS>,
    local: array<real, RESULTS>,
    pad_r: array<real, 3>,
    side: i32, dir: i32, flags: u32, status: u32,
    switches: u32, reversals: u32, sticks: u32, steps: u32,
    events: u32, branch: u32, pad: array<u32, 6>,
}

// Flag bits of State.flags (F_*): generated into the prelude from `flags` in
// src/backend/gpu/layout.rs.

const NO_FIRST_SWITCH: real = -1.0;

fn has(st: ptr<function, State>, f: u32) -> bool { return ((*st).flags & f) != 0u; }
fn set_flag(st: ptr<function, State>, f: u32, on: bool) {
    if (on) { (*st).flags |= f; } else { (*st).flags &= ~f; }
}

fn time_of(st: ptr<function, State>) -> real { return (*st).t_hi - (*st).t_lo; }

fn time_add(st: ptr<function, State>, h: real) {
    let y = h - (*st).t_lo;
    let t = (*st).t_hi + y;
    (*st).t_lo = (t - (*st).t_hi) - y;
    (*st).t_hi = t;
}

fn time_set(st: ptr<function, State>, t: real) {
    (*st).t_hi = t;
    (*st).t_lo = 0.0;
}

fn mode_of(st: ptr<function, State>) -> Mode {
    return Mode((*st).side, (*st).dir, has(st, F_MOTOR_ON), (*st).branch);
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
    (*st).y = array<real, NY>(l.x1_0, v, 0.0, 0.0, 0.0, 0.0);
    (*st).yc = array<real, NY>();
    (*st).flow = vec4<real>();
    (*st).flow_c = vec4<real>();
    (*st).h = min(g.h_initial, l.t_end);
    (*st).side = side_of(phi(l, v, motor_on));
    (*st).dir = select(select(0, -1, v < 0.0), 1, v > 0.0);
    (*st).flags = F_STARTED;
    set_flag(st, F_MOTOR_ON, motor_on);
    (*st).branch = branch_of(l, sliding_speed(1.0, abs(v), l.inv_cos_g));
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
    // The branch a sliding speed rising from rest enters.
    (*st).branch = branch_of(l, 0.0);
    let s = stick_test(l, has(st, F_MOTOR_ON));
    if (s.x > 0.5) {
        set_flag(st, F_STUCK, true);
        (*st).sticks += 1u;
        set_flag(st, F_K1_VALID, false);
        return;
    }
    depart(l, st, s.y);
}

fn depart(l: Lane, st: ptr<function, State>, tf: real) {
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

fn horizon(l: Lane, st: ptr<function, State>) -> real {
    return select(l.t_end, l.t_max, has(st, F_RUNNING_ON));
}

fn reach_time_event(l: Lane, st: ptr<function, State>, t_stop: real) {
    time_set(st, t_stop);
    if (t_stop < horizon(l, st)) {
        cut_motor(l, st);
    } else if (!has(st, F_RUNNING_ON) && l.t_max > l.t_end && l.motor_off < l.t_end
        && !has(st, F_STUCK) && has(st, F_K1_VALID) && real((*st).dir) * (*st).k1[1] < 0.0) {
        set_flag(st, F_RUNNING_ON, true);
    } else {
        set_flag(st, F_DONE, true);
    }
}
