//! Reading an output folder for the report: `summary.csv` for the shown
//! groups, one pass over the results table into bounded aggregates, and
//! the traced lanes of `traces.csv`, decimated to the plot's resolution.
//!
//! Nothing read is trusted to be well formed: a cell that is not of its
//! column's kind, a word its column does not have, a lane out of order or
//! outside the run, a table shorter or longer than the run it belongs to
//! each stop the report with a one-line error (exit code 2), never a
//! panic and never a page of wrong numbers. Time and memory grow with the
//! folder's rows only linearly and with nothing else.

use std::path::Path;

use crate::columns::{results, Column, Summary};
use crate::columns::{CONTACT_END, DRIVE, HOLD, LANE, LOCK_MARGIN_DEG, STATUS};
use crate::error::{Error, Result};
use crate::input::sweep::Sweep;
use crate::output::table::{columns, Cell, RowReader};
use crate::params::{Num, Param};

pub(super) use super::aggregates::LINE_POINTS;
pub use super::aggregates::{GroupData, MapData};
pub(super) use super::cells::{bad_row, check_row, column, num, open_csv, text};
pub use super::extremes::Extreme;
pub use super::line::LineData;
pub use super::require::RequireData;
pub use super::trace::TraceData;

/// Final contacts as `lanes.csv` spells them, with the words the report
/// uses. `stick` is "at rest": held if the motor is cut, stalled if it
/// runs (the outcome says which).
pub const CONTACT_NAMES: [(&str, &str); 3] = [("stick", "at rest"), ("aa", "a-a"), ("bb", "b-b")];

/// Most cells along one axis of a map, and points along a line; longer
/// axes are binned.
const MAP_CELLS: u64 = 120;

/// Lanes listed by name among those that could not be finished.
const UNFINISHED_SHOWN: usize = 20;
/// Histogram bins.
pub(super) const BINS: usize = 40;
/// Traced lanes plotted.
pub(super) const TRACES_SHOWN: usize = 6;

