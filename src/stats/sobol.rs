//! Variance-based sensitivity indices (Sobol') from a Saltelli design.
//!
//! A design of `n` base samples over `d` inputs has `n·(d + 2)` rows, in
//! row groups of `d + 2`: f(A_j), f(AB_j^1), ..., f(AB_j^d), f(B_j), where
//! AB^i is A with column i taken from B (SALib's order for first and total
//! order). For one output, with every value centred on the mean of all the
//! values used (as SALib does: the first-order estimator is not invariant
//! to a shift) and V the population variance of the A and B values:
//!
//! - first order (Saltelli et al. 2010): S1_i = mean(f(B)·(f(AB^i) − f(A))) / V
//! - total (Jansen 1999): ST_i = mean((f(A) − f(AB^i))²) / (2V)
//!
//! Intervals are bootstrap percentiles. The row groups are cut into at
//! most [`MAX_UNITS`] contiguous units of equal size (±1) and a resample
//! draws units with replacement: with one row group a unit (n ≤ 1,024)
//! this is the ordinary bootstrap; past it, a bootstrap over blocks of
//! independent row groups, which estimates the same sampling distribution
//! (the row groups are independent, so a block is a sum of independent
//! terms) at a cost that does not grow with n. Each unit keeps sums, not
//! values, so the memory of one output is `MAX_UNITS × (5 + 3d)` numbers
//! whatever n is.

use rayon::prelude::*;

use crate::input::sampling::Uniforms;

/// Most bootstrap units of a grid point.
pub const MAX_UNITS: usize = 1024;

/// How the intervals are drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bootstrap {
    /// Resamples.
    pub resamples: usize,
    /// Two-sided coverage of the interval, in (0, 1).
    pub confidence: f64,
    /// The seed of the resampling stream (the sweep's `seed`).
    pub seed: u64,
}

/// One index with its interval (NaN where undefined).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Index {
    /// First-order index.
    pub s1: f64,
    /// Its interval's ends.
    pub s1_low: f64,
    /// Its interval's ends.
    pub s1_high: f64,
    /// Total index.
    pub st: f64,
    /// Its interval's ends.
    pub st_low: f64,
    /// Its interval's ends.
    pub st_high: f64,
}

/// The sums of one output over the row groups of a grid point, by
/// bootstrap unit.
#[derive(Clone, Debug)]
pub(crate) struct Accumulator {
    d: usize,
    n: u64,
    units: usize,
    /// Per unit, `5 + 3d` sums of the values less `shift`: count, ΣA, ΣB,
    /// ΣA², ΣB², then per input Σ B·(AB−A), Σ (AB−A), Σ (AB−A)².
    sums: Vec<f64>,
    /// Per unit, the least and greatest A or B value less `shift`.
    lo: Vec<f64>,
    hi: Vec<f64>,
    /// The first value used: subtracted from every value, so the sums
    /// hold deviations, not magnitudes.
    shift: Option<f64>,
}

impl Accumulator {
    /// An empty accumulator for `n` base samples over `d` inputs.
    pub fn new(d: usize, n: u64) -> Accumulator {
        let units = (n as usize).clamp(1, MAX_UNITS);
        Accumulator {
            d,
            n,
            units,
            sums: vec![0.0; units * (5 + 3 * d)],
            lo: vec![f64::INFINITY; units],
            hi: vec![f64::NEG_INFINITY; units],
            shift: None,
        }
    }

    fn k(&self) -> usize {
        5 + 3 * self.d
    }

    /// Adds row group `j` (0 ≤ j < n): its `d + 2` values in design order
    /// (A, AB¹ ... ABᵈ, B), all finite.
    pub fn add(&mut self, j: u64, y: &[f64]) {
        debug_assert_eq!(y.len(), self.d + 2);
        let c0 = *self.shift.get_or_insert(y[0]);
        let u = ((j as u128 * self.units as u128) / self.n.max(1) as u128) as usize;
        let u = u.min(self.units - 1);
        let k = self.k();
        let s = &mut self.sums[u * k..(u + 1) * k];
        let (a, b) = (y[0] - c0, y[self.d + 1] - c0);
        s[0] += 1.0;
        s[1] += a;
        s[2] += b;
        s[3] += a * a;
        s[4] += b * b;
        for i in 0..self.d {
            let dd = (y[1 + i] - c0) - a;
            s[5 + 3 * i] += b * dd;
            s[6 + 3 * i] += dd;
            s[7 + 3 * i] += dd * dd;
        }
        self.lo[u] = self.lo[u].min(a.min(b));
        self.hi[u] = self.hi[u].max(a.max(b));
    }

    /// Row groups added.
    pub fn samples(&self) -> u64 {
        let k = self.k();
        (0..self.units).map(|u| self.sums[u * k] as u64).sum()
    }

