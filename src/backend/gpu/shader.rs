//! The shader: the TSWM hybrid integrator in WGSL, one lane per
//! invocation, in f32.
//!
//! It is the same algorithm as the f64 CPU path, in the same parts and
//! order, one file per Rust module under `shaders/` (listed in
//! [`SHADER_FILES`], in the order a lane's values pass through them) and
//! joined into one source at build time ([`SHADER`]): WGSL has no modules
//! or includes, and a pipeline is made from one source. Each file's first
//! line names the Rust file it mirrors, and a Rust helper with a WGSL twin
//! has the same name there ([`MIRRORED`], and the model's
//! [`KERNEL`](crate::model::kernel::KERNEL)); a test checks the names on
//! both sides and the constants the two share (flags, status and event
//! codes, the Dormand–Prince tableau, the agma law's constants and the
//! limits below). The law codes are not kept in step: the [`prelude`]
//! generates them from the Rust declarations.
//!
//! Differences forced by f32: x1, the works and the time are compensated
//! (Kahan) sums; the per-step tolerance is 1e-6 rather than 1e-8
//! ([`GPU_TOL`](super::layout::GPU_TOL)); event roots are located to a
//! step fraction of [`ROOT_THETA_TOL`] rather than to 1e-13 s; a step
//! below [`STEP_UNDERFLOW`]·max(t, 1) s, not 1e-15·max(t, 1), is an
//! underflow; `tan_small`'s series stops at x^9, exact in f32; "never" is
//! 3e38 rather than infinity. The f64 path computes x^y and the step
//! factor's err^(−1/5) with its own straight-line kernels (so that they
//! run as vector code); here WGSL's `pow` does. Where a mesh power changes
//! sign inside a step, the f64 path finds the zero by the Illinois method,
//! the shader by halvings down to [`P_ZERO_TOL`].

use std::fmt::Write;
use std::sync::LazyLock;

use crate::model::laws::LAW_SLOTS;
use crate::model::{FrictionKind, MotorKind};

/// Lists the shader's files once: [`SHADER_FILES`] names them and
/// [`SHADER`] joins their text, in that order, after the [`prelude`].
macro_rules! shader_files {
    ($($path:literal),* $(,)?) => {
        /// The shader's files under `shaders/`, in the order they are joined.
        pub const SHADER_FILES: &[&str] = &[$($path),*];
        /// The files of [`SHADER_FILES`] joined.
        const FILES: &str = concat!($(include_str!(concat!("../../../shaders/", $path)), "\n"),*);
    };
}

/// The shader source: the [`prelude`] generated from the Rust
/// declarations, then the files of [`SHADER_FILES`].
pub static SHADER: LazyLock<String> = LazyLock::new(|| prelude() + FILES);

/// What the shader reads from the Rust declarations, generated rather than
/// kept in step by hand: each law's code under its word (`MOTOR_KLOSS`,
/// `FRICTION_AGMA`, from `model::laws`) and the number of law slots of a
/// lane.
pub fn prelude() -> String {
    let mut s = String::from("// Generated from the Rust declarations (model/laws.rs).\n");
    for m in MotorKind::ALL {
        let name = m.name().to_uppercase();
        let _ = writeln!(s, "const MOTOR_{name}: u32 = {}u;", m.code());
    }
    for f in FrictionKind::ALL {
        let name = f.name().to_uppercase();
        let _ = writeln!(s, "const FRICTION_{name}: u32 = {}u;", f.code());
    }
    let _ = writeln!(s, "const LAW_SLOTS: u32 = {LAW_SLOTS}u;");
    s
}

shader_files!(
    "model/lane.wgsl",
    "model/kernel.wgsl",
    "model/friction.wgsl",
    "model/mod.wgsl",
    "integrator/result.wgsl",
    "integrator/components.wgsl",
    "integrator/rhs.wgsl",
    "integrator/stepper.wgsl",
    "integrator/control.wgsl",
    "integrator/events.wgsl",
    "integrator/flow.wgsl",
    "integrator/automaton.wgsl",
    "integrator/step.wgsl",
    "integrator/batch.wgsl",
);

/// The functions of the CPU path, beyond the model's kernel, that the
/// shader mirrors by name and role: each is a `fn` in `src/` and in the
/// shader.
pub const MIRRORED: &[&str] = &[
    // model
    "above_branch",
    "motor_force",
    "tan_small",
    "agma_mu",
    "mu_sliding",
    "phi",
    "side_of",
    "motion",
    "stick_test",
    // integrator
    "rhs",
    "stage2_v",
    "stage3_v",
    "stage4_v",
    "stage5_v",
    "stage6_v",
    "increment",
    "error_term",
    "error_scale",
    "dense_coeffs",
    "dense_r5",
    "try_step",
    "step_factor",
    "step_size",
    "retry_size",
    "dense_v",
    "event_value",
    "locate_root",
    "earliest_event",
    "dense_slope",
    "split",
    "crosses",
    "split_whole",
    "split_crossing",
    "dense_w",
    "step_flow",
    "init",
    "set_side",
    "check_mode",
    "come_to_rest",
    "depart",
    "cut_motor",
    "horizon",
    "reach_time_event",
    "time_stop",
    "prepare",
    "finish_step",
    "add_flow",
    "step_to_event",
    "attempt",
];

/// A step below this fraction of max(t, 1) s is a step underflow on the
/// GPU (`STEP_UNDERFLOW` in the shader): f32 resolves a time to 6e-8 of
/// itself, as [`control::STEP_UNDERFLOW`](crate::integrator::control::STEP_UNDERFLOW)
/// is f64's.
pub const STEP_UNDERFLOW: f32 = 1e-7;

/// An event's root is located to this fraction of its step on the GPU
/// (`ROOT_THETA_TOL` in the shader); the f64 path locates it to
/// [`T_ROOT_TOL`](crate::integrator::events::T_ROOT_TOL) seconds.
pub const ROOT_THETA_TOL: f32 = 1e-6;

/// The bisection for a mesh power's zero inside a step ends when its
/// bracket is this fraction of the step (`P_ZERO_TOL` in the shader):
/// 2^-24, f32's resolution on [0, 1], as
/// [`flow::P_ZERO_TOL`](crate::integrator::flow::P_ZERO_TOL) is f64's.
pub const P_ZERO_TOL: f32 = 1.0 / 16_777_216.0;
