//! Section 10's energy flow: the in and out parts of ∫p1 dt and ∫p2 dt
//! (docs/model.md section 10).
//!
//! Why not four more quadratures of max(±p, 0): their integrands have
//! kinks where p crosses zero, which a step's error estimate does not see,
//! so each crossing would need an event that restarts the step; measured,
//! that cost a third of the CPU path's lanes/s. Instead ∫p1 is one more
//! smooth, error-controlled quadrature (w_p1; ∫p2 is w_friction − w_p1),
//! and an accepted step's increment of each goes whole to the in or the
//! out part where the mode says which (`mode_signs`): p2 = S2 ẋ2 has the
//! sign −c·s throughout a mode, and p1 = ψ S2 ẋ1 the sign +1 where c·s =
//! +1 (ψ < 0 there). Only p1 with c·s = −1 changes sign inside a mode
//! (ψ = tan(ρ − γ) passes 0 where ρ crosses γ, which is no event): there
//! the increment goes by the sign of p1 at the step's two ends (the
//! derivatives k1 and k7; `goes_whole`), and where that differs, the
//! step's dense output of the integral, a quartic in θ whose slope is p,
//! gives both the zero (where the slope changes sign, found by the
//! Illinois method) and the part before it (its value there); the part
//! after it is the rest of the increment. So in − out is the quadrature
//! itself, w1_in − w1_out + w2_in − w2_out = w_friction holds to
//! rounding, and no right-hand side is evaluated again.
//!
//! Why the mode and not the ends: where a power tends to 0 (a motor
//! running up to synchronous speed with no load, where S1 and S2 vanish),
//! its values at the ends and the step's increment are the quadrature's
//! error, of either sign, and that error is held to the size of the whole
//! integral (hundreds of J), not to the part's: read by the ends, it went
//! to the part of the other sign, whose value is 0, up to 5e-5 J of it.

use super::components::{powers, NY};
use super::events::{dense_v, illinois};
use super::stepper::Trial;

/// Root finding for the zero of p inside a step ends when the bracket is
/// this narrow, as a fraction of the step: 2^-52, the resolution of f64
/// on [0, 1] (the shader's `P_ZERO_TOL` is 2^-24, f32's).
pub const P_ZERO_TOL: f64 = f64::EPSILON;

/// The signs of the mesh powers (p1, p2) throughout a mode with contact
/// side `side` (c) and direction `dir` (s), each ±1: p2's is −c·s (S2
/// has the sign −c, ẋ2 the sign s), p1's is +1 where c·s = +1 (p1 = ψ S2
/// ẋ1, ψ = −tan(γ + ρ) < 0); 0 where the mode does not decide it (p1 with
/// c·s = −1, whose ψ = tan(ρ − γ) changes sign where ρ crosses γ).
#[inline(always)]
pub(crate) fn mode_signs(side: f64, dir: f64) -> (f64, f64) {
    let cs = side * dir;
    (if cs > 0.0 { 1.0 } else { 0.0 }, -cs)
}

/// Slope dW/dθ of a dense output W(θ) = r0 + θ(r1 + (1−θ)(r2 + θ(r3 +
/// (1−θ) r4))) (see `events::dense_v`): h times the integrand there.
#[inline]
pub(crate) fn dense_slope(r: &[f64; 5], th: f64) -> f64 {
    let th1 = 1.0 - th;
    r[1] + (th1 - th) * r[2] + th * (2.0 - 3.0 * th) * r[3] + 2.0 * th * th1 * (th1 - th) * r[4]
}

/// Shares a step's increment of ∫p dt between the in (p > 0) and out
/// (p < 0) parts, as [in, out], with how far they may be off (see
/// [`split_error`]): `r` is the step's dense output of the integral with
/// r0 = 0 (so r1 is the increment and W(θ) the part up to θ), `p0` and
/// `p_end` the integrand at the step's ends.
#[inline]
pub fn split(r: &[f64; 5], p0: f64, p_end: f64) -> ([f64; 2], f64) {
    if crosses(p0, p_end) {
        return split_crossing(r, p0);
    }
    if !agrees(r[1], p0, p_end) {
        return split_against(r);
    }
    (split_whole(r[1], p0, p_end), 0.0)
}

/// Whether a step's increment `total` of ∫p has the sign of p at the
/// step's ends (`p0`, `p_end`; either may be zero). Where it has not, p
/// took the other sign inside the step (it left a zero at one end, an
/// event's, the other way, or turned and turned back), and the ends do
/// not say which part the increment goes to ([`split_against`]).
#[inline(always)]
pub(crate) fn agrees(total: f64, p0: f64, p_end: f64) -> bool {
    total * (p0 + p_end) >= 0.0
}

