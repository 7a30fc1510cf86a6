//! Reproducible random numbers for tolerance studies.
//!
//! Every draw comes from one ChaCha8 stream keyed by the sweep's `seed`;
//! sample `k` reads a fixed block of that stream (seekable in O(1)), so a
//! lane's values depend only on (seed, k), never on thread count, chunking
//! or machine. The key is built from the seed's bytes (not through
//! `seed_from_u64`, whose expansion belongs to rand_core and may change),
//! and uniforms are made from raw `u64`s here, so a crate upgrade cannot
//! change a study's lanes either.

use rand_chacha::ChaCha8Rng;
use rand_core::{Rng, SeedableRng};

/// A seekable stream of uniforms in (0, 1).
pub struct Uniforms {
    rng: ChaCha8Rng,
}

impl Uniforms {
    /// The stream for `seed`.
    pub fn new(seed: u64) -> Self {
        let mut key = [0u8; 32];
        key[..8].copy_from_slice(&seed.to_le_bytes());
        key[8..16].copy_from_slice(b"tswm-v1\0");
        Uniforms {
            rng: ChaCha8Rng::from_seed(key),
        }
    }

    /// A stream of its own for `seed`, `tag` and `index` (the bootstrap's
    /// resamples of one grid point): its key differs from the design's in
    /// the tag, so the two never share a block.
    pub(crate) fn keyed(seed: u64, tag: [u8; 8], index: u64) -> Self {
        let mut key = [0u8; 32];
        key[..8].copy_from_slice(&seed.to_le_bytes());
        key[8..16].copy_from_slice(&tag);
        key[16..24].copy_from_slice(&index.to_le_bytes());
        Uniforms {
            rng: ChaCha8Rng::from_seed(key),
        }
    }

    /// Positions the stream at the block of sample `k`, `per_sample`
    /// uniforms a block.
    pub(crate) fn seek(&mut self, k: u64, per_sample: u64) {
        self.rng
            .set_word_pos(u128::from(k) * u128::from(per_sample) * 2);
    }

    /// The next uniform, strictly inside (0, 1).
    #[allow(clippy::should_implement_trait)]
    pub fn next(&mut self) -> f64 {
        ((self.rng.next_u64() >> 11) as f64 + 0.5) * (1.0 / (1u64 << 53) as f64)
    }
}

/// A tolerance distribution around a nominal value.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Dist {
    /// Uniform on [nominal − tol, nominal + tol].
    Uniform,
    /// Symmetric triangular on [nominal − tol, nominal + tol].
    Triangular,
    /// Normal with σ = tol/3, truncated to [nominal − tol, nominal + tol].
    Normal,
}

impl Dist {
    /// Maps u in (0, 1) to an offset in [−1, 1] (times tol), by the inverse
    /// CDF, so Latin-hypercube strata map to strata of the distribution.
    pub fn quantile(self, u: f64) -> f64 {
        match self {
            Dist::Uniform => 2.0 * u - 1.0,
            Dist::Triangular => {
                if u < 0.5 {
                    (2.0 * u).sqrt() - 1.0
                } else {
                    1.0 - (2.0 * (1.0 - u)).sqrt()
                }
            }
            Dist::Normal => {
                // Truncated at ±3σ: rescale u into [Φ(−3), Φ(3)].
                let lo = norm_cdf(-3.0);
                let z = norm_ppf(lo + u * (1.0 - 2.0 * lo));
                (z / 3.0).clamp(-1.0, 1.0)
            }
        }
    }
}

/// Standard normal CDF.
pub(crate) fn norm_cdf(x: f64) -> f64 {
    0.5 * libm::erfc(-x / std::f64::consts::SQRT_2)
}

