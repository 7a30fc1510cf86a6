//! The bounded aggregates the report draws from: map panels, a line along
//! one axis, a study's shown groups, and traced lanes (`scan` fills them
//! from an output folder).

use crate::params::Num;

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
    /// self-locking limit, in cell coordinates.
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
                    let x = ix as f64 + 0.5 + a / (a - b);
                    pts.push((x, iy as f64 + 0.5));
                    break;
                }
            }
        }
        pts
    }
}

/// Maps over two grid axes.
pub struct MapData {
    pub x: Num,
    pub y: Num,
    pub xs: Vec<f64>,
    pub ys: Vec<f64>,
    pub binned: bool,
    pub panels: Vec<Panel>,
    pub panel_total: usize,
    pub(super) ix: usize,
    pub(super) iy: usize,
    pub(super) lens: Vec<u64>,
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
    pub fn contact_share(&self, i: usize) -> Vec<(f64, f64)> {
        self.xs
            .iter()
            .zip(&self.contact)
            .filter_map(|(x, c)| {
                let n: u32 = c.iter().sum();
                (n > 0).then(|| (*x, c[i] as f64 / n as f64))
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

/// A traced lane's rows, as plotted.
pub struct TraceRow {
    pub t: f64,
    pub v1: f64,
    pub s1: f64,
    pub s2: f64,
    pub psi: f64,
}

/// One traced lane.
pub struct TraceData {
    pub lane: u64,
    pub thinned: bool,
    pub(super) rows: Vec<TraceRow>,
    pub(super) stride: usize,
    pub(super) seen: usize,
    pub events: Vec<f64>,
}

impl TraceData {
    /// (t, value) points of one column.
    pub fn series(&self, f: fn(&TraceRow) -> f64) -> Vec<(f64, f64)> {
        self.rows.iter().map(|r| (r.t, f(r))).collect()
    }
}