/// Whether a step's increment `total` of ∫p goes whole to the part of p's
/// sign at the step's ends (`p0`, `p_end`): p keeps its sign there, and
/// the increment has that sign too, or is within its own error estimate
/// `est` (where p tends to 0, as a no-load motor nears synchronous speed
/// from above, the increment's sign is the quadrature's error, which the
/// error budget counts in the part it feeds).
#[inline(always)]
pub(crate) fn goes_whole(total: f64, est: f64, p0: f64, p_end: f64) -> bool {
    let noise = (total.abs() <= est) & (p0 + p_end != 0.0);
    !crosses(p0, p_end) & (agrees(total, p0, p_end) | noise)
}

/// [`split`] where the increment has the other sign than p at the step's
/// ends ([`agrees`]): the increment goes to the part of its own sign
/// ([`split_whole`] with the increment in place of p), so that a part
/// never falls, and either part may be off by the area of p's other
/// sign, which is within the area of |p|: at most |r1| + |r2| + |r3| +
/// |r4| (the slope of the dense output is the sum of r1, (1 − 2θ) r2,
/// θ(2 − 3θ) r3 and 2θ(1 − θ)(1 − 2θ) r4, each factor within 1 on
/// [0, 1]). The error budget's local terms take that, so that a lane
/// where it matters is refined. Rare: none on the tests' sweeps at the
/// default tolerance; one step in 6,150 lanes at 1e-7 gave w1_in a
/// negative increment, 7 times the bound, before this.
#[cold]
pub(crate) fn split_against(r: &[f64; 5]) -> ([f64; 2], f64) {
    let parts = split_whole(r[1], r[1], 0.0);
    (parts, r[1].abs() + r[2].abs() + r[3].abs() + r[4].abs())
}

/// Whether p changes sign inside a step from `p0` to `p_end` (a zero at
/// an end is no crossing).
#[inline(always)]
pub(crate) fn crosses(p0: f64, p_end: f64) -> bool {
    p0 * p_end < 0.0
}

/// [`split`] of an increment `total` where p keeps its sign: all of it
/// goes to one part.
#[inline(always)]
pub(crate) fn split_whole(total: f64, p0: f64, p_end: f64) -> [f64; 2] {
    let positive = p0 + p_end > 0.0 || (p0 + p_end == 0.0 && total >= 0.0);
    if positive {
        [total, 0.0]
    } else {
        [0.0, -total]
    }
}

/// [`split`] where p changes sign inside the step (about 1 % of steps,
/// kept out of the hot path).
#[cold]
pub(crate) fn split_crossing(r: &[f64; 5], p0: f64) -> ([f64; 2], f64) {
    let total = r[1];
    let sign = if p0 > 0.0 { 1.0 } else { -1.0 };
    // The zero of the slope by the Illinois method, as events are located:
    // a handful of iterations where bisection takes 52. (The shader
    // bisects: in f32 that is 24 halvings.)
    let g = |th: f64| sign * dense_slope(r, th);
    let (a, b) = illinois(g, g(0.0), g(1.0), P_ZERO_TOL);
    let th = 0.5 * (a + b);
    let first = dense_v(r, th);
    let rest = total - first;
    let parts = if sign > 0.0 {
        [first, -rest]
    } else {
        [rest, -first]
    };
    (parts, split_error(r, th))
}

/// How far [`split`]'s parts may be off where p changes sign at θ inside
/// the step: the quartic's last term there, θ²(1−θ)²|r4| (what the dense
/// output adds to the cubic through the step's ends and slopes, which
/// overstates its own error). For the error budget: a long step across
/// the zero of a strongly curved p splits its increment less accurately
/// than it integrates it.
#[inline]
pub fn split_error(r: &[f64; 5], th: f64) -> f64 {
    let w = th * (1.0 - th);
    w * w * r[4].abs()
}

/// The dense output (r0 = 0) of an increment `dw` of a quadrature over a
/// step of size h with derivatives `q0` and `q_end` at its ends and last
/// coefficient `r4`: the same coefficients as `stepper::dense_coeffs`.
#[inline]
pub(crate) fn dense_w(dw: f64, h: f64, q0: f64, q_end: f64, r4: f64) -> [f64; 5] {
    let r2 = h * q0 - dw;
    [0.0, dw, r2, dw - h * q_end - r2, r4]
}

