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

use crate::backend::Backend;
use crate::columns;
use crate::error::{Error, Result};
use crate::input::lanes::{LaneReader, Source};
use crate::input::sampling::Uniforms;
use crate::input::sweep::search::{Search, FIRST_ROUND_POINTS};
use crate::input::sweep::Sweep;
use crate::integrator::{LaneResult, SearchOutcome};
use crate::model::FrictionTable;
use crate::params::{ParamColumns, Params, Spec, TableName};

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
pub struct SearchBackend<'a> {
    inner: Box<dyn Backend + 'a>,
    search: Search,
    drives: Drives<'a>,
    names: Vec<TableName>,
    /// The source's name, for errors.
    file: std::path::PathBuf,
    /// Drives a group (a share search's grid point; 1 otherwise).
    per_group: u64,
    /// The current chunk's drives' unresolved parameters (a table's).
    specs: Vec<Spec>,
    u: Uniforms,
}

/// One query's answer: whether the requirement is met, the lane's
/// parameters and its results.
pub(super) struct Answer {
    meets: bool,
    params: Params,
    result: LaneResult,
}

/// What a drive's row becomes: its outcome, and the lane it reports.
pub(super) struct Row {
    outcome: SearchOutcome,
    lane: Option<(Params, LaneResult)>,
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
        Ok(SearchBackend {
            inner,
            search,
            drives,
            names: source.friction_tables().names.clone(),
            file,
            per_group,
            specs: Vec::new(),
            u,
        })
    }

    /// Drive `j`'s (lane `first + j`'s) parameters with the searched one
    /// set to `x`, resolved into `out`.
    fn push_query(&mut self, first: u64, j: usize, x: f64, out: &mut ParamColumns) -> Result<()> {
        let at = Some((self.search.param, x));
        let mut spec = Spec::default();
        match &self.drives {
            Drives::Sweep(sweep) => {
                sweep.lane_spec_at(first + j as u64, at, &mut self.u, &mut spec)
            }
            Drives::Table(_) => {
                spec.clone_from(&self.specs[j]);
                spec.set(self.search.param, x);
            }
        }
        self.resolve(&spec, first + j as u64, x, out)
    }

    /// Grid point `point`'s nominal design with the searched parameter at
    /// `x`, resolved into `out` (a sweep's; a table has none).
    fn push_nominal(&self, point: u64, x: f64, out: &mut ParamColumns) -> Result<()> {
        let Drives::Sweep(sweep) = &self.drives else {
            return Err(Error::Internal("a lane table has no nominal design".into()));
        };
        let mut spec = Spec::default();
        sweep.nominal_spec_at(point, Some((self.search.param, x)), &mut spec);
        self.resolve(&spec, point * self.per_group, x, out)
    }

    fn resolve(&self, spec: &Spec, lane: u64, x: f64, out: &mut ParamColumns) -> Result<()> {
        spec.resolve_into(&self.names, out).map_err(|e| {
            Error::input(
                &self.file,
                Some(format!("lane {lane} at {} = {x}", self.search.param.name())),
                Some(e.param),
                format!("{} (a value the search reaches)", e.msg),
            )
        })
    }

    /// Integrates the round `lanes` and answers the requirement for each.
    fn answer(
        &mut self,
        first: u64,
        lanes: &ParamColumns,
        tables: &[FrictionTable],
    ) -> Result<Vec<Answer>> {
        let mut results = Vec::with_capacity(lanes.len());
        self.inner.run_chunk(first, lanes, tables, &mut results)?;
        let col = columns::result(self.search.require.column)
            .ok_or_else(|| Error::Internal("a requirement on no column".into()))?;
        Ok(results
            .into_iter()
            .enumerate()
            .map(|(i, r)| Answer {
                meets: r.status == crate::integrator::Status::Ok
                    && self.search.require.passes(&col.cell(0, &r)),
                params: lanes.params(i),
                result: r,
            })
            .collect())
    }

    /// Runs the queries `(drive, x)` of drives `first..` as one round.
    fn round(
        &mut self,
        first: u64,
        queries: &[(usize, f64)],
        tables: &[FrictionTable],
    ) -> Result<Vec<Answer>> {
        let mut lanes = ParamColumns::with_capacity(queries.len());
        for &(j, x) in queries {
            self.push_query(first, j, x, &mut lanes)?;
        }
        self.answer(first, &lanes, tables)
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
        if let Drives::Table(reader) = &mut self.drives {
            self.specs.clear();
            reader.fill_specs(n, &mut self.specs)?;
        }
        let rows = match self.search.at_least {
            Some(_) => share::search(self, first, n, tables)?,
            None => own::search(self, first, &(0..n).collect::<Vec<_>>(), tables)?,
        };
        out.clear();
        let keep = lanes.clone();
        lanes.clear();
        for (j, row) in rows.into_iter().enumerate() {
            let (p, r) = row
                .lane
                .unwrap_or_else(|| (keep.params(j), LaneResult::EMPTY));
            lanes.push(&p);
            out.push(LaneResult {
                search: Some(row.outcome),
                ..r
            });
        }
        Ok(())
    }
}
