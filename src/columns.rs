//! The table of result columns: one row per column of the results table
//! after the parameter columns, in their order, as `params::table` is for
//! parameters. The CSV header and the Parquet schema, a row's cells, the
//! reader's types, `summary.csv`, `tswm merge`, `tswm check`, the report's
//! labels and choices, and the column table of the docs all derive from
//! [`RESULTS`]; no other place spells a result column's name.
//!
//! Why over 400 lines: the rows and what reads them belong together, as in
//! `params::table`; split, the one place that states each column's facts
//! would become two.

use std::borrow::Cow;

use crate::integrator::{Contact, Drive, Hold, LaneResult, RowPath, SearchStatus, Side, Status};

/// The type of a column's cells (its Parquet type).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// f64; an empty cell (NaN: not applicable) is a null.
    Float,
    /// A count or index (i64, never empty).
    Int,
    /// A word (`motor`, `status`, ...); empty for none.
    Text,
}

/// One cell of a row.
#[derive(Clone, Debug, PartialEq)]
pub enum Cell {
    /// A float column's value (NaN: empty).
    F(f64),
    /// An integer column's value.
    I(u64),
    /// A word (borrowed when it is one of the fixed ones; empty for none).
    S(Cow<'static, str>),
}

impl Cell {
    /// The cell as a number: a float as it is, a count as f64, a word NaN.
    pub fn number(&self) -> f64 {
        match self {
            Cell::F(v) => *v,
            Cell::I(v) => *v as f64,
            Cell::S(_) => f64::NAN,
        }
    }

    /// The cell's word ("" for a number).
    pub fn word(&self) -> &str {
        match self {
            Cell::S(t) => t,
            _ => "",
        }
    }
}

/// Over which lanes `summary.csv` counts the shares of a word column.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Of {
    /// Every lane.
    All,
    /// Lanes whose status is `ok`.
    Ok,
    /// Lanes whose cell is not empty.
    Given,
}

/// How `summary.csv` summarises a column.
#[derive(Clone, Copy, Debug)]
pub enum Summary {
    /// Not summarised (the lane index, the row's path).
    None,
    /// Moments, quantiles and rank correlations of its numbers (empty
    /// cells left out).
    Numbers,
    /// The share of each of its words (the vocabulary of its
    /// [`Value::W`]), with a Wilson interval.
    Shares(Of),
}

/// How `tswm check` compares the CPU's and the GPU's cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Compare {
    /// Not compared.
    None,
    /// Identical (counts and words).
    Exact,
    /// Within this many seconds (a first-switch time, when both have one).
    Seconds(f64),
    /// Within this share of max(1, |value|).
    Relative(f64),
}

/// One row of the table: everything about a result column.
#[derive(Clone, Copy, Debug)]
pub struct Column {
    /// The one name: the header of `lanes.csv`, the Parquet field.
    pub name: &'static str,
    /// Unit ("" for none).
    pub unit: &'static str,
    /// The quantity in words, for axis labels and legends.
    pub quantity: &'static str,
    /// What it means, for the docs.
    pub meaning: &'static str,
    /// When the cell is empty ("" for never).
    pub empty: &'static str,
    /// How `summary.csv` summarises it.
    pub summary: Summary,
    /// How `tswm check` compares it.
    pub compare: Compare,
    /// Plotted by the report unless `[report] results` says otherwise.
    pub plotted: bool,
    /// One of the integrated results that the f64 path's error estimate
    /// covers and the GPU row check tests (x1, v1, the works, the energies).
    pub integrated: bool,
    /// A running value (the `_ss` efficiencies at the final sliding
    /// speed): a lane at rest at its end has no running point, so
    /// `summary.csv` and the report leave such lanes out of its
    /// statistics, ranges and maps (the table keeps the cell, the value's
    /// limit at zero speed, docs/model.md section 10).
    pub running: bool,
    /// How a lane's cell is read from its end state (and so the cells'
    /// type, [`Column::kind`]).
    pub value: Value,
}

