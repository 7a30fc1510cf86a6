//! The Dormand–Prince 5(4) stepper: its tableau, the right-hand side, and
//! one trial step with error estimate and dense output.
//!
//! The per-stage arithmetic is written once, per lane, in the small
//! `stage*_v`, `increment`, `error_term`, `error_scale` and `dense_coeffs`
//! functions; `try_steps` runs them for N interleaved lanes and the
//! shader's `try_step` (section `src/integrator/stepper.rs` of
//! `shaders/tswm.wgsl`) for one, line for line.

use super::{Settings, NY};
use crate::model::{motion, FrictionTable, Lane};

// Dormand–Prince 5(4) tableau. Keep in sync with the shader (a test reads
// its constants and compares).
// Stage times c2..c5 (1/5, 3/10, 4/5, 8/9) are not needed: between events
// the right-hand side is autonomous.
pub const A21: f64 = 1.0 / 5.0;
pub const A31: f64 = 3.0 / 40.0;
pub const A32: f64 = 9.0 / 40.0;
pub const A41: f64 = 44.0 / 45.0;
pub const A42: f64 = -56.0 / 15.0;
pub const A43: f64 = 32.0 / 9.0;
pub const A51: f64 = 19372.0 / 6561.0;
pub const A52: f64 = -25360.0 / 2187.0;
pub const A53: f64 = 64448.0 / 6561.0;
pub const A54: f64 = -212.0 / 729.0;
pub const A61: f64 = 9017.0 / 3168.0;
pub const A62: f64 = -355.0 / 33.0;
pub const A63: f64 = 46732.0 / 5247.0;
pub const A64: f64 = 49.0 / 176.0;
pub const A65: f64 = -5103.0 / 18656.0;
pub const A71: f64 = 35.0 / 384.0;
pub const A73: f64 = 500.0 / 1113.0;
pub const A74: f64 = 125.0 / 192.0;
pub const A75: f64 = -2187.0 / 6784.0;
pub const A76: f64 = 11.0 / 84.0;
pub const E1: f64 = 71.0 / 57600.0;
pub const E3: f64 = -71.0 / 16695.0;
pub const E4: f64 = 71.0 / 1920.0;
pub const E5: f64 = -17253.0 / 339200.0;
pub const E6: f64 = 22.0 / 525.0;
pub const E7: f64 = -1.0 / 40.0;
// Dense output (Hairer & Wanner's dopri5 contd5).
pub const D1: f64 = -12715105075.0 / 11282082432.0;
pub const D3: f64 = 87487479700.0 / 32700410799.0;
pub const D4: f64 = -10690763975.0 / 1880347072.0;
pub const D5: f64 = 701980252875.0 / 199316789632.0;
pub const D6: f64 = -1453857185.0 / 822651844.0;
pub const D7: f64 = 69997945.0 / 29380423.0;

pub use crate::model::Mode;

/// Right-hand side: derivative of (x1, ẋ1, w_motor, w_load, w_friction,
/// w_p1), and D of the mode. Depends on ẋ1 only: x1 and the works are
/// quadratures. p1 = S1 ẋ1 and p2 = S2 ẋ2 are the powers the bodies put
/// into the mesh (docs/model.md section 10).
#[inline]
pub fn rhs(lane: &Lane, tables: &[FrictionTable], mode: Mode, v: f64) -> ([f64; NY], f64) {
    let m = motion(lane, tables, mode, v);
    let v2 = v * lane.tan_g;
    let (p1, p2) = (m.s1 * v, m.s2 * v2);
    ([v, m.acc, m.f1 * v, lane.f2 * v2, p1 + p2, p1], m.d)
}

