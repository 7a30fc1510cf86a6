//! A search (`[search]`) as a design that runs in rounds: the drives of
//! a chunk propose a round of lanes (each drive's query points: its
//! searched parameter set to a value), the backend integrates the whole
//! round at once, and the answers of the requirement decide the next
//! round, until every drive is done. A one-round design (grid, tolerance
//! study, Sobol') is a chunk of lanes run once; a search is a chunk of
//! drives run in rounds, so the pipeline, shards, merge and sinks are
//! the same for both.
//!
//! Two designs: each drive's own search (`own`: a first round of
//! [`FIRST_ROUND_POINTS`] points, then bisection of the bracket where the
//! answer changes, to `tol`), and, with `at_least`, a group's share
//! boundary (`share`: only the drives whose brackets overlap the
//! boundary's and its interval's order statistics are refined).
//!
//! A drive's row is the lane at its final bracket's end that meets the
//! requirement (its searched parameter set there), with the search's
//! columns.

mod own;
mod share;
mod targets;

use crate::backend::Backend;
use crate::columns;
use crate::error::{Error, Result};
use crate::input::lanes::{LaneReader, Source};
use crate::input::sampling::Uniforms;
use crate::input::sweep::search::{Search, FIRST_ROUND_POINTS};
use crate::input::sweep::Shift;
use crate::input::sweep::Sweep;
use crate::integrator::{LaneResult, SearchOutcome};
use crate::model::FrictionTable;
use crate::params::{ParamColumns, Spec, TableName, Varying};

/// Drives a chunk holds (whole groups of a share search, however large).
const CHUNK_DRIVES: u64 = 16_384;

/// Where the drives' parameters come from.
enum Drives<'a> {
    /// A sweep: drive i is its lane i.
    Sweep(&'a Sweep),
    /// A lane table: its rows in order, read as the chunks come.
    Table(Box<LaneReader<'a>>),
}

/// A search run on a backend: the backend of a search run's pipeline.
pub(crate) struct SearchBackend<'a> {
    inner: Box<dyn Backend + 'a>,
    search: Search,
    drives: Drives<'a>,
    names: Vec<TableName>,
    /// The source's name, for errors.
    file: std::path::PathBuf,
    /// Drives a group (a share search's grid point; 1 otherwise).
    per_group: u64,
    /// The current chunk's drives: each resolved but for the searched
    /// parameter, and how its draw moves the value it is queried at.
    chunk: Vec<(Varying, Shift)>,
    /// A lane table's rows of the chunk (reused).
    specs: Vec<Spec>,
    /// A round's lanes, results and answers: buffers kept from round to
    /// round (fresh ones would cost a page fault a few lanes).
    lanes: ParamColumns,
    results: Vec<LaneResult>,
    spare: Vec<Answer>,
    /// Lanes integrated at once.
    batch: usize,
    /// The run's bar, the rounds run and the lanes they integrated.
    bar: Option<crate::progress::Bar>,
    rounds: u64,
    integrated: u64,
    u: Uniforms,
}

/// One query's answer: whether the requirement is met, and the lane's
/// results.
pub(super) struct Answer {
    meets: bool,
    result: LaneResult,
}

/// What a drive's row becomes: its outcome, and the lane it reports (the
/// value it was queried at, and its results).
pub(super) struct Row {
    outcome: SearchOutcome,
    lane: Option<(f64, LaneResult)>,
}

/// `backend`, or for a source with a search (over its lanes `range`) the
/// search run on it.
pub fn around<'a>(
    backend: Box<dyn Backend + 'a>,
    source: &'a Source,
    range: (u64, u64),
) -> Result<Box<dyn Backend + 'a>> {
    Ok(match source.search() {
        Some(_) => Box::new(SearchBackend::new(backend, source, range)?),
        None => backend,
    })
}

