//! Runs a lane source through a backend, chunk by chunk, and hands each
//! chunk's results, in lane order, to a [`Sink`] on its own thread: the
//! results table for `tswm run`, the CPU comparison for `tswm check`.
//!
//! Three stages overlap: a producer thread generates and validates the
//! next chunk of lanes, the calling thread runs the backend on the current
//! one, and the sink's thread consumes the previous one. Chunk buffers
//! circulate between them, so after the first few chunks nothing is
//! allocated and memory stays bounded whatever the sweep's size.

use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

use crate::backend::Backend;
use crate::error::{Error, Result};
use crate::integrator::accuracy::settings_for;
use crate::integrator::trace::simulate_traced;
use crate::integrator::Settings;
use crate::integrator::{Contact, Hold, LaneResult, RowPath, Status};
use crate::lanes::Source;
use crate::lanes_file::{row_cells, Cell, Format, LanesWriter};
use crate::model::{FrictionTable, Lane};
use crate::outdir::names::{SUMMARY, TRACES};
use crate::outdir::AtomicFile;
use crate::output::TracesCsv;
use crate::params::{Num, Params};
use crate::stats::{Grouping, Stats};
use crate::sweep::TraceSpec;

/// What consumes each chunk's results, in lane order.
pub trait Sink: Send {
    /// What the sink gives back when every chunk is in.
    type Output: Send;
    /// Lanes `first..first + params.len()` with their results.
    fn chunk(&mut self, first: u64, params: &[Params], results: &[LaneResult]) -> Result<()>;
    /// Called after the last chunk.
    fn finish(self) -> Result<Self::Output>;
}

/// Counts for the end-of-run summary.
#[derive(Debug, Default, Clone)]
pub struct Summary {
    /// Lanes run.
    pub lanes: u64,
    /// Wall time, s.
    pub seconds: f64,
    /// Lanes by status.
    pub by_status: BTreeMap<Status, u64>,
    /// Lanes by final contact (finished lanes).
    pub by_contact: BTreeMap<Contact, u64>,
    /// Lanes by the path their row came from.
    pub by_path: BTreeMap<RowPath, u64>,
    /// Lanes whose motor is cut, by what became of the load.
    pub by_hold: BTreeMap<Hold, u64>,
    /// The largest t_end of a lane still coasting, and whether one had a
    /// t_max.
    pub coasting_t_end: f64,
    pub coasting_with_t_max: bool,
}

impl Summary {
    fn add(&mut self, p: &Params, r: &LaneResult) {
        self.lanes += 1;
        *self.by_status.entry(r.status).or_default() += 1;
        if r.status == Status::Ok {
            *self.by_contact.entry(r.contact_end).or_default() += 1;
        }
        if let Some(h) = r.hold {
            *self.by_hold.entry(h).or_default() += 1;
            if h == Hold::Coasting {
                self.coasting_t_end = self.coasting_t_end.max(p.get(Num::TEnd));
                self.coasting_with_t_max |= !p.get(Num::TMax).is_nan();
            }
        }
        *self.by_path.entry(r.path).or_default() += 1;
    }

    /// "; hold: held N, runs_away N" for runs whose motors are cut, and
    /// what to do when lanes are still coasting (not decided).
    fn hold_note(&self) -> String {
        if self.by_hold.is_empty() {
            return String::new();
        }
        let list: Vec<String> = self
            .by_hold
            .iter()
            .map(|(h, n)| format!("{} {n}", h.name()))
            .collect();
        let mut s = format!("; hold: {}", list.join(", "));
        if let Some(&n) = self.by_hold.get(&Hold::Coasting) {
            s.push_str(&format!(
                "; {n} lanes still coasting when their run ended: whether they hold is not decided ({})",
                if self.coasting_with_t_max {
                    "set t_max in [base], or raise it".to_string()
                } else {
                    format!(
                        "set t_max in [base] so they run on until held or running away, e.g. t_max = {}",
                        10.0 * self.coasting_t_end
                    )
                }
            ));
        }
        s
    }

    /// "; gpu rows: N checked, M recomputed in f64 (why n, ...)" for runs
    /// with GPU rows, and "; N lanes refined (...)" when the f64 path ran
    /// lanes again; empty otherwise.
    fn recompute_note(&self) -> String {
        let redone: Vec<String> = self
            .by_path
            .iter()
            .filter_map(|(p, n)| match p {
                RowPath::Recomputed(why) => Some(format!("{} {n}", why.name())),
                _ => None,
            })
            .collect();
        let count = |p: RowPath| self.by_path.get(&p).copied().unwrap_or(0);
        let refined = count(RowPath::Refined);
        let refined_note = if refined > 0 {
            format!("; {refined} lanes refined (run again at a tenth of the tolerance: their error estimate was over the bound)")
        } else {
            String::new()
        };
        let cpu = count(RowPath::Cpu) + refined;
        if cpu == self.lanes {
            return refined_note;
        }
        let n: u64 = self.lanes - cpu - self.by_path.get(&RowPath::Gpu).copied().unwrap_or(0);
        format!(
            "; gpu rows: {} trusted, {n} recomputed in f64{}{refined_note}",
            self.by_path.get(&RowPath::Gpu).copied().unwrap_or(0),
            if redone.is_empty() {
                String::new()
            } else {
                format!(" ({})", redone.join(", "))
            }
        )
    }