// ẋ1 at which stages 2 to 6 evaluate the right-hand side (only ẋ1 is
// needed: the right-hand side depends on nothing else).
#[inline]
fn stage2_v(v0: f64, h: f64, k1: f64) -> f64 {
    v0 + h * (A21 * k1)
}
#[inline]
fn stage3_v(v0: f64, h: f64, k1: f64, k2: f64) -> f64 {
    v0 + h * (A31 * k1 + A32 * k2)
}
#[inline]
fn stage4_v(v0: f64, h: f64, k1: f64, k2: f64, k3: f64) -> f64 {
    v0 + h * (A41 * k1 + A42 * k2 + A43 * k3)
}
#[inline]
fn stage5_v(v0: f64, h: f64, k1: f64, k2: f64, k3: f64, k4: f64) -> f64 {
    v0 + h * (A51 * k1 + A52 * k2 + A53 * k3 + A54 * k4)
}
#[inline]
fn stage6_v(v0: f64, h: f64, k1: f64, k2: f64, k3: f64, k4: f64, k5: f64) -> f64 {
    v0 + h * (A61 * k1 + A62 * k2 + A63 * k3 + A64 * k4 + A65 * k5)
}

/// Fifth-order increment of one component over the step.
#[inline]
fn increment(h: f64, k1: f64, k3: f64, k4: f64, k5: f64, k6: f64) -> f64 {
    h * (A71 * k1 + A73 * k3 + A74 * k4 + A75 * k5 + A76 * k6)
}

/// Embedded error estimate of one component.
#[inline]
fn error_term(h: f64, k1: f64, k3: f64, k4: f64, k5: f64, k6: f64, k7: f64) -> f64 {
    h * (E1 * k1 + E3 * k3 + E4 * k4 + E5 * k5 + E6 * k6 + E7 * k7)
}

/// Error scale of one component: tol relative to max(1, |y|) over the step.
#[inline]
fn error_scale(tol: f64, y0: f64, y1: f64) -> f64 {
    tol * (1.0 + y0.abs().max(y1.abs()))
}

/// Dense-output coefficients of a component over the step from its value
/// `v0` to `v1` (see `events::dense_v`).
#[inline]
#[allow(clippy::too_many_arguments)]
fn dense_coeffs(
    v0: f64,
    v1: f64,
    h: f64,
    k1: f64,
    k3: f64,
    k4: f64,
    k5: f64,
    k6: f64,
    k7: f64,
) -> [f64; 5] {
    let r2 = v1 - v0;
    let r3 = h * k1 - r2;
    let r4 = r2 - h * k7 - r3;
    [v0, r2, r3, r4, dense_r5(h, k1, k3, k4, k5, k6, k7)]
}

/// The last dense-output coefficient of a component: the only one that
/// needs the inner stages.
#[inline]
pub(crate) fn dense_r5(h: f64, k1: f64, k3: f64, k4: f64, k5: f64, k6: f64, k7: f64) -> f64 {
    h * (D1 * k1 + D3 * k3 + D4 * k4 + D5 * k5 + D6 * k6 + D7 * k7)
}

/// The outcome of a trial step.
#[derive(Clone, Copy, Default, Debug)]
pub struct Trial {
    pub(crate) y1: [f64; NY],
    pub(crate) k7: [f64; NY],
    /// Error norm: <= 1 means accepted.
    pub(crate) err: f64,
    /// Dense-output coefficients of ẋ1 (r1..r5).
    pub(crate) dense_v: [f64; 5],
    /// The step's increments of ∫p1 and ∫p2 (w_p1, and w_friction −
    /// w_p1), and the last coefficient of their dense outputs (the only
    /// one that needs the inner stages; `flow::dense_w` forms the rest).
    pub(crate) dw: [f64; 2],
    pub(crate) dw_r4: [f64; 2],
    /// The embedded error estimate of each component and, last, of ∫p2 dt
    /// (absolute; the accuracy budget adds them up, see `accuracy`).
    pub(crate) est: [f64; NY + 1],
}

