//! Statistics of a run for `summary.csv`: per grid point of a sampled
//! sweep (or over the whole run), each result number's moments and
//! quantiles, the share of lanes in each status and final contact with a
//! Wilson interval, and the Spearman rank correlation of each sampled
//! input with each result. Lanes of one grid point are consecutive, so
//! one group is held at a time and memory does not grow with the run.

pub mod exact_quantiles;
pub mod grouping;
pub mod moments;
pub mod order;
pub mod quantile;
pub mod sensitivity;
pub mod sobol;
pub mod summary;

pub use grouping::Grouping;
pub use summary::Stats;

/// The 95 % Wilson score interval of a share k/n (Wilson, 1927): unlike
/// the normal approximation it stays inside [0, 1] and is not empty at
/// k = 0 or k = n.
pub(crate) fn wilson(k: u64, n: u64) -> (f64, f64) {
    wilson_z(k, n, Z95)
}

/// z of a two-sided 95 % interval.
pub(crate) const Z95: f64 = 1.959_963_984_540_054;
/// z of a one-sided 95 % bound (either end of a two-sided 90 % interval).
pub(crate) const Z95_ONE_SIDED: f64 = 1.644_853_626_951_472_2;

/// The Wilson score interval of k/n for the normal quantile `z`.
pub(crate) fn wilson_z(k: u64, n: u64, z: f64) -> (f64, f64) {
    if n == 0 {
        return (f64::NAN, f64::NAN);
    }
    let (k, n) = (k as f64, n as f64);
    let p = k / n;
    let z2n = z * z / n;
    let centre = (p + z2n / 2.0) / (1.0 + z2n);
    let half = z / (1.0 + z2n) * (p * (1.0 - p) / n + z * z / (4.0 * n * n)).sqrt();
    // At k = 0 and k = n the ends are 0 and 1 exactly (rounding would
    // leave 1e-20 off).
    let lo = if k == 0.0 {
        0.0
    } else {
        (centre - half).max(0.0)
    };
    let hi = if k == n {
        1.0
    } else {
        (centre + half).min(1.0)
    };
    (lo, hi)
}

/// Spearman's rank correlation of the pairs whose two values are both
/// finite (average ranks for ties); NaN for fewer than 3 pairs or a
/// constant side.
pub(crate) fn spearman(x: &[f64], y: &[f64]) -> (f64, usize) {
    let (xs, ys): (Vec<f64>, Vec<f64>) = x
        .iter()
        .zip(y)
        .filter(|(a, b)| a.is_finite() && b.is_finite())
        .map(|(&a, &b)| (a, b))
        .unzip();
    let n = xs.len();
    if n < 3 || constant(&xs) || constant(&ys) {
        return (f64::NAN, n);
    }
    (correlate(&ranks(&xs), &ranks(&ys)), n)
}

/// Whether every value equals the first (its ranks are then all equal
/// and a correlation with it is NaN: no sort needed to say so).
fn constant(v: &[f64]) -> bool {
    v.iter().all(|&x| x == v[0])
}

/// Pearson's correlation of two rank vectors of 1..=n (ties averaged);
/// NaN for a constant side.
fn correlate(rx: &[f64], ry: &[f64]) -> f64 {
    let n = rx.len();
    let mean = (n as f64 + 1.0) / 2.0;
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in rx.iter().zip(ry) {
        let (da, db) = (a - mean, b - mean);
        sxy += da * db;
        sxx += da * da;
        syy += db * db;
    }
    if sxx == 0.0 || syy == 0.0 {
        return f64::NAN;
    }
    sxy / (sxx * syy).sqrt()
}

/// The rank correlations of many pairs of columns: a column whose
/// values are all finite is ranked once for all its pairs ([`spearman`]
/// of such a pair keeps every lane, so its ranks are the column's).
pub(crate) struct Correlations<'a> {
    cols: &'a [Vec<f64>],
    /// Per column: None until needed; then its whole ranks, or None when
    /// it has a value that is not finite (each pair is then filtered).
    ranked: Vec<Option<Option<Vec<f64>>>>,
}

