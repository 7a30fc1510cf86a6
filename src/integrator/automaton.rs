//! The lane automaton: a lane's state between steps and the transitions of
//! MODEL.md sections 3 and 4 (switches, rest, sticking, departure, motor
//! cut-off), around one trial step of the stepper.
//!
//! A lane is a fixed-size [`LaneState`] that [`advance`] moves forward by
//! at most a given number of step attempts, so the same code runs a lane
//! to its end in one call (CPU) or in slices (the shader keeps the state
//! between dispatches). No allocation, no recursion.

use super::accuracy::ErrorBudget;
use super::events::{earliest_event, EventFn};
use super::flow::step_flow;
use super::result::{speeding_up, EndState, Status};
use super::stepper::{rhs, try_step, Mode, Trial};
use super::{Settings, NY};
use crate::model::{phi, side_of, stick_test, FrictionTable, Lane, FRICTION_PAPER};

/// First step after every start from rest, s: the friction law's
/// derivative is unbounded at rest and the error estimate reads low there.
pub const H_INITIAL: f64 = 1e-6;

/// The complete state of one lane between calls to [`advance`].
#[derive(Clone, Copy, Debug)]
pub struct LaneState {
    pub t: f64,
    pub y: [f64; NY],
    /// Proposed size of the next step.
    pub h: f64,
    /// Contact side c: +1 a-a, −1 b-b (kept through stick phases).
    pub side: i32,
    /// Direction of motion s: +1, −1, or 0 before the first motion.
    pub dir: i32,
    pub stuck: bool,
    pub motor_on: bool,
    pub done: bool,
    /// Running on past t_end towards t_max: the motor is cut and the lane
    /// was still coasting at t_end (MODEL.md section 10).
    pub running_on: bool,
    /// Running on ended because the lane began to speed up.
    pub speeding: bool,
    pub status: Status,
    pub switches: u32,
    pub reversals: u32,
    pub sticks: u32,
    /// NaN until the first switch.
    pub t_first_switch: f64,
    pub steps: u32,
    pub events: u32,
    /// Derivative at (t, y), valid when `k1_valid` (first same as last).
    pub k1: [f64; NY],
    pub k1_valid: bool,
    /// w1_in, w1_out, w2_in, w2_out so far (see `flow`).
    pub flow: [f64; 4],
    /// The estimate of the results' error so far (see `accuracy`).
    pub budget: ErrorBudget,
}

impl LaneState {
    /// The mode the next step is taken in.
    fn mode(&self) -> Mode {
        Mode {
            side: self.side,
            dir: self.dir,
            motor_on: self.motor_on,
        }
    }

    /// Where the lane stopped, for its results.
    pub fn end_state(&self) -> EndState {
        EndState {
            status: self.status,
            stuck: self.stuck,
            side: self.side,
            dir: self.dir,
            motor_on: self.motor_on,
            y: self.y,
            flow: self.flow,
            switches: self.switches,
            reversals: self.reversals,
            sticks: self.sticks,
            t_first_switch: self.t_first_switch,
            steps: self.steps,
            t: self.t,
            speeding: self.speeding,
        }
    }

    fn finish(&mut self, status: Status) {
        self.status = status;
        self.done = true;
    }
}

/// Starts a lane at t = 0.
pub fn init(lane: &Lane, table: Option<&FrictionTable>) -> LaneState {
    let motor_on = !(lane.motor_off <= 0.0);
    let v = lane.v1_0;
    let mut st = LaneState {
        t: 0.0,
        y: [lane.x1_0, v, 0.0, 0.0, 0.0, 0.0],
        h: H_INITIAL.min(lane.t_end),
        side: side_of(phi(lane, v, motor_on)),
        dir: if v > 0.0 {
            1
        } else if v < 0.0 {
            -1
        } else {
            0
        },
        stuck: false,
        motor_on,
        done: false,
        running_on: false,
        speeding: false,
        status: Status::Ok,
        switches: 0,
        reversals: 0,
        sticks: 0,
        t_first_switch: f64::NAN,
        steps: 0,
        events: 0,
        k1: [0.0; NY],
        k1_valid: false,
        flow: [0.0; 4],
        budget: ErrorBudget::default(),
    };
    if v == 0.0 {
        come_to_rest(lane, table, &mut st);
    } else {
        check_mode(lane, table, &mut st);
    }
    st
}

/// Sets the contact side, counting a switch when it changes.
fn set_side(st: &mut LaneState, side: i32) {
    if side != st.side {
        st.switches += 1;
        if st.t_first_switch.is_nan() {
            st.t_first_switch = st.t;
        }
        st.side = side;
    }
}

