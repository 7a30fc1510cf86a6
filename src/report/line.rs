//! Results along one grid axis (the first numeric one, else the first
//! axis of words), a panel per value of the others; and the x axis that a
//! line and a requirement's answer share.

use super::aggregates::{
    axis_indices, bin, bin_values, panel_label, panel_of, panel_values, Band, Positions,
    LINE_POINTS,
};
use crate::input::sweep::{Axis, AxisValues, Sweep};
use crate::params::Param;

/// The axis a line (and a requirement's answer) runs along: the first
/// numeric axis, else the first (of words); None without a grid.
pub(super) fn line_axis(sweep: &Sweep) -> Option<usize> {
    sweep
        .axes
        .iter()
        .position(|a| !a.is_words())
        .or((!sweep.axes.is_empty()).then_some(0))
}

/// The x axis of a line or an answer: a grid axis's values, binned past a
/// cap, or its words.
#[derive(Clone, Debug)]
pub struct XAxis {
    /// The parameter.
    pub param: Param,
    /// Value per point (bin); a word axis's points are 0, 1, 2, ...
    pub xs: Vec<f64>,
    /// The words of a word axis.
    pub words: Option<Vec<String>>,
    /// More values than points: binned.
    pub binned: bool,
    /// Log-spaced.
    pub log: bool,
    /// Where each grid value sits along the axis (lists sorted).
    pub(super) pos: Positions,
}

impl XAxis {
    /// Axis `a` with at most `cap` points.
    pub fn of(a: &Axis, cap: u64) -> XAxis {
        let words = match &a.values {
            AxisValues::Words(w) => Some(w.clone()),
            _ => None,
        };
        XAxis {
            param: a.param,
            xs: match &words {
                Some(w) => (0..w.len()).map(|i| i as f64).collect(),
                None => bin_values(a, cap),
            },
            binned: words.is_none() && a.len() > cap,
            log: matches!(a.values, AxisValues::Range { log: true, .. }),
            pos: Positions::of(a),
            words,
        }
    }

    /// Point `i` in words: the word, or the value.
    pub fn text(&self, i: usize) -> String {
        match &self.words {
            Some(w) => w[i].clone(),
            None => super::plots::tick(self.xs[i]),
        }
    }

    /// The categorical axis of a points chart over the points.
    pub fn categories(&self) -> super::plots::Axis {
        let label = super::words::param_label(self.param);
        match &self.words {
            Some(w) => super::plots::Axis::words(&label, w.clone()),
            None => super::plots::Axis::grid(&label, &self.xs),
        }
    }
}

/// Results along a single grid axis (the first numeric one, else the
/// first axis of words): a panel per value of the other axes.
pub struct LineData {
    pub x: XAxis,
    pub panels: Vec<LinePanel>,
    pub panel_total: u64,
    /// The axis's index among the grid's, and the grid's lengths.
    iaxis: usize,
    lens: Vec<u64>,
    idx: Vec<u64>,
}

/// One panel of a line: the accumulated results per point.
pub struct LinePanel {
    pub label: String,
    /// The other axes' values alone, for a legend.
    pub values: String,
    /// Per result, per point: sum, count, min, max.
    pub(super) acc: Vec<Vec<(f64, u32, f64, f64)>>,
    /// Finished lanes per outcome (`outcome::OUTCOMES`), per point.
    pub(super) outcome: Vec<[u32; super::outcome::N]>,
    /// Whether shares get Wilson intervals.
    independent: bool,
}

impl LineData {
    /// The line of a sweep with a grid, with at most `panels` panels and
    /// `results` results a point.
    pub fn new(sweep: &Sweep, panels: usize, results: usize) -> Option<LineData> {
        let iaxis = line_axis(sweep)?;
        let x = XAxis::of(&sweep.axes[iaxis], LINE_POINTS);
        let lens: Vec<u64> = sweep.axes.iter().map(|a| a.len()).collect();
        let total = lens
            .iter()
            .enumerate()
            .filter(|(i, _)| *i != iaxis)
            .fold(1u64, |p, (_, &l)| p.saturating_mul(l));
        let n = x.xs.len();
        let list = (0..total.min(panels as u64))
            .map(|p| LinePanel {
                label: panel_label(sweep, &[iaxis], p),
                values: panel_values(sweep, &[iaxis], p),
                acc: vec![vec![(0.0, 0, f64::INFINITY, f64::NEG_INFINITY); n]; results],
                outcome: vec![[0; super::outcome::N]; n],
                independent: sweep.independent_lanes(),
            })
            .collect();
        Some(LineData {
            x,
            panels: list,
            panel_total: total,
            iaxis,
            idx: vec![0; lens.len()],
            lens,
        })
    }