/// Standard normal quantile: Acklam's rational approximation refined by
/// one Halley step on the exact CDF (full double precision). The
/// coefficients are kept as published.
#[allow(clippy::excessive_precision)]
pub(crate) fn norm_ppf(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969683028665376e+01,
        2.209460984245205e+02,
        -2.759285104469687e+02,
        1.383577518672690e+02,
        -3.066479806614716e+01,
        2.506628277459239e+00,
    ];
    const B: [f64; 5] = [
        -5.447609879822406e+01,
        1.615858368580409e+02,
        -1.556989798598866e+02,
        6.680131188771972e+01,
        -1.328068155288572e+01,
    ];
    const C: [f64; 6] = [
        -7.784894002430293e-03,
        -3.223964580411365e-01,
        -2.400758277161838e+00,
        -2.549732539343734e+00,
        4.374664141464968e+00,
        2.938163982698783e+00,
    ];
    const D: [f64; 4] = [
        7.784695709041462e-03,
        3.224671290700398e-01,
        2.445134137142996e+00,
        3.754408661907416e+00,
    ];
    let pl = 0.02425;
    let x = if p < pl {
        let q = (-2.0 * p.ln()).sqrt();
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    } else if p <= 1.0 - pl {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    } else {
        let q = (-2.0 * (1.0 - p).ln()).sqrt();
        -(((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    let e = norm_cdf(x) - p;
    let u = e * (2.0 * std::f64::consts::PI).sqrt() * (x * x / 2.0).exp();
    x - u / (1.0 + x * u / 2.0)
}

/// A keyed bijection of [0, n): the Latin-hypercube stratum of each sample
/// in one dimension, computed per sample in O(1) memory (a Feistel network
/// on the next even power of two, cycle-walked into range).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Permutation {
    n: u64,
    half_bits: u32,
    key: u64,
}

impl Permutation {
    /// The permutation of [0, n) for `key`.
    pub fn new(n: u64, key: u64) -> Self {
        let bits = 64 - (n.max(2) - 1).leading_zeros();
        Permutation {
            n,
            half_bits: bits.div_ceil(2).max(1),
            key,
        }
    }

    fn round(&self, r: u64, x: u64) -> u64 {
        let mut z =
            x ^ self.key.rotate_left(17 * r as u32 + 5) ^ (r.wrapping_mul(0x9E37_79B9_7F4A_7C15));
        // splitmix64 finaliser
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Image of `i` < n.
    pub fn apply(&self, i: u64) -> u64 {
        let mask = (1u64 << self.half_bits) - 1;
        let mut x = i;
        loop {
            let (mut l, mut r) = (x >> self.half_bits, x & mask);
            for round in 0..4 {
                let nl = r;
                r = l ^ (self.round(round, r) & mask);
                l = nl;
            }
            x = (l << self.half_bits) | r;
            if x < self.n {
                return x;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniforms_are_seekable_and_reproducible() {
        let mut a = Uniforms::new(7);
        a.seek(3, 4);
        let x: Vec<f64> = (0..4).map(|_| a.next()).collect();
        let mut b = Uniforms::new(7);
        b.seek(0, 4);
        for _ in 0..12 {
            b.next();
        }
        let y: Vec<f64> = (0..4).map(|_| b.next()).collect();
        assert_eq!(x, y);
        assert!(x.iter().all(|&u| u > 0.0 && u < 1.0));
        let mut c = Uniforms::new(8);
        c.seek(3, 4);
        assert_ne!(c.next(), x[0]);
    }

    #[test]
    fn chacha_stream_is_pinned() {
        // The first uniforms of seed 1, computed independently from the
        // ChaCha8 block function (RFC 7539 with 8 rounds, 64-bit counter
        // and stream words) in a few lines of Python. If a crate upgrade
        // changes them, every tolerance study's lanes change: fail loudly.
        let mut u = Uniforms::new(1);
        let got: Vec<u64> = (0..3).map(|_| (u.next() * 1e9) as u64).collect();
        assert_eq!(got, PINNED_SEED1);
    }
    const PINNED_SEED1: [u64; 3] = [960306885, 884786948, 124374106];

    #[test]
    fn normal_quantile_matches_known_values() {
        assert!(norm_ppf(0.5).abs() < 1e-15);
        assert!((norm_ppf(0.975) - 1.959963984540054).abs() < 1e-13);
        assert!((norm_ppf(0.001) + 3.090232306167814).abs() < 1e-12);
        assert!((norm_cdf(1.0) - 0.8413447460685429).abs() < 1e-15);
    }

    #[test]
    fn quantiles_stay_in_band_and_are_symmetric() {
        for d in [Dist::Uniform, Dist::Triangular, Dist::Normal] {
            for i in 1..100 {
                let u = i as f64 / 100.0;
                let q = d.quantile(u);
                assert!((-1.0..=1.0).contains(&q));
                assert!((q + d.quantile(1.0 - u)).abs() < 1e-12, "{d:?} {u}");
            }
        }
        // Normal: tol is 3σ, so the 84.13 % point of the untruncated normal
        // sits near +1σ = tol/3.
        assert!((Dist::Normal.quantile(0.8413) - 1.0 / 3.0).abs() < 0.01);
    }

    #[test]
    fn permutation_is_a_bijection() {
        for n in [1u64, 2, 3, 10, 1000, 4097] {
            let p = Permutation::new(n, 12345);
            let mut seen = vec![false; n as usize];
            for i in 0..n {
                let j = p.apply(i) as usize;
                assert!(!seen[j]);
                seen[j] = true;
            }
        }
    }
}
