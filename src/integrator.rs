//! The hybrid integrator: Dormand–Prince 5(4) with its 4th-order dense
//! output, events located by root finding inside the step, and the lane
//! automaton (contact side, direction, rest and sticking, motor cut-off).
//!
//! A lane is a fixed-size [`LaneState`] that [`advance`] moves forward by at
//! most a given number of steps, so the same code can run a lane to the end
//! in one call (CPU) or in slices (the GPU shader keeps the state between
//! dispatches). No allocation, no recursion.
//!
//! Keep in sync with `shaders/tswm.wgsl`: `advance`, `try_step`,
//! `locate_root`, `come_to_rest`, `set_side` read the same there.

use crate::model::{
    efficiency, motion, phi, side_of, stick_test, FrictionTable, Lane, FRICTION_PAPER,
};

/// Components of the integrated state: x1, ẋ1, w_motor, w_load, w_friction.
pub const NY: usize = 5;

/// Integration settings shared by every lane of a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// Error tolerance per step, relative to max(1, |y|) of each component.
    pub tol: f64,
    /// Most accepted steps a lane may take.
    pub max_steps: u32,
    /// Most events (switches, stops, cut-offs) a lane may have.
    pub max_events: u32,
}

impl Default for Settings {
    fn default() -> Self {
        // tol chosen by measurement: 1e-8 keeps 3000 random user lanes
        // within 4e-7 of a 1e-13 integration (bound 1e-6); 2e-8 does not
        // keep that margin (see README, "Accuracy").
        Settings {
            tol: DEFAULT_TOL,
            max_steps: 1_000_000,
            max_events: 10_000,
        }
    }
}

/// Default per-step tolerance of the f64 path.
pub const DEFAULT_TOL: f64 = 1e-8;

/// Why a lane ended; `Ok` unless it could not be finished.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Status {
    /// Ran to `t_end`.
    Ok,
    /// The mode's D = m1 − ψ m2 tan γ is <= 0 (friction far above the lead angle).
    Inconsistent,
    /// The state became NaN or infinite.
    NonFinite,
    /// More than `max_steps` accepted steps.
    MaxSteps,
    /// More than `max_events` events (chattering).
    MaxEvents,
    /// The step size fell below what the time resolution allows.
    StepUnderflow,
}

impl Status {
    /// Every status, in code order.
    pub const ALL: [Status; 6] = [
        Status::Ok,
        Status::Inconsistent,
        Status::NonFinite,
        Status::MaxSteps,
        Status::MaxEvents,
        Status::StepUnderflow,
    ];

    /// The status word of the results table.
    pub fn name(self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::Inconsistent => "inconsistent",
            Status::NonFinite => "nonfinite",
            Status::MaxSteps => "max_steps",
            Status::MaxEvents => "max_events",
            Status::StepUnderflow => "step_underflow",
        }
    }

    /// Code shared with the shader.
    pub fn code(self) -> u32 {
        self as u32
    }

    /// Status from a shader code.
    pub fn from_code(c: u32) -> Status {
        *Status::ALL.get(c as usize).unwrap_or(&Status::NonFinite)
    }
}

/// Final contact state of a lane.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Contact {
    /// a-a: the worm pushes the wheel.
    Aa,
    /// b-b: the wheel pushes the worm.
    Bb,
    /// At rest, held by static friction.
    Stick,
}

impl Contact {
    /// The word of the results table.
    pub fn name(self) -> &'static str {
        match self {
            Contact::Aa => "aa",
            Contact::Bb => "bb",
            Contact::Stick => "stick",
        }
    }
}

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
}

/// What a lane reports (MODEL.md section 6).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaneResult {
    pub status: Status,
    pub switches: u32,
    /// NaN when none.
    pub t_first_switch: f64,
    pub reversals: u32,
    pub sticks: u32,
    pub contact_end: Contact,
    pub x1_end: f64,
    pub v1_end: f64,
    pub w_motor: f64,
    pub w_load: f64,
    pub w_friction: f64,
    /// Mesh efficiency at t_end (NaN when at rest).
    pub eta_end: f64,
    /// Accepted integration steps.
    pub steps: u32,
}

