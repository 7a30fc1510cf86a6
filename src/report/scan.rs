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

use crate::columns::{Column, Summary};
use crate::columns::{DRIVE, HOLD, STATUS};
use crate::input::sweep::Sweep;
use crate::integrator::Contact;
use crate::params::Param;

pub(super) use super::aggregates::LINE_POINTS;
pub use super::aggregates::{GroupData, MapData};
pub(super) use super::cells::{bad_row, column, num, open_csv, text};
pub use super::extremes::Extreme;
pub use super::line::LineData;
pub use super::require::RequireData;
pub use super::trace::TraceData;

/// Final contacts in the report's order, with the words the report uses
/// beside their own. `stick` is "at rest": held if the motor is cut,
/// stalled if it runs (the outcome says which).
pub(crate) const CONTACT_NAMES: [(Contact, &str); 3] = [
    (Contact::Stick, "at rest"),
    (Contact::Aa, "a-a"),
    (Contact::Bb, "b-b"),
];

/// Most cells along one axis of a map, and points along a line; longer
/// axes are binned.
const MAP_CELLS: u64 = 120;

/// Lanes listed by name among those that could not be finished.
pub(super) const UNFINISHED_SHOWN: usize = 20;
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
    /// Each traced lane's parameters (the grid's and the sampled) and
    /// outcome in words, for its panel's heading.
    pub trace_labels: Vec<(u64, String)>,
    /// The data sheet of a small run (none past `sheet::SHEET_LANES`).
    pub sheet: Option<super::sheet::Sheet>,
}

/// The words of a word column of the results table.
pub(super) fn words_of(c: &Column) -> Vec<&'static str> {
    match c.summary {
        Summary::Shares(_) => c.vocabulary().unwrap_or_default().to_vec(),
        _ => Vec::new(),
    }
}

impl Folder {
    /// The report's aggregates of a run of `sweep` whose results table
    /// is `table` (its file name), before any row is in.
    pub fn start(table: &'static str, sweep: &Sweep) -> Folder {
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
            table,
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
            trace_labels: Vec::new(),
            sheet: None,
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
        }
        f
    }

    /// Whether the report of a run of `sweep` can be gathered while its
    /// rows stream past: not for a study, whose histograms are binned
    /// over the ranges `summary.csv` gives at the run's end.
    pub(crate) fn streams(sweep: &Sweep) -> bool {
        sweep.study.is_none()
    }
}