/// How a lane's cell of a result column is read from its end state, one
/// function a type: a column is filled by calling it over a chunk's
/// lanes, with no cell in between.
#[derive(Clone, Copy, Debug)]
pub enum Value {
    /// The lane's index (a count).
    Lane,
    /// A float; NaN for an empty cell. The function of one lane, and the
    /// same over a block of lanes (one call a block, the reading inlined
    /// in its loop), both from `float!`.
    F(fn(&LaneResult) -> f64, fn(&[LaneResult], &mut Vec<f64>)),
    /// A count, as [`Value::F`] (`count!`).
    I(fn(&LaneResult) -> u64, fn(&[LaneResult], &mut Vec<i64>)),
    /// A word: the code of the lane's word in the vocabulary (None for
    /// an empty cell), and the vocabulary. The Arrow column is a
    /// dictionary whose values are the vocabulary and whose keys are the
    /// codes.
    W(fn(&LaneResult) -> Option<usize>, Vocabulary),
}

/// A word column's words in code order: the values of its Arrow
/// dictionary (keyed by each word's code) and the words `summary.csv`
/// counts.
pub type Vocabulary = fn() -> &'static [&'static str];

/// The [`Vocabulary`] of an enum whose `ALL` lists its variants in
/// declaration order (so that `variant as usize` is its code; a test
/// holds each to it).
macro_rules! vocabulary {
    ($f:ident, $t:ty) => {
        /// The words of
        #[doc = concat!("[`", stringify!($t), "`]")]
        /// in code order.
        pub fn $f() -> &'static [&'static str] {
            static WORDS: std::sync::LazyLock<Vec<&'static str>> =
                std::sync::LazyLock::new(|| <$t>::ALL.iter().map(|w| w.name()).collect());
            &WORDS
        }
    };
}
pub(crate) use vocabulary;

/// A float column's [`Value`] from its reading of one lane.
macro_rules! float {
    ($f:expr) => {
        Value::F($f, |rs, out| out.extend(rs.iter().map($f)))
    };
}

/// A count column's [`Value`] from its reading of one lane.
macro_rules! count {
    ($f:expr) => {
        Value::I($f, |rs, out| {
            let one: fn(&LaneResult) -> u64 = $f;
            out.extend(rs.iter().map(|r| one(r) as i64))
        })
    };
}

/// The names of the columns that code reads by name (each used as its
/// row's name below, so spelled once).
pub(crate) const LANE: &str = "lane";
/// See [`LANE`].
pub(crate) const STATUS: &str = "status";
/// See [`LANE`].
pub(crate) const CONTACT_END: &str = "contact_end";
/// See [`LANE`].
pub(crate) const HOLD: &str = "hold";
/// See [`LANE`].
pub(crate) const DRIVE: &str = "drive";
/// See [`LANE`].
pub(crate) const ETA_DIRECT: &str = "eta_direct";
/// See [`LANE`].
pub(crate) const ETA_INVERSE: &str = "eta_inverse";
/// See [`LANE`].
pub(crate) const ETA_DIRECT_SS: &str = "eta_direct_ss";
/// See [`LANE`].
pub(crate) const ETA_INVERSE_SS: &str = "eta_inverse_ss";
/// See [`LANE`].
pub(crate) const LOCK_MARGIN_DEG: &str = "lock_margin_deg";

/// See [`LANE`].
pub(crate) const V1_END: &str = "v1_end";
/// See [`LANE`].
pub(crate) const ETA_DIRECT_START: &str = "eta_direct_start";
/// See [`LANE`].
pub(crate) const ETA_INVERSE_START: &str = "eta_inverse_start";
/// See [`LANE`].
pub(crate) const T_STOP: &str = "t_stop";
/// See [`LANE`].
pub(crate) const N1_END: &str = "n1_end";
/// See [`LANE`].
pub(crate) const N2_END: &str = "n2_end";

/// See [`LANE`]: the search's columns (a search run's table only).
pub(crate) const SEARCH_LO: &str = "search_lo";
/// See [`SEARCH_LO`].
pub(crate) const SEARCH_HI: &str = "search_hi";
/// See [`SEARCH_LO`].
pub(crate) const CRITICAL: &str = "critical";
/// See [`SEARCH_LO`].
pub(crate) const SEARCH_MEETS: &str = "search_meets";
/// See [`SEARCH_LO`].
pub(crate) const SEARCH_STATUS: &str = "search_status";

/// Bound of `tswm check` on first-switch times, s.
pub const SWITCH_BOUND: f64 = 2e-5;
/// Bound of `tswm check` on x1, v1, the works and energies, and the stop
/// time, relative to max(1, |value|).
pub const VALUE_BOUND: f64 = 5e-5;

/// A number a lane that did not end `ok` does not report (empty cell).
#[inline(always)]
fn ok(r: &LaneResult, v: f64) -> f64 {
    if r.status == Status::Ok {
        v
    } else {
        f64::NAN
    }
}

