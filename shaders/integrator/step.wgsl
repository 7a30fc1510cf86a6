// Mirrors src/integrator/step.rs: one step attempt, prepared, tried and
// finished.

struct StepPlan { ok: bool, mode: Mode, h: real, t_stop: real, landing: bool }

// The lane's next time event: its motor's cut-off, else the end of its run.
fn time_stop(l: Lane, st: ptr<function, State>) -> real {
    let end = horizon(l, st);
    if (has(st, F_MOTOR_ON) && l.motor_off < end) { return l.motor_off; }
    return end;
}

fn prepare(l: Lane, st: ptr<function, State>) -> StepPlan {
    var plan: StepPlan;
    plan.ok = false;
    let t_stop = time_stop(l, st);
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
    let remaining = (t_stop - (*st).t_hi) + (*st).t_lo;
    let s = step_size((*st).h, l.steep != 0u, real((*st).dir), (*st).y[1], (*st).k1[1], remaining);
    return StepPlan(true, m, s.h, t_stop, s.landing);
}


// Why a lane whose step cannot shrink any further stops: where D has
// fallen to within JAM_D of m1 of 0 the wedge jams (inconsistent), else
// a step underflow.
fn underflow_status(l: Lane, m: Mode, v: real) -> u32 {
    if (rhs(l, m, v).d < JAM_D * l.m1) { return S_INCONSISTENT; }
    return S_STEP_UNDERFLOW;
}

fn finish_step(l: Lane, st: ptr<function, State>, plan: StepPlan, tr: Trial) {
    let h = plan.h;
    let fac = step_factor(tr.err);
    if (tr.err > 1.0) {
        let retry = retry_size(h, fac, time_of(st));
        (*st).h = retry.h;
        if (retry.underflow) { finish(st, underflow_status(l, plan.mode, (*st).y[1])); }
        return;
    }
    let h_next = h * fac;
    (*st).steps += 1u;
    if ((*st).steps > g.max_steps) { finish(st, S_MAX_STEPS); return; }
    let ev = earliest_event(l, plan.mode, tr, has(st, F_RUNNING_ON));
    if (ev.x <= 1.0) {
        step_to_event(l, st, plan, ev.x, u32(ev.y), h_next);
    } else if (!(tr.d_end > 0.0)) {
        // D has left (0, inf) inside the mode (through infinity where
        // gamma + rho passes 90 degrees): the mode is inconsistent.
        finish(st, S_INCONSISTENT);
        return;
    } else {
        add_flow(st, tr, h);
        set_flag(st, F_JUST_SWITCHED, false);
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
// state moves, and in f64 the step's share of the error budget.
fn add_flow(st: ptr<function, State>, tr: Trial, h: real) {
    let m = mode_of(st);
    if (flow_turns((*st).k1, tr, h, m)) { set_flag(st, F_FLOW_TURN, true); }
    let f = step_flow((*st).k1, tr, h, m);
    if (KEEP_BUDGET) {
        add_step(st, (*st).k1, tr, f.d);
        add_split(st, f.err);
    }
    let yy = f.d - (*st).flow_c;
    let s = (*st).flow + yy;
    (*st).flow_c = (s - (*st).flow) - yy;
    (*st).flow = s;
}

fn step_to_event(l: Lane, st: ptr<function, State>, plan: StepPlan, theta: real, which: u32, h_next: real) {
    let h_ev = theta * plan.h;
    let ev = try_step(l, plan.mode, (*st).y, (*st).yc, (*st).k1, h_ev, g.tol, g.tol_traj, caps(l, st, h_ev));
    // D has left (0, inf) before the event: the wedge jammed on the way;
    // at rest, D at zero speed (`step_to_event` in src/integrator/step.rs).
    let jammed = which == EV_REST && !(rhs(l, plan.mode, 0.0).d > 0.0);
    if (!(ev.d_end > 0.0) || jammed) {
        finish(st, S_INCONSISTENT);
        return;
    }
    add_flow(st, ev, h_ev);
    time_add(st, h_ev);
    (*st).y = ev.y1;
    (*st).yc = ev.y1c;
    set_flag(st, F_K1_VALID, false);
    (*st).events += 1u;
    (*st).h = max(h_next, h_ev);
    // A switch that ends a mode a switch began, before a step of it was
    // accepted: the switching function grazed zero (touched it and
    // turned back), where f32's rounding of it decides whether the lane
    // stays in the mode at all, and the mode's share of the energy flow.
    if (which == EV_SWITCH && has(st, F_JUST_SWITCHED)) { set_flag(st, F_GRAZE, true); }
    set_flag(st, F_JUST_SWITCHED, which == EV_SWITCH);
    if (which == EV_REST) {
        come_to_rest(l, st);
    } else if (which == EV_SWITCH) {
        set_side(st, -(*st).side);
        check_mode(l, st);
    } else if (which == EV_BRANCH) {
        let e = branch_edges(l, (*st).branch);
        if (left_upwards(real((*st).dir), (*st).y[1], l.inv_cos_g, e)) {
            (*st).branch += 1u;
        } else {
            (*st).branch -= 1u;
        }
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
        let tr = try_step(l, plan.mode, (*st).y, (*st).yc, (*st).k1, plan.h, g.tol, g.tol_traj, caps(l, st, plan.h));
        finish_step(l, st, plan, tr);
    }
}