/// Ends the lane as inconsistent when the current mode has D <= 0.
fn check_mode(lane: &Lane, table: Option<&FrictionTable>, st: &mut LaneState) {
    if st.stuck || st.done {
        return;
    }
    let (k, d) = rhs(lane, table, st.mode(), st.y[1]);
    if !(d > 0.0) {
        st.finish(Status::Inconsistent);
    }
    st.k1 = k;
    st.k1_valid = true;
}

/// ẋ1 is 0 (at start, or at a rest event): stick, or leave in the
/// direction of the tangential force.
fn come_to_rest(lane: &Lane, table: Option<&FrictionTable>, st: &mut LaneState) {
    st.y[1] = 0.0;
    let (stick, tf) = stick_test(lane, st.motor_on);
    if stick {
        st.stuck = true;
        st.sticks += 1;
        st.k1_valid = false;
        return;
    }
    depart(lane, table, st, tf);
}

/// Leaves rest in direction sign(T) on the side of φ.
fn depart(lane: &Lane, table: Option<&FrictionTable>, st: &mut LaneState, tf: f64) {
    let dir = if tf > 0.0 { 1 } else { -1 };
    if st.dir != 0 && dir != st.dir {
        st.reversals += 1;
    }
    st.dir = dir;
    st.stuck = false;
    // Leaving rest the friction law's derivative is unbounded and the
    // embedded error estimate reads low: start with a small step.
    st.h = H_INITIAL;
    set_side(st, side_of(phi(lane, 0.0, st.motor_on)));
    check_mode(lane, table, st);
}

/// The motor is cut at the current time.
fn cut_motor(lane: &Lane, table: Option<&FrictionTable>, st: &mut LaneState) {
    st.motor_on = false;
    st.events += 1;
    st.k1_valid = false;
    if st.stuck {
        let (stick, tf) = stick_test(lane, false);
        if !stick {
            depart(lane, table, st, tf);
        }
    } else {
        set_side(st, side_of(phi(lane, st.y[1], false)));
        check_mode(lane, table, st);
    }
}

/// The end of the lane's run: t_end, or t_max once it runs on.
#[inline]
fn horizon(lane: &Lane, st: &LaneState) -> f64 {
    if st.running_on {
        lane.t_max
    } else {
        lane.t_end
    }
}

/// The lane has reached a time event (`t_stop`): the end of the run, or
/// the motor's cut-off. At t_end a lane whose motor is cut and that is
/// still coasting (sliding, slowing down) runs on towards t_max, when one
/// is set, to find out whether it holds (MODEL.md section 10).
fn reach_time_event(lane: &Lane, table: Option<&FrictionTable>, st: &mut LaneState, t_stop: f64) {
    st.t = t_stop;
    if t_stop < horizon(lane, st) {
        cut_motor(lane, table, st);
    } else if !st.running_on
        && lane.t_max > lane.t_end
        && lane.motor_cut()
        && !st.stuck
        && st.k1_valid
        && !speeding_up(st.dir, st.k1[1])
    {
        st.running_on = true;
    } else {
        st.done = true;
    }
}

/// A step about to be tried: its mode, its size, and the time event it
/// may land on.
#[derive(Clone, Copy, Debug)]
pub struct StepPlan {
    pub(crate) mode: Mode,
    pub(crate) h: f64,
    t_stop: f64,
    landing: bool,
}

impl StepPlan {
    /// A plan for a slot with nothing to step (never tried).
    pub(crate) const IDLE: StepPlan = StepPlan {
        mode: Mode {
            side: 1,
            dir: 1,
            motor_on: false,
        },
        h: 0.0,
        t_stop: 0.0,
        landing: false,
    };
}