const ROW: Column = Column {
    name: "",
    unit: "",
    quantity: "",
    meaning: "",
    empty: "",
    summary: Summary::Numbers,
    compare: Compare::None,
    plotted: false,
    integrated: false,
    running: false,
    value: float!(|_| f64::NAN),
};

const NOT_OK: &str = "the lane's status is not ok";

/// An integrated result: x1, v1 or an energy.
const INTEGRATED: Column = Column {
    compare: Compare::Relative(VALUE_BOUND),
    integrated: true,
    empty: NOT_OK,
    ..ROW
};

vocabulary!(status_words, Status);
vocabulary!(contact_words, Contact);
vocabulary!(hold_words, Hold);
vocabulary!(drive_words, Drive);
vocabulary!(side_words, Side);
vocabulary!(search_status_words, SearchStatus);

/// An indicator output of a sensitivity analysis: 1 where a lane's
/// `column` reads `word`, else 0; named `column=word`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Indicator {
    /// The word column.
    pub column: &'static str,
    /// The word that counts as 1.
    pub word: &'static str,
}

impl Indicator {
    /// Its name in `sensitivity.csv`: `column=word`.
    pub fn name(&self) -> String {
        format!("{}={}", self.column, self.word)
    }
}

/// The indicator outputs of a sensitivity analysis: each final contact
/// (`contact_end=stick` is "at rest": held with the motor cut, stalled
/// with it on), then `status=ok`.
pub fn indicators() -> Vec<Indicator> {
    Contact::ALL
        .iter()
        .map(|c| Indicator {
            column: CONTACT_END,
            word: c.name(),
        })
        .chain([Indicator {
            column: STATUS,
            word: Status::Ok.name(),
        }])
        .collect()
}

