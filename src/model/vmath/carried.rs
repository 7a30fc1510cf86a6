//! x^y carried beyond double precision: the f64 shader's `pow_64`, whose
//! agreement with `std` must not depend on how a GPU compiler rounds,
//! with its multiply-adds written out so that a test can run it as a
//! compiler that fuses them would.

use super::{
    exp_reduced, pow2i, round_int, scale, split_any, LG1, LG2, LG3, LG4, LG5, LG6, LG7, LN2_HI,
    LN2_LO,
};

/// One multiply-add `a · b + c` of the algorithms below, written out so
/// that a test can run them as a compiler that fuses multiply-adds would
/// (NVIDIA's does, in the f64 shader that mirrors this file): [`Separate`]
/// is the CPU path's arithmetic, [`Fused`] that compiler's.
pub trait MulAdd {
    /// a · b + c.
    fn mad(a: f64, b: f64, c: f64) -> f64;
    /// c − a · b.
    fn msub(a: f64, b: f64, c: f64) -> f64;
}

/// Two roundings: the product, then the sum (what Rust compiles `a * b + c` to).
pub struct Separate;

/// One rounding (`f64::mul_add`): what a contracting compiler makes of `a * b + c`.
pub struct Fused;

impl MulAdd for Separate {
    #[inline(always)]
    fn mad(a: f64, b: f64, c: f64) -> f64 {
        a * b + c
    }
    #[inline(always)]
    fn msub(a: f64, b: f64, c: f64) -> f64 {
        c - a * b
    }
}

impl MulAdd for Fused {
    #[inline(always)]
    fn mad(a: f64, b: f64, c: f64) -> f64 {
        a.mul_add(b, c)
    }
    #[inline(always)]
    fn msub(a: f64, b: f64, c: f64) -> f64 {
        (-a).mul_add(b, c)
    }
}

/// x^y within 1 ulp, for x >= 0 and |y| <= 8, its multiply-adds done as
/// `M` says: the f64 shader's `pow_64`, line for line (0, ∞ and NaN as
/// the CPU path's [`super::pow`], and ∞^y the inverse of 0^y). The CPU
/// path keeps its own `pow`, within 1 + 2 |y ln x| ulp, which is far below
/// what its step tolerance resolves: this one in its place costs 10 % more
/// instructions a lane (callgrind, `tswm run` of the heyoka peer's lanes).
///
/// y ln x is carried to about 2^−57 absolute, so the result is within an
/// ulp: e^(y ln x) multiplies an error δ of y ln x into a relative error
/// δ, and y ln x reaches 140 on the model's range, where a rounded ln x
/// alone would be 70 ulp off. No double-length product (fused
/// multiply-add or Dekker's) does it: the head of y ln x is a sum of
/// products of numbers rounded to coarse grids (`grid`), exact in f64
/// whether the products are fused into the sums or not, and its tail is
/// small enough that its roundings do not matter. So a GPU compiler that
/// fuses multiply-adds (NVIDIA's), or that drops (a + b) − a to b (Mesa's,
/// where SPIR-V does not mark arithmetic exact), computes the same head.
#[inline(always)]
pub fn pow_carried<M: MulAdd>(x: f64, y: f64) -> f64 {
    // ln 2 to 28 bits (g · LN2_28 exact for g on a 2^−20 grid), and the rest.
    const LN2_28: f64 = f64::from_bits(0x3fe6_2e42_fe00_0000);
    const LN2_28_TAIL: f64 = f64::from_bits(0x3e1f_473d_e6af_278f);
    let (kf, m) = split_any(x);
    let Series { s_h, d, s, r } = series::<M>(m);
    // y ln x = n ln 2 + head + tail, y = y_h + y_l with y_h on a 2^−20
    // grid, y_h k = n + g (n an integer, g exact), head = g LN2_28 +
    // 2 y_h s_h (exact: multiples of 2^−48 below 8).
    let y_h = grid(y, 20);
    let y_l = y - y_h;
    let (nf, n) = round_int(y_h * kf);
    let g = M::mad(y_h, kf, -nf);
    let head = M::mad(g, LN2_28, 2.0 * y_h * s_h);
    let tail = M::mad(
        y * s,
        r,
        M::mad(
            g,
            LN2_28_TAIL,
            M::mad(
                y_l,
                M::mad(kf, std::f64::consts::LN_2, 2.0 * s),
                2.0 * y_h * d,
            ),
        ),
    );
    // e^(head + tail), reduced by j ln 2 as in exp (head − j LN2_HI exact).
    let (jf, j) = round_int((head + tail) * std::f64::consts::LOG2_E);
    let hi = M::msub(jf, LN2_HI, head);
    let lo = M::mad(jf, LN2_LO, -tail);
    let v = scale(exp_reduced::<M>(hi, lo), (n + j).clamp(-2044, 2044));
    // At 0 and ∞ the power's limit; selects, not branches.
    let at_zero = if y > 0.0 {
        0.0
    } else if y == 0.0 {
        1.0
    } else {
        f64::INFINITY
    };
    if x > 0.0 && x < f64::INFINITY {
        v
    } else if x == 0.0 {
        at_zero
    } else if x == f64::INFINITY {
        1.0 / at_zero
    } else {
        // x < 0 or NaN.
        f64::NAN
    }
}

