//! The structs and constants shared with the shader (`shaders/`), byte for
//! byte. Tests parse the shader with naga and fail when sizes, offsets or
//! constant values drift.

use bytemuck::{Pod, Zeroable};

use super::real::{Real, ShaderReal, Sizes};

use crate::integrator::accuracy::{ErrorBudget, RESULTS};
use crate::integrator::{EndState, Settings, Status, NY};
use crate::model::laws::LAW_SLOTS;
use crate::model::{FrictionTable, Lane, MAX_TABLES, MAX_TABLE_POINTS};

/// "Never" for f32 times: WGSL may assume there are no infinities.
pub const NEVER: f32 = 3.0e38;

/// Flag bits of `GpuState::flags`: the shader's `F_*` constants.
pub mod flags {
    macro_rules! flags {
        ($($(#[$m:meta])* $name:ident = $value:expr;)*) => {
            $($(#[$m])* pub const $name: u32 = $value;)*
            /// Every flag by its name (the shader's `F_*`: `shader::prelude`).
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
        /// A step's p1 turned and turned back inside it (`Recheck::FlowTurn`).
        FLOW_TURN = 256;
        /// The mode began at a switch and has no accepted step yet.
        JUST_SWITCHED = 512;
        /// A switch ended such a mode (`Recheck::SwitchGraze`).
        GRAZE = 1024;
    }
}

/// Vec4s per friction table in [`GpuGlobals`].
const TABLE_VEC4S: usize = MAX_TABLE_POINTS / 4;

/// Declares the structs shared with the shader for one real type (`$r`:
/// the shader's `real`), so that the f32 and the f64 layouts are one
/// declaration: a lane's constants (`Lane` in shaders/model/lane.wgsl), its
/// state between dispatches (`State` in shaders/integrator/automaton.wgsl)
/// and the run's values (`Globals` in shaders/integrator/batch.wgsl). A
/// test compares each with the shader's, for both types.
macro_rules! gpu_layout {
    ($r:ty, $real:expr, $lane:ident, $state:ident, $globals:ident) => {
        #[doc = concat!("A lane's constants in ", stringify!($r), ": `Lane` in shaders/model/lane.wgsl.")]
        #[repr(C)]
        #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
        pub struct $lane {
            /// [`Lane::m1`].
            pub m1: $r,
            /// [`Lane::m2`].
            pub m2: $r,
            /// [`Lane::tan_g`].
            pub tan_g: $r,
            /// [`Lane::sin_g`].
            pub sin_g: $r,
            /// [`Lane::cos_g`].
            pub cos_g: $r,
            /// [`Lane::inv_cos_g`].
            pub inv_cos_g: $r,
            /// [`Lane::f2`].
            pub f2: $r,
            /// [`Lane::v_sync`].
            pub v_sync: $r,
            /// [`Lane::sigma_k`].
            pub sigma_k: $r,
            /// [`Lane::f_crit`].
            pub f_crit: $r,
            /// [`Lane::f1`].
            pub f1: $r,
            /// [`Lane::motor_off`]; [`NEVER`] when the motor is never cut.
            pub motor_off: $r,
            /// [`Lane::law`].
            pub law: [$r; LAW_SLOTS],
            /// [`Lane::mu_s`].
            pub mu_s: $r,
            /// [`Lane::x1_0`].
            pub x1_0: $r,
            /// [`Lane::v1_0`].
            pub v1_0: $r,
            /// [`Lane::t_end`].
            pub t_end: $r,
            /// t_end when the lane does not run on (see `model::Lane::t_max`).
            pub t_max: $r,
            /// 1 / cos αn (see `model::Lane::inv_cos_an`).
            pub inv_cos_an: $r,
            /// [`Lane::branch_speed`]; [`NEVER`] for a law with one branch.
            pub branch_speed: $r,
            /// [`Lane::motor`] as its code ([`MotorKind::code`](crate::model::MotorKind::code)).
            pub motor: u32,
            /// [`Lane::friction`] as its code ([`FrictionKind::code`](crate::model::FrictionKind::code)).
            pub friction: u32,
            /// Which of the run's friction tables.
            pub table: u32,
            /// [`Lane::steep`]: 1 when the friction law is steep at rest.
            pub steep: u32,
        }

        impl From<&Lane> for $lane {
            fn from(l: &Lane) -> Self {
                let never = |v: f64| if v.is_finite() { v as $r } else { NEVER as $r };
                $lane {
                    m1: l.m1 as $r,
                    m2: l.m2 as $r,
                    tan_g: l.tan_g as $r,
                    sin_g: l.sin_g as $r,
                    cos_g: l.cos_g as $r,
                    inv_cos_g: l.inv_cos_g as $r,
                    f2: l.f2 as $r,
                    v_sync: l.v_sync as $r,
                    sigma_k: l.sigma_k as $r,
                    f_crit: l.f_crit as $r,
                    f1: l.f1 as $r,
                    motor_off: never(l.motor_off),
                    law: l.law.map(|v| v as $r),
                    mu_s: l.mu_s as $r,
                    x1_0: l.x1_0 as $r,
                    v1_0: l.v1_0 as $r,
                    t_end: l.t_end as $r,
                    t_max: l.t_max as $r,
                    inv_cos_an: l.inv_cos_an as $r,
                    branch_speed: never(l.branch_speed),
                    motor: l.motor.code(),
                    friction: l.friction.code(),
                    table: l.table,
                    steep: l.steep as u32,
                }
            }
        }

        #[doc = concat!("A lane's integration state between dispatches, in ", stringify!($r), ": `State` in")]
        /// shaders/integrator/automaton.wgsl. 52 reals and 16 words: no
        /// hidden padding in f32 or f64.
        #[repr(C)]
        #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
        pub struct $state {
            /// The time, s: a compensated (Kahan) sum whose value is t_hi − t_lo.
            pub t_hi: $r,
            /// The compensation of `t_hi`.
            pub t_lo: $r,
            /// The step size to try next, s.
            pub h: $r,
            /// < 0 until the first switch.
            pub t_first_switch: $r,
            /// w1_in, w1_out, w2_in, w2_out (a vec4 in the shader).
            pub flow: [$r; 4],
            /// Kahan compensations of `flow`.
            pub flow_c: [$r; 4],
            /// The integrated components (x1, v1, w_motor, w_load, w_friction, w_p1; `NY`).
            pub y: [$r; NY],
            /// Kahan compensations of `y`: the value is y − yc.
            pub yc: [$r; NY],
            /// The derivative at the current state, when [`flags::K1_VALID`] is set.
            pub k1: [$r; NY],
            /// The error budget's lag ([`ErrorBudget`]; kept in f64 only).
            pub lag: $r,
            /// The error budget's phase term of each result (f64 only).
            pub phase: [$r; RESULTS],
            /// The error budget's local term of each result (f64 only).
            pub local: [$r; RESULTS],
            /// Padding (see the struct's text).
            pub pad_r: [$r; 3],
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
            /// The friction law's branch the lane slides on (`Mode::branch`).
            pub branch: u32,
            /// Padding (see the struct's text).
            pub pad: [u32; 6],
        }

        impl $state {
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

            /// The lane's error estimate (zero in f32, which keeps none).
            pub fn budget(&self) -> ErrorBudget {
                let f = |v: $r| v as f64;
                ErrorBudget::from_terms(f(self.lag), self.phase.map(f), self.local.map(f))
            }

            /// Where the lane stopped: its own t_end or t_max exactly when it
            /// stopped there (the shader's time would round them), else the
            /// shader's time.
            fn stop_time(&self, lane: &Lane) -> f64 {
                let t = self.t_hi as f64 - self.t_lo as f64;
                if self.flags & flags::RUNNING_ON == 0 {
                    lane.t_end
                } else if self.t_hi == lane.t_max as $r && self.t_lo == 0.0 {
                    lane.t_max
                } else {
                    t
                }
            }
        }

        #[doc = concat!("Run-wide values and the friction tables, in ", stringify!($r), ": `Globals` in")]
        /// shaders/integrator/batch.wgsl.
        #[repr(C)]
        #[derive(Clone, Copy, Debug, Pod, Zeroable)]
        pub struct $globals {
            /// Lanes in the chunk.
            pub n_lanes: u32,
            /// Step attempts per lane per dispatch.
            pub budget: u32,
            /// A lane's step limit ([`Settings::max_steps`]).
            pub max_steps: u32,
            /// A lane's event limit ([`Settings::max_events`]).
            pub max_events: u32,
            /// Number of friction tables.
            pub n_tables: u32,
            /// Invocations per row of a 2-D dispatch.
            pub row_lanes: u32,
            /// Slots (invocations) working through the chunk's lanes.
            pub n_slots: u32,
            /// Padding to the shader's 16-byte rows.
            pub pad0: u32,
            /// The per-step tolerance of the works.
            pub tol: $r,
            /// The per-step tolerance of x1 and ẋ1.
            pub tol_traj: $r,
            /// The first step after every start from rest, s (`integrator::control::H_INITIAL`).
            pub h_initial: $r,
            /// Padding (see the shader's struct).
            pub pad_r: $r,
            /// Points of each table (a vec4 array in the shader: 16-aligned).
            pub table_n: [[u32; 4]; MAX_TABLES / 4],
            /// Table t's point i is at `[t * TABLE_VEC4S + i / 4][i % 4]`.
            pub table_vs: [[$r; 4]; MAX_TABLES * TABLE_VEC4S],
            /// μ of table t's point i, at `[t * TABLE_VEC4S + i / 4][i % 4]`.
            pub table_mu: [[$r; 4]; MAX_TABLES * TABLE_VEC4S],
        }

        impl $globals {
            /// Globals for a run at per-step tolerances `tol` (the works)
            /// and `tol_traj` (x1 and ẋ1), with `settings`' limits and the
            /// run's friction tables (at most [`MAX_TABLES`]: the sweep
            /// reader refuses more).
            fn with_tol(
                settings: &Settings,
                tables: &[FrictionTable],
                tol: f64,
                tol_traj: f64,
            ) -> $globals {
                let mut g = $globals {
                    n_lanes: 0,
                    budget: 0,
                    max_steps: settings.max_steps,
                    max_events: settings.max_events,
                    n_tables: tables.len().min(MAX_TABLES) as u32,
                    row_lanes: 0,
                    n_slots: 0,
                    pad0: 0,
                    tol: tol as $r,
                    tol_traj: tol_traj as $r,
                    h_initial: crate::integrator::H_INITIAL as $r,
                    pad_r: 0.0,
                    table_n: [[0; 4]; MAX_TABLES / 4],
                    table_vs: [[0.0; 4]; MAX_TABLES * TABLE_VEC4S],
                    table_mu: [[0.0; 4]; MAX_TABLES * TABLE_VEC4S],
                };
                for (k, t) in tables.iter().take(MAX_TABLES).enumerate() {
                    g.table_n[k / 4][k % 4] = t.n as u32;
                    for i in 0..t.n {
                        g.table_vs[k * TABLE_VEC4S + i / 4][i % 4] = t.vs[i] as $r;
                        g.table_mu[k * TABLE_VEC4S + i / 4][i % 4] = t.mu[i] as $r;
                    }
                }
                g
            }
        }

        impl Real for $r {
            type Lane = $lane;
            type State = $state;
            type Globals = $globals;
            const SHADER: ShaderReal = $real;
            fn globals(settings: &Settings, tables: &[FrictionTable]) -> $globals {
                $globals::new(settings, tables)
            }
            fn sizes(g: &mut $globals) -> &mut Sizes {
                bytemuck::from_bytes_mut(&mut bytemuck::bytes_of_mut(g)[..std::mem::size_of::<Sizes>()])
            }
            fn end_state(s: &$state, lane: &Lane) -> EndState {
                s.end_state(lane)
            }
            fn flags(s: &$state) -> u32 {
                s.flags
            }
            fn budget(s: &$state) -> ErrorBudget {
                s.budget()
            }
        }
    };
}

gpu_layout!(f32, ShaderReal::F32, GpuLane, GpuState, GpuGlobals);
gpu_layout!(f64, ShaderReal::F64, GpuLane64, GpuState64, GpuGlobals64);

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
    /// and is replaced by [`GPU_TOL`] on every component) and its friction
    /// tables (at most [`MAX_TABLES`]: the sweep reader refuses more).
    pub fn new(settings: &Settings, tables: &[FrictionTable]) -> GpuGlobals {
        GpuGlobals::with_tol(settings, tables, GPU_TOL_F64, GPU_TOL_F64)
    }
}

/// The settings the f64 GPU path runs a run of `settings` at: the CPU
/// path's own. An f64 lane keeps the CPU path's error budget
/// (`accuracy`), and a lane whose estimate is over the bound is run again
/// on the CPU at [`Settings::tighter`], as a CPU lane is. Its globals, its
/// provenance and `tswm check`'s reference all take them from here.
pub fn f64_settings(settings: &Settings) -> Settings {
    *settings
}

impl GpuGlobals64 {
    /// Globals for a run in f64, at [`f64_settings`] of `settings`.
    pub fn new(settings: &Settings, tables: &[FrictionTable]) -> GpuGlobals64 {
        let t = f64_settings(settings);
        GpuGlobals64::with_tol(settings, tables, t.tol_of(2), t.tol_of(0))
    }
}
