//! Power, logarithm and exponential as straight-line arithmetic: no call,
//! no table, no branch the compiler cannot turn into a select, so a loop
//! over the lanes of a vector compiles to vector instructions, and one
//! lane's value is the same bits whatever the width or instruction set
//! (Rust never contracts `a * b + c` on its own, and the CPU path fuses no
//! multiply-add here: [`Fused`] is for a test).
//!
//! Accuracy, measured against `std` (`tests` below): `ln` and `exp`
//! within 1 ulp (fdlibm's algorithms); `pow(x, y)` within
//! 1 + 2 |y ln x| ulp, for x in [1e-12, 1e4] and y in (0, 5] (the paper
//! law's sliding speeds and exponents b): at most 12 ulp for the default
//! b = 0.612 at sliding speeds from 0.1 mm/s to 100 m/s, and below 7e-14
//! relative anywhere in that range. Far below what the step tolerance
//! resolves (1e-8), and cheaper than [`pow_carried`], which is within
//! 1 ulp by carrying y ln x beyond double precision: the f64 shader's
//! `pow`, whose agreement with `std` must not depend on how a GPU
//! compiler rounds.

mod carried;
pub use carried::{pow_carried, Fused, MulAdd, Separate};

/// ln 2 split for Cody and Waite's reduction: `LN2_HI` has 21 trailing
/// zero bits, so k · LN2_HI is exact for |k| < 2^21.
const LN2_HI: f64 = f64::from_bits(0x3fe6_2e42_fee0_0000);
const LN2_LO: f64 = f64::from_bits(0x3dea_39ef_3579_3c76);
/// Round to nearest (even) by adding and subtracting 1.5 · 2^52.
const ROUND: f64 = 6_755_399_441_055_744.0;

/// The larger of a and b as one select (`maxpd`): `f64::max` also
/// orders NaN, which costs two more instructions in a vector loop. A NaN
/// in either gives b.
#[inline(always)]
pub(crate) fn larger(a: f64, b: f64) -> f64 {
    if a > b {
        a
    } else {
        b
    }
}

