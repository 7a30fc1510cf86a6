//! Runs a lane source through a backend, chunk by chunk, and streams the
//! rows to `lanes.csv` in lane order on a writer thread, so computing the
//! next chunk overlaps writing the last one and memory stays bounded by a
//! few chunks whatever the sweep's size.

use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::integrator::{simulate_batch, Contact, LaneResult, Settings, Status};
use crate::lanes::Source;
use crate::model::{FrictionTable, Lane};
use crate::output::LanesCsv;
use crate::params::Params;

/// Something that turns lane parameters into results.
pub trait Backend {
    /// Short name for the summary ("cpu", "gpu: <adapter>").
    fn name(&self) -> String;
    /// Lanes a chunk should hold for this backend.
    fn chunk_lanes(&self) -> usize;
    /// Computes one chunk; `first` is the lane index of `lanes[0]`.
    fn run_chunk(
        &mut self,
        first: u64,
        lanes: &[Params],
        table: Option<&FrictionTable>,
        out: &mut Vec<LaneResult>,
    ) -> Result<()>;
}

/// The f64 reference path: rayon over lanes, one `simulate` each.
pub struct CpuBackend {
    pool: rayon::ThreadPool,
    /// Integration settings.
    pub settings: Settings,
}

impl CpuBackend {
    /// A CPU backend on `threads` threads (0: all cores).
    pub fn new(threads: usize, settings: Settings) -> Result<CpuBackend> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| Error::Usage(format!("cannot start {threads} threads: {e}")))?;
        Ok(CpuBackend { pool, settings })
    }

    /// Threads in the pool.
    pub fn threads(&self) -> usize {
        self.pool.current_num_threads()
    }
}

/// Runs lanes on the CPU into `out` (cleared first): rayon over blocks of
/// lanes, each block interleaved on its thread (`simulate_batch`).
pub fn run_cpu_lanes(
    pool: &rayon::ThreadPool,
    settings: &Settings,
    lanes: &[Params],
    table: Option<&FrictionTable>,
    out: &mut Vec<LaneResult>,
) {
    const BLOCK: usize = 64;
    out.clear();
    out.resize(lanes.len(), PLACEHOLDER);
    pool.install(|| {
        lanes
            .par_chunks(BLOCK)
            .zip(out.par_chunks_mut(BLOCK))
            .for_each(|(p, o)| {
                let mut l = [Lane::new(&p[0], table); BLOCK];
                for (d, s) in l.iter_mut().zip(p) {
                    *d = Lane::new(s, table);
                }
                simulate_batch(&l[..p.len()], table, settings, o);
            })
    });
}

/// Filler overwritten by every lane's result.
const PLACEHOLDER: LaneResult = LaneResult {
    status: Status::NonFinite,
    switches: 0,
    t_first_switch: f64::NAN,
    reversals: 0,
    sticks: 0,
    contact_end: Contact::Stick,
    x1_end: f64::NAN,
    v1_end: f64::NAN,
    w_motor: f64::NAN,
    w_load: f64::NAN,
    w_friction: f64::NAN,
    eta_end: f64::NAN,
    steps: 0,
};

impl Backend for CpuBackend {
    fn name(&self) -> String {
        format!("cpu ({} threads)", self.threads())
    }
    fn chunk_lanes(&self) -> usize {
        16384
    }
    fn run_chunk(
        &mut self,
        _first: u64,
        lanes: &[Params],
        table: Option<&FrictionTable>,
        out: &mut Vec<LaneResult>,
    ) -> Result<()> {
        run_cpu_lanes(&self.pool, &self.settings, lanes, table, out);
        Ok(())
    }
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
}

impl Summary {
    fn add(&mut self, r: &LaneResult) {
        self.lanes += 1;
        *self.by_status.entry(r.status).or_default() += 1;
        if r.status == Status::Ok {
            *self.by_contact.entry(r.contact_end).or_default() += 1;
        }
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
            "tswm: {} lanes in {:.2} s ({:.0} lanes/s, {backend}); status: {}; contact_end: {}; wrote {}",
            self.lanes,
            self.seconds,
            self.lanes as f64 / self.seconds.max(1e-9),
            status.join(", "),
            if contact.is_empty() { "-".into() } else { contact.join(", ") },
            out.display()
        )
    }
}

/// Runs every lane of `source` on `backend`, writing `out_csv` (complete or
/// not at all). `progress` shows a bar on stderr when it is a terminal.
///
/// Three stages overlap: a producer thread generates and validates the
/// next chunk of lanes, this thread runs the backend on the current one,
/// and a writer thread streams the previous one to disk. Chunk buffers
/// circulate between them, so after the first few chunks nothing is
/// allocated and memory stays bounded whatever the sweep's size.
pub fn run(
    source: &Source,
    backend: &mut dyn Backend,
    out_csv: &Path,
    progress: bool,
) -> Result<Summary> {
    let start = Instant::now();
    let total = source.lane_count();
    let table = source.friction_table().copied();
    let bar = if progress {
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
    let chunk = backend.chunk_lanes().max(1);
    let mut reader = source.reader()?;
    let mut csv = LanesCsv::create(out_csv)?;

    type Batch = (u64, Vec<Params>, Vec<LaneResult>);
    const IN_FLIGHT: usize = 1;
    let (to_backend, from_producer) = std::sync::mpsc::sync_channel::<Result<Batch>>(IN_FLIGHT);
    let (to_writer, from_backend) = std::sync::mpsc::sync_channel::<Batch>(IN_FLIGHT);
    let (recycle, recycled) = std::sync::mpsc::sync_channel::<Batch>(2 * IN_FLIGHT + 2);

    let outcome = std::thread::scope(|scope| -> Result<Summary> {
        scope.spawn(move || {
            let mut first = 0u64;
            loop {
                let (_, mut params, results) = recycled
                    .try_recv()
                    .unwrap_or_else(|_| (0, Vec::with_capacity(chunk), Vec::with_capacity(chunk)));
                params.clear();
                if let Err(e) = reader.fill(chunk, &mut params) {
                    let _ = to_backend.send(Err(e));
                    return;
                }
                if params.is_empty() {
                    return;
                }
                let n = params.len() as u64;
                if to_backend.send(Ok((first, params, results))).is_err() {
                    return; // the run stopped
                }
                first += n;
            }
        });
        let writer = scope.spawn(move || -> Result<(LanesCsv, Summary)> {
            let mut summary = Summary::default();
            for (first, params, results) in from_backend {
                for (i, (p, r)) in params.iter().zip(&results).enumerate() {
                    csv.write(first + i as u64, p, r)?;
                    summary.add(r);
                }
                let _ = recycle.send((0, params, results));
            }
            Ok((csv, summary))
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
            if to_writer.send((first, params, results)).is_err() {
                break; // the writer failed; its error is reported below
            }
            bar.set_position(first + n);
        }
        // Stop the producer (it sees the closed channel) and the writer.
        drop(from_producer);
        drop(to_writer);
        let written = writer
            .join()
            .map_err(|_| Error::Internal("the writer thread panicked".into()))?;
        if let Some(e) = failure {
            return Err(e); // `written`'s partial file is dropped and removed
        }
        let (csv, summary) = written?;
        csv.commit()?;
        Ok(summary)
    });
    bar.finish_and_clear();
    let mut summary = outcome?;
    summary.seconds = start.elapsed().as_secs_f64();
    Ok(summary)
}
