//! One step attempt of a lane: its plan (mode, size, the time event it
//! may land on), the trial step's verdict (`verdict`, shared with the
//! lanes in lockstep), and for the attempts that are not common the
//! automaton's part: the earliest event inside the step and the restart
//! from there in the new mode, a landing on a time event, the step
//! budget. [`advance`] runs attempts until the lane is done or its
//! budget is spent.

use super::automaton::{check_mode, come_to_rest, horizon, reach_time_event, set_side, LaneState};
use super::components::NY;
use super::control::{step_size, JAM_D};
use super::events::{earliest_event, left_upwards, EventFn, Watch};
use super::flow::step_flow;
use super::result::Status;
use super::rhs::rhs;
use super::settings::Settings;
use super::stepper::{try_step, Trial};
use super::verdict::{end_common, verdicts};
use crate::lanewise::Lanewise;
use crate::model::{branch_edges, FrictionTable, Lane, Mode};

/// A step about to be tried: its mode, its size, and the time event it
/// may land on.
#[derive(Clone, Copy, Debug)]
pub struct StepPlan {
    pub(crate) mode: Mode,
    pub(crate) h: f64,
    pub(crate) t_stop: f64,
    pub(crate) landing: bool,
}

impl StepPlan {
    /// A plan for a slot with nothing to step (never tried).
    pub(crate) const IDLE: StepPlan = StepPlan {
        mode: Mode {
            side: 1,
            dir: 1,
            motor_on: false,
            branch: 0,
        },
        h: 0.0,
        t_stop: 0.0,
        landing: false,
    };

    /// A step in `mode` of size `h` towards the time event `t_stop`,
    /// `landing` on it.
    pub(crate) fn new(mode: Mode, h: f64, t_stop: f64, landing: bool) -> StepPlan {
        StepPlan {
            mode,
            h,
            t_stop,
            landing,
        }
    }

    /// Whether the step ends on its time event.
    pub(crate) fn landing(&self) -> bool {
        self.landing
    }
}

/// The lane's next time event: its motor's cut-off, else the end of its
/// run.
#[inline]
pub(crate) fn time_stop(lane: &Lane, st: &LaneState) -> f64 {
    let end = horizon(lane, st);
    if st.motor_on && lane.motor_off < end {
        lane.motor_off
    } else {
        end
    }
}

/// First half of one step attempt: a stick phase jumps to the next time
/// event, the derivative at the step's start is made valid, and the step
/// size is chosen. None when the attempt ends here (stuck, or finished).
#[inline]
pub(crate) fn prepare(
    lane: &Lane,
    tables: &[FrictionTable],
    st: &mut LaneState,
) -> Option<StepPlan> {
    let t_stop = time_stop(lane, st);
    if st.stuck {
        // While stuck every force is constant in time (F1 at ẋ1 = 0, F2),
        // so the stick condition can only fail at a time event.
        reach_time_event(lane, tables, st, t_stop);
        return None;
    }
    let mode = st.mode();
    if !st.k1_valid {
        let (k, d) = rhs(lane, tables, mode, st.y[1]);
        if !(d > 0.0) {
            st.finish(Status::Inconsistent);
            return None;
        }
        st.k1 = k;
        st.k1_valid = true;
    }
    let (h, landing) = step_size(
        st.h,
        lane.steep,
        st.dir as f64,
        st.y[1],
        st.k1[1],
        t_stop - st.t,
    );
    Some(StepPlan {
        mode,
        h,
        t_stop,
        landing,
    })
}

