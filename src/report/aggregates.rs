//! The bounded aggregates the report draws from: map panels, a line along
//! one axis and a study's shown groups (`scan` fills them from an output
//! folder; the answer to a requirement and the traced lanes have modules
//! of their own).

use crate::input::sweep::{Axis, Sweep};
use crate::params::Param;

/// Most points along a line (and values in a requirement's answer);
/// longer axes are binned.
pub(super) const LINE_POINTS: u64 = 1000;

pub(super) use super::bins::{bin, bin_values, Positions};

/// A grid value as a panel's name or a table cell: the word of an axis
/// over laws or tables, else the number, short.
pub(super) fn value_text(a: &Axis, i: u64) -> String {
    if a.is_words() {
        a.text(i)
    } else {
        super::plots::tick(a.value(i))
    }
}

/// One map panel: sums and counts per result and cell.
pub struct Panel {
    pub label: String,
    pub(super) nx: usize,
    pub(super) ny: usize,
    pub(super) sums: Vec<Vec<f64>>,
    pub(super) counts: Vec<Vec<u32>>,
    /// Finished lanes per outcome (`outcome::OUTCOMES`).
    pub(super) outcome: Vec<[u32; super::outcome::N]>,
    pub(super) lock: Vec<(f64, u32)>,
}

impl Panel {
    /// Mean of result `r` per cell (NaN where none).
    pub fn means(&self, r: usize) -> Vec<f64> {
        self.sums[r]
            .iter()
            .zip(&self.counts[r])
            .map(|(s, &n)| if n > 0 { s / n as f64 } else { f64::NAN })
            .collect()
    }

    /// The most frequent outcome per cell (`outcome::N`: no finished
    /// lane); ties go to the outcome listed first.
    pub(crate) fn outcome_cells(&self) -> Vec<usize> {
        let n = super::outcome::N;
        self.outcome
            .iter()
            .map(|c| {
                if c.iter().all(|&k| k == 0) {
                    n
                } else {
                    (0..n).max_by_key(|&i| (c[i], n - i)).unwrap_or(n)
                }
            })
            .collect()
    }

    /// Per cell, whether any of its finished lanes is at rest at its end
    /// (stalled, held, or at rest without a motor): no running point.
    pub(crate) fn at_rest_cells(&self) -> Vec<bool> {
        self.outcome
            .iter()
            .map(|c| super::outcome::AT_REST.iter().any(|&k| c[k] > 0))
            .collect()
    }

    /// Where the mean lock margin changes sign along each row of cells,
    /// interpolated linearly between cell centres: the static
    /// self-locking limit, in cell coordinates (cell i centred on i).
    pub(crate) fn lock_line(&self) -> Vec<(f64, f64)> {
        let m: Vec<f64> = self
            .lock
            .iter()
            .map(|&(s, n)| if n > 0 { s / n as f64 } else { f64::NAN })
            .collect();
        let mut pts = Vec::new();
        for iy in 0..self.ny {
            for ix in 0..self.nx.saturating_sub(1) {
                let (a, b) = (m[iy * self.nx + ix], m[iy * self.nx + ix + 1]);
                if a.is_finite() && b.is_finite() && (a > 0.0) != (b > 0.0) {
                    pts.push((ix as f64 + a / (a - b), iy as f64));
                    break;
                }
            }
        }
        pts
    }
}