/// The result columns, in the order of the results table (after the
/// parameters).
pub const RESULTS: &[Column] = &[
    Column {
        name: LANE,
        quantity: "lane index",
        meaning: "index of the lane in sweep order (0-based): grid point lane / n, sample lane % n",
        summary: Summary::None,
        value: Value::Lane,
        ..ROW
    },
    Column {
        name: STATUS,
        quantity: "lane status",
        meaning: "ok, or why the lane could not be finished: inconsistent (D <= 0, or falling to 0 \
                  where the wedge jams: friction far above the lead angle), nonfinite, max_steps, \
                  max_events, step_underflow",
        summary: Summary::Shares(Of::All),
        compare: Compare::Exact,
        value: Value::W(|r| Some(r.status as usize), status_words),
        ..ROW
    },
    Column {
        name: "switches",
        quantity: "contact switches",
        meaning: "changes of the contact side a-a/b-b (resuming on the same side after a stop is none)",
        compare: Compare::Exact,
        value: count!(|r| u64::from(r.switches)),
        ..ROW
    },
    Column {
        name: "t_first_switch",
        unit: "s",
        quantity: "time of the first switch",
        meaning: "time of the first change of contact side",
        empty: "the lane never switches",
        compare: Compare::Seconds(SWITCH_BOUND),
        value: float!(|r| r.t_first_switch),
        ..ROW
    },
    Column {
        name: "reversals",
        quantity: "direction reversals",
        meaning: "changes of the direction of motion",
        compare: Compare::Exact,
        value: count!(|r| u64::from(r.reversals)),
        ..ROW
    },
    Column {
        name: "sticks",
        quantity: "stick phases",
        meaning: "phases at rest held by static friction (one from t = 0 included)",
        compare: Compare::Exact,
        value: count!(|r| u64::from(r.sticks)),
        ..ROW
    },
    Column {
        name: CONTACT_END,
        quantity: "final contact",
        meaning: "contact at the end: aa (worm pushes wheel), bb (wheel pushes worm), stick (at rest, \
                  stuck by static friction: held if the motor is cut, stalled if it runs)",
        summary: Summary::Shares(Of::Ok),
        compare: Compare::Exact,
        value: Value::W(|r| Some(r.contact_end as usize), contact_words),
        ..ROW
    },
    Column {
        name: "x1_end",
        unit: "m",
        quantity: "final position x1",
        meaning: "position of body 1 (the worm's pitch circle) at the end",
        value: float!(|r| ok(r, r.x1_end)),
        ..INTEGRATED
    },
    Column {
        name: V1_END,
        unit: "m/s",
        quantity: "final speed v1",
        meaning: "speed of body 1 at the end",
        value: float!(|r| ok(r, r.v1_end)),
        ..INTEGRATED
    },
    Column {
        name: "w_motor",
        unit: "J",
        quantity: "motor work",
        meaning: "work of the motor force, the integral of F1 v1",
        value: float!(|r| ok(r, r.w_motor)),
        ..INTEGRATED
    },
    Column {
        name: "w_load",
        unit: "J",
        quantity: "load work",
        meaning: "work of the load, the integral of F2 v2 (negative while lifting)",
        value: float!(|r| ok(r, r.w_load)),
        ..INTEGRATED
    },
    Column {
        name: "w_friction",
        unit: "J",
        quantity: "friction heat",
        meaning: "heat in the mesh, the integral of S1 v1 + S2 v2 (>= 0)",
        value: float!(|r| ok(r, r.w_friction)),
        ..INTEGRATED
    },
    Column {
        name: "eta_end",
        quantity: "efficiency at the end",
        meaning: "instantaneous mesh efficiency in the final mode (direct or inverse flow)",
        empty: "the lane is at rest at the end, or its status is not ok",
        value: float!(|r| ok(r, r.eta_end)),
        ..ROW
    },
    Column {
        name: "steps",
        quantity: "integration steps",
        meaning: "accepted integration steps",
        value: count!(|r| u64::from(r.steps)),
        ..ROW
    },
    Column {
        name: "w1_in",
        unit: "J",
        quantity: "energy the worm side put into the mesh",
        meaning: "energy the worm side put into the mesh, the integral of max(p1, 0) with p1 = S1 v1",
        value: float!(|r| ok(r, r.w1_in)),
        ..INTEGRATED
    },
    Column {
        name: "w1_out",
        unit: "J",
        quantity: "energy the mesh gave the worm side",
        meaning: "energy the mesh gave back to the worm side, the integral of max(-p1, 0)",
        value: float!(|r| ok(r, r.w1_out)),
        ..INTEGRATED
    },
    Column {
        name: "w2_in",
        unit: "J",
        quantity: "energy the wheel side put into the mesh",
        meaning: "energy the wheel side put into the mesh, the integral of max(p2, 0) with p2 = S2 v2",
        value: float!(|r| ok(r, r.w2_in)),
        ..INTEGRATED
    },
    Column {
        name: "w2_out",
        unit: "J",
        quantity: "energy the mesh gave the wheel side",
        meaning: "energy the mesh gave the wheel side, the integral of max(-p2, 0)",
        value: float!(|r| ok(r, r.w2_out)),
        ..INTEGRATED
    },
    Column {
        name: ETA_DIRECT,
        quantity: "direct efficiency (worm drives)",
        meaning: "w2_out / w1_in: the share of the energy the worm side put into the mesh that \
                  reached the wheel side, over the whole run",
        empty: "the worm side put (almost) no energy into the mesh (w1_in <= 1e-6 of w1_in + w2_in), \
                or the status is not ok",
        value: float!(|r| ok(r, r.eta_direct)),
        compare: Compare::Relative(VALUE_BOUND),
        ..ROW
    },
    Column {
        name: ETA_INVERSE,
        quantity: "inverse efficiency (wheel drives)",
        meaning: "w1_out / w2_in: the share of the energy the wheel side put into the mesh that \
                  reached the worm side; 0 when the wheel side only fed friction (a self-locking \
                  drive braking itself)",
        empty: "the wheel side put (almost) no energy into the mesh (w2_in <= 1e-6 of w1_in + w2_in), \
                or the status is not ok",
        value: float!(|r| ok(r, r.eta_inverse)),
        compare: Compare::Relative(VALUE_BOUND),
        ..ROW
    },
    Column {
        name: ETA_DIRECT_SS,
        plotted: true,
        running: true,
        quantity: "running direct efficiency",
        meaning: "tan(gamma) / tan(gamma + rho): steady (running) direct efficiency at the final \
                  sliding speed; at rest, rho's limit at zero speed (the sliding mu, not the \
                  breakaway mu_static: the starting values are eta_direct_start and \
                  eta_inverse_start), which summary.csv and the report leave out: a lane at rest \
                  has no running point",
        empty: NOT_OK,
        value: float!(|r| ok(r, r.eta_direct_ss)),
        compare: Compare::Relative(VALUE_BOUND),
        ..ROW
    },
    Column {
        name: ETA_INVERSE_SS,
        plotted: true,
        running: true,
        quantity: "running inverse efficiency",
        meaning: "tan(gamma - rho) / tan(gamma): steady (running) inverse efficiency at the final \
                  sliding speed; <= 0 means the wheel cannot drive the worm at that speed \
                  (self-locking); at rest as eta_direct_ss, left out of summary.csv and the report",
        empty: NOT_OK,
        value: float!(|r| ok(r, r.eta_inverse_ss)),
        compare: Compare::Relative(VALUE_BOUND),
        ..ROW
    },
    Column {
        name: LOCK_MARGIN_DEG,
        plotted: true,
        unit: "deg",
        quantity: "static lock margin",
        meaning: "rho_s - gamma with rho_s = atan(mu_s / cos(alpha_n)) (the static friction angle): \
                  > 0 means the drive holds its load at rest with the motor off (statically \
                  self-locking)",
        empty: NOT_OK,
        value: float!(|r| ok(r, r.lock_margin_deg)),
        compare: Compare::Relative(VALUE_BOUND),
        ..ROW
    },
    Column {
        name: ETA_DIRECT_START,
        quantity: "starting direct efficiency",
        meaning: "tan(gamma) / tan(gamma + rho_s): the starting efficiency (breakaway from rest, \
                  static friction), as catalogues list it beside the running efficiency",
        empty: NOT_OK,
        compare: Compare::Relative(VALUE_BOUND),
        value: float!(|r| ok(r, r.eta_direct_start)),
        ..ROW
    },
    Column {
        name: ETA_INVERSE_START,
        quantity: "starting inverse efficiency",
        meaning: "tan(gamma - rho_s) / tan(gamma): the starting back-driving efficiency; <= 0 \
                  exactly when lock_margin_deg >= 0 (statically self-locking)",
        empty: NOT_OK,
        compare: Compare::Relative(VALUE_BOUND),
        value: float!(|r| ok(r, r.eta_inverse_start)),
        ..ROW
    },
    Column {
        name: HOLD,
        quantity: "does it hold",
        meaning: "for a lane whose motor is cut before t_end: held (at rest, stuck), runs_away \
                  (sliding and not slowing down) or coasting (sliding and slowing down: not decided; \
                  set t_max)",
        empty: "the motor is not cut before t_end, or the status is not ok",
        summary: Summary::Shares(Of::Given),
        compare: Compare::Exact,
        value: Value::W(|r| r.hold.map(|h| h as usize), hold_words),
        ..ROW
    },
    Column {
        name: DRIVE,
        quantity: "does the motor drive it",
        meaning: "for a lane whose motor runs to the end: runs (sliding in the motor's direction, \
                  the worm side feeding the mesh: p1 = S1 v1 >= 0), overhauled (sliding in the \
                  motor's direction with p1 < 0: the load overhauls and the motor brakes it), \
                  stalled (at rest and stuck: the motor cannot start or keep moving the load) or \
                  back_driven (sliding against the motor: the load drives the worm backwards)",
        empty: "the motor is cut before t_end (see hold), a constant motor has f1 = 0, or the \
                status is not ok",
        summary: Summary::Shares(Of::Given),
        compare: Compare::Exact,
        value: Value::W(|r| r.drive.map(|d| d as usize), drive_words),
        ..ROW
    },
    Column {
        name: T_STOP,
        unit: "s",
        quantity: "stop time",
        meaning: "where the lane stopped: t_end, or for a lane that ran on past t_end (t_max), the \
                  time it was held, began to run away, or reached t_max; every _end value and \
                  integral is taken here",
        empty: NOT_OK,
        compare: Compare::Relative(VALUE_BOUND),
        value: float!(|r| ok(r, r.t_stop)),
        ..ROW
    },
    Column {
        name: N1_END,
        unit: "rpm",
        quantity: "final worm speed",
        meaning: "worm shaft speed where the lane stopped, v1_end / R1 (a lane given in gear terms)",
        empty: "the lane has no geometry in gear terms, or its status is not ok",
        compare: Compare::Relative(VALUE_BOUND),
        value: float!(|r| ok(r, r.n1_end)),
        ..ROW
    },
    Column {
        name: N2_END,
        unit: "rpm",
        quantity: "final wheel speed",
        meaning: "wheel shaft speed where the lane stopped, v1_end tan(gamma) / R2 (a lane given in \
                  gear terms)",
        empty: "the lane has no geometry in gear terms, or its status is not ok",
        compare: Compare::Relative(VALUE_BOUND),
        value: float!(|r| ok(r, r.n2_end)),
        ..ROW
    },
    Column {
        name: "path",
        quantity: "row path",
        meaning: "where the row came from: cpu (f64 path), cpu:refined (run again at a tenth of the \
                  tolerance), gpu (f32, checked and trusted), cpu:REASON (a GPU row recomputed in f64)",
        summary: Summary::None,
        value: Value::W(|r| Some(r.path.code()), RowPath::words),
        ..ROW
    },
];

