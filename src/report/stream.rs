//! The report's one pass over the results table, batch by batch: while
//! a run's rows stream past (`tswm run`), or read back from the folder
//! with only the columns it needs (`tswm report`). Either way the same
//! bounded aggregates, so the two pages are the same, byte for byte.

use std::path::Path;

use arrow_array::RecordBatch;

use super::scan::{words_of, Folder, CONTACT_NAMES, UNFINISHED_SHOWN};
use crate::columns::{results, Summary};
use crate::columns::{CONTACT_END, DRIVE, HOLD, LANE, LOCK_MARGIN_DEG, STATUS};
use crate::error::{Error, Result};
use crate::input::sweep::Sweep;
use crate::integrator::{Contact, Drive, Hold, Status};
use crate::output::batch::{word_runs, Col, Columns};
use crate::output::table::{read_batches, Format};
use crate::params::Num;

/// A word column: its name, allowed words, and whether an empty cell is
/// allowed (a column of words given only for some lanes).
type WordCol = (&'static str, Vec<&'static str>, bool);

impl Folder {
    /// Reads the folder `dir` of a run of `sweep`, whose
    /// `sweep.resolved.toml` states `stated` lanes: `summary.csv`, the
    /// results table's columns the report needs, and `traces.csv`.
    pub fn read(dir: &Path, sweep: &Sweep, stated: u64) -> Result<Folder> {
        let format = Format::of_folder(dir)?;
        let mut f = Folder::start(format.file_name(), sweep);
        if f.study {
            f.read_summary(dir, sweep, f.groups_total.min(sweep.report.panels()))?;
        }
        let mut scan = Scan::new(f, sweep, stated);
        let names = scan.names();
        let path = dir.join(format.file_name());
        read_batches(dir, &names, |b| scan.batch_of(&path, b))?;
        scan.finish(dir, &path)
    }
}

/// The report's pass over a run's rows.
pub struct Scan {
    folder: Folder,
    stated: u64,
    samples: u64,
    /// Whether the sweep has no axes (a study's one group).
    one_group: bool,
    traced_lanes: Vec<u64>,
    /// Each traced lane with its horizon (t_max or t_end).
    traced: Vec<(u64, f64)>,
    words: Vec<WordCol>,
    require: Option<&'static str>,
    vals: Vec<f64>,
}

/// Where a batch holds what the scan reads.
struct Cols<'a> {
    lane: Col<'a>,
    status: Col<'a>,
    contact: Col<'a>,
    hold: Col<'a>,
    drive: Col<'a>,
    lock: Col<'a>,
    t_end: Col<'a>,
    t_max: Col<'a>,
    results: Vec<Col<'a>>,
    shown: Vec<Col<'a>>,
    require: Option<Col<'a>>,
    words: Vec<Col<'a>>,
    /// The data sheet's columns (a small run's).
    sheet: Vec<Col<'a>>,
}

impl Scan {
    /// The pass of a run of `sweep` stating `stated` lanes, into `folder`
    /// (`Folder::start`, with `summary.csv` read for a study).
    pub fn new(mut folder: Folder, sweep: &Sweep, stated: u64) -> Scan {
        if stated <= super::sheet::SHEET_LANES {
            folder.sheet = Some(super::sheet::Sheet::default());
        }
        let words = results()
            .iter()
            .filter(|r| matches!(r.summary, Summary::Shares(..)))
            .map(|r| {
                let maybe = matches!(r.summary, Summary::Shares(crate::columns::Of::Given));
                (r.name, words_of(r), maybe)
            })
            .collect();
        Scan {
            stated,
            samples: sweep.study.as_ref().map_or(1, |s| s.n),
            one_group: sweep.axes.is_empty(),
            traced_lanes: sweep.trace.as_ref().map_or(Vec::new(), |t| t.lanes.clone()),
            traced: Vec::new(),
            words,
            require: folder.require.as_ref().map(|r| r.req.column),
            vals: vec![0.0; folder.results.len()],
            folder,
        }
    }