    /// The one-line summary.
    pub fn line(&self, backend: &str, out: &Path) -> String {
        let status: Vec<String> = self
            .by_status
            .iter()
            .map(|(s, n)| format!("{} {n}", s.name()))
            .collect();
        let contact: Vec<String> = self
            .by_contact
            .iter()
            .map(|(c, n)| format!("{} {n}", c.name()))
            .collect();
        format!(
            "tswm: {} lanes in {:.2} s ({:.0} lanes/s, {backend}); status: {}; contact_end: {}{}{}; wrote {}",
            self.lanes,
            self.seconds,
            self.lanes as f64 / self.seconds.max(1e-9),
            status.join(", "),
            if contact.is_empty() { "-".into() } else { contact.join(", ") },
            self.hold_note(),
            self.recompute_note(),
            out.display()
        )
    }
}

/// The results table as a sink: rows streamed to `lanes.csv` (or
/// `lanes.parquet`), counted for the summary line and into `summary.csv`
/// (not for a shard: a shard's statistics would be of part of a group);
/// traced lanes streamed to `traces.csv`.
struct TableSink {
    table: LanesWriter,
    /// Formats the table's rows in parallel.
    pool: rayon::ThreadPool,
    cells: Vec<Cell>,
    summary: Summary,
    stats: Option<Stats>,
    traces: Option<Tracer>,
}

/// Traced lanes: run again on the f64 path with rows taken on the way
/// (the same integration as the CPU path's, bit for bit, whatever the
/// backend), one lane at a time, so memory does not grow with them.
struct Tracer {
    spec: TraceSpec,
    /// The run's integration settings (a trace's lane is run as its row).
    settings: Settings,
    next: usize,
    out: TracesCsv,
    table: Option<FrictionTable>,
}

impl Tracer {
    fn chunk(&mut self, first: u64, params: &[Params]) -> Result<()> {
        let end = first + params.len() as u64;
        while let Some(&lane) = self.spec.lanes.get(self.next) {
            if lane >= end {
                break;
            }
            let l = Lane::new(&params[(lane - first) as usize], self.table.as_ref());
            let mut failed = None;
            let (out, table) = (&mut self.out, self.table.as_ref());
            // The settings the lane's f64 row comes from, refined or not.
            let set = settings_for(&l, table, &self.settings);
            simulate_traced(&l, table, &set, self.spec.dt, &mut |row| {
                if failed.is_none() {
                    failed = out.write(lane, row).err();
                }
            });
            if let Some(e) = failed {
                return Err(e);
            }
            self.next += 1;
        }
        Ok(())
    }
}

impl Sink for TableSink {
    type Output = Written;
    fn chunk(&mut self, first: u64, params: &[Params], results: &[LaneResult]) -> Result<()> {
        self.table
            .write_lanes(&self.pool, first, params, results, &mut self.cells)?;
        for (i, (p, r)) in params.iter().zip(results).enumerate() {
            if let Some(s) = self.stats.as_mut() {
                let lane = first + i as u64;
                row_cells(lane, p, r, &mut self.cells);
                s.add_row(lane, &self.cells)?;
            }
            self.summary.add(p, r);
        }
        if let Some(t) = self.traces.as_mut() {
            t.chunk(first, params)?;
        }
        Ok(())
    }
    fn finish(self) -> Result<Self::Output> {
        Ok(Written {
            lanes: self.table.into_file()?,
            stats: self.stats.map(Stats::finish).transpose()?,
            traces: self.traces.map(|t| t.out),
            summary: self.summary,
        })
    }
}

/// What a run wrote, not yet committed.
pub struct Written {
    /// `lanes.csv` or `lanes.parquet`.
    pub lanes: AtomicFile,
    /// `summary.csv` (not for a shard).
    pub stats: Option<AtomicFile>,
    /// `traces.csv`, when lanes were traced.
    pub traces: Option<TracesCsv>,
    /// Counts for the summary line.
    pub summary: Summary,
}

/// Where a run's table goes and which lanes it runs.
#[derive(Clone, Copy, Debug)]
pub struct Target<'a> {
    /// The output folder.
    pub dir: &'a Path,
    /// The table's format.
    pub format: Format,
    /// Lanes `start..end` (a shard's), or every lane.
    pub range: Option<(u64, u64)>,
    /// Threads that format the table's rows (0: all cores).
    pub threads: usize,
    /// The run's integration settings (traced lanes are run with them).
    pub settings: Settings,
}

