//! Power, logarithm and exponential as straight-line arithmetic: no call,
//! no table, no branch the compiler cannot turn into a select, so a loop
//! over the lanes of a vector compiles to vector instructions, and one
//! lane's value is the same bits whatever the width or instruction set
//! (Rust never contracts `a * b + c` on its own; the one fused
//! multiply-add, in the exact product, is correctly rounded everywhere).
//!
//! Accuracy, measured against `std` (`tests` below): `ln` and `exp`
//! within 1 ulp, `pow(x, y)` within 1 ulp for x in [1e-12, 1e4] and y in
//! (0, 5] (the paper law's sliding speeds and exponents b). `y ln x` is
//! carried in two parts (an exact product by fused multiply-add), as its
//! rounding alone would cost |y ln x| ulp.

/// ln 2 split for Cody and Waite's reduction: `LN2_HI` has 21 trailing
/// zero bits, so k · LN2_HI is exact for |k| < 2^21.
const LN2_HI: f64 = f64::from_bits(0x3fe6_2e42_fee0_0000);
const LN2_LO: f64 = f64::from_bits(0x3dea_39ef_3579_3c76);
/// Round to nearest (even) by adding and subtracting 1.5 · 2^52.
const ROUND: f64 = 6_755_399_441_055_744.0;

/// (s, e) with s + e = a + b exactly (Knuth's two-sum).
#[inline(always)]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// (p, e) with p + e = a · b exactly: the fused multiply-add's error
/// term, correctly rounded on every target (hardware FMA under AVX2,
/// AVX-512 and NEON; the C library's `fma` elsewhere), so the bits do
/// not depend on the instruction set.
#[inline(always)]
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// (k, m) with x = 2^k · m and m in [√½, √2), for a normal x > 0: the
/// reduction every logarithm here starts from.
#[inline(always)]
pub(crate) fn split_exponent(x: f64) -> (i64, f64) {
    let bits = x.to_bits();
    let k = ((bits >> 52) & 0x7ff) as i64 - 1023;
    let m = f64::from_bits((bits & 0x000f_ffff_ffff_ffff) | 0x3ff0_0000_0000_0000);
    let big = m > std::f64::consts::SQRT_2;
    (k + i64::from(big), if big { m * 0.5 } else { m })
}

/// (x rounded to the nearest integer, ties to even, and that integer as
/// an i64), for |x| < 2^51: the integer is read off the sum's bits, as
/// vector integer arithmetic (a float-to-integer `as` saturates, which
/// no vector instruction does, and so runs lane by lane).
#[inline(always)]
pub(crate) fn round_int(x: f64) -> (f64, i64) {
    let t = x + ROUND;
    (t - ROUND, t.to_bits() as i64 - ROUND.to_bits() as i64)
}

/// k as an f64, exactly, for |k| < 2^51: by the bits of 1.5 · 2^52 + k
/// (an i64-to-float `as` has no vector instruction before AVX-512).
#[inline(always)]
pub(crate) fn int_to_f64(k: i64) -> f64 {
    f64::from_bits((ROUND.to_bits() as i64 + k) as u64) - ROUND
}

/// 2^k for k in the normal range [−1022, 1023], from its exponent field.
#[inline(always)]
pub(crate) fn pow2i(k: i64) -> f64 {
    f64::from_bits(((k + 1023) as u64) << 52)
}

/// ln x as an unevaluated sum hi + lo, about 2^-60 relative, for x > 0
/// (subnormals included); hi is −∞ at 0 and NaN below.
#[inline(always)]
fn ln2(x: f64) -> (f64, f64) {
    // Subnormals: scale into the normal range first.
    let tiny = x < f64::MIN_POSITIVE;
    let xs = if tiny {
        x * 18_014_398_509_481_984.0
    } else {
        x
    }; // 2^54
    let (k, m) = split_exponent(xs);
    let k = k - if tiny { 54 } else { 0 };
    // m in [√½, √2): ln m = 2 atanh(s), s = f / (2 + f), |s| < 0.1716.
    let f = m - 1.0;
    let s = f / (2.0 + f);
    let z = s * s;
    // R = Σ 2 z^i / (2i + 1), i = 1..11: the tail is below 2^-60.
    let mut r = 2.0 / 23.0;
    r = r * z + 2.0 / 21.0;
    r = r * z + 2.0 / 19.0;
    r = r * z + 2.0 / 17.0;
    r = r * z + 2.0 / 15.0;
    r = r * z + 2.0 / 13.0;
    r = r * z + 2.0 / 11.0;
    r = r * z + 2.0 / 9.0;
    r = r * z + 2.0 / 7.0;
    r = r * z + 2.0 / 5.0;
    r = r * z + 2.0 / 3.0;
    r *= z;
    // ln(1 + f) = f − hf² + s (hf² + R), hf² = f²/2 (fdlibm's form);
    // k ln2_hi + f is summed exactly, the small rest added to it.
    let (ff, ffe) = two_prod(f, f);
    let hfsq = 0.5 * ff;
    let kf = int_to_f64(k);
    let small = (s * (hfsq + r) - 0.5 * ffe - hfsq) + kf * LN2_LO;
    let (h, l) = two_sum(kf * LN2_HI, f);
    let (hi, lo) = two_sum(h, l + small);
    if x > 0.0 {
        (hi, lo)
    } else if x == 0.0 {
        (f64::NEG_INFINITY, 0.0)
    } else {
        (f64::NAN, 0.0)
    }
}

