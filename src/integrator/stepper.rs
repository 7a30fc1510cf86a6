//! The Dormand–Prince 5(4) stepper: its tableau, the right-hand side, and
//! one trial step with error estimate and dense output.
//!
//! The per-stage arithmetic is written once, per lane, in the small
//! `stage*_v`, `increment`, `error_term`, `error_scale` and `dense_coeffs`
//! functions; `try_steps` runs them for N interleaved lanes. The shader's
//! `try_step` (`shaders/integrator/stepper.wgsl`) has the same tableau,
//! stages, dense output, error norm (x1 and ẋ1 at their own tolerance,
//! `Settings::traj_weight`) and error estimates for one lane in `real`.

use super::components::{powers, NY};
use super::control::step_factor;
use super::rhs::rhs_lanes;
use super::settings::Settings;
use crate::lanewise::by_lane;
use crate::model::vmath::smaller;
use crate::model::{Coefs, FrictionTable, Lane, Mode};

/// Declares the tableau's coefficients, each with its value as its doc.
macro_rules! tableau {
    ($($name:ident = $value:expr;)*) => {
        $(
            #[doc = concat!("`", stringify!($name), " = ", stringify!($value), "`")]
            pub const $name: f64 = $value;
        )*
        /// Every coefficient by its name (the shader's prelude is
        /// generated from it: `backend::gpu::shader::prelude`).
        pub const TABLEAU: &[(&str, f64)] = &[$((stringify!($name), $name)),*];
    };
}

// Dormand–Prince 5(4): the stages' coefficients a, the error weights e
// (fifth minus fourth order) and the dense output's d (Hairer & Wanner's
// dopri5 contd5). The shader's constants of the same names are
// generated from these ([`TABLEAU`]). Stage times c2..c5 (1/5, 3/10, 4/5, 8/9) are
// not needed: between events the right-hand side is autonomous.
tableau! {
    A21 = 1.0 / 5.0;
    A31 = 3.0 / 40.0;
    A32 = 9.0 / 40.0;
    A41 = 44.0 / 45.0;
    A42 = -56.0 / 15.0;
    A43 = 32.0 / 9.0;
    A51 = 19372.0 / 6561.0;
    A52 = -25360.0 / 2187.0;
    A53 = 64448.0 / 6561.0;
    A54 = -212.0 / 729.0;
    A61 = 9017.0 / 3168.0;
    A62 = -355.0 / 33.0;
    A63 = 46732.0 / 5247.0;
    A64 = 49.0 / 176.0;
    A65 = -5103.0 / 18656.0;
    A71 = 35.0 / 384.0;
    A73 = 500.0 / 1113.0;
    A74 = 125.0 / 192.0;
    A75 = -2187.0 / 6784.0;
    A76 = 11.0 / 84.0;
    E1 = 71.0 / 57600.0;
    E3 = -71.0 / 16695.0;
    E4 = 71.0 / 1920.0;
    E5 = -17253.0 / 339200.0;
    E6 = 22.0 / 525.0;
    E7 = -1.0 / 40.0;
    D1 = -12715105075.0 / 11282082432.0;
    D3 = 87487479700.0 / 32700410799.0;
    D4 = -10690763975.0 / 1880347072.0;
    D5 = 701980252875.0 / 199316789632.0;
    D6 = -1453857185.0 / 822651844.0;
    D7 = 69997945.0 / 29380423.0;
}

// ẋ1 at which stages 2 to 6 evaluate the right-hand side (only ẋ1 is
// needed: the right-hand side depends on nothing else).
#[inline]
pub(crate) fn stage2_v(v0: f64, h: f64, k1: f64) -> f64 {
    v0 + h * (A21 * k1)
}
#[inline]
pub(crate) fn stage3_v(v0: f64, h: f64, k1: f64, k2: f64) -> f64 {
    v0 + h * (A31 * k1 + A32 * k2)
}
#[inline]
pub(crate) fn stage4_v(v0: f64, h: f64, k1: f64, k2: f64, k3: f64) -> f64 {
    v0 + h * (A41 * k1 + A42 * k2 + A43 * k3)
}
#[inline]
pub(crate) fn stage5_v(v0: f64, h: f64, k1: f64, k2: f64, k3: f64, k4: f64) -> f64 {
    v0 + h * (A51 * k1 + A52 * k2 + A53 * k3 + A54 * k4)
}
#[inline]
pub(crate) fn stage6_v(v0: f64, h: f64, k1: f64, k2: f64, k3: f64, k4: f64, k5: f64) -> f64 {
    v0 + h * (A61 * k1 + A62 * k2 + A63 * k3 + A64 * k4 + A65 * k5)
}

