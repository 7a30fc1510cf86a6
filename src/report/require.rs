//! The answer to a sweep's design requirement: per value of the first
//! grid axis (and of the others), the lanes that pass it, and whether the
//! share is met with 95 % confidence.

use super::aggregates::{axis_indices, bin, bin_values, panel_label, panel_of};
use crate::input::sweep::require::Requirement;
use crate::input::sweep::Sweep;
use crate::params::Num;
use crate::stats::{wilson_z, Z95_ONE_SIDED};

/// Whether a share meets a requirement with 95 % confidence.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// The one-sided 95 % lower bound is at least the required share.
    Met,
    /// Neither bound decides: more lanes are needed.
    Undecided,
    /// The one-sided 95 % upper bound is below the required share.
    NotMet,
}

/// The answer to a requirement: lanes that pass it and lanes counted,
/// per value of the first grid axis (binned past a cap) and per value of
/// the other axes (a panel each, at most the panel limit).
pub struct RequireData {
    pub req: Requirement,
    /// The first axis (None: the sweep has no grid).
    pub axis: Option<Num>,
    /// The first axis's values, one per point (bin).
    pub xs: Vec<f64>,
    pub binned: bool,
    pub panel_labels: Vec<String>,
    pub panel_total: u64,
    /// Per panel, per point: (passing, counted).
    pub counts: Vec<Vec<(u64, u64)>>,
    lens: Vec<u64>,
    idx: Vec<u64>,
    cap: u64,
}

impl RequireData {
    /// The counts of `req` over a run of `sweep`.
    pub fn new(req: Requirement, sweep: &Sweep, panels: usize, cap: u64) -> RequireData {
        let lens: Vec<u64> = sweep.axes.iter().map(|a| a.len()).collect();
        let (xs, binned, panel_total, labels) = match sweep.axes.first() {
            None => (vec![f64::NAN], false, 1, vec!["all lanes".to_string()]),
            Some(a) => {
                let total = lens[1..].iter().fold(1u64, |p, &l| p.saturating_mul(l));
                let shown = total.min(panels as u64);
                (
                    bin_values(a, cap),
                    a.len() > cap,
                    total,
                    (0..shown).map(|p| panel_label(sweep, &[0], p)).collect(),
                )
            }
        };
        RequireData {
            req,
            axis: sweep.axes.first().map(|a| a.param),
            counts: vec![vec![(0, 0); xs.len()]; labels.len()],
            xs,
            binned,
            panel_labels: labels,
            panel_total,
            idx: vec![0; lens.len()],
            lens,
            cap,
        }
    }

    /// Adds a lane of grid point `point` that passes or not.
    pub fn add(&mut self, point: u64, passes: bool) {
        let (p, b) = if self.lens.is_empty() {
            (0, 0)
        } else {
            axis_indices(&self.lens, point, &mut self.idx);
            (
                panel_of(&self.lens, &self.idx, &[0]),
                bin(self.idx[0], self.lens[0], self.cap),
            )
        };
        if let Some(c) = self.counts.get_mut(p as usize).and_then(|v| v.get_mut(b)) {
            c.0 += passes as u64;
            c.1 += 1;
        }
    }

    /// The share of (passing, counted), its one-sided 95 % bounds (low,
    /// high) and the verdict.
    pub fn judge(&self, (k, n): (u64, u64)) -> (f64, f64, f64, Option<Verdict>) {
        if n == 0 {
            return (f64::NAN, f64::NAN, f64::NAN, None);
        }
        let (lo, hi) = wilson_z(k, n, Z95_ONE_SIDED);
        let v = if lo >= self.req.at_least {
            Verdict::Met
        } else if hi < self.req.at_least {
            Verdict::NotMet
        } else {
            Verdict::Undecided
        };
        (k as f64 / n as f64, lo, hi, Some(v))
    }

    /// The fewest lanes a grid point needs for a requirement of all its
    /// lanes passing to be confirmed: n / (n + z²) >= at_least.
    pub fn lanes_needed(&self) -> u64 {
        let a = self.req.at_least;
        if a >= 1.0 {
            return u64::MAX;
        }
        let z2 = Z95_ONE_SIDED * Z95_ONE_SIDED;
        (a * z2 / (1.0 - a)).ceil() as u64
    }
}