/// Runs the lanes of `source` that `target` names on `backend`, streaming
/// rows to a temporary file for the table (and the traced lanes' rows to
/// one for `traces.csv` beside it, and statistics to one for
/// `summary.csv` when every lane is run); the caller commits them (with
/// the run's other files) or drops them. `progress` shows a bar on stderr
/// when it is a terminal.
pub fn run(
    source: &Source,
    backend: &mut dyn Backend,
    target: Target<'_>,
    trace: Option<&TraceSpec>,
    progress: bool,
) -> Result<Written> {
    let start = Instant::now();
    let dir = target.dir;
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
                    out: TracesCsv::create(&dir.join(TRACES), target.range.is_some())?,
                    table: source.friction_table().copied(),
                })
            }
        }
        None => None,
    };
    let stats = match target.range {
        None => Some(Stats::create(&dir.join(SUMMARY), Grouping::of(source))?),
        Some(_) => None,
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(target.threads)
        .thread_name(|i| format!("tswm-writer-{i}"))
        .build()
        .map_err(|e| Error::Internal(format!("writer threads: {e}")))?;
    let sink = TableSink {
        // A shard's files are hashed as they are written: its manifest
        // records their SHA-256.
        table: LanesWriter::create(dir, target.format, target.range.is_some())?,
        pool,
        cells: Vec::with_capacity(64),
        stats,
        summary: Summary::default(),
        traces,
    };
    let table = dir.join(target.format.file_name());
    // On failure the sink's partial files are dropped, and so removed.
    let mut written =
        pipeline_range(source, (first, end), backend, progress, sink).map_err(|e| match e {
            Error::Gpu(m) => Error::Gpu(format!("{m}; no {} was written", table.display())),
            e => e,
        })?;
    written.summary.seconds = start.elapsed().as_secs_f64();
    Ok(written)
}

fn progress_bar(show: bool, total: u64) -> indicatif::ProgressBar {
    let bar = if show {
        indicatif::ProgressBar::with_draw_target(
            Some(total),
            indicatif::ProgressDrawTarget::stderr(),
        )
    } else {
        indicatif::ProgressBar::hidden()
    };
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} lanes, {per_sec}, eta {eta}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar
}

/// A chunk on its way: its first lane, its lanes and their results.
type Batch = (u64, Vec<Params>, Vec<LaneResult>);

/// Runs every lane of `source` through `backend` into `sink`, chunk by
/// chunk, in lane order.
pub fn pipeline<S: Sink>(
    source: &Source,
    backend: &mut dyn Backend,
    progress: bool,
    sink: S,
) -> Result<S::Output> {
    pipeline_range(source, (0, source.lane_count()), backend, progress, sink)
}

/// Runs lanes `start..end` of `source` through `backend` into `sink`,
/// chunk by chunk, in lane order.
pub fn pipeline_range<S: Sink>(
    source: &Source,
    (start, end): (u64, u64),
    backend: &mut dyn Backend,
    progress: bool,
    mut sink: S,
) -> Result<S::Output> {
    let table = source.friction_table().copied();
    let bar = progress_bar(progress, end - start);
    let chunk = backend.chunk_lanes().max(1);
    let mut reader = source.reader_range(start, end)?;

    const IN_FLIGHT: usize = 1;
    let (to_backend, from_producer) = std::sync::mpsc::sync_channel::<Result<Batch>>(IN_FLIGHT);
    let (to_sink, from_backend) = std::sync::mpsc::sync_channel::<Batch>(IN_FLIGHT);
    let (recycle, recycled) = std::sync::mpsc::sync_channel::<Batch>(2 * IN_FLIGHT + 2);

    let outcome = std::thread::scope(|scope| -> Result<S::Output> {
        scope.spawn(move || {
            let mut first = start;
            loop {
                let (_, mut params, results) = recycled
                    .try_recv()
                    .unwrap_or_else(|_| (0, Vec::with_capacity(chunk), Vec::with_capacity(chunk)));
                params.clear();
                if let Err(e) = reader.fill(chunk, &mut params) {
                    let _ = to_backend.send(Err(e));
                    return;
                }
                let n = params.len() as u64;
                if n == 0 || to_backend.send(Ok((first, params, results))).is_err() {
                    return; // the end, or the run stopped
                }
                first += n;
            }
        });
        let consumer = scope.spawn(move || -> Result<S::Output> {
            for (first, params, results) in from_backend {
                sink.chunk(first, &params, &results)?;
                let _ = recycle.send((0, params, results));
            }
            sink.finish()
        });
        let mut failure = None;
        for batch in &from_producer {
            let (first, params, mut results) = match batch {
                Ok(b) => b,
                Err(e) => {
                    failure = Some(e);
                    break;
                }
            };
            if let Err(e) = backend.run_chunk(first, &params, table.as_ref(), &mut results) {
                failure = Some(e);
                break;
            }
            let n = params.len() as u64;
            if to_sink.send((first, params, results)).is_err() {
                break; // the sink failed; its error is reported below
            }
            bar.set_position(first + n - start);
        }
        // Stop the producer (it sees the closed channel) and the sink.
        drop(from_producer);
        drop(to_sink);
        let consumed = consumer
            .join()
            .map_err(|_| Error::Internal("the sink thread panicked".into()))?;
        match failure {
            Some(e) => Err(e),
            None => consumed,
        }
    });
    bar.finish_and_clear();
    outcome
}
