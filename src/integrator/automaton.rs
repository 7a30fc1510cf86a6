//! The lane automaton: a lane's state between steps and the transitions of
//! docs/model.md sections 3 to 5 (switches, rest, sticking, departure, motor
//! cut-off, running on past t_end, the friction law's change of branch); `step` takes it through one trial step
//! of the stepper.
//!
//! A lane is a fixed-size [`LaneState`] that [`advance`](super::step::advance) moves forward by
//! at most a given number of step attempts, so the same code runs a lane
//! to its end in one call (CPU) or in slices (the shader keeps the state
//! between dispatches). No allocation, no recursion.

use super::accuracy::ErrorBudget;
use super::components::NY;
use super::control::H_INITIAL;
use super::result::{speeding_up, EndState, Status};
use super::rhs::rhs;
use crate::model::kernel::sliding_speed;
use crate::model::{branch_of, phi, side_of, stick_test, FrictionTable, Lane, Mode};

crate::lanewise_struct! {
    /// The complete state of one lane between calls to
    /// [`advance`](super::step::advance); [`LaneStates`] holds the states
    /// of the lanes one thread steps in lockstep.
    #[derive(Clone, Copy, Debug)]
    pub struct LaneState, LaneStates {
        /// Time, s.
        pub t: f64,
        /// The integrated state (`components`).
        pub y: [f64; NY],
        /// Proposed size of the next step.
        pub h: f64,
        /// Contact side c: +1 a-a, −1 b-b (kept through stick phases).
        pub side: i32,
        /// Direction of motion s: +1, −1, or 0 before the first motion.
        pub dir: i32,
        /// At rest, held by static friction.
        pub stuck: bool,
        /// The motor's force is on.
        pub motor_on: bool,
        /// The friction law's branch the lane slides on (`Mode::branch`).
        pub branch: u32,
        /// Finished, or abandoned with `status`.
        pub done: bool,
        /// Running on past t_end towards t_max: the motor is cut and the lane
        /// was still coasting at t_end (docs/model.md section 10).
        pub running_on: bool,
        /// Running on ended because the lane began to speed up.
        pub speeding: bool,
        /// Why the lane ended.
        pub status: Status,
        /// Contact side changes so far.
        pub switches: u32,
        /// Direction changes so far.
        pub reversals: u32,
        /// Stick phases so far.
        pub sticks: u32,
        /// NaN until the first switch.
        pub t_first_switch: f64,
        /// Accepted steps so far.
        pub steps: u32,
        /// Events so far (switches, stops, cut-offs, branch changes).
        pub events: u32,
        /// Derivative at (t, y), valid when `k1_valid` (first same as last).
        pub k1: [f64; NY],
        /// Whether `k1` is the derivative at the current state.
        pub k1_valid: bool,
        /// w1_in, w1_out, w2_in, w2_out so far (see `flow`).
        pub flow: [f64; 4],
        /// The estimate of the results' error so far (see `accuracy`).
        pub budget: ErrorBudget,
    }
}

impl LaneState {
    /// The mode the next step is taken in.
    pub fn mode(&self) -> Mode {
        Mode {
            side: self.side,
            dir: self.dir,
            motor_on: self.motor_on,
            branch: self.branch,
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

    pub(super) fn finish(&mut self, status: Status) {
        self.status = status;
        self.done = true;
    }
}

/// Starts a lane at t = 0.
pub fn init(lane: &Lane, tables: &[FrictionTable]) -> LaneState {
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
        branch: branch_of(lane, tables, sliding_speed(1.0, v.abs(), lane.inv_cos_g)),
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
        come_to_rest(lane, tables, &mut st);
    } else {
        check_mode(lane, tables, &mut st);
    }
    st
}

/// Sets the contact side, counting a switch when it changes.
pub(crate) fn set_side(st: &mut LaneState, side: i32) {
    if side != st.side {
        st.switches += 1;
        if st.t_first_switch.is_nan() {
            st.t_first_switch = st.t;
        }
        st.side = side;
    }
}

/// Ends the lane as inconsistent when the current mode has D <= 0.
pub(crate) fn check_mode(lane: &Lane, tables: &[FrictionTable], st: &mut LaneState) {
    if st.stuck || st.done {
        return;
    }
    let (k, d) = rhs(lane, tables, st.mode(), st.y[1]);
    if !(d > 0.0) {
        st.finish(Status::Inconsistent);
    }
    st.k1 = k;
    st.k1_valid = true;
}

/// ẋ1 is 0 (at start, or at a rest event): stick, or leave in the
/// direction of the tangential force.
pub(crate) fn come_to_rest(lane: &Lane, tables: &[FrictionTable], st: &mut LaneState) {
    st.y[1] = 0.0;
    // The branch a sliding speed rising from rest enters.
    st.branch = branch_of(lane, tables, 0.0);
    let (stick, tf) = stick_test(lane, st.motor_on);
    if stick {
        st.stuck = true;
        st.sticks += 1;
        st.k1_valid = false;
        return;
    }
    depart(lane, tables, st, tf);
}

/// Leaves rest in direction sign(T) on the side of φ.
pub(crate) fn depart(lane: &Lane, tables: &[FrictionTable], st: &mut LaneState, tf: f64) {
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
    check_mode(lane, tables, st);
}

/// The motor is cut at the current time.
pub(crate) fn cut_motor(lane: &Lane, tables: &[FrictionTable], st: &mut LaneState) {
    st.motor_on = false;
    st.events += 1;
    st.k1_valid = false;
    if st.stuck {
        let (stick, tf) = stick_test(lane, false);
        if !stick {
            depart(lane, tables, st, tf);
        }
    } else {
        set_side(st, side_of(phi(lane, st.y[1], false)));
        check_mode(lane, tables, st);
    }
}

/// The end of the lane's run: t_end, or t_max once it runs on.
#[inline]
pub(crate) fn horizon(lane: &Lane, st: &LaneState) -> f64 {
    if st.running_on {
        lane.t_max
    } else {
        lane.t_end
    }
}

/// The lane has reached a time event (`t_stop`): the end of the run, or
/// the motor's cut-off. At t_end a lane whose motor is cut and that is
/// still coasting (sliding, slowing down) runs on towards t_max, when one
/// is set, to find out whether it holds (docs/model.md section 10).
pub(crate) fn reach_time_event(
    lane: &Lane,
    tables: &[FrictionTable],
    st: &mut LaneState,
    t_stop: f64,
) {
    st.t = t_stop;
    if t_stop < horizon(lane, st) {
        cut_motor(lane, tables, st);
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
