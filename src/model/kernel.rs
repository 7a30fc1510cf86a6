//! The per-lane formulas of the model, each written once (docs/model.md
//! sections 2 to 5): the motor's force, the paper's friction law, the
//! sliding speed, the switching function φ, the force transfer function
//! ψ and the equation of motion. Plain numbers in, a number out, no
//! branch the compiler cannot make a select: the one-lane code calls them
//! with a lane's fields, the vector code with lane j's columns inside a
//! loop over the lanes, and both get the same bits.
//!
//! [`KERNEL`] lists them; the shader has a function of each name
//! (`shaders/model/kernel.wgsl`), and an architecture test fails when one is
//! defined twice in `src/` or missing from the shader.

use super::laws::MotorKind;
use super::vmath::pow;

/// The kernel's functions, by name: each is defined once in `src/` and
/// mirrored by a WGSL function of the same name.
pub const KERNEL: [&str; 8] = [
    "kloss",
    "motor_force_of",
    "paper_rho",
    "sliding_speed",
    "load_term",
    "switching",
    "psi_parts",
    "motion_parts",
];

/// The Kloss force of an induction motor at speed `v`, in the form
/// 2 f σ σk / (σ² + σk²) with slip σ = (v_sync − v)/v_sync: finite at
/// σ = 0, negative above synchronous speed (generator braking).
#[inline(always)]
pub fn kloss(v_sync: f64, sigma_k: f64, f_crit: f64, v: f64) -> f64 {
    let sigma = (v_sync - v) / v_sync;
    let sk = sigma_k;
    2.0 * f_crit * sigma * sk / (sigma * sigma + sk * sk)
}

/// The motor force F1 at speed `v` under law `motor` (`f1` for a constant
/// motor, the [`kloss`] force otherwise); 0 once the motor is off.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn motor_force_of(
    motor: MotorKind,
    on: bool,
    f1: f64,
    v_sync: f64,
    sigma_k: f64,
    f_crit: f64,
    v: f64,
) -> f64 {
    // Both computed, one kept: a select, so a loop over lanes stays
    // vector code.
    let k = kloss(v_sync, sigma_k, f_crit, v);
    let f = if motor == MotorKind::Constant { f1 } else { k };
    if on {
        f
    } else {
        0.0
    }
}

/// The paper's friction angle ρ = (π/180) / (a Vs^b + c), radians, at
/// sliding speed `vs` >= 0 (docs/model.md section 5).
#[inline(always)]
pub(crate) fn paper_rho(fa: f64, fb: f64, fc: f64, vs: f64) -> f64 {
    (std::f64::consts::PI / 180.0) / (fa * pow(vs, fb) + fc)
}

/// The sliding speed Vs = max(s ẋ1, 0) / cos γ of a lane moving in
/// direction `dir` (s) at speed `v` (ẋ1); `inv_cos_g` is 1 / cos γ.
/// Inside a step the direction is frozen: past a rest the speed stays 0,
/// which keeps the right-hand side finite and continuous for root finding.
#[inline(always)]
pub(crate) fn sliding_speed(dir: f64, v: f64, inv_cos_g: f64) -> f64 {
    (dir * v).max(0.0) * inv_cos_g
}

/// F2 / (m2 tan γ): the load's part of the switching function.
#[inline(always)]
pub(crate) fn load_term(f2: f64, m2: f64, tan_g: f64) -> f64 {
    f2 / (m2 * tan_g)
}

/// The switching function φ = F1/m1 − F2/(m2 tan γ) from the motor force
/// `f1` and [`load_term`]: the a-a side when > 0, b-b when < 0.
#[inline(always)]
pub(crate) fn switching(f1: f64, m1: f64, load: f64) -> f64 {
    f1 / m1 - load
}

/// The force transfer function ψ = −tan(γ + c s ρ) = −p/q by the tangent
/// sum, as (p, q) = (tan γ + t, 1 − tan γ t), where `t` is c s tan ρ
/// (the contact side c and direction s of the mode).
#[inline(always)]
pub fn psi_parts(tan_g: f64, t: f64) -> (f64, f64) {
    (tan_g + t, 1.0 - tan_g * t)
}

crate::lanewise_struct! {
    /// What the equation of motion gives in one mode at one speed;
    /// [`Motions`] holds W lanes' as columns.
    #[derive(Clone, Copy, Debug, Default)]
    pub struct Motion, Motions {
        /// ẍ1
        pub acc: f64,
        /// D = m1 − ψ m2 tan γ; the mode is inconsistent when D <= 0.
        pub d: f64,
        /// The motor force F1.
        pub f1: f64,
        /// The contact reaction S1 on body 1.
        pub s1: f64,
        /// The contact reaction S2 on body 2.
        pub s2: f64,
        /// The force transfer function ψ.
        pub psi: f64,
    }
}

/// The equation of motion (docs/model.md section 3) from the motor force
/// `f1` and the signed tan ρ `t` ([`psi_parts`]): multiplied through by
/// q, one division is left on the path to ẍ1.
#[inline(always)]
pub fn motion_parts(f1: f64, t: f64, tan_g: f64, m1: f64, m2: f64, f2: f64) -> Motion {
    let (p, q) = psi_parts(tan_g, t);
    // D·q = m1 q + p m2 tan γ
    let dq = m1 * q + p * m2 * tan_g;
    let acc = (f1 * q + p * f2) / dq;
    Motion {
        acc,
        d: dq / q,
        f1,
        s1: f1 - m1 * acc,
        s2: f2 - m2 * tan_g * acc,
        psi: -p / q,
    }
}
