// Mirrors src/model/vmath: exp of the f64 path and pow_carried, from
// arithmetic only, plus tan. WGSL's own exp, log, pow and tan become
// GLSL.std.450 instructions that SPIR-V defines for 16- and 32-bit floats
// only: for f64 a driver may return anything (gfx-rs/wgpu#6087; Mesa's
// RADV returns NaN for f64 exp). The bit tricks of vmath (exponent
// fields read and written) are frexp and ldexp here, which SPIR-V does
// define for f64, and vmath's rounding by adding and subtracting
// 1.5 * 2^52 is WGSL's round (ties to even, the same integer): a driver
// may simplify (a + b) - b to a (Mesa does: SPIR-V arithmetic is not
// exact unless marked so, and naga does not mark it). The rest is the
// same arithmetic, line for line; a driver may still fuse multiply-adds
// (NVIDIA's does) or reorder sums, which moves exp by an ulp at most, and
// pow is written so that neither moves it by more (see pow_64).
// Needs wgpu's SHADER_F64; tests/it/math64.rs holds each function within
// 4 ulp of Rust's std over 10^6 arguments of its used range.

// ln 2 split for Cody and Waite's reduction (vmath.rs LN2_HI, LN2_LO).
const LN2_HI_64: f64 = 6.93147180369123816490e-01lf;
const LN2_LO_64: f64 = 1.90821492927058770002e-10lf;
const LOG2_E_64: f64 = 1.4426950408889634lf;
const SQRT_2_64: f64 = 1.4142135623730951lf;

// (k, m) with x = 2^k m and m in [sqrt(1/2), sqrt(2)), for x > 0 normal
// or subnormal (vmath.rs split_exponent). WGSL cannot read an f64's
// exponent field (a bitcast keeps an f64 one value, and frexp's f64
// result holds an i64, which needs SHADER_INT64), so the exponent is
// found by scaling with powers of two, which is exact: down by 2^p while
// m >= 2^p, then up while m < 2^(1-p), p = 512, 256, ..., 1 (the binary
// digits of the exponent), leaving m in [1, 2) with the same bits as the
// field read directly.
struct Split64 {
    k: i32,
    m: f64,
}

fn split_exponent_64(x: f64) -> Split64 {
    var m = x;
    var k = 0i;
    // Subnormals: scaled into the normal range first (by 2^54).
    if (m < 2.2250738585072014e-308lf) {
        m = m * 18014398509481984.0lf;
        k = -54i;
    }
    for (var p = 512i; p >= 1i; p = p / 2i) {
        if (m >= ldexp(1.0lf, p)) {
            m = m * ldexp(1.0lf, -p);
            k = k + p;
        }
    }
    for (var p = 512i; p >= 1i; p = p / 2i) {
        if (m < ldexp(1.0lf, 1i - p)) {
            m = m * ldexp(1.0lf, p);
            k = k - p;
        }
    }
    if (m > SQRT_2_64) {
        m = m * 0.5lf;
        k = k + 1i;
    }
    return Split64(k, m);
}

// +inf and NaN, made at run time (a WGSL constant may not overflow).
fn bitcast_inf_64() -> f64 {
    return ldexp(1.0lf, 1023i) * 2.0lf;
}
fn nan_64() -> f64 {
    let inf = bitcast_inf_64();
    return inf - inf;
}

// e^x; 0 below -745, +inf above 709.78 (vmath.rs exp: fdlibm's
// __ieee754_exp, within 1 ulp).
fn exp_64(x: f64) -> f64 {
    let xc = clamp(x, -746.0lf, 710.0lf);
    // x = k ln 2 + r, |r| <= ln 2 / 2, r = hi - lo.
    let kf = round(xc * LOG2_E_64);
    let hi = xc - kf * LN2_HI_64;
    let lo = kf * LN2_LO_64;
    let v = scale_64(exp_reduced_64(hi, lo), i32(kf));
    if (x != x) {
        return x;
    }
    return v;
}

