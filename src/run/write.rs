//! A run written to its folder: the rows streamed to the results table,
//! counted for the summary and into `summary.csv` (not for a shard: a
//! shard's statistics would be of part of a group), and the traced lanes
//! run again with rows taken on the way into `traces.csv`.

use std::path::{Path, PathBuf};
use std::time::Instant;

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
use crate::output::batch::{typed, Builder};
use crate::output::names::{SUMMARY, TRACES};
use crate::output::table::{Format, LanesWriter};
use crate::output::traces::TracesCsv;
use crate::output::AtomicFile;
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
    /// The table's writer (none when the batches are only kept).
    table: Option<LanesWriter>,
    /// Formats the table's rows in parallel.
    pool: rayon::ThreadPool,
    summary: Summary,
    /// Builds each chunk's batch, its buffers kept from chunk to chunk.
    builder: Builder,
    stats: Option<Stats>,
    traces: Option<Tracer>,
    /// The report's aggregates, and the table's path for its errors.
    scan: Option<(Scan, PathBuf)>,
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
            if row.path == RowPath::Gpu {
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
        // The table written while the counts are taken: each is a task
        // of the pool (which splits them further), so neither leaves a
        // core idle while the other's serial part runs.
        let TableSink {
            table,
            pool,
            stats,
            scan,
            ..
        } = self;
        let (written, counted) = pool.install(|| {
            rayon::join(
                || match table.as_mut() {
                    Some(t) => t.write_batch(pool, &batch),
                    None => Ok(()),
                },
                || -> Result<()> {
                    if let Some((s, path)) = scan.as_mut() {
                        s.batch_of(path, &batch)?;
                    }
                    if let Some(s) = stats.as_mut() {
                        s.add_batch(first, &typed(&batch)?, pool)?;
                    }
                    Ok(())
                },
            )
        });
        match self.kept.as_mut() {
            Some(kept) => kept.push(batch),
            None => self.builder.recycle(batch, params),
        }
        written.and(counted)
    }
    fn finish(self) -> Result<Self::Output> {
        let (stats, sensitivity_seconds, boundaries) = match self.stats {
            Some(s) => s.finish_all()?,
            None => (Vec::new(), None, Vec::new()),
        };
        Ok(Written {
            lanes: self.table.map(LanesWriter::into_file).transpose()?,
            stats,
            traces: self.traces.and_then(|t| t.out),
            scan: self.scan.map(|s| s.0),
            summary: Summary {
                sensitivity_seconds,
                boundaries,
                ..self.summary
            },
            batches: self.kept.unwrap_or_default(),
        })
    }
}

/// What a run wrote, not yet committed.
pub struct Written {
    /// `lanes.csv` or `lanes.parquet` (none without a folder).
    pub lanes: Option<AtomicFile>,
    /// `summary.csv` and, for a sensitivity design, `sensitivity.csv`
    /// (not for a shard).
    pub stats: Vec<AtomicFile>,
    /// `traces.csv`, when lanes were traced.
    pub traces: Option<TracesCsv>,
    /// Counts for the summary line.
    pub summary: Summary,
    /// The report's aggregates, when they were gathered on the way.
    pub scan: Option<Scan>,
    /// The table's batches, in lane order, when kept.
    pub batches: Vec<RecordBatch>,
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
    let stats = match (target.range, dir) {
        (None, Some(d)) => Some(Stats::create(&d.join(SUMMARY), Grouping::of(source))?),
        _ => None,
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(target.threads)
        .thread_name(|i| format!("tswm-writer-{i}"))
        .build()
        .map_err(|e| Error::Internal(format!("writer threads: {e}")))?;
    let sink = TableSink {
        // A shard's files are hashed as they are written: its manifest
        // records their SHA-256.
        table: dir
            .map(|d| LanesWriter::create(d, target.format, target.range.is_some(), search))
            .transpose()?,
        pool,
        stats,
        summary: Summary {
            search_param: source.search().map(|s| s.param.name()),
            ..Summary::default()
        },
        builder: Builder::for_run(search),
        traces,
        scan: dir.and_then(|d| scan.map(|s| (s, d.join(target.format.file_name())))),
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
