//! The shader: the TSWM hybrid integrator in WGSL, one lane per
//! invocation, in f32 ([`SHADER`]) or in f64 ([`SHADER_F64`]).
//!
//! It is the same algorithm as the f64 CPU path, in the same parts and
//! order, one file per Rust module under `shaders/` (listed in
//! [`SHADER_FILES`], in the order a lane's values pass through them) and
//! joined into one source at build time: WGSL has no modules or
//! includes, and a pipeline is made from one source. Each file's first
//! line names the Rust file it mirrors, and a Rust helper with a WGSL twin
//! has the same name there ([`MIRRORED`], and the model's
//! [`KERNEL`](crate::model::kernel::KERNEL)); a test checks the names on
//! both sides. The files compute in `real`, which the [`prelude_of`] each
//! shader starts with declares as f32 or f64, with the transcendental
//! functions they call (`pow_r`, `exp_r`, `tan_r`) and the constants the
//! two sides share (law, flag, status and event codes, the Dormand–Prince
//! tableau, the agma law's constants and the limits below), generated
//! from the Rust declarations rather than kept in step by hand; a test
//! fails on a shader file that declares one itself.
//!
//! Differences forced by f32: x1, the works and the time are compensated
//! (Kahan) sums; the per-step tolerance is 1e-6 rather than 1e-8
//! ([`GPU_TOL`](super::layout::GPU_TOL)); event roots are located to a
//! step fraction of [`ROOT_THETA_TOL`] rather than to 1e-13 s; a step
//! below [`STEP_UNDERFLOW`]·max(t, 1) s, not 1e-15·max(t, 1), is an
//! underflow; `tan_small`'s series stops at x^9, exact in f32; "never" is
//! 3e38 rather than infinity. In f64 the limits are the CPU path's (roots
//! to a step fraction of [`ROOT_THETA_TOL_F64`]), the tolerances the CPU
//! path's, the error budget (`accuracy.wgsl`, `KEEP_BUDGET`) kept as the
//! CPU path keeps it, and the sums keep their compensation, which f64
//! does not need. The f64 path
//! computes x^y and the step factor's err^(−1/5) with its own
//! straight-line kernels (so that they run as vector code); here `pow_r`
//! does. Where a mesh power changes sign inside a step, the f64 path
//! finds the zero by the Illinois method, the shader by halvings down to
//! [`P_ZERO_TOL`].

use std::fmt::Write;
use std::sync::LazyLock;

use super::real::ShaderReal;
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

/// The shader source in f32: the [`prelude`] generated from the Rust
/// declarations, then the files of [`SHADER_FILES`].
pub static SHADER: LazyLock<String> = LazyLock::new(|| prelude() + FILES);

/// The shader source in f64: the prelude of [`ShaderReal::F64`], the f64
/// functions written from arithmetic (`shaders/f64/math.wgsl`), then the
/// same files as [`SHADER`]'s.
pub static SHADER_F64: LazyLock<String> = LazyLock::new(|| {
    prelude_of(ShaderReal::F64) + include_str!("../../../shaders/f64/math.wgsl") + "\n" + FILES
});

/// `(name, value)` of Rust constants, each named once: the shader's
/// constant of the same name is generated from it.
macro_rules! named {
    ($($m:ident :: $c:ident),+ $(,)?) => {
        [$((stringify!($c), $m::$c as f64)),+]
    };
}

/// What the shader shares with the Rust, generated from the Rust
/// declarations rather than kept in step by hand: each law's code under
/// its word (`MOTOR_KLOSS`, `FRICTION_AGMA`) and the lane's law slots
/// (`model::laws`); the state's flag bits (`F_*`, `layout::flags`), the
/// status codes (`S_*`, `Status`), the event functions (`EV_*`,
/// `EventFn`), the state's components (`NY`) and a friction table's
/// points (`TABLE_VEC4S`); the Dormand–Prince tableau
/// (`stepper::TABLEAU`); the agma law's constants (`model::laws`); and
/// the f32 limits stated below. The shader's files declare no constant
/// of these names (a test holds them to it). This is [`SHADER`]'s, in
/// f32; [`prelude_of`] gives either.
pub fn prelude() -> String {
    prelude_of(ShaderReal::F32)
}

