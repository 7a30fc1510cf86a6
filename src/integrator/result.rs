//! What a lane reports: its status, final contact and results (docs/model.md
//! section 6), and the one conversion from a lane's end state to them,
//! used by both backends.

use super::components::NY;
pub use super::outcome::{Contact, Drive, Hold, SearchOutcome, SearchStatus, Side};
pub use super::path::{Recheck, RowPath};
use crate::model::kernel::sliding_speed;
use crate::model::{efficiency, motion, mu_at, FrictionTable, Lane};
use crate::params::gear::rpm;

/// Why a lane ended; `Ok` unless it could not be finished.
///
/// The explicit values are the codes the shader writes (`S_*` in
/// `shaders/integrator/result.wgsl`); a test reads them from the shader and compares.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u32)]
pub enum Status {
    /// Ran to `t_end`.
    Ok = 0,
    /// The mode's D = m1 − ψ m2 tan γ is <= 0, or falls to 0 inside the
    /// mode (the wedge jams): friction far above the lead angle.
    Inconsistent = 1,
    /// The state became NaN or infinite.
    NonFinite = 2,
    /// More than `max_steps` accepted steps.
    MaxSteps = 3,
    /// More than `max_events` events (chattering).
    MaxEvents = 4,
    /// The step size fell below what the time resolution allows.
    StepUnderflow = 5,
}

crate::lanewise_scalar!(Status = Status::Ok);

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

    /// Status from a shader code; an unknown code is `NonFinite` (a state
    /// that cannot be trusted), never `Ok`.
    pub(crate) fn from_code(c: u32) -> Status {
        Status::ALL
            .into_iter()
            .find(|s| s.code() == c)
            .unwrap_or(Status::NonFinite)
    }
}

/// What a lane reports (docs/model.md section 6).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaneResult {
    /// How the lane ended (`ok`, or why not).
    pub status: Status,
    /// Contact side switches (a-a to b-b or back).
    pub switches: u32,
    /// NaN when none.
    pub t_first_switch: f64,
    /// Reversals of the direction of motion.
    pub reversals: u32,
    /// Stick phases: times the drive came to rest and held.
    pub sticks: u32,
    /// The contact mode where the lane stopped.
    pub contact_end: Contact,
    /// Worm (body 1) position where the lane stopped, m.
    pub x1_end: f64,
    /// Worm (body 1) speed where the lane stopped, m/s.
    pub v1_end: f64,
    /// Work done by the motor force, J.
    pub w_motor: f64,
    /// Work done against the load force, J.
    pub w_load: f64,
    /// Work lost to friction, J.
    pub w_friction: f64,
    /// Mesh efficiency at t_end (NaN when at rest).
    pub eta_end: f64,
    /// Accepted integration steps.
    pub steps: u32,
    /// J: ∫max(p1, 0), ∫max(−p1, 0), ∫max(p2, 0), ∫max(−p2, 0) with
    /// p1 = S1 ẋ1, p2 = S2 ẋ2 (docs/model.md section 10).
    pub w1_in: f64,
    /// See [`LaneResult::w1_in`].
    pub w1_out: f64,
    /// See [`LaneResult::w1_in`].
    pub w2_in: f64,
    /// See [`LaneResult::w1_in`].
    pub w2_out: f64,
    /// w2_out / w1_in (NaN when w1_in is negligible).
    pub eta_direct: f64,
    /// w1_out / w2_in (NaN when w2_in is negligible).
    pub eta_inverse: f64,
    /// tan γ / tan(γ + ρ(Vs_end)).
    pub eta_direct_ss: f64,
    /// tan(γ − ρ(Vs_end)) / tan γ.
    pub eta_inverse_ss: f64,
    /// ρs − γ, deg (> 0: statically self-locking).
    pub lock_margin_deg: f64,
    /// tan γ / tan(γ + ρs): the starting (breakaway) direct efficiency.
    pub eta_direct_start: f64,
    /// tan(γ − ρs) / tan γ: the starting back-driving efficiency.
    pub eta_inverse_start: f64,
    /// What became of the load, for a lane whose motor is cut before
    /// t_end; None otherwise.
    pub hold: Option<Hold>,
    /// What the motor achieved, for a lane whose motor runs to the end
    /// (and drives: not a `constant` motor with f1 = 0); None otherwise.
    pub drive: Option<Drive>,
    /// Where the lane stopped, s: t_end, or up to t_max for a lane that
    /// ran on while coasting (every `_end` value and integral is taken here).
    pub t_stop: f64,
    /// Worm and wheel shaft speeds where the lane stopped, rpm, for a
    /// lane given in gear terms (docs/model.md section 12); NaN without.
    pub n1_end: f64,
    /// See [`LaneResult::n1_end`].
    pub n2_end: f64,
    /// The path the row came from.
    pub path: RowPath,
    /// A drive's search (`[search]`), for a row of a search run.
    pub search: Option<SearchOutcome>,
}

