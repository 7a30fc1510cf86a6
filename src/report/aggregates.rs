//! The bounded aggregates the report draws from: map panels, a line along
//! one axis, a study's shown groups, the answer to a requirement, and
//! traced lanes decimated to the plot's resolution (`scan` fills them
//! from an output folder).

use super::scan::{bin, bin_values};
use crate::params::Num;
use crate::stats::{wilson_z, Z95_ONE_SIDED};
use crate::sweep::require::Requirement;
use crate::sweep::Sweep;

/// One map panel: sums and counts per result and cell.
pub struct Panel {
    pub label: String,
    pub(super) nx: usize,
    pub(super) ny: usize,
    pub(super) sums: Vec<Vec<f64>>,
    pub(super) counts: Vec<Vec<u32>>,
    pub(super) contact: Vec<[u32; 3]>,
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

    /// The most frequent final contact per cell (3: no finished lane).
    pub fn contact_cells(&self) -> Vec<usize> {
        self.contact
            .iter()
            .map(|c| {
                if c.iter().all(|&k| k == 0) {
                    3
                } else {
                    (0..3).max_by_key(|&i| (c[i], 3 - i)).unwrap_or(3)
                }
            })
            .collect()
    }

    /// Where the mean lock margin changes sign along each row of cells,
    /// interpolated linearly between cell centres: the static
    /// self-locking limit, in cell coordinates (cell i centred on i).
    pub fn lock_line(&self) -> Vec<(f64, f64)> {
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
fn panel_label(sweep: &Sweep, skip: &[usize], p: u64) -> String {
    let mut rest = p;
    let mut label = Vec::new();
    for (i, a) in sweep.axes.iter().enumerate().rev() {
        if skip.contains(&i) {
            continue;
        }
        label.push(format!(
            "{} = {}",
            super::param_label(a.param),
            super::plots::tick(a.value(rest % a.len()))
        ));
        rest /= a.len();
    }
    label.reverse();
    if label.is_empty() {
        "all lanes".into()
    } else {
        label.join(", ")
    }
}

/// A grid point's index on each axis (the last axis runs fastest).
fn axis_indices(lens: &[u64], point: u64, idx: &mut [u64]) {
    let mut rest = point;
    for (i, &len) in lens.iter().enumerate().rev() {
        idx[i] = rest % len;
        rest /= len;
    }
}

/// The panel of a grid point: the mixed-radix index of the axes not in `skip`.
fn panel_of(lens: &[u64], idx: &[u64], skip: &[usize]) -> u64 {
    let mut p = 0u64;
    for (i, &len) in lens.iter().enumerate() {
        if !skip.contains(&i) {
            p = p.saturating_mul(len).saturating_add(idx[i]);
        }
    }
    p
}

/// Maps over two grid axes.
pub struct MapData {
    pub x: Num,
    pub y: Num,
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
}

impl MapData {
    /// The maps of a sweep of two or more axes: x and y from `[report]
    /// axes` (default the first two), a panel per value of the others (at
    /// most `panels`), at most `cells` cells along an axis.
    pub fn new(sweep: &Sweep, panels: usize, cells: u64) -> MapData {
        let spec = &sweep.report;
        let pick = |k: usize| {
            spec.axes
                .get(k)
                .and_then(|n| sweep.axes.iter().position(|a| a.param == *n))
                .unwrap_or(
                    if spec.axes.first().is_some_and(|n| sweep.axes[0].param == *n) {
                        1
                    } else {
                        k
                    },
                )
        };
        let (ix, iy) = (pick(0), pick(1));
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
                contact: vec![[0; 3]; n],
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
        }
    }

    /// Adds a lane of grid point `point`: its plotted results, its final
    /// contact (finished lanes) and lock margin.
    pub fn add(&mut self, point: u64, vals: &[f64], contact: Option<usize>, lock: f64) {
        axis_indices(&self.lens, point, &mut self.idx);
        let p = panel_of(&self.lens, &self.idx, &[self.ix, self.iy]);
        let (cx, cy) = (
            bin(self.idx[self.ix], self.lens[self.ix], self.cells),
            bin(self.idx[self.iy], self.lens[self.iy], self.cells),
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
        if let Some(k) = contact {
            panel.contact[cell][k] += 1;
        }
        if lock.is_finite() {
            panel.lock[cell].0 += lock;
            panel.lock[cell].1 += 1;
        }
    }
}

/// A band point: x, low, high.
pub type Band = (f64, f64, f64);

/// Results along a single grid axis.
pub struct LineData {
    pub axis: Num,
    pub log: bool,
    pub(super) xs: Vec<f64>,
    pub(super) len: u64,
    /// Per result, per point: sum, count, min, max.
    pub(super) acc: Vec<Vec<(f64, u32, f64, f64)>>,
    pub(super) contact: Vec<[u32; 3]>,
}

impl LineData {
    /// The axis values, one per point (bin).
    pub fn xs(&self) -> &[f64] {
        &self.xs
    }

    /// Mean per point, and the (x, min, max) band.
    pub fn curve(&self, r: usize) -> (Vec<(f64, f64)>, Vec<Band>) {
        let mut pts = Vec::new();
        let mut band = Vec::new();
        for (x, &(s, n, lo, hi)) in self.xs.iter().zip(&self.acc[r]) {
            if n > 0 {
                pts.push((*x, s / n as f64));
                band.push((*x, lo, hi));
            }
        }
        (pts, band)
    }

    /// Per point (in order): mean, min and max of result `r` (NaN where
    /// none).
    pub fn per_point(&self, r: usize) -> Vec<(f64, f64, f64)> {
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

    /// Per point: axis value, finished lanes, held share and its
    /// interval, a-a and b-b shares.
    pub fn contact_rows(&self) -> Vec<Vec<String>> {
        let pct = super::percent;
        self.xs
            .iter()
            .zip(&self.contact)
            .map(|(x, c)| {
                let n: u32 = c.iter().sum();
                let share = |k: u32| pct(k as f64 / n as f64);
                let (lo, hi) = crate::stats::wilson(c[0] as u64, n as u64);
                vec![
                    super::plots::tick(*x),
                    n.to_string(),
                    share(c[0]),
                    format!("{} to {}", pct(lo), pct(hi)),
                    share(c[1]),
                    share(c[2]),
                ]
            })
            .collect()
    }

    /// Share of finished lanes with final contact `i`, per point.
    pub fn contact_share(&self, i: usize) -> Vec<(f64, f64, f64)> {
        self.contact
            .iter()
            .map(|c| {
                let n: u32 = c.iter().sum();
                if n == 0 {
                    return (f64::NAN, f64::NAN, f64::NAN);
                }
                let (lo, hi) = crate::stats::wilson(c[i] as u64, n as u64);
                (c[i] as f64 / n as f64, lo, hi)
            })
            .collect()
    }
}

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
    /// Histogram of result `r`.
    pub fn hist(&self, r: usize) -> Option<(f64, f64, &[u64])> {
        self.hists[r]
            .as_ref()
            .map(|(a, b, c)| (*a, *b, c.as_slice()))
    }

    /// The inputs' rank correlations with `result`, largest first.
    pub fn tornado(&self, result: &str) -> Vec<(String, f64)> {
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

/// Time buckets of a trace plot: about two a pixel of its width.
pub const TRACE_BUCKETS: usize = 1000;

/// One series of a bucket: the first, lowest, highest and last value
/// with their times, so that the plot of the bucket's points draws what
/// the plot of every row would (jumps at events included).
#[derive(Clone, Copy)]
struct M4 {
    first: (f64, f64),
    min: (f64, f64),
    max: (f64, f64),
    last: (f64, f64),
}

impl M4 {
    fn new(t: f64, v: f64) -> M4 {
        M4 {
            first: (t, v),
            min: (t, v),
            max: (t, v),
            last: (t, v),
        }
    }

    fn add(&mut self, t: f64, v: f64) {
        if v < self.min.1 {
            self.min = (t, v);
        }
        if v > self.max.1 {
            self.max = (t, v);
        }
        self.last = (t, v);
    }

    /// The bucket's points in time order, once each.
    fn points(&self, out: &mut Vec<(f64, f64)>) {
        let mut p = [self.first, self.min, self.max, self.last];
        p.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (i, q) in p.iter().enumerate() {
            if i == 0 || *q != p[i - 1] {
                out.push(*q);
            }
        }
    }
}

/// Series of a trace: v1, S1, S2, psi.
const SERIES: usize = 4;

/// One traced lane, decimated: per time bucket and series, the M4 points
/// (first, min, max, last), and the buckets that hold an event. Memory
/// is fixed and time linear in the rows, whatever their number or that
/// of events.
pub struct TraceData {
    pub lane: u64,
    /// Rows read.
    pub rows: u64,
    /// Events read (rows that repeat the time before them).
    pub events: u64,
    horizon: f64,
    buckets: Vec<[Option<M4>; SERIES]>,
    event_at: Vec<Option<f64>>,
}

impl TraceData {
    /// A lane traced from 0 to `horizon` s.
    pub fn new(lane: u64, horizon: f64) -> TraceData {
        TraceData {
            lane,
            rows: 0,
            events: 0,
            horizon: if horizon > 0.0 { horizon } else { 1.0 },
            buckets: vec![[None; SERIES]; TRACE_BUCKETS],
            event_at: vec![None; TRACE_BUCKETS],
        }
    }

    fn bucket(&self, t: f64) -> usize {
        let b = (t / self.horizon * TRACE_BUCKETS as f64).floor();
        if b.is_finite() {
            b.clamp(0.0, (TRACE_BUCKETS - 1) as f64) as usize
        } else {
            0
        }
    }

    /// Adds a row at time `t` with v1, S1, S2, psi; `event`: it repeats
    /// the row before's time (an event's after-row).
    pub fn add(&mut self, t: f64, vals: [f64; SERIES], event: bool) {
        self.rows += 1;
        if !t.is_finite() {
            return;
        }
        let b = self.bucket(t);
        if event {
            self.events += 1;
            self.event_at[b].get_or_insert(t);
        }
        for (s, v) in self.buckets[b].iter_mut().zip(vals) {
            if v.is_finite() {
                match s {
                    Some(m) => m.add(t, v),
                    None => *s = Some(M4::new(t, v)),
                }
            }
        }
    }

    /// Whether the plot holds fewer points than the lane has rows.
    pub fn thinned(&self) -> bool {
        let kept: usize = self.buckets.iter().flat_map(|b| b.iter().flatten()).count() * 4;
        self.rows as usize > kept / SERIES
    }

    /// (t, value) points of series `s` (0 v1, 1 S1, 2 S2, 3 psi).
    pub fn series(&self, s: usize) -> Vec<(f64, f64)> {
        let mut out = Vec::new();
        for b in &self.buckets {
            if let Some(m) = &b[s] {
                m.points(&mut out);
            }
        }
        out
    }

    /// Times of the events marked: one per bucket that holds one.
    pub fn marks(&self) -> Vec<f64> {
        self.event_at.iter().flatten().copied().collect()
    }
}
