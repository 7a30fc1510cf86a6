//! Quantiles: exact from a sorted sample, and a streaming estimate with a
//! stated error for samples too large to keep.

use std::collections::BTreeMap;

/// The quantiles `summary.csv` gives (P1, P5, P50, P95, P99).
pub const PROBS: [f64; 5] = [0.01, 0.05, 0.5, 0.95, 0.99];

/// The exact q-quantile of a sorted, non-empty sample: linear interpolation
/// between the order statistics around rank q·(n − 1) (Hyndman and Fan's
/// type 7, the default of numpy and pandas).
pub fn exact(sorted: &[f64], q: f64) -> f64 {
    let r = q * (sorted.len() - 1) as f64;
    let (lo, hi) = (r.floor() as usize, r.ceil() as usize);
    sorted[lo] + (r - lo as f64) * (sorted[hi] - sorted[lo])
}

/// Relative accuracy of [`Sketch`]: every estimate lies within
/// `ALPHA · |x|` of an order statistic x of the sample (see
/// [`Sketch::quantile`]).
pub const ALPHA: f64 = 1e-3;

/// Magnitudes below this count as zero in a [`Sketch`] (an absolute error
/// of at most this much, far below any result's resolution).
pub const TINY: f64 = 1e-12;

/// A streaming quantile estimate with relative accuracy [`ALPHA`]: a
/// histogram over logarithmic buckets (the DDSketch of Masson, Rim and
/// Lee, 2019). Bucket k holds magnitudes in (γ^(k−1), γ^k], γ = (1 + α) /
/// (1 − α), and stands for 2γ^k / (γ + 1), within α of each of them. Its
/// size is bounded by the range of the data, not by its count: at most
/// ln(max/TINY) / ln γ buckets a sign, about 12,000 per decade pair at
/// α = 1e-3, and in practice a few hundred.
#[derive(Clone, Debug, Default)]
pub struct Sketch {
    pos: BTreeMap<i32, u64>,
    neg: BTreeMap<i32, u64>,
    zero: u64,
    n: u64,
    /// The last bucket added to (its sign, positive when true, and index)
    /// and the values added to it since it was last counted in its map:
    /// a sweep's neighbouring lanes mostly share a bucket, and a count
    /// here costs no map lookup.
    run: Option<(bool, i32, u64)>,
    /// The bits of the last value counted in `run`.
    last: u64,
}

fn ln_gamma() -> f64 {
    ((1.0 + ALPHA) / (1.0 - ALPHA)).ln()
}

impl Sketch {
    /// Adds a finite value.
    pub fn add(&mut self, x: f64) {
        self.n += 1;
        if let Some((_, _, c)) = self.run.as_mut().filter(|_| x.to_bits() == self.last) {
            // The value just added again (a result a sweep leaves fixed):
            // its bucket without the logarithm.
            *c += 1;
            return;
        }
        let a = x.abs();
        if a < TINY {
            self.zero += 1;
            return;
        }
        let k = (a.ln() / ln_gamma()).ceil() as i32;
        let pos = x > 0.0;
        match &mut self.run {
            Some((p, j, c)) if *p == pos && *j == k => {
                *c += 1;
                self.last = x.to_bits();
            }
            run => {
                let r = run.replace((pos, k, 1));
                self.last = x.to_bits();
                if let Some(r) = r {
                    self.settle_run(r);
                }
            }
        }
    }

    /// Counts a run of values of one bucket in its map.
    fn settle_run(&mut self, (pos, k, c): (bool, i32, u64)) {
        *if pos { &mut self.pos } else { &mut self.neg }
            .entry(k)
            .or_default() += c;
    }

    /// Values added.
    pub fn count(&self) -> u64 {
        self.n
    }

    /// The estimate of the q-quantile: the value standing for the bucket
    /// that holds the order statistic of rank ⌊q·(n − 1)⌋ (0-based), so it
    /// is within `ALPHA` relative of that order statistic (or within
    /// `TINY` of it when it is smaller). NaN when empty.
    pub fn quantile(&self, q: f64) -> f64 {
        if self.n == 0 {
            return f64::NAN;
        }
        if let Some(r) = self.run {
            let mut settled = self.clone();
            settled.run = None;
            settled.settle_run(r);
            return settled.quantile(q);
        }
        let rank = (q * (self.n - 1) as f64).floor() as u64;
        let g = ln_gamma().exp();
        let value = |k: i32| 2.0 * (k as f64 * ln_gamma()).exp() / (g + 1.0);
        let mut seen = 0;
        // From the most negative up: negative buckets by falling magnitude.
        for (&k, &c) in self.neg.iter().rev() {
            seen += c;
            if rank < seen {
                return -value(k);
            }
        }
        seen += self.zero;
        if rank < seen {
            return 0.0;
        }
        for (&k, &c) in &self.pos {
            seen += c;
            if rank < seen {
                return value(k);
            }
        }
        unreachable!("rank {rank} below the count {}", self.n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_matches_type_7() {
        // numpy.quantile([1, 2, 3, 4], 0.5) = 2.5; 0.01 -> 1.03.
        let s = [1.0, 2.0, 3.0, 4.0];
        assert_eq!(exact(&s, 0.5), 2.5);
        assert!((exact(&s, 0.01) - 1.03).abs() < 1e-15);
        assert_eq!(exact(&[7.0], 0.99), 7.0);
    }
}