// e^(hi - lo) for |hi - lo| <= ln 2 / 2 and a small tail lo (vmath.rs
// exp_reduced): fdlibm's 1 + 2r / (2 - c), c = r - r^2 P(r^2).
fn exp_reduced_64(hi: f64, lo: f64) -> f64 {
    let P1 = 1.66666666666666019037e-01lf;
    let P2 = -2.77777777770155933842e-03lf;
    let P3 = 6.61375632143793436117e-05lf;
    let P4 = -1.65339022054652515390e-06lf;
    let P5 = 4.13813679705723846039e-08lf;
    let r = hi - lo;
    let t = r * r;
    let c = r - t * (P1 + t * (P2 + t * (P3 + t * (P4 + t * P5))));
    return 1.0lf - ((lo - (r * c) / (2.0lf - c)) - hi);
}

// e 2^k for k from -2044 to 2044, in two factors (vmath.rs scale).
fn scale_64(e: f64, k: i32) -> f64 {
    let k1 = k / 2i;
    return ldexp(ldexp(e, k1), k - k1);
}

// x rounded to a multiple of 2^-bits (vmath.rs grid).
fn grid_64(x: f64, bits: i32) -> f64 {
    return ldexp(round(ldexp(x, bits)), -bits);
}

// ln m = 2s + s R(s^2) for m in [sqrt(1/2), sqrt(2)), s = f / (2 + f),
// f = m - 1, with s as a head on a 2^-24 grid and a tail (vmath
// carried.rs series).
struct Series64 {
    s_h: f64,
    d: f64,
    s: f64,
    r: f64,
}

fn series_64(m: f64) -> Series64 {
    let LG1 = 6.666666666666735130e-01lf;
    let LG2 = 3.999999999940941908e-01lf;
    let LG3 = 2.857142874366239149e-01lf;
    let LG4 = 2.222219843214978396e-01lf;
    let LG5 = 1.818357216161805012e-01lf;
    let LG6 = 1.531383769920937332e-01lf;
    let LG7 = 1.479819860511658591e-01lf;
    let f = m - 1.0lf;
    let inv = 1.0lf / (2.0lf + f);
    let s_h = grid_64(f * inv, 24i);
    let f_h = grid_64(f, 24i);
    let f_l = f - f_h;
    let num = f_l * (1.0lf - s_h) + ((f_h - 2.0lf * s_h) - s_h * f_h);
    let d = num * inv;
    let s = num * inv + s_h;
    let z = s * s;
    let w = z * z;
    let t1 = w * (LG2 + w * (LG4 + w * LG6));
    let r = z * (LG1 + w * (LG3 + w * (LG5 + w * LG7))) + t1;
    return Series64(s_h, d, s, r);
}

// x^y for x >= 0 and |y| <= 8: 0^y = 0 for y > 0, 1 for y = 0, +inf for
// y < 0, inf^y the inverse, NaN for x < 0 or NaN (vmath pow_carried, line
// for line, within 1 ulp of std's powf). y ln x is carried beyond double
// precision: its head is a sum of products of numbers on coarse grids,
// exact in f64 whether the driver fuses them into the sums or drops
// (a + b) - a to b, and its tail is small enough that its roundings do not
// matter. (A rounded ln x, multiplied by y, was 112 ulp off on an NVIDIA
// H100, whose compiler fuses multiply-adds; the CPU path's pow, cheaper,
// is that and within 1 + 2 |y ln x| ulp.)
fn pow_64(x: f64, y: f64) -> f64 {
    // ln 2 to 28 bits, and the rest.
    let LN2_28 = 6.93147178739309310913e-01lf;
    let LN2_28_TAIL = 1.82063599850414622404e-09lf;
    let LN_2 = 6.93147180559945286227e-01lf;
    let sp = split_exponent_64(x);
    let kf = f64(sp.k);
    let se = series_64(sp.m);
    let s_h = se.s_h;
    let d = se.d;
    let s = se.s;
    let r = se.r;
    // y ln x = n ln 2 + head + tail.
    let y_h = grid_64(y, 20i);
    let y_l = y - y_h;
    let nf = round(y_h * kf);
    let g = y_h * kf - nf;
    let head = g * LN2_28 + 2.0lf * y_h * s_h;
    let tail = (y * s) * r + (g * LN2_28_TAIL + (y_l * (kf * LN_2 + 2.0lf * s) + 2.0lf * y_h * d));
    let jf = round((head + tail) * LOG2_E_64);
    let hi = head - jf * LN2_HI_64;
    let lo = jf * LN2_LO_64 - tail;
    let v = scale_64(exp_reduced_64(hi, lo), clamp(i32(nf) + i32(jf), -2044i, 2044i));
    var at_zero = bitcast_inf_64();
    if (y > 0.0lf) {
        at_zero = 0.0lf;
    } else if (y == 0.0lf) {
        at_zero = 1.0lf;
    }
    if (x > 0.0lf && x < bitcast_inf_64()) {
        return v;
    }
    if (x == 0.0lf) {
        return at_zero;
    }
    if (x == bitcast_inf_64()) {
        return 1.0lf / at_zero;
    }
    return nan_64();
}