/// The columns a search run's table has after [`RESULTS`] (docs/model.md,
/// "Searches"): each row is a drive, its other results those of the lane
/// at its final bracket's end that meets the requirement.
pub const SEARCH: &[Column] = &[
    Column {
        name: SEARCH_LO,
        quantity: "bracket's lower end",
        meaning: "lower end of the final bracket of the searched parameter (in its unit): the \
                  critical value lies in (search_lo, search_hi]",
        empty: NOT_OK,
        summary: Summary::None,
        value: float!(|r| r.search.map_or(f64::NAN, |s| s.lo)),
        ..ROW
    },
    Column {
        name: SEARCH_HI,
        quantity: "bracket's upper end",
        meaning: "upper end of the final bracket of the searched parameter",
        empty: NOT_OK,
        summary: Summary::None,
        value: float!(|r| r.search.map_or(f64::NAN, |s| s.hi)),
        ..ROW
    },
    Column {
        name: CRITICAL,
        plotted: true,
        quantity: "critical value",
        meaning: "where the requirement's answer changes: the middle of the final bracket, within \
                  tol / 2 of the true value (summary.csv gives its quantiles per grid point from \
                  every drive's bracket)",
        empty: "the search_status is not found",
        summary: Summary::None,
        value: float!(|r| r.search.map_or(f64::NAN, |s| s.critical())),
        ..ROW
    },
    Column {
        name: SEARCH_MEETS,
        quantity: "side that meets the requirement",
        meaning: "below: the requirement is met below the critical value; above: above it",
        empty: "the requirement is met at both ends, at neither, or its answer changes more \
                than once",
        summary: Summary::Shares(Of::Given),
        value: Value::W(
            |r| r.search.and_then(|s| s.side).map(|s| s as usize),
            side_words,
        ),
        ..ROW
    },
    Column {
        name: SEARCH_STATUS,
        quantity: "search status",
        meaning: "found (the critical value lies in a bracket no wider than tol), \
                  met_at_both_ends, met_at_neither_end, several_changes (the first round saw \
                  more than one change: the search assumes one), stopped_clear (a share \
                  boundary's search stopped refining the drive: its bracket lies clear of the \
                  boundary's)",
        summary: Summary::Shares(Of::All),
        compare: Compare::Exact,
        value: Value::W(|r| r.search.map(|s| s.status as usize), search_status_words),
        ..ROW
    },
    Column {
        name: "search_lanes",
        quantity: "lanes integrated",
        meaning: "lanes integrated for this drive's search",
        value: count!(|r| r.search.map_or(0, |s| u64::from(s.lanes))),
        ..ROW
    },
];

