//! The one spelling of a float cell, fast: the shortest text that reads
//! back to the same f64, laid out as Rust's `{:?}` lays it out (decimal
//! for 1e-4 <= |x| < 1e16 with at least one fractional digit, `1.5e-5`
//! style outside), so `lanes.csv` keeps its bytes whichever formatter
//! wrote it.
//!
//! The shortest digits come from `zmij` (Schubfach; four times faster
//! than `core::fmt`'s Grisu with Dragon fallback and nearly twice `ryu`,
//! measured on results-like values, and the same digits: both
//! give the shortest string in the rounding interval, the closest to the
//! value, except at an exact tie, which `core::fmt` decides); `zmij`'s
//! layout is `{:?}`'s but for 1e-5 <= |x| < 1e-4, which is laid out
//! again here.

/// Most bytes of a float's text: `-2.2250738585072014e-308` (a sign, 17
/// digits, a point and a three-digit negative exponent).
pub(crate) const MOST_BYTES: usize = 24;

/// Appends `v`'s text to `out`: nothing for NaN (an empty cell), else the
/// bytes `format!("{v:?}")` gives.
#[inline]
pub(crate) fn push_f64(out: &mut Vec<u8>, v: f64) {
    put_f64(v, |s| super::short_bytes::push(out, s));
}

/// Hands `v`'s text ([`push_f64`]'s bytes) to `put`: where the text goes
/// is the caller's (a growing buffer, or room made for a block of rows).
#[inline]
pub(crate) fn put_f64(v: f64, put: impl FnOnce(&[u8])) {
    let a = v.abs();
    // The common case, `zmij`'s text as it is: a magnitude `zmij` lays out
    // as `{:?}` does, and no tie (NaN fails the comparison).
    if (1e-4..1e16).contains(&a) && !may_tie(v) {
        put(zmij::Buffer::new().format_finite(v).as_bytes());
    } else if v == 0.0 {
        // A result that is exactly zero (a work never done) is common.
        put(if v.is_sign_negative() {
            b"-0.0"
        } else {
            b"0.0"
        });
    } else {
        let mut s = Vec::with_capacity(32);
        push_other(&mut s, v);
        put(&s);
    }
}

/// [`push_f64`] of the values `zmij` does not lay out as `{:?}` does, or
/// that may be a tie, and of NaN and infinities.
#[cold]
fn push_other(out: &mut Vec<u8>, v: f64) {
    if v.is_nan() {
        return;
    }
    if v.is_infinite() {
        // `core::fmt` spells them ("inf", "-inf").
        use std::io::Write as _;
        let _ = write!(out, "{v:?}");
        return;
    }
    let at = out.len();
    out.extend_from_slice(zmij::Buffer::new().format_finite(v).as_bytes());
    // `zmij` lays a number out as `{:?}` does (decimal from 1e-4 below
    // 1e16, else `d.ddde-7`), except below 1e-4 down to 1e-5, which it
    // writes as a decimal, and a positive exponent, which it signs
    // (`1e+16`); an exact tie it rounds to even.
    let a = v.abs();
    if a >= 1e16 {
        if let Some(e) = out[at..].iter().position(|&c| c == b'+') {
            out.remove(at + e);
        }
    }
    if (1e-5..1e-4).contains(&a) || may_tie(v) {
        let mut s = [0u8; 32];
        let n = out.len() - at;
        s[..n].copy_from_slice(&out[at..]);
        out.truncate(at);
        relayout(out, v, &s[..n]);
    }
}