/// Second half of a step attempt: the verdict on the trial step
/// (`verdict::verdicts` of one lane); a common one ends as the lanes in
/// lockstep end theirs (`verdict::end_common`), the others here: a step
/// underflow, the step budget, the earliest event inside the step and the
/// restart from there in the new mode, or the move to the step's end
/// (landing on its time event, or sharing a mesh power's sign change).
#[inline]
pub fn finish_step(
    lane: &Lane,
    tables: &[FrictionTable],
    set: &Settings,
    st: &mut LaneState,
    plan: &StepPlan,
    trial: &Trial,
) {
    let h = plan.h;
    let watch = Watch::of(lane, tables, plan.mode, st.running_on).one();
    let one = |a: f64| [a];
    let v = verdicts::<1>(
        &[true],
        &[h],
        &[plan.landing],
        &[st.t],
        &[st.steps],
        &watch,
        &st.k1.map(one),
        &trial.one(),
        set,
    );
    if !v.slow[0] {
        let mut s = st.one();
        end_common(&mut s, &v, &[h], &trial.one());
        *st = s.lane(0);
        return;
    }
    finish_uncommon(lane, tables, set, st, plan, trial, v.h_next[0]);
}

/// Why a lane whose step cannot shrink any further stops, at speed `v`
/// in `mode`: where D has fallen to within [`JAM_D`] of m1 of 0 the
/// wedge jams (the mode is inconsistent: docs/model.md section 2), else
/// a step underflow.
fn underflow_status(lane: &Lane, tables: &[FrictionTable], mode: Mode, v: f64) -> Status {
    let (_, d) = rhs(lane, tables, mode, v);
    if d < JAM_D * lane.m1 {
        Status::Inconsistent
    } else {
        Status::StepUnderflow
    }
}

/// The automaton's end of an attempt that is not common (the verdict
/// said so, and proposed the next size `h_next`): a step underflow, the
/// step budget, the earliest event inside the step and the restart from
/// there in the new mode, or the move to the step's end (landing on its
/// time event, or sharing a mesh power's sign change). The lanes in
/// lockstep call it for the lanes their verdict found uncommon.
#[inline]
pub(crate) fn finish_uncommon(
    lane: &Lane,
    tables: &[FrictionTable],
    set: &Settings,
    st: &mut LaneState,
    plan: &StepPlan,
    trial: &Trial,
    h_next: f64,
) {
    let h = plan.h;
    if trial.err > 1.0 {
        // Rejected, and too small to try again.
        st.h = h_next;
        st.finish(underflow_status(lane, tables, plan.mode, st.y[1]));
        return;
    }
    st.steps += 1;
    if st.steps > set.max_steps {
        st.finish(Status::MaxSteps);
        return;
    }
    match earliest_event(lane, tables, plan.mode, trial, h, st.running_on) {
        Some((theta, which)) => step_to_event(lane, tables, set, st, plan, theta, which, h_next),
        // D has left (0, inf) inside the mode (through infinity where
        // γ + ρ passes 90°): the mode is inconsistent (docs/model.md
        // section 2).
        None if !(trial.d_end > 0.0) => {
            st.finish(Status::Inconsistent);
            return;
        }
        None => {
            add_flow(st, trial, h);
            st.y = trial.y1;
            st.k1 = trial.k7;
            st.h = h_next;
            if plan.landing {
                reach_time_event(lane, tables, st, plan.t_stop);
            } else {
                st.t += h;
            }
        }
    }
    if !st.y.iter().all(|v| v.is_finite()) {
        st.finish(Status::NonFinite);
    }
}

/// Adds an accepted step's energy flow (from `st`, before it moves).
#[inline]
pub(crate) fn add_flow(st: &mut LaneState, trial: &Trial, h: f64) {
    let (d, split_err) = step_flow(&st.k1, trial, h, st.side as f64, st.dir as f64);
    st.budget.add_step(&st.k1, trial, &d);
    st.budget.add_split(split_err);
    for (f, d) in st.flow.iter_mut().zip(d) {
        *f += d;
    }
}

