//! Sweep files (TOML) and the lanes they stand for.
//!
//! A sweep is a `[base]` parameter set, optional grid axes (`[[grid]]`, a
//! Cartesian product), an optional tolerance study (`[sampling]` with
//! `[[tolerance]]` entries) and optional friction tables (one unnamed
//! `[friction_table]`, or named ones, `[friction_table.bronze]`).
//!
//! Lane order: grid points in row-major order (the first `[[grid]]` axis
//! varies slowest, the last fastest), and for each grid point the samples
//! 0..n of the study. Lane `i` is grid point `i / n`, sample `i % n`.
//! Sample `k` draws the same uniforms at every grid point (common random
//! numbers), so designs are compared under the same tolerances.

mod axes;
mod design;
mod file;
mod laws;
pub mod pareto;
mod parse;
pub mod require;
mod resolved;
pub mod search;
mod study;
mod text;

use crate::input::sampling::Uniforms;
use crate::params::FrictionTables;
use crate::params::{Param, Spec};

pub use design::{Sensitivity, Shift, Study, Tolerance};
pub use file::{Method, MAX_SEED};
pub(crate) use text::read_text;

/// One grid axis: a parameter and its values (numbers, or the words of a
/// law selector or a friction table's name).
#[derive(Clone, Debug)]
pub struct Axis {
    /// The parameter.
    pub param: Param,
    /// Its values.
    pub values: AxisValues,
}

/// An axis's values: a list, or a range computed value by value (so an
/// axis of 10^9 points costs no memory, and provenance keeps its form).
#[derive(Clone, Debug)]
pub enum AxisValues {
    /// `values = [...]`
    List(Vec<f64>),
    /// `from`, `to`, `n`, `scale`
    Range {
        /// First value.
        from: f64,
        /// Last value.
        to: f64,
        /// Number of values, >= 1.
        n: u64,
        /// Log-spaced.
        log: bool,
    },
    /// `values = ["bronze", "cast_iron"]` for `motor`, `friction` or
    /// `friction_table` (each checked when the sweep is read).
    Words(Vec<String>),
}

impl Axis {
    /// Number of values (never 0: validation refuses empty axes).
    #[allow(clippy::len_without_is_empty)]
    pub fn len(&self) -> u64 {
        match &self.values {
            AxisValues::List(v) => v.len() as u64,
            AxisValues::Range { n, .. } => *n,
            AxisValues::Words(w) => w.len() as u64,
        }
    }

    /// Whether the axis runs over words (a law or a table name), not numbers.
    pub(crate) fn is_words(&self) -> bool {
        matches!(self.values, AxisValues::Words(_))
    }

    /// Value `i` (< len) as text: the word, or the number as `lanes.csv`
    /// writes it.
    pub fn text(&self, i: u64) -> String {
        match &self.values {
            AxisValues::Words(w) => w[i as usize].clone(),
            // As lanes.csv writes a float: the shortest text that reads back.
            _ => format!("{:?}", self.value(i)),
        }
    }

    /// Value `i` (< len); NaN for a word axis.
    pub fn value(&self, i: u64) -> f64 {
        match &self.values {
            AxisValues::Words(_) => f64::NAN,
            AxisValues::List(v) => v[i as usize],
            &AxisValues::Range { from, to, n, log } => {
                let frac = if n == 1 {
                    0.0
                } else {
                    i as f64 / (n - 1) as f64
                };
                if log {
                    (from.ln() + (to.ln() - from.ln()) * frac).exp()
                } else {
                    from + (to - from) * frac
                }
            }
        }
    }
}