    /// The axis values, one per point (bin).
    pub fn xs(&self) -> &[f64] {
        &self.x.xs
    }

    /// Adds a lane of grid point `point`: its plotted results and, for a
    /// finished lane, its outcome.
    pub fn add(&mut self, point: u64, vals: &[f64], outcome: Option<usize>) {
        axis_indices(&self.lens, point, &mut self.idx);
        let p = panel_of(&self.lens, &self.idx, &[self.iaxis]);
        let (i, len) = (self.idx[self.iaxis], self.lens[self.iaxis]);
        let b = bin(self.x.pos.at(i), len, LINE_POINTS).min(self.x.xs.len().saturating_sub(1));
        let Some(panel) = self.panels.get_mut(p as usize) else {
            return;
        };
        for (r, &v) in vals.iter().enumerate() {
            if v.is_finite() {
                let a = &mut panel.acc[r][b];
                a.0 += v;
                a.1 += 1;
                a.2 = a.2.min(v);
                a.3 = a.3.max(v);
            }
        }
        if let Some(k) = outcome {
            panel.outcome[b][k] += 1;
        }
    }
}

impl LinePanel {
    /// Mean per point, and the (x, min, max) band, at the points `xs`.
    pub fn curve(&self, xs: &[f64], r: usize) -> (Vec<(f64, f64)>, Vec<Band>) {
        let mut pts = Vec::new();
        let mut band = Vec::new();
        for (x, &(s, n, lo, hi)) in xs.iter().zip(&self.acc[r]) {
            if n > 0 {
                pts.push((*x, s / n as f64));
                band.push((*x, lo, hi));
            }
        }
        (pts, band)
    }

    /// Per point (in order): mean, min and max of result `r` (NaN where
    /// none).
    pub(crate) fn per_point(&self, r: usize) -> Vec<(f64, f64, f64)> {
        self.acc[r]
            .iter()
            .map(|&(s, n, lo, hi)| {
                if n > 0 {
                    (s / n as f64, lo, hi)
                } else {
                    (f64::NAN, f64::NAN, f64::NAN)
                }
            })
            .collect()
    }

    /// Whether shares get Wilson intervals.
    pub fn independent(&self) -> bool {
        self.independent
    }

    /// Finished lanes per outcome over the whole panel.
    pub(crate) fn outcome_totals(&self) -> [u64; super::outcome::N] {
        let mut t = [0u64; super::outcome::N];
        for c in &self.outcome {
            for (a, &k) in t.iter_mut().zip(c) {
                *a += k as u64;
            }
        }
        t
    }

    /// Per point of `x`: axis value, finished lanes, then for each
    /// outcome of `shown` its share with its interval (where the lanes
    /// are independent draws).
    pub(crate) fn outcome_rows(&self, x: &XAxis, shown: &[usize]) -> Vec<Vec<String>> {
        let pct = super::words::percent;
        self.outcome
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let n: u32 = c.iter().sum();
                let mut row = vec![x.text(i), n.to_string()];
                for &k in shown {
                    let (lo, hi) = super::words::interval(c[k] as u64, n as u64, self.independent);
                    row.push(if n == 0 {
                        "-".into()
                    } else if lo.is_nan() {
                        pct(c[k] as f64 / n as f64)
                    } else {
                        format!(
                            "{} ({} to {})",
                            pct(c[k] as f64 / n as f64),
                            pct(lo),
                            pct(hi)
                        )
                    });
                }
                row
            })
            .collect()
    }

    /// Share of finished lanes with outcome `i`, per point.
    pub(crate) fn outcome_share(&self, i: usize) -> Vec<(f64, f64, f64)> {
        self.outcome
            .iter()
            .map(|c| {
                let n: u32 = c.iter().sum();
                if n == 0 {
                    return (f64::NAN, f64::NAN, f64::NAN);
                }
                let (lo, hi) = super::words::interval(c[i] as u64, n as u64, self.independent);
                (c[i] as f64 / n as f64, lo, hi)
            })
            .collect()
    }
}