/// Steps again, exactly to an event at fraction θ of the step, for a
/// full-order state there, and enters the new mode.
#[allow(clippy::too_many_arguments)]
pub(crate) fn step_to_event(
    lane: &Lane,
    tables: &[FrictionTable],
    set: &Settings,
    st: &mut LaneState,
    plan: &StepPlan,
    theta: f64,
    which: EventFn,
    h_next: f64,
) {
    let h_ev = theta * plan.h;
    let ev = trial(lane, tables, plan.mode, st, h_ev, set);
    // D has left (0, inf) before the event: the wedge jammed on the way
    // (D falls to 0 just short of rest where a friction angle that grows
    // as the lane slows meets a light worm side), and the mode is
    // inconsistent there (docs/model.md section 2), however the event
    // came first in the step's dense output. At rest, D at zero speed:
    // the located root is within its tolerance of it, and D is
    // continuous on the way.
    let jammed = which == EventFn::Rest && !(rhs(lane, tables, plan.mode, 0.0).1 > 0.0);
    if !(ev.d_end > 0.0) || jammed {
        st.finish(Status::Inconsistent);
        return;
    }
    add_flow(st, &ev, h_ev);
    st.t += h_ev;
    st.y = ev.y1;
    st.k1_valid = false;
    st.events += 1;
    st.h = h_next.max(h_ev);
    match which {
        EventFn::Rest => come_to_rest(lane, tables, st),
        EventFn::Switch => {
            set_side(st, -st.side);
            check_mode(lane, tables, st);
        }
        EventFn::Speeding => st.speeding = true,
        EventFn::Branch => {
            let (lo, hi) = branch_edges(lane, tables, st.branch);
            if left_upwards(st.dir as f64, st.y[1], lane.inv_cos_g, lo, hi) {
                st.branch += 1;
            } else {
                st.branch -= 1;
            }
            check_mode(lane, tables, st);
        }
    }
    // Running on ends where the question is answered: at rest the lane
    // holds, or it departs and runs away; or it began to speed up.
    if st.running_on && matches!(which, EventFn::Rest | EventFn::Speeding) {
        st.done = true;
    }
    if st.events > set.max_events {
        st.finish(Status::MaxEvents);
    }
}

/// Moves a lane forward by at most `budget` step attempts (accepted or
/// rejected); returns true when the lane is done.
pub fn advance(
    lane: &Lane,
    tables: &[FrictionTable],
    set: &Settings,
    st: &mut LaneState,
    budget: u32,
) -> bool {
    let mut left = budget;
    while !st.done && left > 0 {
        left -= 1;
        attempt(lane, tables, set, st);
    }
    st.done
}

/// One step attempt (accepted or rejected). The shader's entry point loops
/// over it as [`advance`] does, taking a new lane when one finishes.
pub fn attempt(lane: &Lane, tables: &[FrictionTable], set: &Settings, st: &mut LaneState) {
    if let Some(plan) = prepare(lane, tables, st) {
        let trial = trial(lane, tables, plan.mode, st, plan.h, set);
        finish_step(lane, tables, set, st, &plan, &trial);
    }
}

/// A trial step of size `h` from the lane's state, its error held within
/// the budget's caps (`Budgets::caps` of one lane) where the budget steers
/// (`Settings::steers`).
#[inline]
pub(crate) fn trial(
    lane: &Lane,
    tables: &[FrictionTable],
    mode: Mode,
    st: &LaneState,
    h: f64,
    set: &Settings,
) -> Trial {
    let cap = if set.steers() {
        lane_caps(lane, st, h, set)
    } else {
        [f64::INFINITY; NY]
    };
    try_step(lane, tables, mode, &st.y, &st.k1, h, &cap, set)
}

/// `Budgets::caps` of one lane in state `st`, for a step of size `h`
/// under `set`.
pub(crate) fn lane_caps(lane: &Lane, st: &LaneState, h: f64, set: &Settings) -> [f64; NY] {
    let col = |a: &[f64; NY]| a.map(|v| [v]);
    let mut cap = [[0.0]; NY];
    let (y, k1, flow) = (col(&st.y), col(&st.k1), st.flow.map(|v| [v]));
    let b = st.budget.one();
    b.caps(&y, &k1, &flow, &[st.t], &[lane.t_end], &[h], set, &mut cap);
    cap.map(|v| v[0])
}
