//! Quantiles: exact from a kept sample ([`super::exact_quantiles`]), and a
//! streaming estimate with a stated error for samples too large to keep.

use std::collections::BTreeMap;

/// The quantiles `summary.csv` gives (P1, P5, P50, P95, P99).
pub const PROBS: [f64; 5] = [0.01, 0.05, 0.5, 0.95, 0.99];

pub use super::exact_quantiles::{exact, exact_finite};

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
    /// The values added since the last was counted in its map, all of
    /// one bucket: a sweep's neighbouring lanes mostly share a bucket.
    run: Option<Run>,
}

/// Values of one bucket not yet counted in their map, with magnitudes
/// `lo..=hi` known to be in the bucket (the bucket's span, or those of
/// its values): the bucket index ⌈ln|x| / ln γ⌉ never falls as |x|
/// grows, so a magnitude between two of the bucket's is in it, found
/// without a logarithm or a map lookup.
#[derive(Clone, Copy, Debug)]
struct Run {
    pos: bool,
    k: i32,
    count: u64,
    lo: f64,
    hi: f64,
}

fn ln_gamma() -> f64 {
    ((1.0 + ALPHA) / (1.0 - ALPHA)).ln()
}

/// The bucket of a magnitude (at least `TINY`).
#[inline]
fn bucket(a: f64) -> i32 {
    (a.ln() / ln_gamma()).ceil() as i32
}

/// The smallest and largest f64 in bucket `k`, found from γ^(k-1) and
/// γ^k by stepping a few units in the last place until [`bucket`] itself
/// says where the bucket begins and ends; None if that takes more steps
/// than it should (then only the values seen stand for the bucket).
fn span(k: i32) -> Option<(f64, f64)> {
    let g = ln_gamma();
    let lo = (f64::from(k - 1) * g).exp();
    let hi = (f64::from(k) * g).exp();
    // Into the bucket, then to its edge.
    let lo = walk(lo, f64::next_up, |x| bucket(x) < k)?;
    let lo = walk(lo, f64::next_down, |x| bucket(x.next_down()) == k)?;
    let hi = walk(hi, f64::next_down, |x| bucket(x) > k)?;
    let hi = walk(hi, f64::next_up, |x| bucket(x.next_up()) == k)?;
    // Magnitudes below TINY count as zero, whatever their bucket.
    let lo = lo.max(TINY);
    (bucket(lo) == k && bucket(hi) == k && lo <= hi).then_some((lo, hi))
}

/// Steps `x` by `next` while `more(x)`; None after more steps than a few
/// units in the last place should take.
fn walk(mut x: f64, next: fn(f64) -> f64, more: impl Fn(f64) -> bool) -> Option<f64> {
    for _ in 0..64 {
        if !more(x) {
            return Some(x);
        }
        x = next(x);
    }
    None
}

impl Sketch {
    /// Adds a finite value.
    pub fn add(&mut self, x: f64) {
        self.n += 1;
        let a = x.abs();
        if let Some(r) = self.run.as_mut() {
            if r.pos == (x > 0.0) && r.lo <= a && a <= r.hi {
                r.count += 1;
                return;
            }
        }
        if a < TINY {
            self.zero += 1;
            return;
        }
        let k = bucket(a);
        let pos = x > 0.0;
        match &mut self.run {
            Some(r) if r.pos == pos && r.k == k => {
                // A second value in a row in this bucket: more may come
                // (a sweep's neighbouring lanes); the bucket's whole span.
                r.count += 1;
                (r.lo, r.hi) = span(k).unwrap_or((r.lo.min(a), r.hi.max(a)));
            }
            run => {
                let new = Run {
                    pos,
                    k,
                    count: 1,
                    lo: a,
                    hi: a,
                };
                if let Some(r) = run.replace(new) {
                    self.settle_run(r);
                }
            }
        }
    }