impl<'a> SearchBackend<'a> {
    /// The search of `source` (which has one) over its lanes `range`, run
    /// on `inner`.
    pub fn new(
        inner: Box<dyn Backend + 'a>,
        source: &'a Source,
        range: (u64, u64),
    ) -> Result<SearchBackend<'a>> {
        let search = source
            .search()
            .cloned()
            .ok_or_else(|| Error::Internal("a search backend of a run without [search]".into()))?;
        let (drives, file, per_group, u) = match source {
            Source::Sweep { sweep, file } => {
                let per_group = match (&sweep.study, search.at_least) {
                    (Some(st), Some(_)) => st.n,
                    _ => 1,
                };
                (
                    Drives::Sweep(sweep),
                    file.clone(),
                    per_group,
                    sweep.uniforms(),
                )
            }
            Source::Table { table, .. } => (
                Drives::Table(Box::new(source.reader_range(range.0, range.1)?)),
                table.name().to_path_buf(),
                1,
                Uniforms::new(0),
            ),
        };
        let batch = inner.batch_lanes().max(1);
        Ok(SearchBackend {
            inner,
            search,
            drives,
            names: source.friction_tables().names.clone(),
            file,
            per_group,
            chunk: Vec::new(),
            specs: Vec::new(),
            lanes: ParamColumns::default(),
            results: Vec::new(),
            spare: Vec::new(),
            batch,
            bar: None,
            rounds: 0,
            integrated: 0,
            u,
        })
    }

    /// Each drive of the chunk `first..first + n`, resolved but for the
    /// searched parameter (the only part of a query that changes).
    fn load_chunk(&mut self, first: u64, n: usize) -> Result<()> {
        let p = self.search.param;
        self.chunk.clear();
        self.chunk.reserve(n);
        if let Drives::Table(reader) = &mut self.drives {
            self.specs.clear();
            reader.fill_specs(n, &mut self.specs)?;
        }
        let mut spec = Spec::default();
        for j in 0..n {
            let lane = first + j as u64;
            let shift = match &self.drives {
                Drives::Sweep(sweep) => sweep.search_drive(lane, p, &mut self.u, &mut spec),
                Drives::Table(_) => {
                    spec.clone_from(&self.specs[j]);
                    Shift::NONE
                }
            };
            let varying = spec.varying(p, &self.names).map_err(|e| {
                Error::input(
                    &self.file,
                    Some(format!("lane {lane}")),
                    Some(e.param),
                    e.msg,
                )
            })?;
            self.chunk.push((varying, shift));
        }
        Ok(())
    }

    /// Drive `j`'s (lane `first + j`'s) parameters with the searched one
    /// at `x` (its nominal value: the drive's draw moves it), resolved
    /// into `out`.
    fn push_query(&self, first: u64, j: usize, x: f64, out: &mut ParamColumns) -> Result<()> {
        let (varying, shift) = &self.chunk[j];
        varying
            .resolve_into(shift.apply(x), &self.names, out)
            .map_err(|e| self.reached(e, first + j as u64, x))
    }

    /// Grid point `point`'s nominal design with the searched parameter at
    /// `x`, resolved into `out` (a sweep's; a table has none).
    fn push_nominal(&self, point: u64, x: f64, out: &mut ParamColumns) -> Result<()> {
        let Drives::Sweep(sweep) = &self.drives else {
            return Err(Error::Internal("a lane table has no nominal design".into()));
        };
        let mut spec = Spec::default();
        sweep.nominal_spec_at(point, Some((self.search.param, x)), &mut spec);
        spec.resolve_into(&self.names, out)
            .map_err(|e| self.reached(e, point * self.per_group, x))
    }

    /// The error of lane `lane` queried at `x`.
    fn reached(&self, e: crate::params::ParamError, lane: u64, x: f64) -> Error {
        Error::input(
            &self.file,
            Some(format!("lane {lane} at {} = {x}", self.search.param.name())),
            Some(e.param),
            format!("{} (a value the search reaches)", e.msg),
        )
    }

    /// Integrates the round `lanes` and answers the requirement for each.
    fn answer(
        &mut self,
        first: u64,
        lanes: &ParamColumns,
        tables: &[FrictionTable],
    ) -> Result<Vec<Answer>> {
        let mut answers = std::mem::take(&mut self.spare);
        answers.clear();
        self.answer_into(first, lanes, tables, &mut answers)?;
        self.round_done();
        Ok(answers)
    }

    /// [`SearchBackend::answer`], appended to `answers`.
    fn answer_into(
        &mut self,
        first: u64,
        lanes: &ParamColumns,
        tables: &[FrictionTable],
        answers: &mut Vec<Answer>,
    ) -> Result<()> {
        let mut results = std::mem::take(&mut self.results);
        self.inner.run_chunk(first, lanes, tables, &mut results)?;
        self.integrated += lanes.len() as u64;
        let col = columns::result(self.search.require.column)
            .ok_or_else(|| Error::Internal("a requirement on no column".into()))?;
        answers.extend(results.drain(..).map(|r| Answer {
            meets: r.status == crate::integrator::Status::Ok
                && self.search.require.passes(&col.cell(0, &r)),
            result: r,
        }));
        self.results = results;
        Ok(())
    }

    /// Keeps a round's answers' buffer for the next round.
    fn reuse(&mut self, answers: Vec<Answer>) {
        self.spare = answers;
    }

    /// Runs the queries `(drive, x)` of drives `first..` as one round.
    fn round(
        &mut self,
        first: u64,
        queries: &[(usize, f64)],
        tables: &[FrictionTable],
    ) -> Result<Vec<Answer>> {
        let mut lanes = std::mem::take(&mut self.lanes);
        let mut answers = std::mem::take(&mut self.spare);
        answers.clear();
        // In batches whose lanes stay in cache from their building to
        // their integration (a round's lane columns built whole would be
        // written out to memory and read back).
        for batch in queries.chunks(self.batch) {
            lanes.clear();
            for &(j, x) in batch {
                self.push_query(first, j, x, &mut lanes)?;
            }
            self.answer_into(first, &lanes, tables, &mut answers)?;
        }
        self.lanes = lanes;
        self.round_done();
        Ok(answers)
    }

    /// Counts a round, and says so on the bar.
    fn round_done(&mut self) {
        self.rounds += 1;
        if let Some(bar) = &self.bar {
            bar.set_message(self.progress());
        }
    }

    /// The rounds run and lanes integrated so far, as the bar says them.
    fn progress(&self) -> String {
        format!(
            "{} rounds, {} lanes integrated",
            self.rounds, self.integrated
        )
    }

    /// The first round's points of the bracket.
    fn points(&self) -> Vec<f64> {
        let (a, b) = (self.search.from, self.search.to);
        let k = FIRST_ROUND_POINTS;
        (0..k)
            .map(|p| {
                if p == k - 1 {
                    b
                } else {
                    a + (b - a) * p as f64 / (k - 1) as f64
                }
            })
            .collect()
    }
}