/// What the report needs from an output folder.
pub struct Folder {
    /// The table's file name (`lanes.csv` or `lanes.parquet`).
    pub table: &'static str,
    pub lanes: u64,
    /// Lanes per status word, in the table's order of words.
    pub by_status: Vec<(&'static str, u64)>,
    pub by_contact: [u64; 3],
    /// Lanes per `hold` word (held, runs_away, coasting).
    pub by_hold: Vec<(&'static str, u64)>,
    /// Lanes whose motor is cut before t_end (those with a `hold`).
    pub hold_lanes: u64,
    /// Lanes per `drive` word (runs, stalled, back_driven).
    pub by_drive: Vec<(&'static str, u64)>,
    /// Lanes whose motor runs to the end (those with a `drive`).
    pub drive_lanes: u64,
    /// Finished lanes per outcome (`outcome::OUTCOMES`).
    pub by_outcome: [u64; super::outcome::N],
    /// The largest t_end and t_max among lanes still coasting.
    pub coasting_t_end: f64,
    pub coasting_t_max: f64,
    /// Per plotted result: the smallest and largest value over the
    /// finished lanes, with the lanes they came from.
    pub extremes: Vec<Extreme>,
    /// Lanes a grid point (the samples of a study; 1 without).
    pub samples: u64,
    pub unfinished: Vec<Vec<String>>,
    pub unfinished_total: u64,
    /// Parameters listed for unfinished lanes: the grid's and the sampled.
    pub shown_params: Vec<Param>,
    pub results: Vec<&'static Column>,
    pub study: bool,
    /// Whether the lanes are independent draws (see `Sweep::independent_lanes`).
    pub independent: bool,
    /// Whether shares get Wilson intervals: the lanes are sampled (a
    /// `[sampling]` study) and independent. A grid or a lane table samples
    /// nothing, and its shares are exact.
    pub sampled: bool,
    pub map: Option<MapData>,
    pub line: Option<LineData>,
    pub groups: Vec<GroupData>,
    pub groups_total: usize,
    pub traces: Vec<TraceData>,
    pub require: Option<RequireData>,
}

/// The words of a word column of the results table.
fn words_of(c: &Column) -> Vec<&'static str> {
    match c.summary {
        Summary::Shares(w, _) => w(),
        _ => Vec::new(),
    }
}

/// Where the scan reads a row of the results table.
struct Cols {
    lane: usize,
    status: usize,
    contact: usize,
    hold: usize,
    drive: usize,
    lock: usize,
    t_end: usize,
    t_max: usize,
    results: Vec<usize>,
    shown: Vec<usize>,
    require: Option<usize>,
    /// Word columns.
    words: Vec<super::cells::WordCol>,
}

impl Folder {
    /// Reads the folder `dir` of a run of `sweep`, whose
    /// `sweep.resolved.toml` states `stated` lanes.
    pub fn read(dir: &Path, sweep: &Sweep, stated: u64) -> Result<Folder> {
        let spec = &sweep.report;
        let results: Vec<&'static Column> = spec
            .results()
            .iter()
            .filter_map(|n| crate::columns::result(n))
            .collect();
        let panels = spec.panels();
        let study = sweep.study.is_some();
        let lens: Vec<u64> = sweep.axes.iter().map(|a| a.len()).collect();
        let mut shown_params: Vec<Param> = sweep.axes.iter().map(|a| a.param).collect();
        if let Some(st) = &sweep.study {
            shown_params.extend(st.params.iter().map(|t| Param::Num(t.param)));
        }
        let word_counts = |name: &str| -> Vec<(&'static str, u64)> {
            crate::columns::result(name)
                .map(|c| words_of(c).into_iter().map(|w| (w, 0)).collect())
                .unwrap_or_default()
        };
        let mut f = Folder {
            table: crate::output::table::Format::of_folder(dir)?.file_name(),
            lanes: 0,
            by_status: word_counts(STATUS),
            by_contact: [0; 3],
            by_hold: word_counts(HOLD),
            hold_lanes: 0,
            by_drive: word_counts(DRIVE),
            drive_lanes: 0,
            by_outcome: [0; super::outcome::N],
            coasting_t_end: f64::NAN,
            coasting_t_max: f64::NAN,
            extremes: vec![Extreme::default(); spec.results().len()],
            samples: sweep.study.as_ref().map_or(1, |s| s.n),
            unfinished: Vec::new(),
            unfinished_total: 0,
            shown_params,
            results,
            study,
            independent: sweep.independent_lanes(),
            sampled: study && sweep.independent_lanes(),
            map: None,
            line: None,
            groups: Vec::new(),
            groups_total: 0,
            traces: Vec::new(),
            require: spec
                .require
                .as_ref()
                .map(|r| RequireData::new(r.clone(), sweep, panels, LINE_POINTS)),
        };
        // Two numeric axes make maps (the others, words included, panels);
        // fewer, a line along one axis with a panel per value of the others.
        if sweep.axes.iter().filter(|a| !a.is_words()).count() >= 2 {
            f.map = Some(MapData::new(sweep, panels, MAP_CELLS));
        } else {
            f.line = LineData::new(sweep, panels, f.results.len());
        }
        if study {
            let groups_total = if sweep.axes.is_empty() {
                1
            } else {
                lens.iter().product::<u64>() as usize
            };
            f.groups_total = groups_total;
            f.read_summary(dir, sweep, groups_total.min(panels))?;
        }
        let traced = f.scan_lanes(dir, sweep, stated)?;
        f.read_traces(dir, &traced)?;
        Ok(f)
    }

    fn columns_of(&self, path: &Path, head: &csv::ByteRecord) -> Result<Cols> {
        let c = |n: &str| column(path, head, n);
        let word_cols = results()
            .iter()
            .filter(|r| matches!(r.summary, Summary::Shares(..)))
            .map(|r| {
                let maybe = matches!(r.summary, Summary::Shares(_, crate::columns::Of::Given));
                Ok((c(r.name)?, r.name, words_of(r), maybe))
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Cols {
            lane: c(LANE)?,
            status: c(STATUS)?,
            contact: c(CONTACT_END)?,
            hold: c(HOLD)?,
            drive: c(DRIVE)?,
            lock: c(LOCK_MARGIN_DEG)?,
            t_end: c(Num::TEnd.name())?,
            t_max: c(Num::TMax.name())?,
            results: self
                .results
                .iter()
                .map(|r| c(r.name))
                .collect::<Result<_>>()?,
            shown: self
                .shown_params
                .iter()
                .map(|n| c(n.name()))
                .collect::<Result<_>>()?,
            require: match &self.require {
                Some(r) => Some(c(r.req.column)?),
                None => None,
            },
            words: word_cols,
        })
    }

    /// One pass over the results table. Returns the horizon (t_max or
    /// t_end) of each lane the sweep traces, for the traces' decimation.
    fn scan_lanes(&mut self, dir: &Path, sweep: &Sweep, stated: u64) -> Result<Vec<(u64, f64)>> {
        let mut rd = RowReader::open_folder(dir)?;
        let path = rd.path().to_path_buf();
        let kinds = columns();
        let head = rd.header().clone();
        if head.len() != kinds.len() || head.iter().zip(&kinds).any(|(h, k)| h != k.0.as_bytes()) {
            return Err(Error::input(
                &path,
                Some("line 1".into()),
                None,
                "its columns are not those of this tswm version's table; run it again",
            ));
        }
        let cols = self.columns_of(&path, &head)?;
        let samples = sweep.study.as_ref().map_or(1, |s| s.n);
        let traced_lanes: Vec<u64> = sweep.trace.as_ref().map_or(Vec::new(), |t| t.lanes.clone());
        let mut traced = Vec::new();
        let mut rec = csv::ByteRecord::new();
        let mut cells: Vec<Cell> = Vec::with_capacity(kinds.len());
        let mut vals = vec![0.0; cols.results.len()];
        while rd.read_cells(&mut rec, &kinds, &mut cells)? {
            let lane = self.lanes;
            check_row(&path, lane, stated, &cells, &rec, cols.lane, &cols.words)?;
            self.lanes += 1;
            if traced_lanes.binary_search(&lane).is_ok() {
                let (te, tm) = (cells[cols.t_end].number(), cells[cols.t_max].number());
                traced.push((lane, if tm.is_finite() { tm.max(te) } else { te }));
            }
            let (ok, outcome) = self.count_outcomes(lane, &cells, &rec, &cols);
            for (v, &i) in vals.iter_mut().zip(&cols.results) {
                *v = cells[i].number();
            }
            if ok {
                for (e, &v) in self.extremes.iter_mut().zip(&vals) {
                    e.add(lane, v);
                }
            }
            let point = lane / samples;
            if let (Some(r), Some(i)) = (self.require.as_mut(), cols.require) {
                let passes = r.req.passes(&cells[i]);
                r.add(point, passes);
            }
            let outcome = if ok { outcome } else { None };
            if let Some(m) = self.map.as_mut() {
                m.add(point, &vals, outcome, cells[cols.lock].number());
            }
            if let Some(l) = self.line.as_mut() {
                l.add(point, &vals, outcome);
            }
            if self.study {
                let g = if sweep.axes.is_empty() {
                    0
                } else {
                    point as usize
                };
                if let Some(gd) = self.groups.get_mut(g) {
                    gd.add(&vals);
                }
            }
        }
        if self.lanes != stated {
            return Err(Error::input(
                &path,
                None,
                None,
                format!(
                    "has {} rows, but its sweep.resolved.toml states {stated} lanes: the table is \
                     incomplete or belongs to another run; run it again",
                    self.lanes
                ),
            ));
        }
        Ok(traced)
    }

    /// Counts a lane's status, hold, drive, final contact and outcome, and
    /// lists it when it did not finish; whether it is ok, and its
    /// outcome's index (`outcome::OUTCOMES`).
    fn count_outcomes(
        &mut self,
        lane: u64,
        cells: &[Cell],
        rec: &csv::ByteRecord,
        cols: &Cols,
    ) -> (bool, Option<usize>) {
        let status = cells[cols.status].word();
        let ok = status == "ok";
        if let Some(e) = self.by_status.iter_mut().find(|e| e.0 == status) {
            e.1 += 1;
        }
        let hold = cells[cols.hold].word();
        if !hold.is_empty() {
            self.hold_lanes += 1;
            if let Some(e) = self.by_hold.iter_mut().find(|e| e.0 == hold) {
                e.1 += 1;
            }
            if hold == "coasting" {
                let (te, tm) = (cells[cols.t_end].number(), cells[cols.t_max].number());
                self.coasting_t_end = self.coasting_t_end.max(te);
                if tm.is_finite() {
                    self.coasting_t_max = self.coasting_t_max.max(tm);
                }
            }
        }
        let drive = cells[cols.drive].word();
        if !drive.is_empty() {
            self.drive_lanes += 1;
            if let Some(e) = self.by_drive.iter_mut().find(|e| e.0 == drive) {
                e.1 += 1;
            }
        }
        let contact_word = cells[cols.contact].word();
        let contact = CONTACT_NAMES.iter().position(|c| c.0 == contact_word);
        let outcome = super::outcome::of(contact_word, hold, drive);
        if !ok {
            self.unfinished_total += 1;
            if self.unfinished.len() < UNFINISHED_SHOWN {
                let mut r = vec![lane.to_string(), status.to_string()];
                r.extend(cols.shown.iter().map(|&i| text(rec, i)));
                self.unfinished.push(r);
            }
        } else {
            if let Some(k) = contact {
                self.by_contact[k] += 1;
            }
            self.by_outcome[outcome] += 1;
        }
        (ok, Some(outcome))
    }
}