/// The increments of (w1_in, w1_out, w2_in, w2_out) over an accepted step
/// of size `h`, from the derivative `k1` at its start to `trial`, in the
/// mode of contact side `side` and direction `dir` ([`mode_signs`]), and
/// how far the split of ∫p1 and of ∫p2 may be off ([`split_error`]; 0
/// where the mode decides the part).
#[inline]
pub(crate) fn step_flow(
    k1: &[f64; NY],
    trial: &Trial,
    h: f64,
    side: f64,
    dir: f64,
) -> ([f64; 4], [f64; 2]) {
    let (s1, s2) = mode_signs(side, dir);
    let ([i1, o1], e1) = if s1 != 0.0 {
        (split_whole(trial.dw[0], s1, 0.0), 0.0)
    } else {
        let k7 = &trial.k7;
        let (p1_0, _) = powers(k1[4], k1[5]);
        let (p1_end, _) = powers(k7[4], k7[5]);
        if goes_whole(trial.dw[0], trial.est[5], p1_0, p1_end) {
            (split_whole(trial.dw[0], p1_0, p1_end), 0.0)
        } else {
            let r1 = dense_w(trial.dw[0], h, p1_0, p1_end, trial.dw_r4[0]);
            split(&r1, p1_0, p1_end)
        }
    };
    let [i2, o2] = split_whole(trial.dw[1], s2, 0.0);
    ([i1, o1, i2, o2], [e1, 0.0])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_is_the_derivative_of_the_dense_output() {
        let r = [0.0, 0.7, -0.3, 0.45, 0.2];
        for th in [0.0, 0.1, 0.37, 0.5, 0.9, 1.0] {
            let d = 1e-6;
            let fd = (dense_v(&r, th + d) - dense_v(&r, th - d)) / (2.0 * d);
            assert!((dense_slope(&r, th) - fd).abs() < 1e-8, "{th}");
        }
    }

    #[test]
    fn a_crossing_splits_at_the_zero() {
        // W(θ) = θ − θ²: slope 1 − 2θ, zero at 1/2, W(1/2) = 1/4, W(1) = 0.
        // As a dense output: r1 = 0, r2 = 1 (θ(1−θ)·1), r3 = r4 = 0.
        let r = [0.0, 0.0, 1.0, 0.0, 0.0];
        let ([inp, out], err) = split(&r, 1.0, -1.0);
        assert_eq!(err, 0.0); // r4 = 0: the quartic is the cubic
        assert!(
            (inp - 0.25).abs() < 1e-15 && (out - 0.25).abs() < 1e-15,
            "{inp} {out}"
        );
        assert_eq!(
            split(&[0.0, 2.0, 0.0, 0.0, 0.0], 1.0, 3.0),
            ([2.0, 0.0], 0.0)
        );
        assert_eq!(
            split(&[0.0, -2.0, 0.0, 0.0, 0.0], -1.0, 0.0),
            ([0.0, 2.0], 0.0)
        );
        // The zero at 1/2 and r4 = 1: the error term is (1/4)² = 1/16.
        assert_eq!(split(&[0.0, 0.0, 1.0, 0.0, 1.0], 1.0, -1.0).1, 1.0 / 16.0);
    }

    /// Where p keeps its sign at the step's ends, a part never falls and
    /// in − out is the increment, whatever the step: random dense outputs
    /// and ends of either sign, zeros at the ends among them. Where the
    /// increment has the other sign than p at the ends (p left a zero at
    /// an end the other way), it goes to its own sign's part, and the
    /// error term covers the area of p's other sign: measured on the
    /// dense output itself, each part is within the error term of the
    /// area of its sign.
    #[test]
    fn a_split_never_lowers_a_part_and_says_how_far_it_may_be_off() {
        use rand_core::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let mut u = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
        let mut against = 0;
        for case in 0..20_000 {
            let h = 0.1 * u().abs();
            let mut p0 = u();
            let mut p_end = u();
            match case % 4 {
                0 => p_end = 0.0,
                1 => p0 *= 1e-3,
                _ => {}
            }
            if crosses(p0, p_end) {
                p_end = -p_end;
            }
            let dw = h * (0.5 * (p0 + p_end) + 0.3 * u());
            let r = dense_w(dw, h, p0, p_end, 0.5 * h * u());
            let ([inp, out], err) = split(&r, p0, p_end);
            assert!(inp >= 0.0 && out >= 0.0, "{r:?} {p0} {p_end}: {inp} {out}");
            assert!(
                (inp - out - dw).abs() <= 1e-15 * dw.abs().max(h),
                "{inp} {out} {dw}"
            );
            if !crosses(p0, p_end) && !agrees(dw, p0, p_end) {
                against += 1;
                // The areas of each sign of the slope, by the midpoint rule.
                let n = 4000;
                let (mut pos, mut neg) = (0.0, 0.0);
                for k in 0..n {
                    let s = dense_slope(&r, (k as f64 + 0.5) / n as f64) / n as f64;
                    if s > 0.0 {
                        pos += s
                    } else {
                        neg -= s
                    }
                }
                assert!((inp - pos).abs() <= err + 1e-6 * h, "{inp} {pos} {err}");
                assert!((out - neg).abs() <= err + 1e-6 * h, "{out} {neg} {err}");
            }
        }
        assert!(against > 1000, "{against} steps against their ends");
    }
}
