//! Step-size control: the size a step is tried at, the factor a trial
//! step's error norm asks the next step to grow or shrink by, the size
//! tried again after a rejection, and where a step is too small to go on.

use crate::model::vmath::{int_to_f64, pow2i, round_int, split_exponent};

/// First step after every start from rest, s: the friction law's
/// derivative is unbounded at rest and the error estimate reads low there.
pub const H_INITIAL: f64 = 1e-6;

/// A step below this fraction of max(t, 1) s is a step underflow: f64
/// resolves a time to 2.2e-16 of itself, so below about 1e-15 of it the
/// steps stop moving the lane (the shader's f32 stops at 1e-7).
pub const STEP_UNDERFLOW: f64 = 1e-15;

/// A step underflow where D has fallen below this fraction of m1 is the
/// wedge jamming, not a step too small for a smooth motion: in a mode
/// with c·s = −1 whose friction angle grows along the motion (a wheel
/// that overhauls a self-locking drive, slowing down), D falls
/// continuously to 0, as the square root of the time left, and the
/// acceleration m1·φ/D grows without bound, so the steps shrink until
/// they underflow within a few 1e-7 of m1 of D = 0 (on random such lanes,
/// 8.5e-8 to 8.5e-7). D ≤ 0 makes the mode inconsistent (docs/model.md
/// section 2), and so does D reaching 0 (the shader's f32 stops at
/// [`JAM_D_F32`](crate::backend::gpu::shader::JAM_D_F32)).
pub const JAM_D: f64 = 1e-4;

/// The size of the step to try from the proposed size `h`, at speed `v`
/// and acceleration `a` in direction `dir`, `remaining` before the next
/// time event; and whether the step lands on that event. `steep`: the
/// lane's friction law is steep at rest (`Lane::steep`).
#[inline(always)]
pub(crate) fn step_size(
    h: f64,
    steep: bool,
    dir: f64,
    v: f64,
    a: f64,
    remaining: f64,
) -> (f64, bool) {
    let mut h = h;
    // Approaching rest under the paper and agma laws, ρ(Vs) has an
    // unbounded derivative at the stop, as it has at a start, and the
    // error estimate reads low there: grade the steps into the stop.
    if steep && a * dir < 0.0 {
        let t_rest = -v / a;
        h = h.min((0.5 * t_rest).max(H_INITIAL));
    }
    let landing = h >= remaining;
    (if landing { remaining } else { h }, landing)
}

/// The size to try again after a rejected trial of size `h` whose error
/// asks for the factor `fac`, and whether it is too small to go on at
/// time `t` (step underflow).
#[inline(always)]
pub(crate) fn retry_size(h: f64, fac: f64, t: f64) -> (f64, bool) {
    let h = h * fac.min(1.0);
    (h, h < STEP_UNDERFLOW * t.max(1.0))
}

/// Step-size factor from a trial's error norm: 0.9 err^(−1/5), kept
/// within [0.2, 5]. The power is [`inv_fifth_root`], not the C library's
/// `pow`: a step size needs no last-bit accuracy, and straight-line
/// arithmetic makes the factor the same bits on every platform and at
/// every vector width.
#[inline(always)]
pub(crate) fn step_factor(err: f64) -> f64 {
    // Selects, not branches, so a loop over lanes stays vector code.
    // Below 1.9e-4, 0.9 err^(−1/5) is over 5: the clamp's value; an
    // infinite (or NaN) norm shrinks the step all it may.
    let x = if err < 1e-4 {
        1.0
    } else if err < f64::INFINITY {
        err
    } else {
        1e300
    };
    let f = (0.9 * inv_fifth_root(x)).clamp(0.2, 5.0);
    if err < 1e-4 {
        5.0
    } else {
        f
    }
}

/// x^(−1/5) for x in [1e-4, f64::MAX], within 1e-8 relative (a test
/// compares it with `powf`): 2^(−log2(x)/5) with a series for each part.
#[inline(always)]
pub(crate) fn inv_fifth_root(x: f64) -> f64 {
    let (e, m) = split_exponent(x);
    // log2 m = (2 / ln 2) atanh(s), s = (m − 1)/(m + 1), |s| < 0.1716:
    // the series to s^7 leaves s^9/9 < 2e-8.
    let s = (m - 1.0) / (m + 1.0);
    let z = s * s;
    let c = 2.0 / std::f64::consts::LN_2;
    let log2m = s * c * (1.0 + z * (1.0 / 3.0 + z * (1.0 / 5.0 + z * (1.0 / 7.0))));
    let t = -0.2 * (int_to_f64(e) + log2m);
    // 2^t = 2^k e^(f ln 2), k = round(t), |f ln 2| <= 0.35: Taylor to
    // the 8th power leaves 1e-10.
    let (k, ki) = round_int(t);
    let r = (t - k) * std::f64::consts::LN_2;
    let mut p = 1.0 / 40320.0;
    p = p * r + 1.0 / 5040.0;
    p = p * r + 1.0 / 720.0;
    p = p * r + 1.0 / 120.0;
    p = p * r + 1.0 / 24.0;
    p = p * r + 1.0 / 6.0;
    p = p * r + 0.5;
    p = p * r + 1.0;
    p = p * r + 1.0;
    // k is in [−205, 3]: 2^k is a normal number.
    p * pow2i(ki)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::sampling::Uniforms;

    #[test]
    fn the_step_factor_follows_the_fifth_root_within_1e_8() {
        let mut u = Uniforms::new(22);
        let mut worst: f64 = 0.0;
        for _ in 0..200_000 {
            let x = 10f64.powf(-4.0 + 312.0 * u.next());
            let y = 10f64.powf(-4.0 + 8.0 * u.next());
            for x in [x, y] {
                let want = x.powf(-0.2);
                worst = worst.max((inv_fifth_root(x) - want).abs() / want);
            }
        }
        assert!(worst < 1e-8, "worst {worst:e}");
        assert_eq!(step_factor(0.0), 5.0);
        assert_eq!(step_factor(1e-300), 5.0);
        assert_eq!(step_factor(f64::INFINITY), 0.2);
        assert_eq!(step_factor(f64::NAN), 0.2);
        assert_eq!(step_factor(1e30), 0.2);
        assert!((step_factor(1.0) - 0.9).abs() < 1e-12);
    }
}
