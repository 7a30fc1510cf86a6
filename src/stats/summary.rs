//! `summary.csv`: one block of rows per group (a grid point of a sampled
//! sweep, or the whole run), written as each group ends.

use std::fmt::Write as _;
use std::path::Path;

mod add;
mod search;

pub use search::Boundary;

use super::grouping::Grouping;
use super::moments::Moments;
use super::quantile::{self, Sketch, PROBS};
use super::sensitivity::SensitivityCsv;
use super::{wilson, Correlations};
use crate::columns::{results_for, Column as Column_, Kind, Of, Summary};
use crate::error::Result;
use crate::output::csv_lines::{push_f64, CsvLines};
use crate::output::names::SENSITIVITY;
use crate::output::AtomicFile;
use crate::params::{Num, Param, N_NUM};

/// Lanes of a group kept for exact quantiles and rank correlations; past
/// this the quantiles come from a [`Sketch`] (error stated there) and the
/// rank correlations from the group's first `EXACT_MAX` lanes (the lanes of
/// a study are independent draws, so these are a random sample). Memory:
/// 8 bytes × (21 results + sampled inputs) × this, about 20 MB.
pub const EXACT_MAX: usize = 100_000;

/// One result column of one group.
#[derive(Default)]
struct Column {
    /// Count, mean, variance, min and max of its finite values.
    m: Moments,
    /// Past `EXACT_MAX` lanes: every finite value so far.
    sketch: Option<Sketch>,
}

/// The shares of one word column of one group: lanes per word, and the
/// lanes counted (the denominator, see [`Of`]).
#[derive(Clone)]
struct Shares {
    words: Vec<&'static str>,
    of: Of,
    counts: Vec<u64>,
    total: u64,
}

/// The group being accumulated.
struct Group {
    id: u64,
    axis_values: Vec<String>,
    lanes: u64,
    cols: Vec<Column>,
    shares: Vec<Shares>,
    /// The first `EXACT_MAX` lanes' values: results, then inputs.
    kept: Vec<Vec<f64>>,
    /// A search's drives (their brackets), every one of the group.
    drives: Vec<search::Drive>,
}

/// Where in a row of the results table (parameters, then results) the
/// statistics read.
struct Layout {
    /// The number columns' cells, in table order.
    numbers: Vec<usize>,
    /// The word columns' cells and their words.
    words: Vec<(usize, Shares)>,
    /// The status cell.
    status: usize,
    /// Which number columns are running values (`Column::running`), left
    /// out for a lane at rest, and the final contact's cell that says so.
    running: Vec<bool>,
    contact: usize,
    /// A search's cells: search_lo, search_hi, search_meets, search_status.
    search: Option<[usize; 4]>,
    /// Each parameter's cell, by `Num` index.
    params: [usize; N_NUM],
}

impl Layout {
    fn new(search: bool) -> Layout {
        let first = Param::COLUMNS.len();
        let results = results_for(search);
        let at = |name: &str| first + results.iter().position(|c| c.name == name).unwrap_or(0);
        let words = results
            .iter()
            .enumerate()
            .filter_map(|(i, c)| match c.summary {
                Summary::Shares(of) => {
                    let words = c.vocabulary().unwrap_or_default();
                    let n = words.len();
                    Some((
                        first + i,
                        Shares {
                            words: words.to_vec(),
                            of,
                            counts: vec![0; n],
                            total: 0,
                        },
                    ))
                }
                _ => None,
            })
            .collect();
        let numbers: Vec<&Column_> = results
            .iter()
            .copied()
            .filter(|c| matches!(c.summary, Summary::Numbers))
            .collect();
        Layout {
            numbers: numbers.iter().map(|c| at(c.name)).collect(),
            words,
            status: at(crate::columns::STATUS),
            running: numbers.iter().map(|c| c.running).collect(),
            contact: at(crate::columns::CONTACT_END),
            search: search.then(|| {
                use crate::columns::{SEARCH_HI, SEARCH_LO, SEARCH_MEETS, SEARCH_STATUS};
                [
                    at(SEARCH_LO),
                    at(SEARCH_HI),
                    at(SEARCH_MEETS),
                    at(SEARCH_STATUS),
                ]
            }),
            params: std::array::from_fn(|k| {
                Param::COLUMNS
                    .iter()
                    .position(|p| *p == Param::Num(Num::ALL[k]))
                    .unwrap_or(0)
            }),
        }
    }
}