impl Backend for SearchBackend<'_> {
    fn name(&self) -> String {
        self.inner.name()
    }
    fn tolerance(&self) -> f64 {
        self.inner.tolerance()
    }
    fn show_on(&mut self, bar: &crate::progress::Bar) {
        bar.count_drives(self.progress());
        self.bar = Some(bar.clone());
    }
    fn chunk_lanes(&self) -> usize {
        // Whole groups: a share boundary needs its group's every drive.
        (CHUNK_DRIVES.div_ceil(self.per_group) * self.per_group) as usize
    }
    fn run_chunk(
        &mut self,
        first: u64,
        lanes: &ParamColumns,
        tables: &[FrictionTable],
        out: &mut Vec<LaneResult>,
    ) -> Result<()> {
        self.run_rows(first, &mut lanes.clone(), tables, out)
    }
    fn run_rows(
        &mut self,
        first: u64,
        lanes: &mut ParamColumns,
        tables: &[FrictionTable],
        out: &mut Vec<LaneResult>,
    ) -> Result<()> {
        let n = lanes.len();
        self.load_chunk(first, n)?;
        let rows = match self.search.at_least {
            Some(_) => share::search(self, first, n, tables)?,
            None => own::search(self, first, &(0..n).collect::<Vec<_>>(), tables)?,
        };
        out.clear();
        // The drives' lanes as given, for a row with no lane of its own.
        let given = std::mem::replace(lanes, ParamColumns::with_capacity(n));
        for (j, row) in rows.into_iter().enumerate() {
            let r = match row.lane {
                Some((x, r)) => {
                    self.push_query(first, j, x, lanes)?;
                    r
                }
                None => {
                    lanes.push(&given.params(j));
                    LaneResult::EMPTY
                }
            };
            out.push(LaneResult {
                search: Some(row.outcome),
                ..r
            });
        }
        Ok(())
    }
}
