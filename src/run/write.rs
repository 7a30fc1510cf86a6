//! A run written to its folder: the rows streamed to the results table,
//! counted for the summary and into `summary.csv` (not for a shard: a
//! shard's statistics would be of part of a group), and the traced lanes
//! run again with rows taken on the way into `traces.csv`.

use std::path::{Path, PathBuf};
use std::time::Instant;

pub use super::consumers::Written;
use super::consumers::{feed, Consumer, ReportScan};
use super::pipeline::{pipeline_timed, Sink};
use super::summary::Summary;
use crate::backend::Backend;
use crate::error::{Error, Result};
use crate::input::lanes::Source;
use crate::input::sweep::TraceSpec;
use crate::integrator::batch::settings_for;
use crate::integrator::trace::simulate_traced;
use crate::integrator::{LaneResult, Recheck, RowPath, Settings};
use crate::model::{FrictionTable, Lane};
use crate::output::batch::Builder;
use crate::output::names::{SUMMARY, TRACES};
use crate::output::table::{Format, LanesWriter};
use crate::output::traces::TracesCsv;
use crate::params::{LaneParams, ParamColumns};
use crate::progress::Show;
use crate::report::Scan;
use crate::stats::{Grouping, Stats};
use arrow_array::RecordBatch;

/// The results table as a sink: rows streamed to `lanes.csv` (or
/// `lanes.parquet`), counted for the summary line and into `summary.csv`
/// (not for a shard: a shard's statistics would be of part of a group);
/// traced lanes streamed to `traces.csv`.
struct TableSink {
    /// What each batch is fed to: the table's writer, the statistics,
    /// the report's aggregates (none of them when the batches are only
    /// kept).
    consumers: Vec<Box<dyn Consumer>>,
    /// The writer threads: each consumer a task, which it splits further.
    pool: rayon::ThreadPool,
    summary: Summary,
    /// Builds each chunk's batch, its buffers kept from chunk to chunk.
    builder: Builder,
    traces: Option<Tracer>,
    /// The batches, kept in lane order (Python's `tswm.run`); None:
    /// their buffers go back to the builder.
    kept: Option<Vec<RecordBatch>>,
}

/// Traced lanes: run again on the f64 path with rows taken on the way
/// (the same integration as the CPU path's, bit for bit, whatever the
/// backend), one lane at a time, so memory does not grow with them.
struct Tracer {
    spec: TraceSpec,
    /// The run's integration settings (a trace's lane is run as its row).
    settings: Settings,
    next: usize,
    /// `traces.csv` (none when no folder is written: the traced lanes'
    /// rows are still the f64 rows of their traces).
    out: Option<TracesCsv>,
    tables: Vec<FrictionTable>,
}

impl Tracer {
    /// Traces the traced lanes of the chunk of `params` from lane `first`;
    /// a traced lane's row that came from the GPU becomes the f64 row of
    /// the integration its trace is taken from (`cpu:traced`), so a row
    /// and its trace are one integration on every backend.
    fn chunk(
        &mut self,
        first: u64,
        params: &ParamColumns,
        results: &mut [LaneResult],
    ) -> Result<()> {
        let end = first + params.len() as u64;
        while let Some(&lane) = self.spec.lanes.get(self.next) {
            if lane >= end {
                break;
            }
            let l = Lane::new(&params.row((lane - first) as usize), &self.tables);
            let mut failed = None;
            let (out, tables) = (&mut self.out, &self.tables);
            // The settings the lane's f64 row comes from, refined or not.
            let set = settings_for(&l, tables, &self.settings);
            let r = simulate_traced(&l, tables, &set, self.spec.dt, &mut |row| {
                if let (None, Some(out)) = (&failed, out.as_mut()) {
                    failed = out.write(lane, row).err();
                }
            });
            if let Some(e) = failed {
                return Err(e);
            }
            let radii = params.row((lane - first) as usize).radii();
            let row = &mut results[(lane - first) as usize];
            if matches!(row.path, RowPath::Gpu | RowPath::Gpu64) {
                *row = LaneResult {
                    path: RowPath::Recomputed(Recheck::Traced),
                    ..r.with_shaft_speeds(&l, radii)
                };
            }
            self.next += 1;
        }
        Ok(())
    }
}