    /// The indices of each input with bootstrap intervals; `counts` are the
    /// resamples' unit counts from [`resample_counts`] (shared by every
    /// output of a grid point).
    pub fn indices(&self, counts: &[u32], boot: &Bootstrap) -> Vec<Index> {
        let k = self.k();
        let d = self.d;
        let mut total = vec![0.0; k];
        for u in 0..self.units {
            for (t, s) in total.iter_mut().zip(&self.sums[u * k..(u + 1) * k]) {
                *t += s;
            }
        }
        let constant = self
            .lo
            .iter()
            .zip(&self.hi)
            .filter(|(l, _)| l.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), (a, b)| {
                (l.min(*a), h.max(*b))
            });
        let mut out = vec![
            Index {
                s1: f64::NAN,
                s1_low: f64::NAN,
                s1_high: f64::NAN,
                st: f64::NAN,
                st_low: f64::NAN,
                st_high: f64::NAN,
            };
            d
        ];
        if total[0] == 0.0 || constant.0 >= constant.1 {
            return out;
        }
        // The centre of every value used, kept for the resamples as
        // SALib keeps its normalised outputs.
        let centre = {
            let n = total[0];
            let sab: f64 = (0..d).map(|i| total[6 + 3 * i]).sum();
            ((d as f64 + 1.0) * total[1] + total[2] + sab) / (n * (d as f64 + 2.0))
        };
        let point = estimate(&total, d, centre);
        let mut s1s = vec![Vec::with_capacity(boot.resamples); d];
        let mut sts = vec![Vec::with_capacity(boot.resamples); d];
        let mut t = vec![0.0; k];
        for c in counts.chunks_exact(self.units) {
            t.iter_mut().for_each(|x| *x = 0.0);
            let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
            for (u, &cu) in c.iter().enumerate() {
                if cu == 0 || self.sums[u * k] == 0.0 {
                    continue;
                }
                let w = f64::from(cu);
                for (x, s) in t.iter_mut().zip(&self.sums[u * k..(u + 1) * k]) {
                    *x += w * s;
                }
                lo = lo.min(self.lo[u]);
                hi = hi.max(self.hi[u]);
            }
            if t[0] == 0.0 || lo >= hi {
                // No variance in this resample: no index to take.
                continue;
            }
            for (i, (s1, st)) in estimate(&t, d, centre).into_iter().enumerate() {
                if s1.is_finite() && st.is_finite() {
                    s1s[i].push(s1);
                    sts[i].push(st);
                }
            }
        }
        let p = (1.0 - boot.confidence) / 2.0;
        for (i, o) in out.iter_mut().enumerate() {
            (o.s1, o.st) = point[i];
            (o.s1_low, o.s1_high) = (percentile(&mut s1s[i], p), percentile(&mut s1s[i], 1.0 - p));
            (o.st_low, o.st_high) = (percentile(&mut sts[i], p), percentile(&mut sts[i], 1.0 - p));
        }
        out
    }

    /// Bootstrap units of this accumulator.
    pub fn units(&self) -> usize {
        self.units
    }
}

/// (S1, ST) of each input from the sums `t` (see [`Accumulator`]), the
/// values centred on `centre` (in the shifted frame).
fn estimate(t: &[f64], d: usize, centre: f64) -> Vec<(f64, f64)> {
    let n = t[0];
    let m = (t[1] + t[2]) / (2.0 * n);
    let var = (t[3] + t[4]) / (2.0 * n) - m * m;
    (0..d)
        .map(|i| {
            // Σ (B − c)(AB − A) = Σ B(AB − A) − c Σ (AB − A).
            let s1 = (t[5 + 3 * i] - centre * t[6 + 3 * i]) / n / var;
            let st = 0.5 * t[7 + 3 * i] / n / var;
            // A variance lost to rounding (values all but equal) gives no
            // index, never an infinite one.
            let finite = |x: f64| {
                if var > 0.0 && x.is_finite() {
                    x
                } else {
                    f64::NAN
                }
            };
            (finite(s1), finite(st))
        })
        .collect()
}

/// The `p` quantile of `v` by linear interpolation between order
/// statistics (NumPy's default), NaN for no values; sorts `v`.
pub(crate) fn percentile(v: &mut [f64], p: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let h = p * (v.len() - 1) as f64;
    let lo = h.floor() as usize;
    let hi = (lo + 1).min(v.len() - 1);
    v[lo] + (h - lo as f64) * (v[hi] - v[lo])
}

/// The unit counts of every resample of grid point `group` (resample-major,
/// `units` a resample): each resample draws `units` units with replacement
/// from the pinned ChaCha8 stream of `boot.seed`, keyed apart from the
/// design's draws and by the group.
pub(crate) fn resample_counts(boot: &Bootstrap, group: u64, units: usize) -> Vec<u32> {
    let mut counts = vec![0u32; boot.resamples * units];
    counts.par_chunks_mut(units).enumerate().for_each(|(b, c)| {
        let mut u = Uniforms::keyed(boot.seed, *b"tswm-bs\0", group);
        u.seek(b as u64, units as u64);
        for _ in 0..units {
            let x = ((u.next() * units as f64) as usize).min(units - 1);
            c[x] += 1;
        }
    });
    counts
}

#[cfg(test)]
mod tests;