    /// Adds the finite values of `xs` in order (the others are left
    /// out), as [`Sketch::add`] one at a time does: values that fall in
    /// the bucket of the run before them are counted in one step.
    pub(crate) fn add_all(&mut self, xs: &[f64]) {
        let mut i = 0;
        while i < xs.len() {
            if let Some(r) = self.run.as_mut() {
                let (lo, hi, pos) = (r.lo, r.hi, r.pos);
                // Not NaN, not infinite: outside every finite span.
                let inside = |x: f64| ((x > 0.0) == pos) & (lo <= x.abs()) & (x.abs() <= hi);
                // Whole groups of 8 at a time (compared as a vector, no
                // branch inside), then one at a time.
                let rest = &xs[i..];
                let mut whole = 0;
                for g in rest.chunks_exact(8) {
                    let mut all = true;
                    for &x in g {
                        all &= inside(x);
                    }
                    if !all {
                        break;
                    }
                    whole += 8;
                }
                let k = whole + rest[whole..].iter().take_while(|&&x| inside(x)).count();
                r.count += k as u64;
                self.n += k as u64;
                i += k;
                if i == xs.len() {
                    break;
                }
            }
            if xs[i].is_finite() {
                self.add(xs[i]);
            }
            i += 1;
        }
    }

    /// Counts a run of values of one bucket in its map.
    fn settle_run(&mut self, r: Run) {
        *if r.pos { &mut self.pos } else { &mut self.neg }
            .entry(r.k)
            .or_default() += r.count;
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

    /// The sketch's quantiles are those of every value counted in its
    /// bucket one at a time (the runs it keeps change no count): smooth
    /// sequences (a sweep's), repeated values, noise and signs mixed.
    #[test]
    fn runs_count_as_single_values_do() {
        use rand_core::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let mut u = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        let seqs: Vec<Vec<f64>> = vec![
            (0..50_000)
                .map(|i| 1e-3 * (1.0 + i as f64 * 1e-5))
                .collect(),
            (0..50_000)
                .map(|i| ((i as f64) * 1e-3).sin() * 40.0)
                .collect(),
            (0..50_000)
                .map(|i| if i % 7 == 0 { 0.0 } else { 3.25 })
                .collect(),
            (0..50_000)
                .map(|_| (u() - 0.5) * 10f64.powf(8.0 * u() - 4.0))
                .collect(),
        ];
        for xs in seqs {
            let mut s = Sketch::default();
            let (mut pos, mut neg, mut zero) = (BTreeMap::new(), BTreeMap::new(), 0u64);
            for &x in &xs {
                s.add(x);
                let a = x.abs();
                if a < TINY {
                    zero += 1;
                    continue;
                }
                let k = (a.ln() / ln_gamma()).ceil() as i32;
                *if x > 0.0 { &mut pos } else { &mut neg }
                    .entry(k)
                    .or_default() += 1u64;
            }
            let naive = Sketch {
                pos,
                neg,
                zero,
                n: xs.len() as u64,
                run: None,
            };
            // A slice at a time, with cells that are not finite between
            // the values (left out), in pieces of every length.
            let mut all = Sketch::default();
            let mut with_gaps: Vec<f64> = Vec::new();
            for (i, &x) in xs.iter().enumerate() {
                with_gaps.push(x);
                if i % 97 == 0 {
                    with_gaps.push(if i % 2 == 0 { f64::NAN } else { f64::INFINITY });
                }
            }
            let mut at = 0;
            for len in (1..).map(|k| k * k % 1000) {
                let end = (at + len).min(with_gaps.len());
                all.add_all(&with_gaps[at..end]);
                at = end;
                if at == with_gaps.len() {
                    break;
                }
            }
            assert_eq!(all.count(), s.count());
            for q in [0.0, 0.01, 0.05, 0.3, 0.5, 0.95, 0.99, 1.0] {
                assert_eq!(
                    s.quantile(q).to_bits(),
                    naive.quantile(q).to_bits(),
                    "q {q}"
                );
                assert_eq!(s.quantile(q).to_bits(), all.quantile(q).to_bits(), "q {q}");
            }
        }
    }

    /// A bucket's span is exact: its ends are in it, the floats beyond
    /// them are not.
    #[test]
    fn spans_are_exact() {
        for k in (-27_000..300_000).step_by(997) {
            if let Some((lo, hi)) = span(k) {
                assert!(bucket(lo) == k && bucket(hi) == k, "{k}");
                assert!(lo == TINY || bucket(lo.next_down()) < k, "{k}");
                assert!(bucket(hi.next_up()) > k, "{k}");
            }
        }
    }
}