impl<'a> Correlations<'a> {
    /// Pairs among `cols` (columns of one length).
    pub fn new(cols: &'a [Vec<f64>]) -> Correlations<'a> {
        Correlations {
            cols,
            ranked: vec![None; cols.len()],
        }
    }

    fn whole(&mut self, c: usize) -> Option<&[f64]> {
        let col = &self.cols[c];
        self.ranked[c]
            .get_or_insert_with(|| {
                let whole = col.iter().all(|x| x.is_finite()) && !col.is_empty();
                // A constant column keeps its (equal) ranks unsorted.
                whole.then(|| match constant(col) {
                    true => vec![(col.len() as f64 + 1.0) / 2.0; col.len()],
                    false => ranks(col),
                })
            })
            .as_deref()
    }

    /// [`spearman`] of columns `x` and `y`, value for value.
    pub(crate) fn spearman(&mut self, x: usize, y: usize) -> (f64, usize) {
        let n = self.cols[x].len();
        if n >= 3 && self.whole(x).is_some() && self.whole(y).is_some() {
            let rank = |c: usize| self.ranked[c].as_ref().and_then(|r| r.as_deref());
            if let (Some(rx), Some(ry)) = (rank(x), rank(y)) {
                return (correlate(rx, ry), n);
            }
        }
        spearman(&self.cols[x], &self.cols[y])
    }
}

/// 1-based ranks, ties sharing their average rank.
fn ranks(v: &[f64]) -> Vec<f64> {
    // Values beside their indices, sorted in place: a sort through an
    // index into `v` reads `v` at random and costs several times more on
    // the large groups of a tolerance study. Ties get their average rank
    // whatever their order, so an unstable sort gives the same ranks.
    let mut sorted: Vec<(f64, u32)> = v.iter().zip(0u32..).map(|(&x, i)| (x, i)).collect();
    sorted.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
    let mut r = vec![0.0; v.len()];
    let mut i = 0;
    while i < sorted.len() {
        let mut j = i;
        while j + 1 < sorted.len() && sorted[j + 1].0 == sorted[i].0 {
            j += 1;
        }
        let avg = (i + j) as f64 / 2.0 + 1.0;
        for &(_, k) in &sorted[i..=j] {
            r[k as usize] = avg;
        }
        i = j + 1;
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wilson_matches_a_known_interval() {
        // Wilson's interval for 8 of 10 at 95 %: 0.4902 to 0.9433
        // (e.g. statsmodels proportion_confint(8, 10, method="wilson")).
        let (lo, hi) = wilson(8, 10);
        assert!(
            (lo - 0.490_162).abs() < 1e-6 && (hi - 0.943_318).abs() < 1e-6,
            "{lo} {hi}"
        );
        let (lo, hi) = wilson(0, 50);
        assert!(lo == 0.0 && (hi - 0.071_348).abs() < 1e-6, "{hi}");
    }

    /// Pairs of columns with ties, constants and values that are not
    /// finite: the cached ranks give [`spearman`]'s values bit for bit.
    #[test]
    fn correlations_of_many_pairs_are_spearman_of_each() {
        let n = 500;
        let mut seed = 7u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let cols: Vec<Vec<f64>> = (0..6)
            .map(|c| {
                (0..n)
                    .map(|i| match c {
                        0 => next(),
                        1 => (next() * 5.0).floor(),
                        2 => 3.0,
                        3 if i % 37 == 0 => f64::NAN,
                        3 => next() - 0.5,
                        4 if i % 11 == 0 => f64::INFINITY,
                        _ => (i as f64).sin(),
                    })
                    .collect()
            })
            .collect();
        let mut pairs = Correlations::new(&cols);
        for x in 0..cols.len() {
            for y in 0..cols.len() {
                let (a, na) = pairs.spearman(x, y);
                let (b, nb) = spearman(&cols[x], &cols[y]);
                assert_eq!((a.to_bits(), na), (b.to_bits(), nb), "{x} {y}");
            }
        }
    }

    #[test]
    fn spearman_of_known_samples() {
        // scipy.stats.spearmanr([1,2,3,4,5], [5,6,7,8,7]) = 0.8207826816681233
        let (r, n) = spearman(&[1., 2., 3., 4., 5.], &[5., 6., 7., 8., 7.]);
        assert_eq!(n, 5);
        assert!((r - 0.820_782_681_668_123_3).abs() < 1e-12, "{r}");
        let (r, _) = spearman(&[1., 2., 3., f64::NAN], &[3., 2., 1., 0.]);
        assert!((r + 1.0).abs() < 1e-15);
    }
}