/// The error budget's constants the f64 shader's step control reads
/// (`caps`, `capped`): its aim, the tolerances it steers at, and the
/// floor of a capped error scale and the loosest tolerance it follows.
const BUDGET_REALS: [(&str, f64); 4] = [
    ("BUDGET_AIM", crate::integrator::accuracy::BUDGET_AIM),
    ("STEER_ABOVE", crate::integrator::settings::STEER_ABOVE),
    ("REFINE_FACTOR", crate::integrator::settings::REFINE_FACTOR),
    ("CAP_FLOOR_TOL", crate::integrator::settings::CAP_FLOOR_TOL),
];

/// The prelude with `real` as `real`: the alias, the transcendental
/// functions the files call (`pow_r`, `exp_r`, `tan_r`: WGSL's built-ins
/// in f32, the ones of `shaders/f64/math.wgsl` in f64, since the
/// built-ins are not defined for f64 in SPIR-V), the constants in that
/// type, and the limits of that type's path.
pub fn prelude_of(real: ShaderReal) -> String {
    use crate::integrator::events::EventFn;
    use crate::integrator::{accuracy, Status, NY};
    use crate::model::laws;
    let mut s = String::from("// Generated from the Rust declarations (backend/gpu/shader.rs).\n");
    let (ty, suffix, f) = match real {
        ShaderReal::F32 => ("f32", "f", ""),
        ShaderReal::F64 => ("f64", "lf", "_64"),
    };
    let _ = writeln!(s, "alias real = {ty};");
    let _ = writeln!(
        s,
        "fn pow_r(x: real, y: real) -> real {{ return pow{f}(x, y); }}"
    );
    let _ = writeln!(s, "fn exp_r(x: real) -> real {{ return exp{f}(x); }}");
    let _ = writeln!(s, "fn tan_r(x: real) -> real {{ return tan{f}(x); }}");
    // The error budget (`integrator::accuracy`) is kept in f64 only: an
    // f32 row is vouched for by the host's checks, not by an estimate.
    let _ = writeln!(s, "const KEEP_BUDGET: bool = {};", real == ShaderReal::F64);
    let mut u32s: Vec<(String, u32)> = Vec::new();
    u32s.extend(MotorKind::ALL.map(|m| (format!("MOTOR_{}", m.name().to_uppercase()), m.code())));
    u32s.extend(
        FrictionKind::ALL.map(|f| (format!("FRICTION_{}", f.name().to_uppercase()), f.code())),
    );
    u32s.push(("LAW_SLOTS".into(), LAW_SLOTS as u32));
    u32s.extend(
        super::layout::flags::ALL
            .iter()
            .map(|&(n, v)| (format!("F_{n}"), v)),
    );
    u32s.extend(Status::ALL.map(|st| (format!("S_{}", st.name().to_uppercase()), st.code())));
    u32s.extend(
        EventFn::ALL.map(|e| (format!("EV_{}", format!("{e:?}").to_uppercase()), e as u32)),
    );
    u32s.push(("NY".into(), NY as u32));
    u32s.push(("RESULTS".into(), accuracy::RESULTS as u32));
    u32s.push((
        "TABLE_VEC4S".into(),
        (crate::model::MAX_TABLE_POINTS / 4) as u32,
    ));
    for (n, v) in u32s {
        let _ = writeln!(s, "const {n}: u32 = {v}u;");
    }
    let mut reals: Vec<(&str, f64)> = crate::integrator::stepper::TABLEAU.to_vec();
    reals.extend(named!(
        laws::FT_PER_MIN_PER_M_PER_S,
        laws::AGMA_LOW_A,
        laws::AGMA_LOW_B,
        laws::AGMA_LOW_E,
        laws::AGMA_HIGH_A,
        laws::AGMA_HIGH_B,
        laws::AGMA_HIGH_E,
        laws::AGMA_HIGH_C,
    ));
    reals.push(("PI", std::f64::consts::PI));
    reals.extend(BUDGET_REALS);
    reals.extend(match real {
        ShaderReal::F32 => [
            ("STEP_UNDERFLOW", STEP_UNDERFLOW as f64),
            ("JAM_D", JAM_D_F32 as f64),
            ("ROOT_THETA_TOL", ROOT_THETA_TOL as f64),
            ("P_ZERO_TOL", P_ZERO_TOL as f64),
        ],
        ShaderReal::F64 => [
            ("STEP_UNDERFLOW", crate::integrator::control::STEP_UNDERFLOW),
            ("JAM_D", crate::integrator::control::JAM_D),
            ("ROOT_THETA_TOL", ROOT_THETA_TOL_F64),
            ("P_ZERO_TOL", crate::integrator::flow::P_ZERO_TOL),
        ],
    });
    for (n, v) in reals {
        // Rust's shortest digits of the value in the shader's type, read
        // back as that value.
        let _ = match real {
            ShaderReal::F32 => writeln!(s, "const {n}: real = {:?}{suffix};", v as f32),
            ShaderReal::F64 => writeln!(s, "const {n}: real = {v:?}{suffix};"),
        };
    }
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
    "integrator/accuracy.wgsl",
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
    "branch_of",
    "branch_edges",
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
    "capped",
    "dense_coeffs",
    "dense_r5",
    "try_step",
    "step_factor",
    "step_size",
    "retry_size",
    "dense_v",
    "event_value",
    "locate_root",
    "branch_value",
    "crossed_edge",
    "left_upwards",
    "earliest_event",
    "dense_slope",
    "split",
    "crosses",
    "split_whole",
    "agrees",
    "split_against",
    "split_crossing",
    "dense_w",
    "step_flow",
    "split_error",
    "powers",
    "parts",
    "rates",
    "add_step",
    "add_split",
    "caps",
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

/// A step underflow on the GPU where D has fallen below this fraction
/// of m1 is the wedge jamming (`JAM_D` in the shader; the f64 path's is
/// [`control::JAM_D`](crate::integrator::control::JAM_D)). D falls as
/// the square root of the time left, so f32's underflow, 1e8 times f64's
/// in a step's size, would come at D some 1e4 times as large: f64's
/// 8.5e-8 to 8.5e-7 of m1 would be 1e-3 to 1e-2. On random jamming lanes
/// f32's steps cross D = 0 before they underflow (the step's end finds
/// D < 0); this bound, five times that estimate, is kept for lanes that
/// do not.
pub const JAM_D_F32: f32 = 5e-2;

/// An event's root is located to this fraction of its step on the GPU
/// (`ROOT_THETA_TOL` in the shader); the f64 path locates it to
/// [`T_ROOT_TOL`](crate::integrator::events::T_ROOT_TOL) seconds.
pub const ROOT_THETA_TOL: f32 = 1e-6;

/// An event's root is located to this fraction of its step in f64: the
/// f64 path's [`T_ROOT_TOL`](crate::integrator::events::T_ROOT_TOL) of
/// 1e-13 s on a step of 0.1 s, within 100 Illinois iterations from any
/// step.
pub const ROOT_THETA_TOL_F64: f64 = 1e-12;

/// The bisection for a mesh power's zero inside a step ends when its
/// bracket is this fraction of the step (`P_ZERO_TOL` in the shader):
/// 2^-24, f32's resolution on [0, 1], as
/// [`flow::P_ZERO_TOL`](crate::integrator::flow::P_ZERO_TOL) is f64's.
pub const P_ZERO_TOL: f32 = 1.0 / 16_777_216.0;
