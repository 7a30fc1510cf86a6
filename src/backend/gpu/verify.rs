//! The host's check of every GPU row: a row is trusted only when nothing
//! in it says that f32 could not carry the lane; otherwise the lane is
//! recomputed on the f64 path and the row says so (`path` = `cpu:REASON`).
//!
//! Thresholds, by measurement (`cargo run --release --example gpu_trust --
//! random|long|stiff`, docs/gpu.md): on 10,000 random user lanes the
//! energy residual's worst is 1.1e-6, so 1e-5 leaves a factor 9; every
//! GPU row off by more than 5e-3 in the long-horizon and stiff-motor sets
//! has a residual of at least 5.9e-5, or a critical slip of at most
//! 3.7e-4 (1e-3 leaves a factor 2.7), or a status other than `ok`; with
//! the check no row off by more than 5e-3 stays uncaught in any set.

use crate::integrator::{EndState, LaneResult, Recheck, Status};
use crate::model::{FrictionTable, Lane, MotorKind};

/// Largest energy-balance residual (relative to the largest energy term)
/// a trusted row may have.
pub(crate) const ENERGY_RESIDUAL: f64 = 1e-5;

/// Critical slip below which a Kloss motor counts as too stiff for f32:
/// near synchronous speed one f32 step of ẋ1 then moves the motor force
/// by more than 1e-4 of its peak.
pub(crate) const STIFF_SIGMA_K: f64 = 1e-3;

/// Relative rounding of the f32 path's energies, measured as above
/// (worst energy residual 1e-6): a work smaller than this share of the
/// energy that flowed is not resolved to the GPU bound.
const F32_ENERGY_RESOLUTION: f64 = 1e-6;

/// What a trusted row promises at worst: 100 times the GPU bound on x1, v1
/// and the works (5e-5 of max(1, |value|), `tswm check`).
pub const TRUSTED_BOUND: f64 = 100.0 * crate::columns::VALUE_BOUND;

/// Whether f32 represents a lane's inputs: finite, and not so small that
/// they vanish. Lanes that fail go to the f64 path without a GPU attempt.
pub(crate) fn representable(lane: &Lane) -> bool {
    let vals = [
        lane.m1,
        lane.m2,
        lane.tan_g,
        lane.sin_g,
        lane.cos_g,
        lane.inv_cos_g,
        lane.f2,
        lane.v_sync,
        lane.sigma_k,
        lane.f_crit,
        lane.f1,
        lane.law[0],
        lane.law[1],
        lane.law[2],
        lane.law[3],
        lane.law[4],
        lane.mu_s,
        lane.x1_0,
        lane.v1_0,
        lane.t_end,
        lane.t_max,
    ];
    let ok = |v: f64| {
        let a = v.abs();
        a == 0.0 || (a >= f32::MIN_POSITIVE as f64 && a <= f32::MAX as f64)
    };
    vals.into_iter().all(ok) && (lane.motor_off.is_infinite() || ok(lane.motor_off))
}

/// Why a GPU row cannot be trusted, if it cannot: `r` is the row of the
/// lane's end state `end`; `finished` says whether the lane reached its
/// end within the dispatch budget.
pub fn recheck(
    lane: &Lane,
    tables: &[FrictionTable],
    end: &EndState,
    r: &LaneResult,
    finished: bool,
) -> Option<Recheck> {
    if !finished {
        return Some(Recheck::Unfinished);
    }
    if r.status != Status::Ok {
        return Some(Recheck::GpuStatus);
    }
    if !r
        .integrated()
        .iter()
        .all(|v| v.is_finite() && v.abs() <= f32::MAX as f64)
    {
        return Some(Recheck::NonFinite);
    }
    if lane.motor == MotorKind::Kloss && lane.sigma_k < STIFF_SIGMA_K {
        return Some(Recheck::StiffMotor);
    }
    // docs/model.md section 6: w_motor + w_load − w_friction = ΔKE.
    let m = lane.m1 + lane.m2 * lane.tan_g * lane.tan_g;
    let ke = 0.5 * m * (r.v1_end * r.v1_end - lane.v1_0 * lane.v1_0);
    let scale = [
        1.0,
        r.w_motor.abs(),
        r.w_load.abs(),
        r.w_friction,
        ke.abs(),
        r.w1_in,
        r.w2_in,
    ]
    .into_iter()
    .fold(0.0, f64::max);
    // docs/model.md section 10: w1_in − w1_out + w2_in − w2_out = w_friction.
    let mesh = r.w1_in - r.w1_out + r.w2_in - r.w2_out - r.w_friction;
    if (r.w_motor + r.w_load - r.w_friction - ke).abs() > ENERGY_RESIDUAL * scale
        || mesh.abs() > ENERGY_RESIDUAL * scale
    {
        return Some(Recheck::EnergyBalance);
    }
    // w_motor (a motor that drives, then brakes) and w_load (a reversal)
    // have integrands that change sign; w_friction's, p1 + p2, is the
    // difference of the two mesh powers, nearly equal where the mesh
    // passes nearly all of its power (an efficiency near 1).
    let res = F32_ENERGY_RESOLUTION * scale;
    let resolved = |w: f64| res <= TRUSTED_BOUND * w.abs().max(1.0);
    if !resolved(r.w_motor) || !resolved(r.w_load) || !resolved(r.w_friction) {
        return Some(Recheck::Cancellation);
    }
    if !efficiency_resolved(r.eta_direct, r.w2_out, r.w1_in, r.w2_in, res)
        || !efficiency_resolved(r.eta_inverse, r.w1_out, r.w2_in, r.w1_in, res)
    {
        return Some(Recheck::Efficiency);
    }
    // The words at the end hold within the bound of the end speed.
    let dv = crate::columns::VALUE_BOUND * r.v1_end.abs().max(1.0);
    if !end.words_decided(lane, tables, (r.hold, r.drive), dv) {
        return Some(Recheck::EndSign);
    }
    None
}

/// Whether an efficiency `eta` = `out` / `inp` (NaN: empty, its input at
/// most `EMPTY_SHARE` of the mesh's, `inp` + `other`: docs/model.md section 10)
/// is what f32's energies, each known to `res` J, vouch for: its ratio
/// within the trusted bound (a quotient's error, (res + eta res) / inp
/// to first order, without the first res where `out` is 0), and its
/// emptiness, where some energy went in, not within `res` of the
/// threshold.
fn efficiency_resolved(eta: f64, out: f64, inp: f64, other: f64, res: f64) -> bool {
    let fed = crate::integrator::result::EMPTY_SHARE * (inp + other);
    if inp > 0.0 && (inp - fed).abs() <= res {
        return false;
    }
    // An output of exactly 0 is the mode's (no step gave it any): exact.
    let d_out = if out == 0.0 { 0.0 } else { res };
    eta.is_nan() || d_out + res * eta.abs() <= TRUSTED_BOUND * inp.abs()
}

/// Why an f64 GPU row cannot be trusted, if it cannot: only a lane the
/// dispatch budget cut short. An f64 lane runs the CPU path's algorithm at
/// its settings (`layout::f64_settings`), error budget included, so its
/// row is held to the CPU path's bound; no f32 limit applies. (A lane
/// whose estimate is over the bound is run again at the tighter settings
/// by the backend, as on the CPU path.)
pub fn recheck_f64(finished: bool) -> Option<Recheck> {
    (!finished).then_some(Recheck::Unfinished)
}