/// A parsed, validated sweep: a function from lane index to parameters.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// The base parameter set (unset values take docs/model.md defaults).
    pub base: Spec,
    /// Grid axes, slowest first.
    pub axes: Vec<Axis>,
    /// Optional tolerance study.
    pub study: Option<Study>,
    /// The friction tables (for `friction = "table"`), possibly none.
    pub tables: FrictionTables,
    /// Lanes to trace (`[trace]`), if any.
    pub trace: Option<TraceSpec>,
    /// What the report shows (`[report]`).
    pub report: ReportSpec,
    /// Each drive's critical value of a parameter (`[search]`), if asked.
    pub search: Option<search::Search>,
    /// The line of each parameter the file sets (`[base]` key, grid axis,
    /// tolerance), so a lane's error can point at it.
    pub key_lines: Vec<(&'static str, usize)>,
}

/// What `report.html` shows, from the sweep's `[report]` table.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ReportSpec {
    /// A title for the page (free text, shown escaped).
    pub title: Option<String>,
    /// The grid parameters of the heat maps (x, then y); empty: the first
    /// two numeric axes.
    pub axes: Vec<Param>,
    /// Result columns to plot; empty: those the table of result columns
    /// marks `plotted`.
    pub results: Vec<String>,
    /// Most panels (one per value of the other axes, or per grid point of
    /// a study).
    pub panels: usize,
    /// A design requirement whose answer the report states.
    pub require: Option<require::Requirement>,
    /// The objectives of a Pareto front the report draws (none: no front).
    pub pareto: Vec<pareto::Objective>,
}

impl ReportSpec {
    /// Panels unless `[report] panels` says otherwise.
    pub(crate) const DEFAULT_PANELS: usize = 6;
    /// Most panels allowed (each is a few tens of kB of SVG).
    pub(crate) const MAX_PANELS: usize = 48;

    /// The results to plot.
    pub fn results(&self) -> Vec<String> {
        if self.results.is_empty() {
            // The table of result columns marks them.
            crate::columns::plotted()
                .map(|c| c.name.to_string())
                .collect()
        } else {
            self.results.clone()
        }
    }

    /// The panel limit.
    pub(crate) fn panels(&self) -> usize {
        if self.panels == 0 {
            Self::DEFAULT_PANELS
        } else {
            self.panels
        }
    }
}

/// Which lanes to trace and how often (docs/model.md section 11).
#[derive(Clone, Debug, PartialEq)]
pub struct TraceSpec {
    /// Lane indices, ascending, no repeats.
    pub lanes: Vec<u64>,
    /// Interval between rows, s.
    pub dt: f64,
}

impl TraceSpec {
    /// Checks a trace request against a run of `lanes` lanes; the message
    /// says what is allowed.
    pub fn new(mut lanes: Vec<u64>, dt: f64, total: u64) -> std::result::Result<TraceSpec, String> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(format!("dt must be a time > 0 s, got {dt}"));
        }
        if let Some(&bad) = lanes.iter().find(|&&l| l >= total) {
            return Err(format!(
                "lane {bad} is not in the run; allowed: 0 to {}",
                total.saturating_sub(1)
            ));
        }
        lanes.sort_unstable();
        lanes.dedup();
        Ok(TraceSpec { lanes, dt })
    }
}
impl Sweep {
    pub(crate) fn lane_count_checked(&self) -> std::result::Result<u64, String> {
        let mut n: u64 = self.study.as_ref().map_or(1, |s| s.n);
        for a in &self.axes {
            n = n
                .checked_mul(a.len())
                .ok_or("the sweep has more than 2^64 lanes")?;
        }
        Ok(n)
    }

    /// Number of lanes.
    pub fn lane_count(&self) -> u64 {
        self.lane_count_checked().unwrap_or(u64::MAX)
    }

    /// Samples per grid point (1 without a study).
    fn samples(&self) -> u64 {
        self.study.as_ref().map_or(1, |s| s.n)
    }

    /// The parameters of lane `i` (not yet validated).
    pub fn lane_spec(&self, i: u64, u: &mut Uniforms) -> Spec {
        let mut spec = self.base.clone();
        self.lane_spec_into(i, u, &mut spec);
        spec
    }

