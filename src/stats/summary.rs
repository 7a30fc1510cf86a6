//! `summary.csv`: one block of rows per group (a grid point of a sampled
//! sweep, or the whole run), written as each group ends.

use std::fmt::Write as _;
use std::path::Path;

use super::quantile::{self, Sketch, PROBS};
use super::{spearman, wilson};
use crate::error::Result;
use crate::integrator::{Contact, LaneResult, Status};
use crate::lanes::Source;
use crate::outdir::AtomicFile;
use crate::output::CsvLines;
use crate::params::{Num, Params};
use crate::sweep::Axis;

/// The result number columns of `lanes.csv` that get statistics, in its
/// order.
pub const NUMBER_COLUMNS: [&str; 20] = [
    "switches",
    "t_first_switch",
    "reversals",
    "sticks",
    "x1_end",
    "v1_end",
    "w_motor",
    "w_load",
    "w_friction",
    "eta_end",
    "steps",
    "w1_in",
    "w1_out",
    "w2_in",
    "w2_out",
    "eta_direct",
    "eta_inverse",
    "eta_direct_ss",
    "eta_inverse_ss",
    "lock_margin_deg",
];

/// A lane's values of [`NUMBER_COLUMNS`] as `lanes.csv` holds them: NaN
/// for an empty cell (a lane that could not be finished reports no
/// numbers but its counts).
pub fn numbers(r: &LaneResult) -> [f64; 20] {
    let ok = r.status == Status::Ok;
    let v = |x: f64| if ok { x } else { f64::NAN };
    [
        r.switches as f64,
        r.t_first_switch,
        r.reversals as f64,
        r.sticks as f64,
        v(r.x1_end),
        v(r.v1_end),
        v(r.w_motor),
        v(r.w_load),
        v(r.w_friction),
        v(r.eta_end),
        r.steps as f64,
        v(r.w1_in),
        v(r.w1_out),
        v(r.w2_in),
        v(r.w2_out),
        v(r.eta_direct),
        v(r.eta_inverse),
        v(r.eta_direct_ss),
        v(r.eta_inverse_ss),
        v(r.lock_margin_deg),
    ]
}

/// Lanes of a group kept for exact quantiles and rank correlations; past
/// this the quantiles come from a [`Sketch`] (error stated there) and the
/// rank correlations from the group's first `EXACT_MAX` lanes (the lanes of
/// a study are independent draws, so these are a random sample). Memory:
/// 8 bytes × (20 results + sampled inputs) × this, about 20 MB.
pub const EXACT_MAX: usize = 100_000;

/// How lanes fall into groups, and which inputs are sampled.
#[derive(Clone, Debug, Default)]
pub struct Grouping {
    /// Lanes per group (0: the whole run is one group).
    pub per_group: u64,
    /// The grid's axes, whose values name a group.
    pub axes: Vec<Axis>,
    /// The sampled inputs, for rank correlations.
    pub inputs: Vec<Num>,
}

impl Grouping {
    /// A sampled sweep with a grid: one group per grid point; otherwise the
    /// whole run.
    pub fn of(source: &Source) -> Grouping {
        match source {
            Source::Sweep { sweep, .. } => {
                let inputs = sweep
                    .study
                    .as_ref()
                    .map(|s| s.params.iter().map(|t| t.param).collect())
                    .unwrap_or_default();
                match &sweep.study {
                    Some(st) if !sweep.axes.is_empty() => Grouping {
                        per_group: st.n,
                        axes: sweep.axes.clone(),
                        inputs,
                    },
                    _ => Grouping {
                        inputs,
                        ..Grouping::default()
                    },
                }
            }
            Source::Table { .. } => Grouping::default(),
        }
    }

    fn group_of(&self, lane: u64) -> u64 {
        lane.checked_div(self.per_group).unwrap_or(0)
    }
}

/// The grid values of grid point `point` (the last axis runs fastest, as
/// in `Sweep::lane_spec`); the lanes' own values may differ, when a
/// tolerance scatters an axis parameter.
fn grid_values(axes: &[Axis], point: u64) -> Vec<f64> {
    let mut rest = point;
    let mut v: Vec<f64> = axes
        .iter()
        .rev()
        .map(|a| {
            let x = a.value(rest % a.len());
            rest /= a.len();
            x
        })
        .collect();
    v.reverse();
    v
}