/// ln m = 2s + s R(s²) for m in [√½, √2), s = f / (2 + f), f = m − 1,
/// with s as a head on a grid and a tail.
struct Series {
    /// s to 2^−24 (22 bits): 2 y_h s_h is exact.
    s_h: f64,
    /// s − s_h, from the exact remainder f − s_h (2 + f).
    d: f64,
    /// s, rounded.
    s: f64,
    /// R(s²), fdlibm's polynomial.
    r: f64,
}

#[inline(always)]
fn series<M: MulAdd>(m: f64) -> Series {
    let f = m - 1.0;
    let inv = 1.0 / (2.0 + f);
    // s = s_h + δ: s_h on a 2^−24 grid (22 bits), δ from the exact
    // remainder f − s_h (2 + f) = (f_h − 2 s_h − s_h f_h) + f_l (1 − s_h),
    // whose first group is exact (multiples of 2^−48 below 2^−23).
    let s_h = grid(f * inv, 24);
    let f_h = grid(f, 24);
    let f_l = f - f_h;
    let num = M::mad(f_l, 1.0 - s_h, M::msub(s_h, f_h, M::msub(2.0, s_h, f_h)));
    let d = num * inv;
    let s = M::mad(num, inv, s_h);
    let z = s * s;
    let w = z * z;
    let t1 = w * M::mad(w, M::mad(w, LG6, LG4), LG2);
    let r = M::mad(z, M::mad(w, M::mad(w, M::mad(w, LG7, LG5), LG3), LG1), t1);
    Series { s_h, d, s, r }
}

/// x rounded to the nearest multiple of 2^−bits (ties to even), for
/// |x| 2^bits < 2^51: exact, and the same in the f64 shader (`round`).
#[inline(always)]
fn grid(x: f64, bits: i64) -> f64 {
    round_int(x * pow2i(bits)).0 * pow2i(-bits)
}

#[cfg(test)]
mod tests {
    use super::super::tests::ulps;
    use super::*;
    use crate::input::sampling::Uniforms;

    /// x^y's arguments over the model's range: sliding speeds 1e-12 to
    /// 1e4 m/s (log-uniform) to exponents in [−5, 5].
    fn pow_args(u: &mut Uniforms) -> (f64, f64) {
        (10f64.powf(-12.0 + 16.0 * u.next()), 10.0 * u.next() - 5.0)
    }

    #[test]
    fn pow_carried_is_within_one_ulp_of_std_over_the_models_range() {
        let mut u = Uniforms::new(3);
        let mut worst = 0;
        for _ in 0..1_000_000 {
            let (x, y) = pow_args(&mut u);
            let d = ulps(carried(x, y), x.powf(y));
            assert!(d <= 1, "pow_carried({x}, {y}): {d} ulp");
            worst = worst.max(d);
        }
        eprintln!("pow_carried: worst {worst} ulp from std over 10^6 arguments");
        // Every exponent, and the edges.
        for x in [1e-300f64, 5e-324, 3e-310, 0.5, 1.0, 2.0, 1e300] {
            for y in [-5.0, -0.2, 1e-9, 0.612, 1.0, 2.0, 5.0] {
                let want = x.powf(y);
                let d = ulps(carried(x, y), want);
                // Subnormal results have fewer bits: held to 1e-15 of them.
                assert!(
                    d <= 1 || (carried(x, y) - want).abs() <= 1e-15 * want,
                    "pow_carried({x:e}, {y}): {} against {want:e}",
                    carried(x, y)
                );
            }
        }
        assert_eq!(carried(0.0, 0.6), 0.0);
        assert_eq!(carried(0.0, 0.0), 1.0);
        assert_eq!(carried(0.0, -0.2), f64::INFINITY);
        assert_eq!(carried(2.0, 0.0), 1.0);
        assert_eq!(carried(1.0, 3.7), 1.0);
        assert_eq!(carried(f64::INFINITY, 0.5), f64::INFINITY);
        assert!(carried(-1.0, 0.5).is_nan());
        assert!(carried(f64::NAN, 0.5).is_nan());
    }

    /// [`pow_carried`] as the CPU computes it.
    fn carried(x: f64, y: f64) -> f64 {
        pow_carried::<Separate>(x, y)
    }

    /// A compiler that fuses every multiply-add (NVIDIA's, on the f64
    /// shader's `pow_64`) gets within an ulp of the CPU's
    /// [`pow_carried`]: the exact head of y ln x does not move, and the
    /// rest moves e^(y ln x) far less than an ulp.
    #[test]
    fn pow_carried_holds_within_one_ulp_when_every_multiply_add_is_fused() {
        let mut u = Uniforms::new(4);
        let mut worst = 0;
        for _ in 0..1_000_000 {
            let (x, y) = pow_args(&mut u);
            let d = ulps(pow_carried::<Fused>(x, y), carried(x, y));
            assert!(d <= 1, "pow({x}, {y}) fused: {d} ulp");
            worst = worst.max(d);
        }
        eprintln!("pow_carried fused against separate: worst {worst} ulp over 10^6 arguments");
    }
}