    /// [`Sweep::lane_spec`] into `spec` (its earlier contents replaced):
    /// a lane source reuses one.
    pub(crate) fn lane_spec_into(&self, i: u64, u: &mut Uniforms, spec: &mut Spec) {
        // A search's drive as one lane: the searched parameter at the
        // bracket's lower end (the lane its first round starts with).
        let at = self.search.as_ref().map(|s| (s.param, s.from));
        self.lane_spec_at(i, at, u, spec)
    }

    /// [`Sweep::lane_spec_into`] with the nominal value of `at`'s
    /// parameter set to its value (a search's query point): the value a
    /// grid would set, around which the lane's tolerance, if any, draws.
    pub(crate) fn lane_spec_at(
        &self,
        i: u64,
        at: Option<(crate::params::Num, f64)>,
        u: &mut Uniforms,
        spec: &mut Spec,
    ) {
        let n = self.samples();
        self.point_spec(i / n, at, spec);
        if let Some(st) = &self.study {
            st.draw(i % n, spec, u);
        }
        self.keep_own_law_params(spec);
    }

    /// Lane `i` as a search's drive of `searched`: its values without
    /// the searched parameter, and how the drive's draw moves the value
    /// it is queried at. With `spec.set(searched, shift.apply(x))`, the
    /// lane is [`Sweep::lane_spec_at`] `i` at `x`, value for value.
    pub(crate) fn search_drive(
        &self,
        i: u64,
        searched: crate::params::Num,
        u: &mut Uniforms,
        spec: &mut Spec,
    ) -> Shift {
        let n = self.samples();
        self.point_spec(i / n, None, spec);
        spec.num[searched as usize] = None;
        let shift = match &self.study {
            Some(st) => st.draw_around(i % n, spec, u, Some(searched)),
            None => Shift::NONE,
        };
        self.keep_own_law_params(spec);
        shift
    }

    /// The nominal design of grid point `point` (its values without the
    /// study's draws), with `at`'s parameter set: a search's design point.
    pub(crate) fn nominal_spec_at(
        &self,
        point: u64,
        at: Option<(crate::params::Num, f64)>,
        spec: &mut Spec,
    ) {
        self.point_spec(point, at, spec);
        self.keep_own_law_params(spec);
    }

    /// The base with grid point `point`'s values, and `at`'s parameter set.
    fn point_spec(&self, point: u64, at: Option<(crate::params::Num, f64)>, spec: &mut Spec) {
        spec.clone_from(&self.base);
        let mut g = point;
        for a in self.axes.iter().rev() {
            let len = a.len();
            match (a.param, &a.values) {
                (Param::Num(p), _) => spec.set(p, a.value(g % len)),
                (p, AxisValues::Words(w)) => {
                    // Every word was checked by `set_text` when the sweep was read.
                    let _ = spec.set_text(p, &w[(g % len) as usize]);
                }
                _ => {}
            }
            g /= len;
        }
        if let Some((p, x)) = at {
            spec.set(p, x);
        }
    }

    /// Where lane `lane`'s error on `param` (one name, or several, comma
    /// separated) lies: "lane N", with the line of the first of them the
    /// file sets.
    pub(crate) fn lane_at(&self, lane: u64, param: &str) -> String {
        let line = param.split(", ").find_map(|p| {
            self.key_lines
                .iter()
                .find(|(k, _)| *k == p)
                .map(|(_, l)| *l)
        });
        match line {
            Some(l) => format!("lane {lane} (line {l})"),
            None => format!("lane {lane}"),
        }
    }

    /// Whether its lanes are independent draws, so that a share of them
    /// has a Wilson interval: not for a sensitivity design, whose row
    /// groups share every input but one.
    pub(crate) fn independent_lanes(&self) -> bool {
        self.study.as_ref().is_none_or(|s| s.sensitivity.is_none())
    }

    /// A stream of uniforms for this sweep's study.
    pub(crate) fn uniforms(&self) -> Uniforms {
        Uniforms::new(self.study.as_ref().map_or(0, |s| s.seed))
    }
}

#[cfg(test)]
mod tests;