impl LaneResult {
    /// The integrated results, which the f64 path's error estimate covers
    /// and the GPU row check tests: x1, v1, w_motor, w_load, w_friction,
    /// w1_in, w1_out, w2_in, w2_out (the table's order; the table of
    /// result columns marks the same ones `integrated`).
    pub fn integrated(&self) -> [f64; 9] {
        [
            self.x1_end,
            self.v1_end,
            self.w_motor,
            self.w_load,
            self.w_friction,
            self.w1_in,
            self.w1_out,
            self.w2_in,
            self.w2_out,
        ]
    }

    /// The row with its worm and wheel shaft speeds where the lane
    /// stopped, rpm, from the pitch radii R1 and R2 of a lane given in
    /// gear terms (docs/model.md section 12; NaN radii, a lane without a
    /// geometry, give NaN: empty cells). The radii are no constant the
    /// integrator reads, so the lane's row gets them here, from its
    /// parameters, not from its [`Lane`].
    #[inline]
    pub(crate) fn with_shaft_speeds(mut self, lane: &Lane, (r1, r2): (f64, f64)) -> LaneResult {
        self.n1_end = rpm(self.v1_end, r1);
        self.n2_end = rpm(self.v1_end * lane.tan_g, r2);
        self
    }

    /// A row with no results, for buffers that every lane's result
    /// overwrites.
    pub const EMPTY: LaneResult = LaneResult {
        status: Status::NonFinite,
        switches: 0,
        t_first_switch: f64::NAN,
        reversals: 0,
        sticks: 0,
        contact_end: Contact::Stick,
        x1_end: f64::NAN,
        v1_end: f64::NAN,
        w_motor: f64::NAN,
        w_load: f64::NAN,
        w_friction: f64::NAN,
        eta_end: f64::NAN,
        steps: 0,
        w1_in: f64::NAN,
        w1_out: f64::NAN,
        w2_in: f64::NAN,
        w2_out: f64::NAN,
        eta_direct: f64::NAN,
        eta_inverse: f64::NAN,
        eta_direct_ss: f64::NAN,
        eta_inverse_ss: f64::NAN,
        lock_margin_deg: f64::NAN,
        eta_direct_start: f64::NAN,
        eta_inverse_start: f64::NAN,
        hold: None,
        drive: None,
        t_stop: f64::NAN,
        n1_end: f64::NAN,
        n2_end: f64::NAN,
        path: RowPath::Cpu,
        search: None,
    };
}

/// An efficiency is empty where its input is at most this share of the
/// energy fed into the mesh, w1_in + w2_in (docs/model.md section 10).
pub(crate) const EMPTY_SHARE: f64 = 1e-6;

/// Section 10's efficiencies and margin from a lane's energies and final
/// speed: (eta_direct, eta_inverse, eta_direct_ss, eta_inverse_ss,
/// lock_margin_deg, eta_direct_start, eta_inverse_start).
pub fn engineering(lane: &Lane, tables: &[FrictionTable], flow: &[f64; 4], v_end: f64) -> [f64; 7] {
    let [w1_in, w1_out, w2_in, w2_out] = *flow;
    let fed = EMPTY_SHARE * (w1_in + w2_in);
    let ratio = |out: f64, inp: f64| if inp > fed { out / inp } else { f64::NAN };
    // Steady values at the final sliding speed (at rest: the sliding law's
    // limit at zero speed, which summary.csv and the report leave out).
    // γ from tan γ, not the lane's own γ: atan(tan γ) differs from γ in
    // the last bit for about 2 % of lead angles, and these columns keep
    // the bits of every earlier release.
    let g = lane.tan_g.atan();
    let rho = mu_at(
        lane,
        tables,
        sliding_speed(1.0, v_end.abs(), lane.inv_cos_g),
    )
    .atan();
    // The static friction angle ρs = atan(μs / cos αn) (`mu_s` holds the
    // division): breakaway from rest, and the static lock margin.
    let rho_s = lane.mu_s.atan();
    [
        ratio(w2_out, w1_in),
        ratio(w1_out, w2_in),
        lane.tan_g / (g + rho).tan(),
        (g - rho).tan() / lane.tan_g,
        (rho_s - g).to_degrees(),
        lane.tan_g / (g + rho_s).tan(),
        (g - rho_s).tan() / lane.tan_g,
    ]
}