/// Streams statistics into `summary.csv`.
pub struct Stats {
    grouping: Grouping,
    layout: Layout,
    group: Option<Group>,
    /// A lane's number cells (reused).
    values: Vec<f64>,
    out: CsvLines,
    /// `sensitivity.csv`, for a sensitivity design.
    sensitivity: Option<SensitivityCsv>,
    /// The word columns' cells by name (for the indicators).
    word_cells: Vec<(&'static str, usize)>,
    /// A share search's boundaries, a group each, as they are written.
    boundaries: Vec<Boundary>,
}

/// The columns of `summary.csv` after `group` and the grid's parameters.
pub const SUMMARY_COLUMNS: &str = "kind,name,input,count,mean,std,min,p1,p5,p50,p95,p99,max,\
quantiles,share,ci95_low,ci95_high,rho";

/// The type of each of [`SUMMARY_COLUMNS`]' cells, in its order (a
/// reader, Python's `tswm.summary`, takes them so and guesses nothing).
pub const SUMMARY_KINDS: [Kind; 18] = {
    use Kind::{Float as F, Int as I, Text as T};
    [T, T, T, I, F, F, F, F, F, F, F, F, F, T, F, F, F, F]
};

/// The type of `summary.csv`'s first column, `group` (a grid point's
/// index); the grid's parameters follow it, typed as parameters.
pub const GROUP_KIND: Kind = Kind::Int;

/// [`SUMMARY_COLUMNS`] with [`SUMMARY_KINDS`].
pub fn summary_fields() -> impl Iterator<Item = (&'static str, Kind)> {
    SUMMARY_COLUMNS.split(',').zip(SUMMARY_KINDS)
}

impl Stats {
    /// Starts `path` for lanes grouped by `grouping`.
    pub fn create(path: &Path, grouping: Grouping) -> Result<Stats> {
        let mut head = String::from("group");
        for a in &grouping.axes {
            let _ = write!(head, ",{}", a.param.name());
        }
        let out = CsvLines::create(path, &format!("{head},{SUMMARY_COLUMNS}"))?;
        let layout = Layout::new(grouping.search.is_some());
        let sensitivity = match &grouping.sensitivity {
            Some(d) => Some(SensitivityCsv::create(
                &path.with_file_name(SENSITIVITY),
                d.clone(),
            )?),
            None => None,
        };
        let first = Param::COLUMNS.len();
        let word_cells = results_for(grouping.search.is_some())
            .into_iter()
            .enumerate()
            .filter(|(_, c)| matches!(c.summary, Summary::Shares(..)))
            .map(|(i, c)| (c.name, first + i))
            .collect();
        Ok(Stats {
            sensitivity,
            word_cells,
            boundaries: Vec::new(),
            grouping,
            values: vec![0.0; layout.numbers.len()],
            layout,
            group: None,
            out,
        })
    }

    /// Writes the last group; the file, to be committed with the run's
    /// other files.
    /// With the files, the seconds spent on sensitivity indices (a
    /// sensitivity design).
    pub fn finish(self) -> Result<(Vec<AtomicFile>, Option<f64>)> {
        self.finish_all().map(|(f, s, _)| (f, s))
    }

    /// [`Stats::finish`], with a share search's boundaries, a group each.
    #[allow(clippy::type_complexity)]
    pub(crate) fn finish_all(mut self) -> Result<(Vec<AtomicFile>, Option<f64>, Vec<Boundary>)> {
        if let Some(g) = self.group.take() {
            self.write_group(g)?;
        }
        let boundaries = std::mem::take(&mut self.boundaries);
        let mut files = vec![self.out.into_file()];
        let mut seconds = None;
        if let Some(sn) = self.sensitivity {
            let (f, s) = sn.finish()?;
            files.push(f);
            seconds = Some(s);
        }
        Ok((files, seconds, boundaries))
    }

    fn write_group(&mut self, g: Group) -> Result<()> {
        let results = results_for(self.grouping.search.is_some());
        let names: Vec<&str> = results
            .iter()
            .filter(|c| matches!(c.summary, Summary::Numbers))
            .map(|c| c.name)
            .collect();
        let mut key = g.id.to_string();
        for v in &g.axis_values {
            let _ = write!(key, ",{v}");
        }
        for (i, c) in g.cols.iter().enumerate() {
            let cells = number_cells(c, &g.kept[i]);
            self.row(&key, "number", names[i], "", c.m.count, cells)?;
        }
        let word_columns: Vec<&str> = self
            .layout
            .words
            .iter()
            .map(|(i, _)| results[i - Param::COLUMNS.len()].name)
            .collect();
        for (column, sh) in word_columns.iter().zip(&g.shares) {
            for (word, &k) in sh.words.iter().zip(&sh.counts) {
                // An interval only where the lanes are sampled: none for a
                // grid or a lane table (the share is exact) or a
                // sensitivity design (its row groups are not independent).
                let (lo, hi) = if self.grouping.sampled {
                    wilson(k, sh.total)
                } else {
                    (f64::NAN, f64::NAN)
                };
                let mut cells = Cells::default();
                cells.0[10] = num(k as f64 / sh.total as f64);
                cells.0[11] = num(lo);
                cells.0[12] = num(hi);
                self.row(&key, column, word, "", k, cells)?;
            }
        }
        self.search_rows(&key, &g)?;
        let results = names.len();
        let mut pairs = Correlations::new(&g.kept);
        for (j, input) in self.grouping.inputs.clone().iter().enumerate() {
            for (i, name) in names.iter().enumerate() {
                let (rho, n) = pairs.spearman(results + j, i);
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

/// A number column's cells in a group: its moments and quantiles (exact
/// from the kept values, or the sketch's estimate).
fn number_cells(c: &Column, kept: &[f64]) -> Cells {
    let mut cells = Cells::default();
    if c.m.count > 0 {
        let sd = c.m.std();
        let qs: Vec<f64> = match &c.sketch {
            Some(s) => PROBS.iter().map(|&q| s.quantile(q)).collect(),
            None => {
                quantile::exact_finite(kept, &PROBS).unwrap_or_else(|| vec![f64::NAN; PROBS.len()])
            }
        };
        let moments = [c.m.mean, sd, c.m.min]
            .into_iter()
            .chain(qs)
            .chain([c.m.max]);
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
    cells
}

/// A number cell: empty for NaN, else the shortest text that reads back.
fn num(v: f64) -> String {
    let mut s = String::new();
    push_f64(&mut s, v);
    s
}

#[cfg(test)]
mod kinds_tests {
    use super::*;

    #[test]
    fn every_summary_column_has_its_kind() {
        assert_eq!(SUMMARY_COLUMNS.split(',').count(), SUMMARY_KINDS.len());
    }
}
