//! Backends: what turns lane parameters into results (the f64 CPU path
//! in [`cpu`], the f32 GPU path in [`gpu`]), and which one a run gets
//! (`--backend auto|cpu|gpu`).

pub mod cpu;
pub mod gpu;

pub use cpu::CpuBackend;

use crate::error::Result;
use crate::input::testmodels::paper_like;
use crate::integrator::{LaneResult, Settings};
use crate::model::FrictionTable;
use crate::params::ParamColumns;
use gpu::{Gpu, GpuBackend};

/// Something that turns lane parameters into results.
pub trait Backend {
    /// Short name for the summary ("cpu (2 threads, avx2 x4)", "gpu: ADAPTER").
    fn name(&self) -> String;
    /// Per-step tolerance the lanes are integrated at (for provenance).
    fn tolerance(&self) -> f64;
    /// Lanes a chunk should hold for this backend.
    fn chunk_lanes(&self) -> usize;
    /// Lanes worth integrating at once when the caller builds them just
    /// before (a search's round): as many as keep the backend busy, and no
    /// more, so that they are still in cache when integrated. By default
    /// a chunk.
    fn batch_lanes(&self) -> usize {
        self.chunk_lanes()
    }
    /// Computes one chunk; `first` is the lane index of `lanes[0]`.
    fn run_chunk(
        &mut self,
        first: u64,
        lanes: &ParamColumns,
        tables: &[FrictionTable],
        out: &mut Vec<LaneResult>,
    ) -> Result<()>;
    /// Gives the run's progress bar to a backend that has more to say on
    /// it than the rows done (a search: its rounds and lanes). By default
    /// nothing.
    fn show_on(&mut self, _bar: &crate::progress::Bar) {}
    /// Computes the rows of one chunk, whose lanes it may change: a search
    /// ([`crate::run::search`]) sets each drive's searched parameter to
    /// where its row's results were taken. By default the chunk's lanes,
    /// unchanged.
    fn run_rows(
        &mut self,
        first: u64,
        lanes: &mut ParamColumns,
        tables: &[FrictionTable],
        out: &mut Vec<LaneResult>,
    ) -> Result<()> {
        self.run_chunk(first, lanes, tables, out)
    }
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
    let lanes: ParamColumns = paper_like(AUTO_TRIAL_LANES, 7)
        .iter()
        .map(|s| s.resolve(&[]).expect("paper-like lanes are valid"))
        .collect();
    let mut out = Vec::new();
    let mut rate = |b: &mut dyn Backend| -> Result<f64> {
        let t = std::time::Instant::now();
        b.run_chunk(0, &lanes, &[], &mut out)?;
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
    fn batch_lanes(&self) -> usize {
        self.inner.batch_lanes()
    }
    fn run_chunk(
        &mut self,
        first: u64,
        lanes: &ParamColumns,
        tables: &[FrictionTable],
        out: &mut Vec<LaneResult>,
    ) -> Result<()> {
        self.inner.run_chunk(first, lanes, tables, out)
    }
}
