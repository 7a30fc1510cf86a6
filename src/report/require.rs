//! The answer to a sweep's design requirement: per value of the line's
//! axis (and of the others), the lanes that pass it, and whether the
//! share is met: with 95 % confidence where lanes are samples of a
//! tolerance study, exactly where every lane of the grid is counted.

use super::aggregates::{axis_indices, bin, panel_of, panel_short};
use super::line::{line_axis, XAxis};
use crate::input::sweep::require::Requirement;
use crate::input::sweep::Sweep;
use crate::stats::{wilson_z, Z95_ONE_SIDED};

/// Whether a share meets a requirement (with 95 % confidence, for samples).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Verdict {
    /// The share (for samples, its one-sided 95 % lower bound) is at
    /// least the required share.
    Met,
    /// Neither bound decides: more lanes are needed.
    Undecided,
    /// The one-sided 95 % upper bound is below the required share.
    NotMet,
}

/// The answer to a requirement: lanes that pass it and lanes counted,
/// per value of the line's axis (binned past a cap) and per value of the
/// other axes (a panel each, at most the panel limit).
pub struct RequireData {
    pub req: Requirement,
    /// The axis the answer runs along (None: the sweep has no grid).
    pub x: Option<XAxis>,
    /// No tolerance study: every lane of a grid point is counted, not
    /// sampled, so a share is exact and needs no confidence bound.
    pub exact: bool,
    pub panel_labels: Vec<String>,
    /// The other axes' names ("t2, friction_table"), whose values make
    /// the panels.
    pub others: String,
    pub panel_total: u64,
    /// Per panel, per point: (passing, counted).
    pub counts: Vec<Vec<(u64, u64)>>,
    /// Lanes whose cell of the tested column has a value: none, and the
    /// requirement cannot be answered (the column is empty by its
    /// definition for every lane, e.g. `hold` without `motor_off`).
    pub valued: u64,
    lens: Vec<u64>,
    idx: Vec<u64>,
    iaxis: usize,
    cap: u64,
}

impl RequireData {
    /// The counts of `req` over a run of `sweep`.
    pub fn new(req: Requirement, sweep: &Sweep, panels: usize, cap: u64) -> RequireData {
        let lens: Vec<u64> = sweep.axes.iter().map(|a| a.len()).collect();
        let iaxis = line_axis(sweep);
        let (x, panel_total, labels) = match iaxis {
            None => (None, 1, vec!["all lanes".to_string()]),
            Some(i) => {
                let total = lens
                    .iter()
                    .enumerate()
                    .filter(|(k, _)| *k != i)
                    .fold(1u64, |p, (_, &l)| p.saturating_mul(l));
                let shown = total.min(panels as u64);
                (
                    Some(XAxis::of(&sweep.axes[i], cap)),
                    total,
                    (0..shown).map(|p| panel_short(sweep, &[i], p)).collect(),
                )
            }
        };
        let points = x.as_ref().map_or(1, |x| x.xs.len());
        let others = sweep
            .axes
            .iter()
            .enumerate()
            .filter(|(k, _)| Some(*k) != iaxis)
            .map(|(_, a)| a.param.name())
            .collect::<Vec<_>>()
            .join(", ");
        RequireData {
            req,
            x,
            exact: sweep.study.is_none(),
            counts: vec![vec![(0, 0); points]; labels.len()],
            panel_labels: labels,
            others,
            panel_total,
            idx: vec![0; lens.len()],
            lens,
            iaxis: iaxis.unwrap_or(0),
            cap,
            valued: 0,
        }
    }

    /// Adds a lane of grid point `point` that passes or not.
    pub fn add(&mut self, point: u64, passes: bool) {
        let (p, b) = if self.lens.is_empty() {
            (0, 0)
        } else {
            axis_indices(&self.lens, point, &mut self.idx);
            let i = self.iaxis;
            (
                panel_of(&self.lens, &self.idx, &[i]),
                bin(
                    self.x
                        .as_ref()
                        .map_or(self.idx[i], |x| x.pos.at(self.idx[i])),
                    self.lens[i],
                    self.cap,
                ),
            )
        };
        if let Some(c) = self.counts.get_mut(p as usize).and_then(|v| v.get_mut(b)) {
            c.0 += passes as u64;
            c.1 += 1;
        }
    }

    /// The share of (passing, counted), its one-sided 95 % bounds (low,
    /// high; the share itself where it is exact) and the verdict.
    pub(crate) fn judge(&self, (k, n): (u64, u64)) -> (f64, f64, f64, Option<Verdict>) {
        if n == 0 {
            return (f64::NAN, f64::NAN, f64::NAN, None);
        }
        let share = k as f64 / n as f64;
        if self.exact {
            let v = if share >= self.req.at_least {
                Verdict::Met
            } else {
                Verdict::NotMet
            };
            return (share, share, share, Some(v));
        }
        let (lo, hi) = wilson_z(k, n, Z95_ONE_SIDED);
        let v = if lo >= self.req.at_least {
            Verdict::Met
        } else if hi < self.req.at_least {
            Verdict::NotMet
        } else {
            Verdict::Undecided
        };
        (share, lo, hi, Some(v))
    }

    /// The fewest lanes a grid point needs for a requirement of all its
    /// lanes passing to be confirmed: n / (n + z²) >= at_least.
    pub(crate) fn lanes_needed(&self) -> u64 {
        let a = self.req.at_least;
        if a >= 1.0 {
            return u64::MAX;
        }
        let z2 = Z95_ONE_SIDED * Z95_ONE_SIDED;
        (a * z2 / (1.0 - a)).ceil() as u64
    }
}