// tan x for the friction angles of the laws (|x| < pi/2, and a few
// periods past it): x = k pi/2 + r with pi/2 as fdlibm's 33-bit head
// (k pi/2's head exact for |k| < 2^20) and its tail, then fdlibm's
// __kernel_tan on |r| <= pi/4 (within 1 ulp there), -1/tan r for odd k.
fn tan_64(x: f64) -> f64 {
    let PIO2_1 = 1.57079632673412561417e+00lf;
    let PIO2_1T = 6.07710050650619224932e-11lf;
    let INV_PIO2 = 6.36619772367581382433e-01lf;
    let kf = round(x * INV_PIO2);
    let k = i32(kf);
    let r = (x - kf * PIO2_1) - kf * PIO2_1T;
    let t = kernel_tan_64(r);
    if ((k & 1) != 0) {
        return -1.0lf / t;
    }
    return t;
}

// fdlibm's __kernel_tan for |x| <= pi/4 (its tail y = 0): a degree-27
// odd polynomial, past |x| >= 0.6744 on pi/4 - |x| instead.
fn kernel_tan_64(x0: f64) -> f64 {
    let T0 = 3.33333333333334091986e-01lf;
    let T1 = 1.33333333333201242699e-01lf;
    let T2 = 5.39682539762260521377e-02lf;
    let T3 = 2.18694882948595424599e-02lf;
    let T4 = 8.86323982359930005737e-03lf;
    let T5 = 3.59207910759131235356e-03lf;
    let T6 = 1.45620945432529025516e-03lf;
    let T7 = 5.88041240820264096874e-04lf;
    let T8 = 2.46463134818469906812e-04lf;
    let T9 = 7.81794442939557092300e-05lf;
    let T10 = 7.14072491382608190305e-05lf;
    let T11 = -1.85586374855275456654e-05lf;
    let T12 = 2.59073051863633712884e-05lf;
    let PIO4 = 7.85398163397448278999e-01lf;
    let PIO4_LO = 3.06161699786838301793e-17lf;
    var x = x0;
    var y = 0.0lf;
    let big = abs(x) >= 0.6744lf;
    var sgn = 1.0lf;
    if (big) {
        if (x < 0.0lf) {
            x = -x;
            sgn = -1.0lf;
        }
        x = (PIO4 - x) + (PIO4_LO - y);
        y = 0.0lf;
    }
    let z = x * x;
    let w = z * z;
    // Odd and even terms, each a polynomial in w = x^4.
    let r = T1 + w * (T3 + w * (T5 + w * (T7 + w * (T9 + w * T11))));
    let v = z * (T2 + w * (T4 + w * (T6 + w * (T8 + w * (T10 + w * T12)))));
    let s = z * x;
    let rr = y + z * (s * (r + v) + y);
    let rs = rr + T0 * s;
    let w2 = x + rs;
    if (big) {
        // tan(pi/4 - x) = (1 - tan x) / (1 + tan x), written as fdlibm does.
        let v2 = 1.0lf;
        return sgn * (v2 - 2.0lf * (x - (w2 * w2 / (w2 + v2) - rs)));
    }
    return w2;
}