// Dormand–Prince 5(4) tableau.
// Stage times c2..c5 (1/5, 3/10, 4/5, 8/9) are not needed: between events
// the right-hand side is autonomous.
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
// Dense output (Hairer & Wanner's dopri5 contd5).
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

/// First step after every start from rest, s: the friction law's
/// derivative is unbounded at rest and the error estimate reads low there.
pub const H_INITIAL: f64 = 1e-6;
/// Root-location tolerance for events, s.
const T_ROOT_TOL: f64 = 1e-13;

/// The mode a step is taken in: frozen for the whole step.
#[derive(Clone, Copy)]
pub struct Mode {
    side: i32,
    dir: i32,
    motor_on: bool,
}

/// Right-hand side: derivative of (x1, ẋ1, w_motor, w_load, w_friction),
/// and D of the mode. Depends on ẋ1 only: x1 and the works are quadratures.
fn rhs(lane: &Lane, table: Option<&FrictionTable>, mode: Mode, v: f64) -> ([f64; NY], f64) {
    let m = motion(lane, table, mode.side, mode.dir, mode.motor_on, v);
    let v2 = v * lane.tan_g;
    (
        [v, m.acc, m.f1 * v, lane.f2 * v2, m.s1 * v + m.s2 * v2],
        m.d,
    )
}

/// The outcome of a trial step.
#[derive(Clone, Copy, Default)]
pub struct Trial {
    pub(crate) y1: [f64; NY],
    pub(crate) k7: [f64; NY],
    /// Error norm: <= 1 means accepted.
    pub(crate) err: f64,
    /// Dense-output coefficients of ẋ1 (r1..r5).
    pub(crate) dense_v: [f64; 5],
}

/// One trial step of size h from (y, k1).
#[inline]
pub(crate) fn try_step(
    lane: &Lane,
    table: Option<&FrictionTable>,
    mode: Mode,
    y: &[f64; NY],
    k1: &[f64; NY],
    h: f64,
    tol: f64,
) -> Trial {
    try_steps::<1>([lane], table, [mode], &[*y], &[*k1], [h], [true], tol)[0]
}

/// Trial steps of N lanes at once (lanes with `active[j]` false are
/// skipped). Each stage is computed for every lane before the next stage,
/// so the lanes' independent chains of pow, tan and divisions overlap in
/// the processor; per lane the arithmetic is exactly that of one lane, so
/// results do not depend on N.
#[inline]
#[allow(clippy::too_many_arguments)]
pub(crate) fn try_steps<const N: usize>(
    lane: [&Lane; N],
    table: Option<&FrictionTable>,
    mode: [Mode; N],
    y: &[[f64; NY]; N],
    k1: &[[f64; NY]; N],
    h: [f64; N],
    active: [bool; N],
    tol: f64,
) -> [Trial; N] {
    let z = [[0.0; NY]; N];
    let (mut k2, mut k3, mut k4, mut k5, mut k6, mut k7) = (z, z, z, z, z, z);
    let mut tr = [Trial::default(); N];
    // Stages need only ẋ1: the right-hand side depends on nothing else.
    for j in (0..N).filter(|&j| active[j]) {
        k2[j] = rhs(lane[j], table, mode[j], y[j][1] + h[j] * (A21 * k1[j][1])).0;
    }
    for j in (0..N).filter(|&j| active[j]) {
        k3[j] = rhs(
            lane[j],
            table,
            mode[j],
            y[j][1] + h[j] * (A31 * k1[j][1] + A32 * k2[j][1]),
        )
        .0;
    }
    for j in (0..N).filter(|&j| active[j]) {
        let v = y[j][1] + h[j] * (A41 * k1[j][1] + A42 * k2[j][1] + A43 * k3[j][1]);
        k4[j] = rhs(lane[j], table, mode[j], v).0;
    }
    for j in (0..N).filter(|&j| active[j]) {
        let v =
            y[j][1] + h[j] * (A51 * k1[j][1] + A52 * k2[j][1] + A53 * k3[j][1] + A54 * k4[j][1]);
        k5[j] = rhs(lane[j], table, mode[j], v).0;
    }
    for j in (0..N).filter(|&j| active[j]) {
        let v = y[j][1]
            + h[j]
                * (A61 * k1[j][1]
                    + A62 * k2[j][1]
                    + A63 * k3[j][1]
                    + A64 * k4[j][1]
                    + A65 * k5[j][1]);
        k6[j] = rhs(lane[j], table, mode[j], v).0;
    }
    for j in (0..N).filter(|&j| active[j]) {
        let (k1, k3, k4, k5, k6, h) = (&k1[j], &k3[j], &k4[j], &k5[j], &k6[j], h[j]);
        for i in 0..NY {
            tr[j].y1[i] =
                y[j][i] + h * (A71 * k1[i] + A73 * k3[i] + A74 * k4[i] + A75 * k5[i] + A76 * k6[i]);
        }
    }
    for j in (0..N).filter(|&j| active[j]) {
        k7[j] = rhs(lane[j], table, mode[j], tr[j].y1[1]).0;
    }
    for j in (0..N).filter(|&j| active[j]) {
        let (k1, k3, k4, k5, k6, k7, h, t) = (
            &k1[j], &k3[j], &k4[j], &k5[j], &k6[j], &k7[j], h[j], &mut tr[j],
        );
        let mut err: f64 = 0.0;
        for i in 0..NY {
            let e =
                h * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i]);
            let sc = tol * (1.0 + y[j][i].abs().max(t.y1[i].abs()));
            err = err.max(e.abs() / sc);
        }
        t.err = if err.is_finite() { err } else { f64::INFINITY };
        let v0 = y[j][1];
        let r2 = t.y1[1] - v0;
        let r3 = h * k1[1] - r2;
        let r4 = r2 - h * k7[1] - r3;
        let r5 = h * (D1 * k1[1] + D3 * k3[1] + D4 * k4[1] + D5 * k5[1] + D6 * k6[1] + D7 * k7[1]);
        t.k7 = *k7;
        t.dense_v = [v0, r2, r3, r4, r5];
    }
    tr
}

