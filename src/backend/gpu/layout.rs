//! The structs and constants shared with the shader (`shaders/`), byte for
//! byte. Tests parse the shader with naga and fail when sizes, offsets or
//! constant values drift.

use bytemuck::{Pod, Zeroable};

use crate::integrator::{EndState, Settings, Status, NY};
use crate::model::laws::LAW_SLOTS;
use crate::model::{FrictionTable, Lane, MAX_TABLES, MAX_TABLE_POINTS};

/// "Never" for f32 times: WGSL may assume there are no infinities.
pub const NEVER: f32 = 3.0e38;

/// A lane's constants, f32: `Lane` in shaders/model/lane.wgsl (a test
/// compares the layouts).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuLane {
    /// [`Lane::m1`] in f32.
    pub m1: f32,
    /// [`Lane::m2`] in f32.
    pub m2: f32,
    /// [`Lane::tan_g`] in f32.
    pub tan_g: f32,
    /// [`Lane::sin_g`] in f32.
    pub sin_g: f32,
    /// [`Lane::cos_g`] in f32.
    pub cos_g: f32,
    /// [`Lane::inv_cos_g`] in f32.
    pub inv_cos_g: f32,
    /// [`Lane::f2`] in f32.
    pub f2: f32,
    /// [`Lane::motor`] as its code ([`MotorKind::code`](crate::model::MotorKind::code)).
    pub motor: u32,
    /// [`Lane::v_sync`] in f32.
    pub v_sync: f32,
    /// [`Lane::sigma_k`] in f32.
    pub sigma_k: f32,
    /// [`Lane::f_crit`] in f32.
    pub f_crit: f32,
    /// [`Lane::f1`] in f32.
    pub f1: f32,
    /// [`Lane::motor_off`] in f32; [`NEVER`] when the motor is never cut.
    pub motor_off: f32,
    /// [`Lane::friction`] as its code ([`FrictionKind::code`](crate::model::FrictionKind::code)).
    pub friction: u32,
    /// [`Lane::law`] in f32.
    pub law: [f32; LAW_SLOTS],
    /// [`Lane::mu_s`] in f32.
    pub mu_s: f32,
    /// [`Lane::x1_0`] in f32.
    pub x1_0: f32,
    /// [`Lane::v1_0`] in f32.
    pub v1_0: f32,
    /// [`Lane::t_end`] in f32.
    pub t_end: f32,
    /// t_end when the lane does not run on (see `model::Lane::t_max`).
    pub t_max: f32,
    /// Which of the run's friction tables.
    pub table: u32,
    /// 1 / cos αn (see `model::Lane::inv_cos_an`).
    pub inv_cos_an: f32,
    /// [`Lane::steep`]: 1 when the friction law is steep at rest.
    pub steep: u32,
    /// [`Lane::branch_speed`] in f32; [`NEVER`] for a law with one branch.
    pub branch_speed: f32,
}

impl From<&Lane> for GpuLane {
    fn from(l: &Lane) -> Self {
        GpuLane {
            m1: l.m1 as f32,
            m2: l.m2 as f32,
            tan_g: l.tan_g as f32,
            sin_g: l.sin_g as f32,
            cos_g: l.cos_g as f32,
            inv_cos_g: l.inv_cos_g as f32,
            f2: l.f2 as f32,
            motor: l.motor.code(),
            v_sync: l.v_sync as f32,
            sigma_k: l.sigma_k as f32,
            f_crit: l.f_crit as f32,
            f1: l.f1 as f32,
            motor_off: if l.motor_off.is_finite() {
                l.motor_off as f32
            } else {
                NEVER
            },
            friction: l.friction.code(),
            law: l.law.map(|v| v as f32),
            mu_s: l.mu_s as f32,
            x1_0: l.x1_0 as f32,
            v1_0: l.v1_0 as f32,
            t_end: l.t_end as f32,
            t_max: l.t_max as f32,
            table: l.table,
            inv_cos_an: l.inv_cos_an as f32,
            steep: l.steep as u32,
            branch_speed: if l.branch_speed.is_finite() {
                l.branch_speed as f32
            } else {
                NEVER
            },
        }
    }
}