/// One result column of one group.
#[derive(Default)]
struct Column {
    count: u64,
    mean: f64,
    m2: f64,
    min: f64,
    max: f64,
    /// Past `EXACT_MAX` lanes: every finite value so far.
    sketch: Option<Sketch>,
}

impl Column {
    fn add(&mut self, x: f64) {
        if !x.is_finite() {
            return;
        }
        // Welford's update: stable for any count.
        self.count += 1;
        let d = x - self.mean;
        self.mean += d / self.count as f64;
        self.m2 += d * (x - self.mean);
        if self.count == 1 {
            (self.min, self.max) = (x, x);
        } else {
            self.min = self.min.min(x);
            self.max = self.max.max(x);
        }
        if let Some(s) = self.sketch.as_mut() {
            s.add(x);
        }
    }
}

/// The group being accumulated.
struct Group {
    id: u64,
    axis_values: Vec<f64>,
    lanes: u64,
    by_status: [u64; 6],
    by_contact: [u64; 3],
    cols: Vec<Column>,
    /// The first `EXACT_MAX` lanes' values: results, then inputs.
    kept: Vec<Vec<f64>>,
}

/// Streams statistics into `summary.csv`.
pub struct Stats {
    grouping: Grouping,
    group: Option<Group>,
    out: CsvLines,
}

/// The columns of `summary.csv` after `group` and the grid's parameters.
pub const SUMMARY_COLUMNS: &str = "kind,name,input,count,mean,std,min,p1,p5,p50,p95,p99,max,\
quantiles,share,ci95_low,ci95_high,rho";

const CONTACTS: [Contact; 3] = [Contact::Aa, Contact::Bb, Contact::Stick];

impl Stats {
    /// Starts `path` for lanes grouped by `grouping`.
    pub fn create(path: &Path, grouping: Grouping) -> Result<Stats> {
        let mut head = String::from("group");
        for a in &grouping.axes {
            let _ = write!(head, ",{}", a.param.name());
        }
        let out = CsvLines::create(path, &format!("{head},{SUMMARY_COLUMNS}"))?;
        Ok(Stats {
            grouping,
            group: None,
            out,
        })
    }

    /// Adds lane `lane` (lanes come in order).
    pub fn add(&mut self, lane: u64, p: &Params, r: &LaneResult) -> Result<()> {
        self.add_values(lane, r.status, r.contact_end, &numbers(r), |n| p.get(n))
    }

    /// Adds lane `lane` as its row of `lanes.csv` gives it: its status,
    /// final contact, [`NUMBER_COLUMNS`] values (NaN for an empty cell) and
    /// parameters (`input`, for the sampled ones). Lanes come in order.
    pub fn add_values(
        &mut self,
        lane: u64,
        status: Status,
        contact_end: Contact,
        values: &[f64; 20],
        input: impl Fn(Num) -> f64,
    ) -> Result<()> {
        let id = self.grouping.group_of(lane);
        if self.group.as_ref().is_some_and(|g| g.id != id) {
            let g = self.group.take().expect("checked");
            self.write_group(g)?;
        }
        let (axes, inputs) = (&self.grouping.axes, &self.grouping.inputs);
        let g = self.group.get_or_insert_with(|| Group {
            id,
            axis_values: grid_values(axes, id),
            lanes: 0,
            by_status: [0; 6],
            by_contact: [0; 3],
            cols: (0..NUMBER_COLUMNS.len())
                .map(|_| Column::default())
                .collect(),
            kept: vec![Vec::new(); NUMBER_COLUMNS.len() + inputs.len()],
        });
        g.lanes += 1;
        g.by_status[Status::ALL.iter().position(|&s| s == status).unwrap_or(0)] += 1;
        if status == Status::Ok {
            g.by_contact[CONTACTS.iter().position(|&c| c == contact_end).unwrap_or(0)] += 1;
        }
        for (c, &x) in g.cols.iter_mut().zip(values) {
            c.add(x);
        }
        if g.kept[0].len() < EXACT_MAX {
            let ins = inputs.iter().map(|&n| input(n));
            for (k, x) in g.kept.iter_mut().zip(values.iter().copied().chain(ins)) {
                k.push(x);
            }
        } else if g.cols[0].sketch.is_none() {
            // From here on the quantiles are estimates over every value.
            for (i, c) in g.cols.iter_mut().enumerate() {
                let mut s = Sketch::default();
                for &x in g.kept[i].iter().filter(|x| x.is_finite()) {
                    s.add(x);
                }
                if values[i].is_finite() {
                    s.add(values[i]);
                }
                c.sketch = Some(s);
            }
        }
        Ok(())
    }