/// ln x for x > 0 (subnormals included); NaN below 0, −∞ at 0.
#[inline(always)]
pub fn ln(x: f64) -> f64 {
    let (hi, lo) = ln2(x);
    hi + lo
}

/// e^(x + xl), xl a small correction to x; 0 below −745, +∞ above
/// 709.78.
#[inline(always)]
fn exp2sum(x: f64, xl: f64) -> f64 {
    let xc = x.clamp(-746.0, 710.0);
    let (kf, k) = round_int(xc * std::f64::consts::LOG2_E);
    let r = (xc - kf * LN2_HI) + (xl - kf * LN2_LO);
    // e^r, |r| <= 0.3466: Taylor to r^13 (the tail is below 2^-58).
    let mut p = 1.0 / 6_227_020_800.0;
    p = p * r + 1.0 / 479_001_600.0;
    p = p * r + 1.0 / 39_916_800.0;
    p = p * r + 1.0 / 3_628_800.0;
    p = p * r + 1.0 / 362_880.0;
    p = p * r + 1.0 / 40_320.0;
    p = p * r + 1.0 / 5_040.0;
    p = p * r + 1.0 / 720.0;
    p = p * r + 1.0 / 120.0;
    p = p * r + 1.0 / 24.0;
    p = p * r + 1.0 / 6.0;
    p = p * r + 0.5;
    let e = 1.0 + (r + r * r * p);
    // 2^k in two factors, so k down to −1075 and up to 1024 is reached
    // without an out-of-range exponent field.
    let k1 = k / 2;
    let k2 = k - k1;
    let (s1, s2) = (pow2i(k1), pow2i(k2));
    let v = e * s1 * s2;
    if x.is_nan() {
        x
    } else {
        v
    }
}

/// e^x; 0 below −745, +∞ above 709.78.
#[inline(always)]
pub fn exp(x: f64) -> f64 {
    exp2sum(x, 0.0)
}

/// x^y for x >= 0 (the powers of a sliding speed): exp(y ln x), with
/// 0^y = 0 for y > 0, 1 for y = 0, +∞ for y < 0; NaN for x < 0.
#[inline(always)]
pub fn pow(x: f64, y: f64) -> f64 {
    // y ln x in two parts: its rounding would cost |y ln x| ulp.
    let (hi, lo) = ln2(x);
    let (p, e) = two_prod(y, if hi.is_finite() { hi } else { 0.0 });
    let v = exp2sum(if hi.is_finite() { p } else { y * hi }, e + y * lo);
    if x == 0.0 {
        if y > 0.0 {
            0.0
        } else if y == 0.0 {
            1.0
        } else {
            f64::INFINITY
        }
    } else {
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::sampling::Uniforms;

    /// Distance in units in the last place.
    fn ulps(a: f64, b: f64) -> u64 {
        if a == b {
            return 0;
        }
        let (a, b) = (a.to_bits() as i64, b.to_bits() as i64);
        (a - b).unsigned_abs()
    }

    #[test]
    fn the_split_of_ln2_is_ln2() {
        assert_eq!(LN2_HI.to_bits() & 0x1f_ffff, 0);
        assert_eq!(LN2_HI + LN2_LO, std::f64::consts::LN_2);
    }

    #[test]
    fn ln_is_within_one_ulp_of_std() {
        let mut u = Uniforms::new(1);
        let mut worst = 0;
        for _ in 0..200_000 {
            // Log-uniform over [1e-300, 1e300] and over the model's range.
            let x = 10f64.powf(-300.0 + 600.0 * u.next());
            let z = 10f64.powf(-12.0 + 16.0 * u.next());
            for x in [x, z, 1.0 + 1e-3 * (u.next() - 0.5)] {
                worst = worst.max(ulps(ln(x), x.ln()));
            }
        }
        assert!(worst <= 1, "ln: worst {worst} ulp");
        assert_eq!(ln(1.0), 0.0);
        assert_eq!(ln(0.0), f64::NEG_INFINITY);
        assert!(ln(-1.0).is_nan());
        assert!((ln(5e-324) - 5e-324f64.ln()).abs() < 1e-12);
    }

    #[test]
    fn exp_is_within_one_ulp_of_std() {
        let mut u = Uniforms::new(2);
        let mut worst = 0;
        for _ in 0..200_000 {
            let x = -700.0 + 1400.0 * u.next();
            let z = -2.0 + 4.0 * u.next();
            for x in [x, z] {
                worst = worst.max(ulps(exp(x), x.exp()));
            }
        }
        assert!(worst <= 1, "exp: worst {worst} ulp");
        assert_eq!(exp(0.0), 1.0);
        assert_eq!(exp(-800.0), 0.0);
        assert_eq!(exp(800.0), f64::INFINITY);
    }

    #[test]
    fn pow_is_within_one_ulp_of_std_over_the_models_range() {
        let mut u = Uniforms::new(3);
        let mut worst = 0;
        for _ in 0..500_000 {
            let x = 10f64.powf(-12.0 + 16.0 * u.next());
            let y = 5.0 * u.next();
            worst = worst.max(ulps(pow(x, y), x.powf(y)));
        }
        eprintln!("pow: worst {worst} ulp against std");
        assert!(worst <= 1, "pow: worst {worst} ulp");
        assert_eq!(pow(0.0, 0.6), 0.0);
        assert_eq!(pow(0.0, 0.0), 1.0);
        assert_eq!(pow(2.0, 0.0), 1.0);
        assert!(pow(-1.0, 0.5).is_nan());
    }
}