/// The result columns.
pub fn results() -> &'static [Column] {
    RESULTS
}

/// The result columns of a run's table: [`RESULTS`], and for a search
/// [`SEARCH`] after them.
pub(crate) fn results_for(search: bool) -> Vec<&'static Column> {
    let mut v: Vec<&'static Column> = RESULTS.iter().collect();
    if search {
        v.extend(SEARCH);
    }
    v
}

/// A result column by name (a search's too).
pub fn result(name: &str) -> Option<&'static Column> {
    results().iter().chain(SEARCH).find(|c| c.name == name)
}

/// The result columns the report plots unless told otherwise.
pub fn plotted() -> impl Iterator<Item = &'static Column> {
    results().iter().filter(|c| c.plotted)
}

/// The result columns `summary.csv` gives numbers for, in table order.
pub(crate) fn number_columns() -> impl Iterator<Item = &'static Column> {
    results()
        .iter()
        .filter(|c| matches!(c.summary, Summary::Numbers))
}

/// Whether a result column is an inverse efficiency (`eta_inverse`,
/// `_ss`, `_start`), whose values <= 0 mean the wheel cannot drive the
/// worm: the drive is self-locking there.
pub(crate) fn is_inverse_efficiency(name: &str) -> bool {
    name.starts_with(ETA_INVERSE)
}