/// The other axes' values of panel `p` (mixed radix, slowest first),
/// as "name = value" parts; every axis but those of `skip`.
pub(super) fn panel_label(sweep: &Sweep, skip: &[usize], p: u64) -> String {
    let parts = panel_parts(sweep, skip, p);
    if parts.is_empty() {
        return "all lanes".into();
    }
    parts
        .iter()
        .map(|(a, v)| format!("{} = {v}", super::words::param_label(a.param)))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Panel `p` in short: "t2 = -50 N m, friction_table = bronze" ("all
/// lanes" for none), for sentences and titles.
pub(super) fn panel_short(sweep: &Sweep, skip: &[usize], p: u64) -> String {
    let parts = panel_parts(sweep, skip, p);
    if parts.is_empty() {
        return "all lanes".into();
    }
    parts
        .iter()
        .map(|(a, v)| {
            let unit = match a.param {
                crate::params::Param::Num(n) if !n.def().unit.is_empty() => {
                    format!(" {}", n.def().unit)
                }
                _ => String::new(),
            };
            format!("{} = {v}{unit}", a.param.name())
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// Panel `p`'s values alone, for a legend: "bronze", "bronze, 0.05".
pub(super) fn panel_values(sweep: &Sweep, skip: &[usize], p: u64) -> String {
    let parts = panel_parts(sweep, skip, p);
    parts
        .into_iter()
        .map(|(_, v)| v)
        .collect::<Vec<_>>()
        .join(", ")
}

/// The other axes and their values at panel `p`, slowest first.
fn panel_parts<'a>(sweep: &'a Sweep, skip: &[usize], p: u64) -> Vec<(&'a Axis, String)> {
    let mut rest = p;
    let mut parts = Vec::new();
    for (i, a) in sweep.axes.iter().enumerate().rev() {
        if skip.contains(&i) {
            continue;
        }
        parts.push((a, value_text(a, rest % a.len())));
        rest /= a.len();
    }
    parts.reverse();
    parts
}

/// A grid point's index on each axis (the last axis runs fastest).
pub(super) fn axis_indices(lens: &[u64], point: u64, idx: &mut [u64]) {
    let mut rest = point;
    for (i, &len) in lens.iter().enumerate().rev() {
        idx[i] = rest % len;
        rest /= len;
    }
}

/// The panel of a grid point: the mixed-radix index of the axes not in `skip`.
pub(super) fn panel_of(lens: &[u64], idx: &[u64], skip: &[usize]) -> u64 {
    let mut p = 0u64;
    for (i, &len) in lens.iter().enumerate() {
        if !skip.contains(&i) {
            p = p.saturating_mul(len).saturating_add(idx[i]);
        }
    }
    p
}

/// Maps over two numeric grid axes.
pub struct MapData {
    pub x: Param,
    pub y: Param,
    pub xs: Vec<f64>,
    pub ys: Vec<f64>,
    pub binned: bool,
    pub panels: Vec<Panel>,
    pub panel_total: u64,
    ix: usize,
    iy: usize,
    lens: Vec<u64>,
    idx: Vec<u64>,
    cells: u64,
    /// Where x's and y's values sit along the map's axes.
    pos: (Positions, Positions),
}

impl MapData {
    /// The maps of a sweep of two or more numeric axes: x and y from
    /// `[report] axes`, else the first two numeric axes, a panel per value
    /// of the others (words included; at most `panels`), at most `cells`
    /// cells along an axis.
    pub fn new(sweep: &Sweep, panels: usize, cells: u64) -> MapData {
        let spec = &sweep.report;
        let mut order: Vec<usize> = spec
            .axes
            .iter()
            .filter_map(|n| sweep.axes.iter().position(|a| a.param == *n))
            .collect();
        for (i, a) in sweep.axes.iter().enumerate() {
            if order.len() < 2 && !a.is_words() && !order.contains(&i) {
                order.push(i);
            }
        }
        let (ix, iy) = (order[0], order[1]);
        let lens: Vec<u64> = sweep.axes.iter().map(|a| a.len()).collect();
        let (ax, ay) = (&sweep.axes[ix], &sweep.axes[iy]);
        let others = lens
            .iter()
            .enumerate()
            .filter(|(i, _)| *i != ix && *i != iy)
            .fold(1u64, |p, (_, &l)| p.saturating_mul(l));
        let (xs, ys) = (bin_values(ax, cells), bin_values(ay, cells));
        let n = xs.len() * ys.len();
        let results = spec.results().len();
        let shown = others.min(panels as u64);
        let list = (0..shown)
            .map(|p| Panel {
                label: panel_label(sweep, &[ix, iy], p),
                nx: xs.len(),
                ny: ys.len(),
                sums: vec![vec![0.0; n]; results],
                counts: vec![vec![0; n]; results],
                outcome: vec![[0; super::outcome::N]; n],
                lock: vec![(0.0, 0); n],
            })
            .collect();
        MapData {
            x: ax.param,
            y: ay.param,
            binned: ax.len() > cells || ay.len() > cells,
            xs,
            ys,
            panels: list,
            panel_total: others,
            ix,
            iy,
            idx: vec![0; lens.len()],
            lens,
            cells,
            pos: (Positions::of(ax), Positions::of(ay)),
        }
    }

    /// Adds a lane of grid point `point`: its plotted results, its
    /// outcome (finished lanes) and lock margin.
    pub fn add(&mut self, point: u64, vals: &[f64], outcome: Option<usize>, lock: f64) {
        axis_indices(&self.lens, point, &mut self.idx);
        let p = panel_of(&self.lens, &self.idx, &[self.ix, self.iy]);
        let (cx, cy) = (
            bin(
                self.pos.0.at(self.idx[self.ix]),
                self.lens[self.ix],
                self.cells,
            ),
            bin(
                self.pos.1.at(self.idx[self.iy]),
                self.lens[self.iy],
                self.cells,
            ),
        );
        let Some(panel) = self.panels.get_mut(p as usize) else {
            return;
        };
        let cell = cy * panel.nx + cx;
        for (r, v) in vals.iter().enumerate() {
            if v.is_finite() {
                panel.sums[r][cell] += v;
                panel.counts[r][cell] += 1;
            }
        }
        if let Some(k) = outcome {
            panel.outcome[cell][k] += 1;
        }
        if lock.is_finite() {
            panel.lock[cell].0 += lock;
            panel.lock[cell].1 += 1;
        }
    }
}

/// A band point: x, low, high.
pub(crate) type Band = (f64, f64, f64);

/// A shown group of a study.
pub struct GroupData {
    pub label: String,
    pub quantile_rows: Vec<Vec<String>>,
    pub contact_rows: Vec<Vec<String>>,
    /// Per result: histogram range and counts.
    pub(super) hists: Vec<Option<(f64, f64, Vec<u64>)>>,
    /// (result, input, rho).
    pub(super) spearman: Vec<(String, String, f64)>,
}

impl GroupData {
    /// Adds a lane's plotted results to the group's histograms.
    pub fn add(&mut self, vals: &[f64]) {
        for (r, &v) in vals.iter().enumerate() {
            if let (Some((lo, hi, counts)), true) = (self.hists[r].as_mut(), v.is_finite()) {
                // Halves: the span of two finite values cannot overflow.
                let w = (0.5 * *hi - 0.5 * *lo).max(f64::MIN_POSITIVE);
                let bins = counts.len();
                let k = ((0.5 * v - 0.5 * *lo) / w * bins as f64)
                    .floor()
                    .clamp(0.0, (bins - 1) as f64);
                counts[k as usize] += 1;
            }
        }
    }

    /// Histogram of result `r`.
    pub(crate) fn hist(&self, r: usize) -> Option<(f64, f64, &[u64])> {
        self.hists[r]
            .as_ref()
            .map(|(a, b, c)| (*a, *b, c.as_slice()))
    }

    /// The inputs' rank correlations with `result`, largest first.
    pub(crate) fn tornado(&self, result: &str) -> Vec<(String, f64)> {
        let mut v: Vec<(String, f64)> = self
            .spearman
            .iter()
            .filter(|s| s.0 == result)
            .map(|s| (s.1.clone(), s.2))
            .collect();
        v.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()));
        v
    }
}