/// Appends `v` laid out as `{:?}` lays it out, from `zmij`'s text `s` of
/// it where `zmij`'s digits are the shortest `{:?}` would give, else from
/// `core::fmt`.
#[cold]
fn relayout(out: &mut Vec<u8>, v: f64, s: &[u8]) {
    let tie = may_tie(v);
    let body = s.strip_prefix(b"-").unwrap_or(s);
    if let (false, Some(d)) = (tie, body.strip_prefix(b"0.0000")) {
        // 1e-5 <= |v| < 1e-4, which `zmij` spells "0.0000ddd": "d.dde-5".
        if v < 0.0 {
            out.push(b'-');
        }
        out.push(d[0]);
        if d.len() > 1 {
            out.push(b'.');
            out.extend_from_slice(&d[1..]);
        }
        out.extend_from_slice(b"e-5");
        return;
    }
    // An exact tie between two shortest spellings (`zmij` rounds it to
    // even, `core::fmt` up; rare: a value with few fractional bits and
    // many digits), or a layout `zmij` does not use: `core::fmt` decides.
    use std::io::Write as _;
    let _ = write!(out, "{v:?}");
}

/// Whether `v` (finite, not zero; its first digit at 10^lead) may lie
/// exactly halfway between two shortest spellings. A tie needs the digit
/// after the shortest spelling's last (at most 17 digits from lead) to
/// be `v`'s last nonzero digit, a 5 at 10^-f for `v` with f fractional
/// bits, and the two spellings 10^(1-f) apart to both lie within half a
/// unit in the last place (2^u) of `v`: f <= 17 - lead, 2^u >= 10^(1-f).
/// Integers (u >= 0) never tie. lead is bounded below from the binary
/// exponent (a needless `true` only costs time).
#[inline]
fn may_tie(v: f64) -> bool {
    let bits = v.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    if biased == 0 {
        return false; // subnormal: hundreds of fractional digits
    }
    let mant = (bits & ((1u64 << 52) - 1)) | (1u64 << 52);
    let u = biased - 1075;
    // 2^e2 <= |v| < 2^(e2+1): lead >= floor(e2 log10 2) >= this.
    let lead = ((biased - 1023) * 30103).div_euclid(100_000) - 1;
    let f = -(u + mant.trailing_zeros() as i32);
    u < 0
        && f >= 1
        && f <= 17 - lead
        // With a margin: a needless fallback only costs time.
        && f64::from(u) * std::f64::consts::LOG10_2 >= f64::from(1 - f) - 1e-6
}

#[cfg(test)]
mod tests {
    use super::push_f64;
    use rand_core::{Rng, SeedableRng};

    fn same(v: f64) {
        let mut out = Vec::new();
        push_f64(&mut out, v);
        assert!(out.len() <= super::MOST_BYTES, "bits {:#x}", v.to_bits());
        let want = if v.is_nan() {
            String::new()
        } else {
            format!("{v:?}")
        };
        assert_eq!(
            String::from_utf8(out).unwrap(),
            want,
            "bits {:#x}",
            v.to_bits()
        );
    }

    /// The text is `core::fmt`'s `{:?}`, byte for byte: random bit
    /// patterns (every exponent), random values of every decade, round
    /// numbers, the boundaries of the decimal layout and the extremes.
    #[test]
    fn float_text_is_debug_text() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(28);
        let n: usize = std::env::var("TSWM_FLOAT_TEXT_N").map_or(200_000, |v| v.parse().unwrap());
        for _ in 0..n {
            same(f64::from_bits(rng.next_u64()));
            let m = (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
            let e = (rng.next_u64() % 60) as i32 - 30;
            same(m * 10f64.powi(e));
            same(-((rng.next_u64() % 1_000_000) as f64) / 1000.0);
            // Few fractional bits and many digits: where exact ties lie.
            let k = (rng.next_u64() >> (11 + rng.next_u64() % 40)) as f64;
            let f = (rng.next_u64() % 24) as i32;
            same((k + 0.5) * 2f64.powi(-f));
            same(k * 2f64.powi(-f));
        }
        for v in [
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.1,
            1e-4,
            9.999e-5,
            1e-5,
            1e15,
            9.999999999999998e15,
            1e16,
            1e17,
            123456789.0,
            5e-324,
            f64::MAX,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            f64::MIN,
            -1.2345678901234567e-300,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            0.3,
            2.0f64.powi(60),
            1.0 / 3.0,
        ] {
            same(v);
        }
    }
}