/// Flag bits of `GpuState::flags`: the shader's `F_*` constants.
pub mod flags {
    macro_rules! flags {
        ($($(#[$m:meta])* $name:ident = $value:expr;)*) => {
            $($(#[$m])* pub const $name: u32 = $value;)*
            /// Every flag by its name (the shader's `F_*` constants are
            /// generated from it: `shader::prelude`).
            pub const ALL: &[(&str, u32)] = &[$((stringify!($name), $name)),*];
        };
    }
    flags! {
        /// At rest, held.
        STUCK = 1;
        /// Motor force on.
        MOTOR_ON = 2;
        /// Finished or abandoned.
        DONE = 4;
        /// k1 holds the derivative at the current state.
        K1_VALID = 8;
        /// `init` has run.
        STARTED = 16;
        /// Running on past t_end towards t_max.
        RUNNING_ON = 32;
        /// Running on ended because the lane began to speed up.
        SPEEDING = 64;
        /// On the friction law's upper branch.
        UPPER = 128;
        /// A step's mesh power turned and turned back inside it
        /// ([`Recheck::FlowTurn`](crate::integrator::path::Recheck::FlowTurn)).
        FLOW_TURN = 256;
    }
}

/// A lane's integration state between dispatches. Keep in sync with
/// `State` in shaders/integrator/automaton.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuState {
    /// The time, s: a compensated (Kahan) sum whose value is t_hi − t_lo.
    pub t_hi: f32,
    /// The compensation of `t_hi`.
    pub t_lo: f32,
    /// The step size to try next, s.
    pub h: f32,
    /// < 0 until the first switch.
    pub t_first_switch: f32,
    /// w1_in, w1_out, w2_in, w2_out (a vec4 in the shader: 16-aligned).
    pub flow: [f32; 4],
    /// Kahan compensations of `flow`.
    pub flow_c: [f32; 4],
    /// The integrated components (x1, v1, w_motor, w_load, w_friction, w_p1; `NY`).
    pub y: [f32; NY],
    /// Kahan compensations of `y`: the value is y − yc.
    pub yc: [f32; NY],
    /// The derivative at the current state, when [`flags::K1_VALID`] is set.
    pub k1: [f32; NY],
    /// The contact side: 1 (a-a) or −1 (b-b).
    pub side: i32,
    /// The direction of motion: 1, −1, or 0 before the first start.
    pub dir: i32,
    /// Bits of [`flags`].
    pub flags: u32,
    /// How the lane ended ([`Status::code`]), once [`flags::DONE`] is set.
    pub status: u32,
    /// Contact side switches so far.
    pub switches: u32,
    /// Reversals of the direction of motion so far.
    pub reversals: u32,
    /// Stick phases so far.
    pub sticks: u32,
    /// Accepted steps so far.
    pub steps: u32,
    /// Events (switches, rests, motor cut-off, ...) so far.
    pub events: u32,
    /// Padding to the shader's 16-byte rows.
    pub pad0: u32,
    /// Padding to the shader's 16-byte rows.
    pub pad1: u32,
    /// Padding to the shader's 16-byte rows.
    pub pad2: u32,
    /// Padding to the shader's 16-byte rows.
    pub pad3: u32,
    /// Padding to the shader's 16-byte rows.
    pub pad4: u32,
}

impl GpuState {
    /// Where the lane `lane` stopped, in f64 (compensated sums folded in).
    pub fn end_state(&self, lane: &Lane) -> EndState {
        let val = |i: usize| self.y[i] as f64 - self.yc[i] as f64;
        // A lane the dispatch budget cut short never says `ok`.
        let finished = self.flags & flags::DONE != 0;
        EndState {
            status: if finished {
                Status::from_code(self.status)
            } else {
                Status::MaxSteps
            },
            stuck: self.flags & flags::STUCK != 0,
            side: self.side,
            dir: self.dir,
            motor_on: self.flags & flags::MOTOR_ON != 0,
            y: std::array::from_fn(val),
            flow: std::array::from_fn(|i| self.flow[i] as f64 - self.flow_c[i] as f64),
            switches: self.switches,
            reversals: self.reversals,
            sticks: self.sticks,
            t_first_switch: if self.t_first_switch < 0.0 {
                f64::NAN
            } else {
                self.t_first_switch as f64
            },
            steps: self.steps,
            t: self.stop_time(lane),
            speeding: self.flags & flags::SPEEDING != 0,
        }
    }

    /// Where the lane stopped: its own t_end or t_max exactly when it
    /// stopped there (the f32 time would round them), else the f32 time.
    fn stop_time(&self, lane: &Lane) -> f64 {
        let t = self.t_hi as f64 - self.t_lo as f64;
        if self.flags & flags::RUNNING_ON == 0 {
            lane.t_end
        } else if self.t_hi == lane.t_max as f32 && self.t_lo == 0.0 {
            lane.t_max
        } else {
            t
        }
    }
}

/// Vec4s per friction table in [`GpuGlobals`].
const TABLE_VEC4S: usize = MAX_TABLE_POINTS / 4;

/// Run-wide values and the friction tables. Keep in sync with `Globals` in
/// shaders/integrator/batch.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuGlobals {
    /// Lanes in the chunk.
    pub n_lanes: u32,
    /// Step attempts per lane per dispatch.
    pub budget: u32,
    /// A lane's step limit ([`Settings::max_steps`]).
    pub max_steps: u32,
    /// A lane's event limit ([`Settings::max_events`]).
    pub max_events: u32,
    /// The per-step tolerance ([`GPU_TOL`]).
    pub tol: f32,
    /// The first step after every start from rest, s (`integrator::control::H_INITIAL`).
    pub h_initial: f32,
    /// Number of friction tables.
    pub n_tables: u32,
    /// Invocations per row of a 2-D dispatch.
    pub row_lanes: u32,
    /// Slots (invocations) working through the chunk's lanes.
    pub n_slots: u32,
    /// Padding to the shader's 16-byte rows.
    pub pad0: u32,
    /// Padding to the shader's 16-byte rows.
    pub pad1: u32,
    /// Padding to the shader's 16-byte rows.
    pub pad2: u32,
    /// Points of each table (a vec4 array in the shader: 16-aligned).
    pub table_n: [[u32; 4]; MAX_TABLES / 4],
    /// Table t's point i is at `[t * TABLE_VEC4S + i / 4][i % 4]`.
    pub table_vs: [[f32; 4]; MAX_TABLES * TABLE_VEC4S],
    /// μ of table t's point i, at `[t * TABLE_VEC4S + i / 4][i % 4]`.
    pub table_mu: [[f32; 4]; MAX_TABLES * TABLE_VEC4S],
}

/// The counters slots share. Keep in sync with `Control` in
/// shaders/integrator/batch.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuControl {
    /// Slots still holding an unfinished lane after a dispatch.
    pub n_active: u32,
    /// The next lane no slot has taken yet.
    pub next_lane: u32,
}

/// Per-step tolerance of the f32 path: the tightest at which f32 rounding
/// stays well below the error being controlled (see docs/gpu.md).
pub const GPU_TOL_F64: f64 = 1e-6;
/// [`GPU_TOL_F64`] as the shader gets it.
pub const GPU_TOL: f32 = GPU_TOL_F64 as f32;

impl GpuGlobals {
    /// Globals for a run with `settings` (its tolerance is the f64 path's
    /// and is replaced by [`GPU_TOL`]) and its friction tables (at most
    /// [`MAX_TABLES`]: the sweep reader refuses more).
    pub fn new(settings: &Settings, tables: &[FrictionTable]) -> GpuGlobals {
        let mut g = GpuGlobals {
            n_lanes: 0,
            budget: 0,
            max_steps: settings.max_steps,
            max_events: settings.max_events,
            tol: GPU_TOL,
            h_initial: crate::integrator::H_INITIAL as f32,
            n_tables: tables.len().min(MAX_TABLES) as u32,
            row_lanes: 0,
            n_slots: 0,
            pad0: 0,
            pad1: 0,
            pad2: 0,
            table_n: [[0; 4]; MAX_TABLES / 4],
            table_vs: [[0.0; 4]; MAX_TABLES * TABLE_VEC4S],
            table_mu: [[0.0; 4]; MAX_TABLES * TABLE_VEC4S],
        };
        for (k, t) in tables.iter().take(MAX_TABLES).enumerate() {
            g.table_n[k / 4][k % 4] = t.n as u32;
            for i in 0..t.n {
                g.table_vs[k * TABLE_VEC4S + i / 4][i % 4] = t.vs[i] as f32;
                g.table_mu[k * TABLE_VEC4S + i / 4][i % 4] = t.mu[i] as f32;
            }
        }
        g
    }
}
