//! `sensitivity.csv`: first-order and total Sobol' indices of every result
//! with respect to every input of a sensitivity design, per grid point,
//! from the lanes as they stream past (one grid point held at a time).
//!
//! The lanes of a grid point come in row groups of `d + 2` (A, AB¹ ...
//! ABᵈ, B). A row group is used for a result when every lane of it is
//! `ok` and has the result's value; otherwise it is dropped for that
//! result and the `samples` column, the row groups used, says so. The
//! indicator `status=ok` uses every row group (it is what a lane that is
//! not `ok` changes). Memory per grid point: for each result, the sums of
//! [`MAX_UNITS`] bootstrap units (`(5 + 3d) × 8` bytes each) and the
//! resampled indices (`bootstrap × 2d × 8` bytes), plus the resamples'
//! unit counts (`bootstrap × MAX_UNITS × 4` bytes): about 10 MB for 6
//! inputs, 28 results and 1,000 resamples, whatever the number of base
//! samples.

use std::fmt::Write as _;
use std::path::Path;

use rayon::prelude::*;

use super::sobol::{resample_counts, Accumulator, Bootstrap, Index, MAX_UNITS};
use crate::columns::Kind;
use crate::columns::{indicators, number_columns, Indicator};
use crate::error::Result;
use crate::input::sweep::Sensitivity;
use crate::output::csv_lines::{push_f64, CsvLines};
use crate::output::AtomicFile;
use crate::params::Num;

/// The columns of `sensitivity.csv`.
pub const SENSITIVITY_COLUMNS: &str =
    "group,result,input,s1,s1_low,s1_high,st,st_low,st_high,samples";

/// The type of each of [`SENSITIVITY_COLUMNS`]' cells, in its order.
pub const SENSITIVITY_KINDS: [Kind; 10] = {
    use Kind::{Float as F, Int as I, Text as T};
    [I, T, T, F, F, F, F, F, F, I]
};

/// [`SENSITIVITY_COLUMNS`] with [`SENSITIVITY_KINDS`].
pub fn sensitivity_fields() -> impl Iterator<Item = (&'static str, Kind)> {
    SENSITIVITY_COLUMNS.split(',').zip(SENSITIVITY_KINDS)
}

/// A sensitivity design as the statistics need it.
#[derive(Clone, Debug, PartialEq)]
pub struct Design {
    /// The inputs, in design order.
    pub inputs: Vec<Num>,
    /// Base samples N of a grid point.
    pub base: u64,
    /// The intervals' bootstrap.
    pub boot: Bootstrap,
}

impl Design {
    fn row(&self) -> u64 {
        self.inputs.len() as u64 + 2
    }
}

/// The results analysed, in `sensitivity.csv` order: every number column,
/// then the indicators.
pub(crate) fn result_names() -> Vec<String> {
    number_columns()
        .map(|c| c.name.to_string())
        .chain(indicators().iter().map(Indicator::name))
        .collect()
}

struct Group {
    id: u64,
    accs: Vec<Accumulator>,
}

/// Streams a sensitivity design's lanes into `sensitivity.csv`.
pub(crate) struct SensitivityCsv {
    design: Design,
    names: Vec<String>,
    numbers: usize,
    indicators: Vec<Indicator>,
    group: Option<Group>,
    /// The row group being filled: `d + 2` rows of one value per result.
    rows: Vec<f64>,
    /// Every lane of the row group so far is `ok`.
    rows_ok: bool,
    out: CsvLines,
    /// Time spent here (adding lanes, computing and writing indices).
    busy: std::time::Duration,
}

impl SensitivityCsv {
    /// Starts `path` for `design`.
    pub fn create(path: &Path, design: Design) -> Result<SensitivityCsv> {
        let names = result_names();
        let indicators = indicators();
        let numbers = names.len() - indicators.len();
        Ok(SensitivityCsv {
            rows: vec![f64::NAN; names.len() * design.row() as usize],
            design,
            names,
            numbers,
            indicators,
            group: None,
            rows_ok: true,
            out: CsvLines::create(path, SENSITIVITY_COLUMNS)?,
            busy: std::time::Duration::ZERO,
        })
    }