    /// The columns the pass reads, by name.
    pub fn names(&self) -> Vec<&'static str> {
        let f = &self.folder;
        let mut n = vec![LANE, LOCK_MARGIN_DEG, Num::TEnd.name(), Num::TMax.name()];
        n.extend(self.words.iter().map(|w| w.0));
        n.extend(f.results.iter().map(|r| r.name));
        n.extend(f.shown_params.iter().map(|p| p.name()));
        n.extend(self.require);
        if self.folder.sheet.is_some() {
            n.extend(super::sheet::names());
        }
        let mut seen = std::collections::HashSet::new();
        n.retain(|x| seen.insert(*x));
        n
    }

    /// Finds the columns of `b`.
    fn cols<'a>(&self, b: &'a RecordBatch) -> Result<Cols<'a>> {
        let c = Columns::new(b);
        let get = |n: &str| {
            c.get(n)
                .ok_or_else(|| Error::Internal(format!("the report's batch has no column {n}")))
        };
        let f = &self.folder;
        Ok(Cols {
            lane: get(LANE)?,
            status: get(STATUS)?,
            contact: get(CONTACT_END)?,
            hold: get(HOLD)?,
            drive: get(DRIVE)?,
            lock: get(LOCK_MARGIN_DEG)?,
            t_end: get(Num::TEnd.name())?,
            t_max: get(Num::TMax.name())?,
            results: f
                .results
                .iter()
                .map(|r| get(r.name))
                .collect::<Result<_>>()?,
            shown: f
                .shown_params
                .iter()
                .map(|p| get(p.name()))
                .collect::<Result<_>>()?,
            require: self.require.map(get).transpose()?,
            words: self.words.iter().map(|w| get(w.0)).collect::<Result<_>>()?,
            sheet: if f.sheet.is_some() {
                super::sheet::names()
                    .into_iter()
                    .map(get)
                    .collect::<Result<_>>()?
            } else {
                Vec::new()
            },
        })
    }

    /// Adds the rows of `b`, the next lanes in order; `path` names the
    /// table in an error. A run of rows with the same words has them
    /// checked and read once.
    pub(crate) fn batch_of(&mut self, path: &Path, b: &RecordBatch) -> Result<()> {
        let cols = self.cols(b)?;
        let mut start = 0;
        for end in word_runs(&cols.words, 0..b.num_rows()) {
            self.check_lane(path, &cols, start)?;
            self.check_words(path, &cols, start)?;
            let words = RowWords::of(&cols, start);
            for row in start..end {
                if row > start {
                    self.check_lane(path, &cols, row)?;
                }
                self.row(&cols, row, &words);
            }
            start = end;
        }
        Ok(())
    }

    /// Checks that row `row` is the next lane, within the run's lanes.
    fn check_lane(&self, path: &Path, c: &Cols<'_>, row: usize) -> Result<()> {
        let lane = self.folder.lanes;
        let at = || Some(format!("row {}", lane + 1));
        if c.lane.count(row) != Some(lane as i64) {
            return Err(Error::input(
                path,
                at(),
                Some(LANE),
                format!(
                    "is {}, expected {lane}: a table's rows are its lanes 0, 1, 2, ... in order; \
                     not a table tswm wrote",
                    c.lane.text(row)
                ),
            ));
        }
        if lane >= self.stated {
            return Err(Error::input(
                path,
                at(),
                Some(LANE),
                format!(
                    "lane {lane} is not in the run: its sweep.resolved.toml states {} lanes; \
                     the table belongs to another run",
                    self.stated
                ),
            ));
        }
        Ok(())
    }

    /// Checks that every word column of row `row` holds one of its words.
    fn check_words(&self, path: &Path, c: &Cols<'_>, row: usize) -> Result<()> {
        let at = || Some(format!("row {}", self.folder.lanes + 1));
        for ((name, words, maybe), col) in self.words.iter().zip(&c.words) {
            // A cell holds a word of its column's vocabulary, keyed by its
            // code (every reader refuses another word), or is empty:
            // `hold` for a lane whose motor runs to the end, `drive` for
            // one whose motor is cut.
            if col.code(row).is_none() && !*maybe {
                let w = col.word(row);
                return Err(Error::input(
                    path,
                    at(),
                    Some(name),
                    format!(
                        "`{}` is not one of {}; not a tswm table",
                        crate::error::shown(w, 40),
                        words.join(", ")
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Adds row `row`, whose words are `w`.
    fn row(&mut self, c: &Cols<'_>, row: usize, w: &RowWords<'_>) {
        let f = &mut self.folder;
        let lane = f.lanes;
        f.lanes += 1;
        if self.traced_lanes.binary_search(&lane).is_ok() {
            let (te, tm) = (c.t_end.number(row), c.t_max.number(row));
            self.traced
                .push((lane, if tm.is_finite() { tm.max(te) } else { te }));
            let word = if w.ok {
                super::outcome::OUTCOMES[w.outcome].0.to_string()
            } else {
                format!("status {}", w.status)
            };
            let label = super::trace::label(&f.shown_params, &c.shown, row, &word);
            f.trace_labels.push((lane, label));
        }
        count_outcomes(f, lane, c, row, w);
        if let Some(sheet) = f.sheet.as_mut() {
            sheet
                .lanes
                .push(c.sheet.iter().map(|col| col.text(row)).collect());
        }
        for ((v, col), r) in self.vals.iter_mut().zip(&c.results).zip(&f.results) {
            // A lane at rest has no running point: its running values are
            // left out of the ranges, maps, lines and groups (counted).
            *v = if r.running && w.at_rest {
                f64::NAN
            } else {
                col.number(row)
            };
        }
        if w.ok {
            for ((e, &v), r) in f.extremes.iter_mut().zip(&self.vals).zip(&f.results) {
                if r.running && w.at_rest {
                    e.at_rest += 1;
                }
                e.add(lane, v);
            }
        }
        let point = lane / self.samples;
        if let (Some(r), Some(col)) = (f.require.as_mut(), c.require) {
            let passes = r.req.passes_value(col.word(row), col.number(row));
            if !col.word(row).is_empty() || col.number(row).is_finite() {
                r.valued += 1;
            }
            r.add(point, passes);
        }
        let outcome = w.ok.then_some(w.outcome);
        if let Some(m) = f.map.as_mut() {
            m.add(point, &self.vals, outcome, c.lock.number(row));
        }
        if let Some(l) = f.line.as_mut() {
            l.add(point, &self.vals, outcome);
        }
        if f.study {
            let g = if self.one_group { 0 } else { point as usize };
            if let Some(gd) = f.groups.get_mut(g) {
                gd.add(&self.vals);
            }
        }
    }

    /// The aggregates, once every row is in: the table `path` must hold
    /// the run's every lane; the traced lanes are read from `traces.csv`
    /// of `dir`.
    pub fn finish(mut self, dir: &Path, path: &Path) -> Result<Folder> {
        if self.folder.lanes != self.stated {
            return Err(Error::input(
                path,
                None,
                None,
                format!(
                    "has {} rows, but its sweep.resolved.toml states {} lanes: the table is \
                     incomplete or belongs to another run; run it again",
                    self.folder.lanes, self.stated
                ),
            ));
        }
        self.folder.read_traces(dir, &self.traced)?;
        Ok(self.folder)
    }
}

/// A row's words, read once for a run of rows that share them: where
/// each is counted, whether the lane is ok, and its outcome's index
/// (`outcome::OUTCOMES`).
struct RowWords<'a> {
    status: &'a str,
    ok: bool,
    /// The status's, hold's and drive's codes: their places in
    /// `by_status`, `by_hold` and `by_drive` (the columns' vocabularies).
    status_at: Option<usize>,
    hold_at: Option<usize>,
    drive_at: Option<usize>,
    coasting: bool,
    contact: Option<usize>,
    /// At rest at its end (final contact `stick`).
    at_rest: bool,
    outcome: usize,
}

impl<'a> RowWords<'a> {
    fn of(c: &Cols<'a>, row: usize) -> RowWords<'a> {
        let (hold, drive) = (c.hold.code(row), c.drive.code(row));
        let contact = c.contact.code(row);
        RowWords {
            status: c.status.word(row),
            ok: c.status.code(row) == Some(Status::Ok as usize),
            status_at: c.status.code(row),
            hold_at: hold,
            drive_at: drive,
            coasting: hold == Some(Hold::Coasting as usize),
            contact: contact.and_then(|k| CONTACT_NAMES.iter().position(|x| x.0 as usize == k)),
            at_rest: contact == Some(Contact::Stick as usize),
            outcome: super::outcome::of(
                contact.map(|k| Contact::ALL[k]),
                hold.map(|k| Hold::ALL[k]),
                drive.map(|k| Drive::ALL[k]),
            ),
        }
    }
}

/// Counts a lane's status, hold, drive, final contact and outcome, and
/// lists it when it did not finish.
fn count_outcomes(f: &mut Folder, lane: u64, c: &Cols<'_>, row: usize, w: &RowWords<'_>) {
    if let Some(k) = w.status_at {
        f.by_status[k].1 += 1;
    }
    if let Some(k) = w.hold_at {
        f.hold_lanes += 1;
        f.by_hold[k].1 += 1;
        if w.coasting {
            let (te, tm) = (c.t_end.number(row), c.t_max.number(row));
            f.coasting_t_end = f.coasting_t_end.max(te);
            if tm.is_finite() {
                f.coasting_t_max = f.coasting_t_max.max(tm);
            }
        }
    }
    if let Some(k) = w.drive_at {
        f.drive_lanes += 1;
        f.by_drive[k].1 += 1;
    }
    if !w.ok {
        f.unfinished_total += 1;
        if f.unfinished.len() < UNFINISHED_SHOWN {
            let mut r = vec![lane.to_string(), w.status.to_string()];
            r.extend(c.shown.iter().map(|col| col.text(row)));
            f.unfinished.push(r);
        }
    } else {
        if let Some(k) = w.contact {
            f.by_contact[k] += 1;
        }
        f.by_outcome[w.outcome] += 1;
    }
}