/// "quantity, name (unit)": an axis label.
pub fn label(name: &str, quantity: &str, unit: &str) -> String {
    match (quantity.is_empty(), unit.is_empty()) {
        (true, true) => name.to_string(),
        (true, false) => format!("{name} ({unit})"),
        (false, true) => format!("{quantity}, {name}"),
        (false, false) => format!("{quantity}, {name} ({unit})"),
    }
}

/// The result column table of `docs/outputs.md`, rendered from the rows
/// (a test keeps the page equal to it).
#[cfg(test)]
pub(crate) fn docs_table() -> String {
    table_of(results())
}

/// The search columns' table of `docs/outputs.md` ([`SEARCH`]).
#[cfg(test)]
pub(crate) fn search_docs_table() -> String {
    table_of(SEARCH)
}

#[cfg(test)]
fn table_of(columns: &[Column]) -> String {
    let mut s = String::from("| column | unit | meaning | empty when |\n|---|---|---|---|\n");
    for c in columns {
        s += &format!(
            "| `{}` | {} | {} | {} |\n",
            c.name,
            c.unit,
            c.meaning,
            if c.empty.is_empty() { "never" } else { c.empty }
        );
    }
    s
}

impl Column {
    /// The cells' type.
    pub fn kind(&self) -> Kind {
        match self.value {
            Value::F(..) => Kind::Float,
            Value::Lane | Value::I(..) => Kind::Int,
            Value::W(..) => Kind::Text,
        }
    }

    /// Lane `lane`'s cell, its end state `r`.
    pub fn cell(&self, lane: u64, r: &LaneResult) -> Cell {
        match self.value {
            Value::Lane => Cell::I(lane),
            Value::F(f, _) => Cell::F(f(r)),
            Value::I(f, _) => Cell::I(f(r)),
            Value::W(code, words) => Cell::S(Cow::Borrowed(code(r).map_or("", |c| words()[c]))),
        }
    }

    /// A word column's vocabulary (None for a number column).
    pub fn vocabulary(&self) -> Option<&'static [&'static str]> {
        match self.value {
            Value::W(_, words) => Some(words()),
            _ => None,
        }
    }

    /// The column's axis label.
    pub fn label(&self) -> String {
        label(self.name, self.quantity, self.unit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_not_parameters() {
        let names: Vec<&str> = results().iter().map(|c| c.name).collect();
        for (i, n) in names.iter().enumerate() {
            assert!(!names[..i].contains(n), "{n} twice");
            assert!(crate::params::Param::from_name(n).is_none(), "{n}");
        }
        assert_eq!(names.first(), Some(&LANE));
        assert_eq!(names.last(), Some(&"path"));
    }

    #[test]
    fn the_integrated_results_are_the_lane_results_in_the_error_budgets_order() {
        // Marked here, listed by `LaneResult::integrated`: the same nine.
        let r = LaneResult {
            status: Status::Ok,
            x1_end: 1.0,
            v1_end: 2.0,
            w_motor: 3.0,
            w_load: 4.0,
            w_friction: 5.0,
            w1_in: 6.0,
            w1_out: 7.0,
            w2_in: 8.0,
            w2_out: 9.0,
            ..LaneResult::EMPTY
        };
        let marked: Vec<f64> = results()
            .iter()
            .filter(|c| c.integrated)
            .map(|c| c.cell(0, &r).number())
            .collect();
        assert_eq!(marked, r.integrated());
        let names: Vec<&str> = results()
            .iter()
            .filter(|c| c.integrated)
            .map(|c| c.name)
            .collect();
        assert_eq!(names.len(), crate::integrator::accuracy::RESULTS);
        assert_eq!(
            names,
            [
                "x1_end",
                "v1_end",
                "w_motor",
                "w_load",
                "w_friction",
                "w1_in",
                "w1_out",
                "w2_in",
                "w2_out"
            ]
        );
    }

    /// The outputs page's table is the table.
    #[test]
    fn the_outputs_pages_column_table_is_the_table() {
        let page = include_str!("../docs/outputs.md");
        for want in [docs_table(), search_docs_table()] {
            assert!(
                page.contains(&want),
                "docs/outputs.md's column table differs; it should read:\n{want}"
            );
        }
    }
}