impl Sink for TableSink {
    type Output = Written;
    fn chunk(
        &mut self,
        first: u64,
        params: &mut ParamColumns,
        results: &[LaneResult],
    ) -> Result<()> {
        // Traced lanes first: a GPU row of one is replaced by its trace's.
        let mut traced_rows;
        let results = match self.traces.as_mut() {
            Some(t)
                if t.spec
                    .lanes
                    .iter()
                    .any(|&l| (first..first + params.len() as u64).contains(&l)) =>
            {
                traced_rows = results.to_vec();
                t.chunk(first, params, &mut traced_rows)?;
                &traced_rows[..]
            }
            _ => results,
        };
        self.summary.add_chunk(params, results);
        // The parameter columns move into the batch (no copy) and come
        // back when it is written.
        let batch = self.builder.build(first, params, results, &self.pool)?;
        // Each consumer a task of the pool, so none leaves a core idle
        // while another's serial part runs.
        let fed = feed(&mut self.consumers, first, &batch, &self.pool);
        match self.kept.as_mut() {
            Some(kept) => kept.push(batch),
            None => self.builder.recycle(batch, params),
        }
        fed
    }
    fn finish(self) -> Result<Self::Output> {
        let mut out = Written {
            lanes: None,
            stats: Vec::new(),
            traces: self.traces.and_then(|t| t.out),
            scan: None,
            summary: self.summary,
            batches: self.kept.unwrap_or_default(),
        };
        for c in self.consumers {
            c.finish(&mut out)?;
        }
        Ok(out)
    }
}

/// Where a run's table goes and which lanes it runs.
#[derive(Clone, Copy, Debug)]
pub struct Target<'a> {
    /// The output folder; None: no file is written, the batches kept.
    pub dir: Option<&'a Path>,
    /// The table's format.
    pub format: Format,
    /// Lanes `start..end` (a shard's), or every lane.
    pub range: Option<(u64, u64)>,
    /// Threads that format the table's rows (0: all cores).
    pub threads: usize,
    /// The run's integration settings (traced lanes are run with them).
    pub settings: Settings,
    /// Keep the table's batches (for a caller in the same process).
    pub keep: bool,
}

/// Runs the lanes of `source` that `target` names on `backend`, streaming
/// rows to a temporary file for the table (and the traced lanes' rows to
/// one for `traces.csv` beside it, and statistics to one for
/// `summary.csv` when every lane is run); the caller commits them (with
/// the run's other files) or drops them. Without a folder nothing is
/// written and the batches are kept. `show` shows the progress.
pub fn run(
    source: &Source,
    backend: &mut dyn Backend,
    target: Target<'_>,
    trace: Option<&TraceSpec>,
    scan: Option<Scan>,
    show: &Show,
) -> Result<Written> {
    let start = Instant::now();
    let dir = target.dir;
    let search = source.search().is_some();
    let (first, end) = target.range.unwrap_or((0, source.lane_count()));
    let traces = match trace {
        Some(spec) => {
            // A shard traces the traced lanes in its range.
            let lanes: Vec<u64> = spec
                .lanes
                .iter()
                .copied()
                .filter(|l| (first..end).contains(l))
                .collect();
            if lanes.is_empty() {
                None
            } else {
                Some(Tracer {
                    spec: TraceSpec { lanes, dt: spec.dt },
                    settings: target.settings,
                    next: 0,
                    out: dir
                        .map(|d| TracesCsv::create(&d.join(TRACES), target.range.is_some()))
                        .transpose()?,
                    tables: source.friction_tables().tables.clone(),
                })
            }
        }
        None => None,
    };
    let consumers = consumers(dir, &target, source, scan)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(target.threads)
        .thread_name(|i| format!("tswm-writer-{i}"))
        .build()
        .map_err(|e| Error::Internal(format!("writer threads: {e}")))?;
    let sink = TableSink {
        consumers,
        pool,
        summary: Summary {
            search_param: source.search().map(|s| s.param.name()),
            ..Summary::default()
        },
        builder: Builder::for_run(search),
        traces,
        kept: target.keep.then(Vec::new),
    };
    let table = dir.map_or_else(PathBuf::new, |d| d.join(target.format.file_name()));
    // On failure the sink's partial files are dropped, and so removed.
    let (mut written, busy) =
        pipeline_timed(source, (first, end), backend, show, sink).map_err(|e| match e {
            Error::Gpu(m) => Error::Gpu(format!("{m}; no {} was written", table.display())),
            e => e,
        })?;
    written.summary.seconds = start.elapsed().as_secs_f64();
    written.summary.busy = busy;
    Ok(written)
}

/// The consumers of a run's batches in `dir`: the results table, the
/// statistics (not for a shard: they would be of part of a group) and the
/// report's aggregates when `scan`; none without a folder.
fn consumers(
    dir: Option<&Path>,
    target: &Target<'_>,
    source: &Source,
    scan: Option<Scan>,
) -> Result<Vec<Box<dyn Consumer>>> {
    let mut consumers: Vec<Box<dyn Consumer>> = Vec::new();
    let Some(d) = dir else {
        return Ok(consumers);
    };
    // A shard's files are hashed as they are written: its manifest
    // records their SHA-256.
    let (hashed, search) = (target.range.is_some(), source.search().is_some());
    consumers.push(Box::new(LanesWriter::create(
        d,
        target.format,
        hashed,
        search,
    )?));
    if target.range.is_none() {
        consumers.push(Box::new(Stats::create(
            &d.join(SUMMARY),
            Grouping::of(source),
        )?));
    }
    if let Some(s) = scan {
        consumers.push(Box::new(ReportScan(s, d.join(target.format.file_name()))));
    }
    Ok(consumers)
}
