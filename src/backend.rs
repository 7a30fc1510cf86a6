//! Backends: what turns lane parameters into results (the f64 CPU path
//! here, the f32 GPU path in [`crate::gpu`]), and which one a run gets
//! (`--backend auto|cpu|gpu`).

use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::gpu::{Gpu, GpuBackend};
use crate::integrator::{simulate_batch, LaneResult, Settings};
use crate::model::{FrictionTable, Lane};
use crate::params::{Num, Params, Spec};
use crate::sampling::Uniforms;

/// Something that turns lane parameters into results.
pub trait Backend {
    /// Short name for the summary ("cpu (2 threads)", "gpu: <adapter>").
    fn name(&self) -> String;
    /// Per-step tolerance the lanes are integrated at (for provenance).
    fn tolerance(&self) -> f64;
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

/// Which backend integrates the lanes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Choice {
    /// A hardware GPU if there is one, else the faster of CPU and software GPU.
    Auto,
    /// The f64 CPU path.
    Cpu,
    /// The f32 WGSL path on the best adapter.
    Gpu,
}

/// The f64 reference path: rayon over blocks of lanes, each block
/// interleaved on its thread.
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
pub(crate) const PLACEHOLDER: LaneResult = LaneResult::EMPTY;

impl Backend for CpuBackend {
    fn name(&self) -> String {
        format!("cpu ({} threads)", self.threads())
    }
    fn tolerance(&self) -> f64 {
        self.settings.tol
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

/// Paper-like lanes: the paper's design (Kloss motor, paper friction,
/// start at rest, t_end 2 s) with the load spread uniformly over ±6 kN, so
/// lanes cover direct and inverse flow, switches and stalls. The `auto`
/// trial runs them; the throughput benchmarks too.
pub fn paper_like(n: usize, seed: u64) -> Vec<Spec> {
    let mut u = Uniforms::new(seed);
    (0..n)
        .map(|i| {
            u.seek(i as u64, 1);
            let mut s = Spec::default();
            s.set(Num::F2, -6000.0 + 12000.0 * u.next());
            s
        })
        .collect()
}

/// Below this many lanes `auto` runs on the CPU without a trial: opening a
/// software adapter and compiling its pipeline costs more than it can save.
pub const AUTO_TRIAL_MIN_LANES: u64 = 20_000;

/// Lanes of the `auto` trial.
const AUTO_TRIAL_LANES: usize = 4096;

/// Opens the backend a run asked for, for a run of `lanes` lanes.
///
/// `auto`: a hardware GPU when there is one; else, for runs of at least
/// [`AUTO_TRIAL_MIN_LANES`] lanes with a software adapter present, the
/// faster of the CPU path and that adapter on a trial of 4096 paper-like
/// lanes run on both; else the CPU path.
pub fn open(
    choice: Choice,
    lanes: u64,
    threads: usize,
    settings: Settings,
) -> Result<Box<dyn Backend>> {
    let cpu = || -> Result<Box<dyn Backend>> { Ok(Box::new(CpuBackend::new(threads, settings)?)) };
    match choice {
        Choice::Cpu => cpu(),
        Choice::Gpu => {
            let c = CpuBackend::new(threads, settings)?;
            Ok(Box::new(GpuBackend::with_cpu(
                Gpu::new(false)?,
                settings,
                c,
            )))
        }
        Choice::Auto => {
            if let Ok(gpu) = Gpu::new(true) {
                let c = CpuBackend::new(threads, settings)?;
                return Ok(Box::new(GpuBackend::with_cpu(gpu, settings, c)));
            }
            if lanes < AUTO_TRIAL_MIN_LANES {
                return cpu();
            }
            let Ok(soft) = Gpu::new(false) else {
                return cpu();
            };
            let c = CpuBackend::new(threads, settings)?;
            let recompute = CpuBackend::new(threads, settings)?;
            let g = GpuBackend::with_cpu(soft, settings, recompute);
            trial(Box::new(c), Box::new(g))
        }
    }
}

/// Runs the trial lanes on both and keeps the faster, named with the
/// trial's figures.
fn trial(mut cpu: Box<dyn Backend>, mut soft: Box<dyn Backend>) -> Result<Box<dyn Backend>> {
    let lanes: Vec<_> = paper_like(AUTO_TRIAL_LANES, 7)
        .iter()
        .map(|s| s.resolve(false).expect("paper-like lanes are valid"))
        .collect();
    let mut out = Vec::new();
    let mut rate = |b: &mut dyn Backend| -> Result<f64> {
        let t = std::time::Instant::now();
        b.run_chunk(0, &lanes, None, &mut out)?;
        Ok(lanes.len() as f64 / t.elapsed().as_secs_f64())
    };
    let rc = rate(cpu.as_mut())?;
    let Ok(rg) = rate(soft.as_mut()) else {
        return Ok(cpu);
    };
    Ok(Box::new(if rg > rc {
        Auto {
            inner: soft,
            why: format!("auto: {rg:.0} vs cpu {rc:.0} lanes/s in a trial"),
        }
    } else {
        Auto {
            inner: cpu,
            why: format!("auto: {rc:.0} vs software gpu {rg:.0} lanes/s in a trial"),
        }
    }))
}

/// A backend chosen by the `auto` trial, named with the trial's figures.
struct Auto {
    inner: Box<dyn Backend>,
    why: String,
}

impl Backend for Auto {
    fn name(&self) -> String {
        format!("{} [{}]", self.inner.name(), self.why)
    }
    fn tolerance(&self) -> f64 {
        self.inner.tolerance()
    }
    fn chunk_lanes(&self) -> usize {
        self.inner.chunk_lanes()
    }
    fn run_chunk(
        &mut self,
        first: u64,
        lanes: &[Params],
        table: Option<&FrictionTable>,
        out: &mut Vec<LaneResult>,
    ) -> Result<()> {
        self.inner.run_chunk(first, lanes, table, out)
    }
}