    /// Writes the last group; the file, to be committed with the run's
    /// other files.
    pub fn finish(mut self) -> Result<AtomicFile> {
        if let Some(g) = self.group.take() {
            self.write_group(g)?;
        }
        Ok(self.out.into_file())
    }

    fn write_group(&mut self, g: Group) -> Result<()> {
        let mut key = g.id.to_string();
        for v in &g.axis_values {
            let _ = write!(key, ",{v:?}");
        }
        for (i, c) in g.cols.iter().enumerate() {
            let mut cells = Cells::default();
            if c.count > 0 {
                let sd = if c.count > 1 {
                    (c.m2 / (c.count - 1) as f64).sqrt()
                } else {
                    f64::NAN
                };
                let qs: Vec<f64> = match &c.sketch {
                    Some(s) => PROBS.iter().map(|&q| s.quantile(q)).collect(),
                    None => {
                        let mut v: Vec<f64> = g.kept[i]
                            .iter()
                            .copied()
                            .filter(|x| x.is_finite())
                            .collect();
                        v.sort_by(f64::total_cmp);
                        PROBS.iter().map(|&q| quantile::exact(&v, q)).collect()
                    }
                };
                let moments = [c.mean, sd, c.min].into_iter().chain(qs).chain([c.max]);
                for (cell, x) in cells.0[..9].iter_mut().zip(moments) {
                    *cell = num(x);
                }
                cells.0[9] = if c.sketch.is_some() {
                    "estimate"
                } else {
                    "exact"
                }
                .into();
            }
            self.row(&key, "number", NUMBER_COLUMNS[i], "", c.count, cells)?;
        }
        let ok = g.by_status[Status::Ok as usize];
        let shares = Status::ALL
            .iter()
            .map(|s| ("status", s.name(), g.by_status[*s as usize], g.lanes))
            .chain(
                CONTACTS
                    .iter()
                    .enumerate()
                    .map(|(i, c)| ("contact_end", c.name(), g.by_contact[i], ok)),
            );
        for (kind, name, k, n) in shares {
            let (lo, hi) = wilson(k, n);
            let mut cells = Cells::default();
            cells.0[10] = num(k as f64 / n as f64);
            cells.0[11] = num(lo);
            cells.0[12] = num(hi);
            self.row(&key, kind, name, "", k, cells)?;
        }
        let results = NUMBER_COLUMNS.len();
        for (j, input) in self.grouping.inputs.clone().iter().enumerate() {
            for (i, name) in NUMBER_COLUMNS.iter().enumerate() {
                let (rho, n) = spearman(&g.kept[results + j], &g.kept[i]);
                if rho.is_nan() {
                    continue;
                }
                let mut cells = Cells::default();
                cells.0[13] = num(rho);
                self.row(&key, "spearman", name, input.name(), n as u64, cells)?;
            }
        }
        Ok(())
    }

    fn row(
        &mut self,
        key: &str,
        kind: &str,
        name: &str,
        input: &str,
        count: u64,
        cells: Cells,
    ) -> Result<()> {
        let line = self.out.line();
        let _ = write!(
            line,
            "{key},{kind},{name},{input},{count},{}",
            cells.0.join(",")
        );
        self.out.end_line()
    }
}

/// The 14 cells after `count`: mean, std, min, P1, P5, P50, P95, P99, max,
/// quantiles, share, ci95_low, ci95_high, rho.
#[derive(Default)]
struct Cells([String; 14]);

/// A number cell: empty for NaN, else the shortest text that reads back.
fn num(v: f64) -> String {
    if v.is_nan() {
        String::new()
    } else {
        format!("{v:?}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn number_columns_are_lanes_csv_result_columns_in_order() {
        let text = ["lane", "status", "contact_end", "path"];
        let want: Vec<&str> = crate::output::RESULT_COLUMNS
            .iter()
            .copied()
            .filter(|c| !text.contains(c))
            .collect();
        assert_eq!(NUMBER_COLUMNS.to_vec(), want);
    }
}