/// Fifth-order increment of one component over the step.
#[inline]
pub(crate) fn increment(h: f64, k1: f64, k3: f64, k4: f64, k5: f64, k6: f64) -> f64 {
    h * (A71 * k1 + A73 * k3 + A74 * k4 + A75 * k5 + A76 * k6)
}

/// Embedded error estimate of one component.
#[inline]
pub(crate) fn error_term(h: f64, k1: f64, k3: f64, k4: f64, k5: f64, k6: f64, k7: f64) -> f64 {
    h * (E1 * k1 + E3 * k3 + E4 * k4 + E5 * k5 + E6 * k6 + E7 * k7)
}

/// Error scale of one component: tol relative to max(1, |y|) over the step.
#[inline]
pub(crate) fn error_scale(tol: f64, y0: f64, y1: f64) -> f64 {
    tol * (1.0 + y0.abs().max(y1.abs()))
}

/// The error scale `s` held within the error budget's cap `c`
/// (`Budgets::caps`, which floors it).
#[inline(always)]
pub(crate) fn capped(s: f64, c: f64) -> f64 {
    smaller(s, c)
}

/// Dense-output coefficients of a component over the step from its value
/// `v0` to `v1` (see `events::dense_v`).
#[inline]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dense_coeffs(
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

crate::lanewise_struct! {
    /// The outcome of a trial step; [`Trials`] holds W lanes' at once,
    /// component-major (`y1[i][j]`: component i of lane j), as
    /// `try_steps` computes them.
    #[derive(Clone, Copy, Debug)]
    pub struct Trial, Trials {
        /// The state at the step's end.
        pub(crate) y1: [f64; NY],
        /// The derivative at the step's end.
        pub(crate) k7: [f64; NY],
        /// Error norm: <= 1 means accepted.
        pub(crate) err: f64,
        /// The step-size factor the norm asks for (`control::step_factor`).
        pub(crate) fac: f64,
        /// The switch event's function at the step's end (`events`).
        pub(crate) g_switch: f64,
        /// Dense-output coefficients of ẋ1 (r1..r5).
        pub(crate) dense_v: [f64; 5],
        /// The step's increments of ∫p1 and ∫p2 (w_p1, and w_friction −
        /// w_p1).
        pub(crate) dw: [f64; 2],
        /// The last coefficient of their dense outputs (the only one
        /// that needs the inner stages; `flow::dense_w` forms the rest).
        pub(crate) dw_r4: [f64; 2],
        /// The embedded error estimate of each component and, last, of
        /// ∫p2 dt (absolute; the accuracy budget adds them up, see
        /// `accuracy`).
        pub(crate) est: [f64; NY + 1],
        /// D at the step's end: the mode is inconsistent where it is
        /// not > 0 (`step::finish_uncommon`).
        pub(crate) d_end: f64,
        /// The derivatives at stages 2 to 6 (`try_steps`' scratch).
        pub(crate) stages: [[f64; NY]; 5],
    }
}

/// One trial step of size h from (y, k1), each component's error held
/// within `cap` ([`capped`]): [`try_steps`] of one lane.
#[inline]
#[allow(clippy::too_many_arguments)]
pub(crate) fn try_step(
    lane: &Lane,
    tables: &[FrictionTable],
    mode: Mode,
    y: &[f64; NY],
    k1: &[f64; NY],
    h: f64,
    cap: &[f64; NY],
    set: &Settings,
) -> Trial {
    let mut tr = Trials::<1>::zero();
    let col = |a: &[f64; NY]| -> [[f64; 1]; NY] { a.map(|v| [v]) };
    try_steps::<1>(
        &Coefs::of(&[lane], &[mode]),
        [lane],
        tables,
        &col(y),
        &col(k1),
        [h],
        &col(cap),
        set,
        &mut tr,
    );
    tr.lane(0)
}