/// One trial step of size h from (y, k1).
#[inline]
pub(crate) fn try_step(
    lane: &Lane,
    tables: &[FrictionTable],
    mode: Mode,
    y: &[f64; NY],
    k1: &[f64; NY],
    h: f64,
    set: &Settings,
) -> Trial {
    try_steps::<1>([lane], tables, [mode], &[*y], &[*k1], [h], [true], set)[0]
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
    tables: &[FrictionTable],
    mode: [Mode; N],
    y: &[[f64; NY]; N],
    k1: &[[f64; NY]; N],
    h: [f64; N],
    active: [bool; N],
    set: &Settings,
) -> [Trial; N] {
    // x1 and ẋ1 may be held tighter than the works (`Settings::traj_weight`).
    let tol_of = |i: usize| {
        if i < 2 {
            set.tol * set.traj_weight
        } else {
            set.tol
        }
    };
    let z = [[0.0; NY]; N];
    let (mut k2, mut k3, mut k4, mut k5, mut k6, mut k7) = (z, z, z, z, z, z);
    let mut tr = [Trial::default(); N];
    let f = |j: usize, v: f64| rhs(lane[j], tables, mode[j], v).0;
    let on = || (0..N).filter(|&j| active[j]);
    for j in on() {
        k2[j] = f(j, stage2_v(y[j][1], h[j], k1[j][1]));
    }
    for j in on() {
        k3[j] = f(j, stage3_v(y[j][1], h[j], k1[j][1], k2[j][1]));
    }
    for j in on() {
        k4[j] = f(j, stage4_v(y[j][1], h[j], k1[j][1], k2[j][1], k3[j][1]));
    }
    for j in on() {
        let v = stage5_v(y[j][1], h[j], k1[j][1], k2[j][1], k3[j][1], k4[j][1]);
        k5[j] = f(j, v);
    }
    for j in on() {
        let (a, b, c, d, e) = (k1[j][1], k2[j][1], k3[j][1], k4[j][1], k5[j][1]);
        k6[j] = f(j, stage6_v(y[j][1], h[j], a, b, c, d, e));
    }
    for j in on() {
        for i in 0..NY {
            let dy = increment(h[j], k1[j][i], k3[j][i], k4[j][i], k5[j][i], k6[j][i]);
            tr[j].y1[i] = y[j][i] + dy;
        }
    }
    for j in on() {
        k7[j] = f(j, tr[j].y1[1]);
    }
    for j in on() {
        let (k1, k3, k4, k5, k6, k7, h, t) = (
            &k1[j], &k3[j], &k4[j], &k5[j], &k6[j], &k7[j], h[j], &mut tr[j],
        );
        let mut err: f64 = 0.0;
        for i in 0..NY {
            let e = error_term(h, k1[i], k3[i], k4[i], k5[i], k6[i], k7[i]);
            err = err.max(e.abs() / error_scale(tol_of(i), y[j][i], t.y1[i]));
            t.est[i] = e.abs();
        }
        t.err = if err.is_finite() { err } else { f64::INFINITY };
        t.k7 = *k7;
        t.dense_v = dense_coeffs(
            y[j][1], t.y1[1], h, k1[1], k3[1], k4[1], k5[1], k6[1], k7[1],
        );
        // ∫p1 is component 5; ∫p2 the difference of components 4 and 5.
        let p2 = |k: &[f64; NY]| k[4] - k[5];
        let (a, c, d, e, f, g) = (p2(k1), p2(k3), p2(k4), p2(k5), p2(k6), p2(k7));
        t.dw = [
            increment(h, k1[5], k3[5], k4[5], k5[5], k6[5]),
            increment(h, a, c, d, e, f),
        ];
        t.dw_r4 = [
            dense_r5(h, k1[5], k3[5], k4[5], k5[5], k6[5], k7[5]),
            dense_r5(h, a, c, d, e, f, g),
        ];
        t.est[NY] = error_term(h, a, c, d, e, f, g).abs();
    }
    tr
}