/// A lane's state where it stopped, in f64, as either backend holds it:
/// the CPU path's `LaneState`, or the shader's `State` with its
/// compensated sums folded in.
#[derive(Clone, Copy, Debug)]
pub struct EndState {
    /// How the lane ended.
    pub status: Status,
    /// At rest and held.
    pub stuck: bool,
    /// Contact side c: +1 a-a, −1 b-b.
    pub side: i32,
    /// Direction of motion s.
    pub dir: i32,
    /// Whether the motor force is still on.
    pub motor_on: bool,
    /// x1, ẋ1, w_motor, w_load, w_friction, w_p1.
    pub y: [f64; NY],
    /// w1_in, w1_out, w2_in, w2_out.
    pub flow: [f64; 4],
    /// Contact side switches.
    pub switches: u32,
    /// Reversals of the direction of motion.
    pub reversals: u32,
    /// Stick phases.
    pub sticks: u32,
    /// NaN until the first switch.
    pub t_first_switch: f64,
    /// Accepted steps.
    pub steps: u32,
    /// Where the lane stopped, s.
    pub t: f64,
    /// It stopped running on because it began to speed up (the
    /// `Speeding` event): it runs away.
    pub speeding: bool,
}

impl EndState {
    /// The lane's row of results. The end efficiency is evaluated here, in
    /// f64, from the final mode and speed.
    pub fn result(&self, lane: &Lane, tables: &[FrictionTable]) -> LaneResult {
        let v = self.y[1];
        let ok = self.status == Status::Ok;
        let m = motion(lane, tables, self.mode_at(lane, tables, v), v);
        let eta_end = if self.stuck || v == 0.0 || !ok {
            f64::NAN
        } else {
            efficiency(lane, &m, self.side, self.dir, v)
        };
        let (hold, drive) = if ok {
            self.words(lane, &m, v)
        } else {
            (None, None)
        };
        let [eta_direct, eta_inverse, eta_direct_ss, eta_inverse_ss, lock_margin_deg, eta_direct_start, eta_inverse_start] =
            engineering(lane, tables, &self.flow, v);
        LaneResult {
            status: self.status,
            switches: self.switches,
            t_first_switch: self.t_first_switch,
            reversals: self.reversals,
            sticks: self.sticks,
            contact_end: if self.stuck {
                Contact::Stick
            } else if self.side > 0 {
                Contact::Aa
            } else {
                Contact::Bb
            },
            x1_end: self.y[0],
            v1_end: v,
            w_motor: self.y[2],
            w_load: self.y[3],
            w_friction: self.y[4],
            eta_end,
            steps: self.steps,
            w1_in: self.flow[0],
            w1_out: self.flow[1],
            w2_in: self.flow[2],
            w2_out: self.flow[3],
            eta_direct,
            eta_inverse,
            eta_direct_ss,
            eta_inverse_ss,
            lock_margin_deg,
            eta_direct_start,
            eta_inverse_start,
            hold,
            drive,
            t_stop: self.t,
            // Set by `with_shaft_speeds` where the lane's radii are known.
            n1_end: f64::NAN,
            n2_end: f64::NAN,
            path: RowPath::Cpu,
            search: None,
        }
    }
}

/// Whether a sliding lane moving in direction `dir` with acceleration
/// `acc` is not slowing down (ẋ1 ẍ1 >= 0; at zero the load keeps its
/// speed and friction does not stop it). Its negation is "coasting".
#[inline]
pub(crate) fn speeding_up(dir: i32, acc: f64) -> bool {
    !(dir as f64 * acc < 0.0)
}