/// ẋ1 at fraction θ of the step, from the dense output.
#[inline]
fn dense_v(r: &[f64; 5], th: f64) -> f64 {
    let th1 = 1.0 - th;
    r[0] + th * (r[1] + th1 * (r[2] + th * (r[3] + th1 * r[4])))
}

/// Which event function a root is sought for.
#[derive(Clone, Copy, PartialEq)]
enum EventFn {
    /// c·φ(ẋ1): leaves > 0 when the contact side flips.
    Switch,
    /// s·ẋ1: leaves > 0 when the lane comes to rest.
    Rest,
}

#[inline]
fn event_value(lane: &Lane, mode: Mode, which: EventFn, v: f64) -> f64 {
    match which {
        EventFn::Switch => mode.side as f64 * phi(lane, v, mode.motor_on),
        EventFn::Rest => mode.dir as f64 * v,
    }
}

/// Locates θ in [0, 1] where the event function crosses from >= 0 to < 0,
/// by the Illinois method on the dense output. Returns the bracket's left
/// end, so the event lies at most `theta_tol` after it.
fn locate_root(
    lane: &Lane,
    mode: Mode,
    which: EventFn,
    r: &[f64; 5],
    g_end: f64,
    theta_tol: f64,
) -> f64 {
    let (mut a, mut fa) = (0.0, event_value(lane, mode, which, r[0]));
    let (mut b, mut fb) = (1.0, g_end);
    if fa <= 0.0 {
        return 0.0;
    }
    let mut side = 0;
    for _ in 0..100 {
        if b - a <= theta_tol {
            break;
        }
        let mut c = (a * fb - b * fa) / (fb - fa);
        // Keep the secant point strictly inside, else bisect.
        if !(c > a && c < b) {
            c = 0.5 * (a + b);
        }
        let fc = event_value(lane, mode, which, dense_v(r, c));
        if fc >= 0.0 {
            a = c;
            fa = fc;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            b = c;
            fb = fc;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
    }
    a
}

/// Starts a lane at t = 0.
pub fn init(lane: &Lane, table: Option<&FrictionTable>) -> LaneState {
    let motor_on = !(lane.motor_off <= 0.0);
    let v = lane.v1_0;
    let mut st = LaneState {
        t: 0.0,
        y: [lane.x1_0, v, 0.0, 0.0, 0.0],
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
        status: Status::Ok,
        switches: 0,
        reversals: 0,
        sticks: 0,
        t_first_switch: f64::NAN,
        steps: 0,
        events: 0,
        k1: [0.0; NY],
        k1_valid: false,
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
    let mode = Mode {
        side: st.side,
        dir: st.dir,
        motor_on: st.motor_on,
    };
    let (k, d) = rhs(lane, table, mode, st.y[1]);
    if !(d > 0.0) {
        st.status = Status::Inconsistent;
        st.done = true;
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

/// A step about to be tried: its mode, its size, and the time event it
/// may land on.
#[derive(Clone, Copy)]
pub struct StepPlan {
    pub(crate) mode: Mode,
    pub(crate) h: f64,
    t_stop: f64,
    landing: bool,
}

/// First half of one step attempt: a stick phase jumps to the next time
/// event, the derivative at the step's start is made valid, and the step
/// size is chosen. None when the attempt ends here (stuck, or finished).
pub fn prepare(lane: &Lane, table: Option<&FrictionTable>, st: &mut LaneState) -> Option<StepPlan> {
    // The next time event: motor cut-off, else the end of the run.
    let t_stop = if st.motor_on && lane.motor_off < lane.t_end {
        lane.motor_off
    } else {
        lane.t_end
    };
    if st.stuck {
        // While stuck every force is constant in time (F1 at ẋ1 = 0, F2),
        // so the stick condition can only fail at a time event.
        st.t = t_stop;
        if t_stop >= lane.t_end {
            st.done = true;
        } else {
            cut_motor(lane, table, st);
        }
        return None;
    }
    let mode = Mode {
        side: st.side,
        dir: st.dir,
        motor_on: st.motor_on,
    };
    if !st.k1_valid {
        let (k, d) = rhs(lane, table, mode, st.y[1]);
        if !(d > 0.0) {
            st.status = Status::Inconsistent;
            st.done = true;
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
    let (mode, h) = (plan.mode, plan.h);
    let fac = if trial.err == 0.0 {
        5.0
    } else {
        (0.9 * trial.err.powf(-0.2)).clamp(0.2, 5.0)
    };
    if trial.err > 1.0 {
        st.h = h * fac.min(1.0);
        if st.h < 1e-15 * st.t.max(1.0) {
            st.status = Status::StepUnderflow;
            st.done = true;
        }
        return;
    }
    let h_next = h * fac;
    st.steps += 1;
    if st.steps > set.max_steps {
        st.status = Status::MaxSteps;
        st.done = true;
        return;
    }
    // Events inside the step: the earliest root wins.
    let g_rest = event_value(lane, mode, EventFn::Rest, trial.y1[1]);
    let g_switch = event_value(lane, mode, EventFn::Switch, trial.y1[1]);
    let theta_tol = T_ROOT_TOL / h;
    let mut theta = 2.0;
    let mut which = EventFn::Rest;
    if g_rest < 0.0 {
        theta = locate_root(lane, mode, EventFn::Rest, &trial.dense_v, g_rest, theta_tol);
    }
    if g_switch < 0.0 {
        let th = locate_root(
            lane,
            mode,
            EventFn::Switch,
            &trial.dense_v,
            g_switch,
            theta_tol,
        );
        if th < theta {
            theta = th;
            which = EventFn::Switch;
        }
    }
    if theta <= 1.0 {
        // Step again, exactly to the event, for a full-order state there.
        let h_ev = theta * h;
        let ev = try_step(lane, table, mode, &st.y, &st.k1, h_ev, set.tol);
        st.t += h_ev;
        st.y = ev.y1;
        st.k1_valid = false;
        st.events += 1;
        st.h = h_next.max(h_ev);
        if which == EventFn::Rest {
            come_to_rest(lane, table, st);
        } else {
            set_side(st, -st.side);
            check_mode(lane, table, st);
        }
        if st.events > set.max_events {
            st.status = Status::MaxEvents;
            st.done = true;
        }
    } else {
        st.y = trial.y1;
        st.k1 = trial.k7;
        st.h = h_next;
        if plan.landing {
            st.t = plan.t_stop;
            if plan.t_stop >= lane.t_end {
                st.done = true;
            } else {
                cut_motor(lane, table, st);
            }
        } else {
            st.t += h;
        }
    }
    if !st.y.iter().all(|v| v.is_finite()) {
        st.status = Status::NonFinite;
        st.done = true;
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
        if let Some(plan) = prepare(lane, table, st) {
            let trial = try_step(lane, table, plan.mode, &st.y, &st.k1, plan.h, set.tol);
            finish_step(lane, table, set, st, &plan, &trial);
        }
    }
    st.done
}

/// What a finished (or abandoned) lane reports.
pub fn result(lane: &Lane, table: Option<&FrictionTable>, st: &LaneState) -> LaneResult {
    let v = st.y[1];
    let eta_end = if st.stuck || v == 0.0 || st.status != Status::Ok {
        f64::NAN
    } else {
        let m = motion(lane, table, st.side, st.dir, st.motor_on, v);
        efficiency(lane, &m, st.side, st.dir, v)
    };
    LaneResult {
        status: st.status,
        switches: st.switches,
        t_first_switch: st.t_first_switch,
        reversals: st.reversals,
        sticks: st.sticks,
        contact_end: if st.stuck {
            Contact::Stick
        } else if st.side > 0 {
            Contact::Aa
        } else {
            Contact::Bb
        },
        x1_end: st.y[0],
        v1_end: v,
        w_motor: st.y[2],
        w_load: st.y[3],
        w_friction: st.y[4],
        eta_end,
        steps: st.steps,
    }
}

/// Lanes one thread interleaves in [`simulate_batch`]. Measured on one
/// thread (paper-like lanes): 1 lane 23.7k lanes/s, 2: 38.8k, 4: 45.1k,
/// 8: 46.5k; 4 takes nearly all of it with half the state of 8.
pub const INTERLEAVE: usize = 4;

/// Runs `lanes` to their ends, `out[i]` for `lanes[i]`, interleaving
/// [`INTERLEAVE`] lanes on this thread: each slot takes the next lane when
/// its lane finishes. Per lane the arithmetic is exactly [`simulate`]'s.
pub fn simulate_batch(
    lanes: &[Lane],
    table: Option<&FrictionTable>,
    set: &Settings,
    out: &mut [LaneResult],
) {
    const N: usize = INTERLEAVE;
    assert_eq!(lanes.len(), out.len());
    if lanes.is_empty() {
        return;
    }
    let mut next = 0;
    let mut slot: [Option<usize>; N] = [None; N];
    let mut st = [init(&lanes[0], table); N];
    let empty = StepPlan {
        mode: Mode {
            side: 1,
            dir: 1,
            motor_on: false,
        },
        h: 0.0,
        t_stop: 0.0,
        landing: false,
    };
    loop {
        // Refill finished slots.
        for j in 0..N {
            if let Some(i) = slot[j] {
                if !st[j].done {
                    continue;
                }
                out[i] = result(&lanes[i], table, &st[j]);
                slot[j] = None;
            }
            if next < lanes.len() {
                st[j] = init(&lanes[next], table);
                slot[j] = Some(next);
                next += 1;
            }
        }
        if slot.iter().all(Option::is_none) {
            break;
        }
        let mut plan = [empty; N];
        let mut active = [false; N];
        for j in 0..N {
            if let Some(i) = slot[j] {
                if !st[j].done {
                    if let Some(p) = prepare(&lanes[i], table, &mut st[j]) {
                        plan[j] = p;
                        active[j] = true;
                    }
                }
            }
        }
        if !active.iter().any(|&a| a) {
            continue;
        }
        let lane: [&Lane; N] = std::array::from_fn(|j| &lanes[slot[j].unwrap_or(0)]);
        let y: [[f64; NY]; N] = std::array::from_fn(|j| st[j].y);
        let k1: [[f64; NY]; N] = std::array::from_fn(|j| st[j].k1);
        let trial = try_steps::<N>(
            lane,
            table,
            std::array::from_fn(|j| plan[j].mode),
            &y,
            &k1,
            std::array::from_fn(|j| plan[j].h),
            active,
            set.tol,
        );
        for j in (0..N).filter(|&j| active[j]) {
            finish_step(lane[j], table, set, &mut st[j], &plan[j], &trial[j]);
        }
    }
}

/// Runs one lane from t = 0 to its end.
pub fn simulate(lane: &Lane, table: Option<&FrictionTable>, set: &Settings) -> LaneResult {
    let mut st = init(lane, table);
    advance(lane, table, set, &mut st, u32::MAX);
    result(lane, table, &st)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Spec;

    fn paper() -> Lane {
        Lane::new(&Spec::default().resolve(false).unwrap(), None)
    }

    #[test]
    fn dense_output_interpolates_ends() {
        let r = [1.0, 0.5, 0.3, -0.2, 0.1];
        assert_eq!(dense_v(&r, 0.0), 1.0);
        assert!((dense_v(&r, 1.0) - 1.5).abs() < 1e-15);
    }

    #[test]
    fn locate_root_finds_a_known_crossing() {
        // A constant-force lane: ẋ1 is linear in time, so the rest event of
        // a decelerating lane is known exactly.
        let mut l = paper();
        l.motor = crate::model::MOTOR_CONSTANT;
        l.f1 = 0.0;
        let mode = Mode {
            side: 1,
            dir: 1,
            motor_on: true,
        };
        // v(θ) = 1 − 4θ as dense coefficients: r2 = −4, r3 = h k1 − r2 = 0, ...
        let r = [1.0, -4.0, 0.0, 0.0, 0.0];
        let th = locate_root(&l, mode, EventFn::Rest, &r, -3.0, 1e-14);
        assert!((th - 0.25).abs() < 1e-13, "{th}");
    }

    #[test]
    fn switch_time_is_located_inside_the_step() {
        // Paper case 1: the switch is at 0.486653423342 s (MODEL.md 7).
        let r = simulate(&paper(), None, &Settings::default());
        assert_eq!(r.switches, 1);
        assert!(
            (r.t_first_switch - 0.48665342334234873).abs() < 1e-8,
            "{}",
            r.t_first_switch
        );
    }

    #[test]
    fn constant_force_deceleration_stops_at_the_analytic_time() {
        // Coulomb friction, constant forces: the rest time is v0 / |a|.
        let mut s = Spec {
            friction: Some(crate::params::FrictionKind::Coulomb),
            ..Default::default()
        };
        s.motor = Some(crate::params::MotorKind::Constant);
        s.set(crate::params::Num::F1, 0.0);
        s.set(crate::params::Num::F2, -4774.0);
        s.set(crate::params::Num::Mu, 0.2);
        s.set(crate::params::Num::V10, 2.0);
        s.set(crate::params::Num::TEnd, 3.0);
        let l = Lane::new(&s.resolve(false).unwrap(), None);
        let m = motion(&l, None, 1, 1, true, 1.0);
        let t_rest = 2.0 / -m.acc;
        let mut st = init(&l, None);
        // Advance until the stop, then check its time.
        while !st.stuck && !st.done {
            advance(&l, None, &Settings::default(), &mut st, 1);
        }
        assert!(st.stuck);
        assert!((st.t - t_rest).abs() < 1e-12, "{} vs {}", st.t, t_rest);
        let x_rest = 2.0 * t_rest / 2.0;
        assert!((st.y[0] - x_rest).abs() < 1e-10);
    }
}

#[cfg(test)]
mod batch_tests {
    use super::*;
    use crate::params::{FrictionKind, Num};

    /// Interleaving changes nothing: every field, bit for bit.
    #[test]
    fn simulate_batch_equals_simulate() {
        let table = FrictionTable::new(&[0.0, 0.5, 2.0, 5.0], &[0.13, 0.07, 0.05, 0.04]).unwrap();
        let mut specs = crate::testmodels::random_user_lanes(300, 5);
        for (i, s) in specs.iter_mut().enumerate().filter(|(i, _)| i % 5 == 0) {
            s.friction = Some(FrictionKind::Table);
            s.num[Num::Mu as usize] = None;
            s.num[Num::MuStatic as usize] = None;
            s.set(Num::F2, -3000.0 + 20.0 * i as f64);
        }
        let lanes: Vec<Lane> = specs
            .iter()
            .map(|s| Lane::new(&s.resolve(true).unwrap(), Some(&table)))
            .collect();
        let set = Settings::default();
        let mut out = vec![simulate(&lanes[0], Some(&table), &set); lanes.len()];
        simulate_batch(&lanes, Some(&table), &set, &mut out);
        for (l, got) in lanes.iter().zip(&out) {
            let want = simulate(l, Some(&table), &set);
            assert_eq!(format!("{want:?}"), format!("{got:?}"));
        }
    }
}