/// Trial steps of N lanes at once from states `y` with derivatives `k1`
/// (component-major), each lane in its mode (its constants `c`), into
/// `tr`; every lane is computed, its own `h[j]` (the caller ignores the
/// lanes it has no step for). Each stage is computed for every lane
/// before the next stage, lanes as vector elements; per lane the
/// arithmetic is exactly that of one lane, so a lane's trial, and its
/// row, do not depend on N or on the lanes beside it.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn try_steps<const N: usize>(
    c: &Coefs<N>,
    lane: [&Lane; N],
    tables: &[FrictionTable],
    y0: &[[f64; N]; NY],
    k1: &[[f64; N]; NY],
    h: [f64; N],
    cap: &[[f64; N]; NY],
    set: &Settings,
    tr: &mut Trials<N>,
) {
    // The stages' derivatives in `tr`, written before they are read:
    // locals would be zeroed at every attempt.
    let [k2, k3, k4, k5, k6] = &mut tr.stages;
    let k7 = &mut tr.k7;
    let v0 = &y0[1];
    let a1 = &k1[1];
    let v: [f64; N] = by_lane(|j| stage2_v(v0[j], h[j], a1[j]));
    rhs_lanes(c, &lane, tables, &v, k2, |_, _| {});
    let v: [f64; N] = by_lane(|j| stage3_v(v0[j], h[j], a1[j], k2[1][j]));
    rhs_lanes(c, &lane, tables, &v, k3, |_, _| {});
    let v: [f64; N] = by_lane(|j| stage4_v(v0[j], h[j], a1[j], k2[1][j], k3[1][j]));
    rhs_lanes(c, &lane, tables, &v, k4, |_, _| {});
    let v: [f64; N] = by_lane(|j| stage5_v(v0[j], h[j], a1[j], k2[1][j], k3[1][j], k4[1][j]));
    rhs_lanes(c, &lane, tables, &v, k5, |_, _| {});
    let v: [f64; N] =
        by_lane(|j| stage6_v(v0[j], h[j], a1[j], k2[1][j], k3[1][j], k4[1][j], k5[1][j]));
    rhs_lanes(c, &lane, tables, &v, k6, |_, _| {});
    let y1 = &mut tr.y1;
    for i in 0..NY {
        for j in 0..N {
            let dy = increment(h[j], k1[i][j], k3[i][j], k4[i][j], k5[i][j], k6[i][j]);
            y1[i][j] = y0[i][j] + dy;
        }
    }
    let d_end = &mut tr.d_end;
    let f1_end = rhs_lanes(c, &lane, tables, &y1[1], k7, |j, d| d_end[j] = d);
    // The rest component-major too, every lane, so each loop is vector
    // arithmetic.
    let est = &mut tr.est;
    let mut err = [0.0f64; N];
    for i in 0..NY {
        let tol = set.tol_of(i);
        for j in 0..N {
            let et = error_term(
                h[j], k1[i][j], k3[i][j], k4[i][j], k5[i][j], k6[i][j], k7[i][j],
            );
            est[i][j] = et.abs();
            let s = capped(error_scale(tol, y0[i][j], y1[i][j]), cap[i][j]);
            err[j] = err[j].max(est[i][j] / s);
        }
    }
    tr.g_switch = c.switch_values(&f1_end);
    for (e, fac) in err.iter_mut().zip(&mut tr.fac) {
        *e = if e.is_finite() { *e } else { f64::INFINITY };
        *fac = step_factor(*e);
    }
    tr.err = err;
    for j in 0..N {
        let (a, b, c3, d, e, f) = (k1[1][j], k3[1][j], k4[1][j], k5[1][j], k6[1][j], k7[1][j]);
        let r = dense_coeffs(y0[1][j], y1[1][j], h[j], a, b, c3, d, e, f);
        for (dv, r) in tr.dense_v.iter_mut().zip(r) {
            dv[j] = r;
        }
        // The quadratures of p1 and p2.
        let w = |k: &[[f64; N]; NY]| powers(k[4][j], k[5][j]).0;
        let p2 = |k: &[[f64; N]; NY]| powers(k[4][j], k[5][j]).1;
        let (a, b, c3, d, e, f) = (w(k1), w(k3), w(k4), w(k5), w(k6), w(k7));
        tr.dw[0][j] = increment(h[j], a, b, c3, d, e);
        tr.dw_r4[0][j] = dense_r5(h[j], a, b, c3, d, e, f);
        let (a, b, c3, d, e, f) = (p2(k1), p2(k3), p2(k4), p2(k5), p2(k6), p2(k7));
        tr.dw[1][j] = increment(h[j], a, b, c3, d, e);
        tr.dw_r4[1][j] = dense_r5(h[j], a, b, c3, d, e, f);
        est[NY][j] = error_term(h[j], a, b, c3, d, e, f).abs();
    }
}