/// The smaller of a and b as one select (`minpd`; see [`larger`]).
#[inline(always)]
pub(crate) fn smaller(a: f64, b: f64) -> f64 {
    if a < b {
        a
    } else {
        b
    }
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

/// (k as an f64, m) with x = 2^k · m and m in [√½, √2), for any x > 0,
/// subnormals scaled into the normal range first (by 2^54).
#[inline(always)]
fn split_any(x: f64) -> (f64, f64) {
    let tiny = x < f64::MIN_POSITIVE;
    let xs = if tiny {
        x * 18_014_398_509_481_984.0
    } else {
        x
    };
    let (k, m) = split_exponent(xs);
    (int_to_f64(k - if tiny { 54 } else { 0 }), m)
}

/// 2^k for k in the normal range [−1022, 1023], from its exponent field.
#[inline(always)]
pub(crate) fn pow2i(k: i64) -> f64 {
    f64::from_bits(((k + 1023) as u64) << 52)
}

// fdlibm's minimax coefficients of R(z) = (ln((1+s)/(1−s)) − 2s) / s,
// z = s², within 2^−58.45 (`ln` and `carried::series`).
const LG1: f64 = f64::from_bits(0x3fe5_5555_5555_5593); // 0.6666666666666735
const LG2: f64 = f64::from_bits(0x3fd9_9999_9997_fa04); // 0.3999999999940942
const LG3: f64 = f64::from_bits(0x3fd2_4924_9422_9359); // 0.2857142874366239
const LG4: f64 = f64::from_bits(0x3fcc_71c5_1d8e_78af); // 0.22222198432149784
const LG5: f64 = f64::from_bits(0x3fc7_4664_96cb_03de); // 0.1818357216161805
const LG6: f64 = f64::from_bits(0x3fc3_9a09_d078_c69f); // 0.15313837699209373
const LG7: f64 = f64::from_bits(0x3fc2_f112_df3e_5244); // 0.14798198605116586

/// ln x for x > 0 (subnormals included); NaN below 0, −∞ at 0. Within
/// 1 ulp: fdlibm's `__ieee754_log`, its branches made selects.
#[inline(always)]
pub fn ln(x: f64) -> f64 {
    let (kf, m) = split_any(x);
    // m in [√½, √2): ln m = 2 atanh(s), s = f / (2 + f), |s| < 0.1716,
    // = f − hf² + s (hf² + R(s²)), hf² = f²/2.
    let f = m - 1.0;
    let s = f / (2.0 + f);
    let z = s * s;
    let w = z * z;
    let t1 = w * (LG2 + w * (LG4 + w * LG6));
    let t2 = z * (LG1 + w * (LG3 + w * (LG5 + w * LG7)));
    let r = t2 + t1;
    let hfsq = 0.5 * f * f;
    let v = kf * LN2_HI - ((hfsq - (s * (hfsq + r) + kf * LN2_LO)) - f);
    if x > 0.0 {
        v
    } else if x == 0.0 {
        f64::NEG_INFINITY
    } else {
        f64::NAN
    }
}

/// e^x; 0 below −745, +∞ above 709.78. Within 1 ulp: fdlibm's
/// `__ieee754_exp`, its branches made selects.
#[inline(always)]
pub fn exp(x: f64) -> f64 {
    let xc = x.clamp(-746.0, 710.0);
    // x = k ln 2 + r, |r| <= ln 2 / 2, r = hi − lo.
    let (kf, k) = round_int(xc * std::f64::consts::LOG2_E);
    let hi = xc - kf * LN2_HI;
    let lo = kf * LN2_LO;
    let v = scale(exp_reduced::<Separate>(hi, lo), k);
    if x.is_nan() {
        x
    } else {
        v
    }
}

/// e^(hi − lo) for |hi − lo| <= ln 2 / 2 and a small tail lo: fdlibm's
/// e^r = 1 + 2r / (2 − c), c = r − r² P(r²), written as
/// 1 − ((lo − r c / (2 − c)) − hi) so that the rounding of r = hi − lo
/// reaches only the correction r c / (2 − c).
#[inline(always)]
fn exp_reduced<M: MulAdd>(hi: f64, lo: f64) -> f64 {
    // fdlibm's minimax coefficients of P.
    const P1: f64 = f64::from_bits(0x3fc5_5555_5555_553e); // 0.16666666666666602
    const P2: f64 = f64::from_bits(0xbf66_c16c_16be_bd93); // -0.0027777777777015593
    const P3: f64 = f64::from_bits(0x3f11_566a_af25_de2c); // 6.613756321437934e-05
    const P4: f64 = f64::from_bits(0xbebb_bd41_c5d2_6bf1); // -1.6533902205465252e-06
    const P5: f64 = f64::from_bits(0x3e66_3769_72be_a4d0); // 4.1381367970572385e-08
    let r = hi - lo;
    let t = r * r;
    let p = M::mad(t, M::mad(t, M::mad(t, M::mad(t, P5, P4), P3), P2), P1);
    let c = M::msub(t, p, r);
    1.0 - ((lo - (r * c) / (2.0 - c)) - hi)
}

/// e · 2^k for k from −2044 to 2044, in two factors so that no exponent
/// field leaves its range (e · 2^k is then 0 or ∞ where it should be).
#[inline(always)]
fn scale(e: f64, k: i64) -> f64 {
    let k1 = k / 2;
    e * pow2i(k1) * pow2i(k - k1)
}

/// x^y for x >= 0 (the powers of a sliding speed): exp(y ln x), with
/// 0^y = 0 for y > 0, 1 for y = 0, +∞ for y < 0; NaN for x < 0. The
/// product t = y ln x is rounded once and ln x is within 1 ulp, which
/// costs about 2|t| ulp of the result (e^(t(1 + ε)) = e^t (1 + tε)):
/// within 1 + 2 |y ln x| ulp of `powf` (see the module's text).
#[inline(always)]
pub fn pow(x: f64, y: f64) -> f64 {
    let v = exp(y * ln(x));
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
    pub(super) fn ulps(a: f64, b: f64) -> u64 {
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
    fn pow_is_within_its_stated_ulps_of_std_over_the_models_range() {
        let mut u = Uniforms::new(3);
        let (mut worst, mut rel, mut paper): (f64, f64, u64) = (0.0, 0.0, 0);
        for i in 0..500_000 {
            let x = 10f64.powf(-12.0 + 16.0 * u.next());
            let y = 5.0 * u.next();
            let t = (y * x.ln()).abs();
            let (got, want) = (pow(x, y), x.powf(y));
            let d = ulps(got, want) as f64;
            worst = worst.max(d / (1.0 + 2.0 * t));
            rel = rel.max((got - want).abs() / want);
            assert!(d <= 1.0 + 2.0 * t, "pow({x}, {y}): {d} ulp");
            // The default exponent at 0.1 mm/s to 100 m/s.
            let v = 10f64.powf(-4.0 + 6.0 * u.next());
            let b = if i % 2 == 0 { 0.612 } else { y.min(0.612) };
            paper = paper.max(ulps(pow(v, b), v.powf(b)));
        }
        eprintln!(
            "pow: worst {worst:.3} of the bound 1 + 2 |y ln x| ulp, {rel:.2e} relative; \
             b <= 0.612 at 0.1 mm/s to 100 m/s: {paper} ulp"
        );
        assert!(rel < 7e-14, "pow: {rel:e} relative");
        assert!(paper <= 12, "pow: {paper} ulp at the paper's exponent");
        assert_eq!(pow(0.0, 0.6), 0.0);
        assert_eq!(pow(0.0, 0.0), 1.0);
        assert_eq!(pow(2.0, 0.0), 1.0);
        assert!(pow(-1.0, 0.5).is_nan());
    }
}