/// First half of one step attempt: a stick phase jumps to the next time
/// event, the derivative at the step's start is made valid, and the step
/// size is chosen. None when the attempt ends here (stuck, or finished).
pub fn prepare(lane: &Lane, table: Option<&FrictionTable>, st: &mut LaneState) -> Option<StepPlan> {
    // The next time event: motor cut-off, else the end of the run.
    let end = horizon(lane, st);
    let t_stop = if st.motor_on && lane.motor_off < end {
        lane.motor_off
    } else {
        end
    };
    if st.stuck {
        // While stuck every force is constant in time (F1 at ẋ1 = 0, F2),
        // so the stick condition can only fail at a time event.
        reach_time_event(lane, table, st, t_stop);
        return None;
    }
    let mode = st.mode();
    if !st.k1_valid {
        let (k, d) = rhs(lane, table, mode, st.y[1]);
        if !(d > 0.0) {
            st.finish(Status::Inconsistent);
            return None;
        }
        st.k1 = k;
        st.k1_valid = true;
    }
    let mut h = st.h;
    // Approaching rest under the paper law, ρ(Vs) has an unbounded
    // derivative at the stop, as it has at a start, and the error estimate
    // reads low there: grade the steps into the stop.
    if lane.friction == FRICTION_PAPER && st.k1[1] * (st.dir as f64) < 0.0 {
        let t_rest = -st.y[1] / st.k1[1];
        h = h.min((0.5 * t_rest).max(H_INITIAL));
    }
    let remaining = t_stop - st.t;
    let landing = h >= remaining;
    if landing {
        h = remaining;
    }
    Some(StepPlan {
        mode,
        h,
        t_stop,
        landing,
    })
}

/// Step-size factor from a trial's error norm.
fn step_factor(err: f64) -> f64 {
    if err == 0.0 {
        5.0
    } else {
        (0.9 * err.powf(-0.2)).clamp(0.2, 5.0)
    }
}

/// Second half of a step attempt: accept or reject the trial step, locate
/// the earliest event inside it and restart from there in the new mode, or
/// move to the step's end.
pub fn finish_step(
    lane: &Lane,
    table: Option<&FrictionTable>,
    set: &Settings,
    st: &mut LaneState,
    plan: &StepPlan,
    trial: &Trial,
) {
    let h = plan.h;
    let fac = step_factor(trial.err);
    if trial.err > 1.0 {
        st.h = h * fac.min(1.0);
        if st.h < 1e-15 * st.t.max(1.0) {
            st.finish(Status::StepUnderflow);
        }
        return;
    }
    let h_next = h * fac;
    st.steps += 1;
    if st.steps > set.max_steps {
        st.finish(Status::MaxSteps);
        return;
    }
    match earliest_event(lane, table, plan.mode, trial, h, st.running_on) {
        Some((theta, which)) => step_to_event(lane, table, set, st, plan, theta, which, h_next),
        None => {
            add_flow(st, trial, h);
            st.y = trial.y1;
            st.k1 = trial.k7;
            st.h = h_next;
            if plan.landing {
                reach_time_event(lane, table, st, plan.t_stop);
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
fn add_flow(st: &mut LaneState, trial: &Trial, h: f64) {
    let d = step_flow(&st.k1, trial, h);
    st.budget.add_step(&st.k1, trial, &d);
    for (f, d) in st.flow.iter_mut().zip(d) {
        *f += d;
    }
}

/// Steps again, exactly to an event at fraction θ of the step, for a
/// full-order state there, and enters the new mode.
#[allow(clippy::too_many_arguments)]
fn step_to_event(
    lane: &Lane,
    table: Option<&FrictionTable>,
    set: &Settings,
    st: &mut LaneState,
    plan: &StepPlan,
    theta: f64,
    which: EventFn,
    h_next: f64,
) {
    let h_ev = theta * plan.h;
    let ev = try_step(lane, table, plan.mode, &st.y, &st.k1, h_ev, set);
    add_flow(st, &ev, h_ev);
    st.t += h_ev;
    st.y = ev.y1;
    st.k1_valid = false;
    st.events += 1;
    st.h = h_next.max(h_ev);
    match which {
        EventFn::Rest => come_to_rest(lane, table, st),
        EventFn::Switch => {
            set_side(st, -st.side);
            check_mode(lane, table, st);
        }
        EventFn::Speeding => st.speeding = true,
    }
    // Running on ends where the question is answered: at rest the lane
    // holds, or it departs and runs away; or it began to speed up.
    if st.running_on && (which != EventFn::Switch) {
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
    table: Option<&FrictionTable>,
    set: &Settings,
    st: &mut LaneState,
    budget: u32,
) -> bool {
    let mut left = budget;
    while !st.done && left > 0 {
        left -= 1;
        attempt(lane, table, set, st);
    }
    st.done
}

/// One step attempt (accepted or rejected). The shader's entry point loops
/// over it as [`advance`] does, taking a new lane when one finishes.
pub fn attempt(lane: &Lane, table: Option<&FrictionTable>, set: &Settings, st: &mut LaneState) {
    if let Some(plan) = prepare(lane, table, st) {
        let trial = try_step(lane, table, plan.mode, &st.y, &st.k1, plan.h, set);
        finish_step(lane, table, set, st, &plan, &trial);
    }
}