    /// Adds the `k`-th lane of grid point `group` (lanes in order): its
    /// number cells (NaN where empty, in `number_columns` order), whether
    /// it is `ok`, and its words by column name.
    pub fn add<'a>(
        &mut self,
        group: u64,
        k: u64,
        numbers: &[f64],
        words: impl Fn(&str) -> &'a str,
    ) -> Result<()> {
        let start = std::time::Instant::now();
        let r = self.add_timed(group, k, numbers, words);
        self.busy += start.elapsed();
        r
    }

    fn add_timed<'a>(
        &mut self,
        group: u64,
        k: u64,
        numbers: &[f64],
        words: impl Fn(&str) -> &'a str,
    ) -> Result<()> {
        if self.group.as_ref().is_some_and(|g| g.id != group) {
            let g = self.group.take().expect("checked");
            self.write_group(g)?;
        }
        let (d, n) = (self.design.inputs.len(), self.design.base);
        self.group.get_or_insert_with(|| Group {
            id: group,
            accs: (0..self.names.len())
                .map(|_| Accumulator::new(d, n))
                .collect(),
        });
        let r = self.names.len();
        let (j, m) = (k / self.design.row(), (k % self.design.row()) as usize);
        if m == 0 {
            self.rows_ok = true;
        }
        let ok = words(crate::columns::STATUS) == crate::integrator::Status::Ok.name();
        self.rows_ok &= ok;
        let row = &mut self.rows[m * r..(m + 1) * r];
        row[..self.numbers].copy_from_slice(numbers);
        for (x, ind) in row[self.numbers..].iter_mut().zip(&self.indicators) {
            *x = f64::from(u8::from(words(ind.column) == ind.word));
        }
        if m as u64 == self.design.row() - 1 && j < n {
            let g = self.group.as_mut().expect("set above");
            let mut buf = [0.0; Sensitivity::MAX_INPUTS + 2];
            let y = &mut buf[..d + 2];
            for (i, acc) in g.accs.iter_mut().enumerate() {
                // status=ok is what a lane that is not ok changes: it uses
                // every row group.
                let status = i >= self.numbers
                    && self.indicators[i - self.numbers].column == crate::columns::STATUS;
                for (mm, yy) in y.iter_mut().enumerate() {
                    *yy = self.rows[mm * r + i];
                }
                if status || (self.rows_ok && y.iter().all(|v| v.is_finite())) {
                    acc.add(j, y);
                }
            }
        }
        Ok(())
    }

    /// Writes the last grid point; the file, to be committed with the
    /// run's other files, and the seconds spent on the analysis.
    pub fn finish(mut self) -> Result<(AtomicFile, f64)> {
        let start = std::time::Instant::now();
        if let Some(g) = self.group.take() {
            self.write_group(g)?;
        }
        let busy = self.busy + start.elapsed();
        Ok((self.out.into_file(), busy.as_secs_f64()))
    }

    fn write_group(&mut self, g: Group) -> Result<()> {
        let boot = self.design.boot;
        let units = g.accs.first().map_or(1, Accumulator::units);
        debug_assert!(units <= MAX_UNITS);
        let counts = resample_counts(&boot, g.id, units);
        let indices: Vec<Vec<Index>> = g
            .accs
            .par_iter()
            .map(|a| a.indices(&counts, &boot))
            .collect();
        for ((name, acc), idx) in self.names.iter().zip(&g.accs).zip(&indices) {
            for (input, x) in self.design.inputs.iter().zip(idx) {
                let line = self.out.line();
                let _ = write!(line, "{},{name},{}", g.id, input.name());
                for v in [x.s1, x.s1_low, x.s1_high, x.st, x.st_low, x.st_high] {
                    line.push(',');
                    push_f64(line, v);
                }
                let _ = write!(line, ",{}", acc.samples());
                self.out.end_line()?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_sensitivity_column_has_its_kind() {
        assert_eq!(
            SENSITIVITY_COLUMNS.split(',').count(),
            SENSITIVITY_KINDS.len()
        );
    }
    use crate::stats::sobol::resample_counts;

    /// A row group with a lane that is not ok is dropped for every result
    /// but `status=ok`, and counted in `samples`; the indices are those of
    /// the other row groups.
    #[test]
    fn a_row_group_with_a_lane_not_ok_is_dropped_and_counted() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sensitivity.csv");
        let design = Design {
            inputs: vec![Num::ALL[0], Num::ALL[1]],
            base: 8,
            boot: Bootstrap {
                resamples: 50,
                confidence: 0.9,
                seed: 3,
            },
        };
        let names = result_names();
        let numbers = names.len() - indicators().len();
        let mut w = SensitivityCsv::create(&path, design.clone()).unwrap();
        let mut direct = Accumulator::new(2, 8);
        let value = |j: u64, m: u64| ((j * 7 + m * 3) % 11) as f64 + 0.25 * m as f64;
        for j in 0..8u64 {
            let mut y = Vec::new();
            for m in 0..4u64 {
                let mut cells = vec![f64::NAN; numbers];
                cells[0] = value(j, m);
                y.push(cells[0]);
                let status = if (j, m) == (3, 2) { "max_steps" } else { "ok" };
                let contact = if (j + m) % 2 == 0 { "stick" } else { "aa" };
                w.add(0, j * 4 + m, &cells, |c| {
                    if c == "status" {
                        status
                    } else {
                        contact
                    }
                })
                .unwrap();
            }
            if j != 3 {
                direct.add(j, &y);
            }
        }
        crate::output::atomic::commit_together(vec![w.finish().unwrap().0], &[]).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let rows: Vec<Vec<&str>> = text
            .lines()
            .skip(1)
            .map(|l| l.split(',').collect())
            .collect();
        let first = rows.iter().find(|r| r[1] == names[0]).unwrap();
        assert_eq!(first[9], "7", "{first:?}");
        let ok = rows.iter().find(|r| r[1] == "status=ok").unwrap();
        assert_eq!(ok[9], "8");
        let stick = rows.iter().find(|r| r[1] == "contact_end=stick").unwrap();
        assert_eq!(stick[9], "7");
        // A result no lane has: no row group, no index.
        let empty = rows.iter().find(|r| r[1] == names[1]).unwrap();
        assert_eq!(&empty[3..], ["", "", "", "", "", "", "0"]);
        let want = direct.indices(
            &resample_counts(&design.boot, 0, direct.units()),
            &design.boot,
        );
        assert_eq!(first[3].parse::<f64>().unwrap(), want[0].s1);
        assert_eq!(first[6].parse::<f64>().unwrap(), want[0].st);
    }
}
