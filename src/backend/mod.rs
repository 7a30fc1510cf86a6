//! Backends: what turns lane parameters into results (the f64 CPU path
//! in [`cpu`], the GPU path in f32 or f64 in [`gpu`]), and which one a run
//! gets (`--backend auto|cpu|gpu`, `--precision auto|f32|f64`).

pub mod cpu;
pub mod gpu;

pub use cpu::CpuBackend;

use crate::error::Result;
use crate::input::testmodels::paper_like;
use crate::integrator::{LaneResult, Settings};
use crate::model::FrictionTable;
use crate::params::ParamColumns;
use gpu::{Gpu, GpuBackend, ShaderReal};

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

/// The GPU's arithmetic (`--precision`; the CPU path is f64 always).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Precision {
    /// f64 where the adapter has 64-bit floats and a trial finds it no
    /// slower per row than f32 with its recomputed rows; else f32.
    #[default]
    Auto,
    /// f32: every row checked, the untrusted ones recomputed on the f64
    /// CPU path; rows within 5e-5.
    F32,
    /// f64: the CPU path's algorithm and bound (1e-6) on the device;
    /// refused on an adapter without 64-bit floats.
    F64,
}

/// Below this many lanes `auto` runs on the CPU without a trial: opening a
/// software adapter and compiling its pipeline costs more than it can save.
pub const AUTO_TRIAL_MIN_LANES: u64 = 20_000;

/// Lanes of the `auto` trial.
const AUTO_TRIAL_LANES: usize = 4096;

/// Opens the backend a run asked for, for a run of `lanes` lanes.
///
/// `auto`: a hardware GPU when there is one; else, for runs of at least
/// [`AUTO_TRIAL_MIN_LANES`] lanes with a software adapter present and a
/// precision other than f64, the faster of the CPU path and that adapter
/// on a trial of 4096 paper-like lanes run on both; else the CPU path.
/// The GPU computes in `precision` ([`open_gpu`]); the CPU path is f64,
/// and refuses `f32`.
pub fn open(
    choice: Choice,
    precision: Precision,
    lanes: u64,
    threads: usize,
    settings: Settings,
) -> Result<Box<dyn Backend>> {
    let cpu = || -> Result<Box<dyn Backend>> { Ok(Box::new(CpuBackend::new(threads, settings)?)) };
    match choice {
        Choice::Cpu if precision == Precision::F32 => Err(crate::error::Error::Usage(
            "--precision f32 is the GPU's f32 path; --backend cpu computes in f64 \
             (use --precision f64 or auto, or --backend gpu)"
                .into(),
        )),
        Choice::Cpu => cpu(),
        Choice::Gpu => open_gpu(false, precision, lanes, threads, settings),
        Choice::Auto => {
            if let Ok(b) = open_gpu(true, precision, lanes, threads, settings) {
                return Ok(b);
            }
            // A software adapter's f64 takes ten times its f32's time a
            // lane (`auto_trial`): 935 lanes/s against the CPU path's
            // 44,475 on a trial at --tol 1e-12. No trial for it.
            if lanes < AUTO_TRIAL_MIN_LANES || precision == Precision::F64 {
                return cpu();
            }
            let Ok(soft) = open_gpu(false, precision, lanes, threads, settings) else {
                return cpu();
            };
            trial([cpu()?, soft], ["cpu", "software gpu"])
        }
    }
}

/// Opens the best adapter (hardware only, with `hardware_only`) in
/// `precision`: `f64` is refused on an adapter without 64-bit floats;
/// `auto` takes the real type [`auto_trial`] names, or f64 unless f32 (its
/// recomputed rows included) is faster on the trial lanes.
pub fn open_gpu(
    hardware_only: bool,
    precision: Precision,
    lanes: u64,
    threads: usize,
    settings: Settings,
) -> Result<Box<dyn Backend>> {
    let on = |gpu: Gpu| -> Result<Box<dyn Backend>> {
        let c = CpuBackend::new(threads, settings)?;
        Ok(Box::new(GpuBackend::with_cpu(gpu, settings, c)))
    };
    match precision {
        Precision::F32 => on(Gpu::open(hardware_only, ShaderReal::F32)?),
        Precision::F64 => on(Gpu::open(hardware_only, ShaderReal::F64)?),
        Precision::Auto => {
            let g32 = Gpu::open(hardware_only, ShaderReal::F32)?;
            if !auto_trial(g32.has_f64(), gpu::is_hardware(&g32.info), lanes) {
                return on(g32);
            }
            let Ok(g64) = Gpu::open(hardware_only, ShaderReal::F64) else {
                return on(g32);
            };
            trial([on(g64)?, on(g32)?], ["gpu f64", "gpu f32"])
        }
    }
}

/// Whether `--precision auto` tries f64 against f32 on an adapter: only
/// where it has 64-bit floats (`has_f64`), is hardware (a software
/// adapter runs f64 at half its vector width and the f64 functions from
/// arithmetic: lavapipe took 10 times f32's time a lane, docs/gpu.md) and
/// the run has [`AUTO_TRIAL_MIN_LANES`] lanes or more. Otherwise f32.
pub fn auto_trial(has_f64: bool, hardware: bool, lanes: u64) -> bool {
    has_f64 && hardware && lanes >= AUTO_TRIAL_MIN_LANES
}

/// Runs the trial lanes on both backends and keeps the faster (the first
/// when they tie), named with the trial's figures; `words` name them.
fn trial(backends: [Box<dyn Backend>; 2], words: [&str; 2]) -> Result<Box<dyn Backend>> {
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
    let [mut first, mut second] = backends;
    let r1 = rate(first.as_mut())?;
    let Ok(r2) = rate(second.as_mut()) else {
        return Ok(first);
    };
    let (inner, rw, rl, loser) = if r2 > r1 {
        (second, r2, r1, words[0])
    } else {
        (first, r1, r2, words[1])
    };
    Ok(Box::new(Auto {
        inner,
        why: format!("auto: {rw:.0} vs {loser} {rl:.0} lanes/s in a trial"),
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

#[cfg(test)]
mod tests {
    /// A tolerance is the f64 path's: given one, `--precision auto` means
    /// f64, and an explicit precision stays as asked.
    #[test]
    fn a_tolerance_asks_for_f64() {
        use crate::cli::LanesArgs;
        let args = |tol, precision| LanesArgs {
            sweep: None,
            lanes: None,
            threads: None,
            tol,
            precision,
        };
        assert_eq!(
            args(None, Precision::Auto).asked_precision(),
            Precision::Auto
        );
        assert_eq!(
            args(Some(1e-12), Precision::Auto).asked_precision(),
            Precision::F64
        );
        assert_eq!(
            args(Some(1e-6), Precision::F32).asked_precision(),
            Precision::F32
        );
        assert_eq!(args(None, Precision::F32).asked_precision(), Precision::F32);
        assert_eq!(
            args(Some(1e-8), Precision::F64).asked_precision(),
            Precision::F64
        );
    }

    /// In f64, `--backend auto` runs no trial on a software adapter (its
    /// f64 is ten times slower than its f32): the CPU path, named plainly,
    /// however many lanes. (Without a software adapter, the CPU too.)
    #[test]
    fn auto_in_f64_takes_the_cpu_without_a_trial() {
        let b = open(
            Choice::Auto,
            Precision::F64,
            1_000_000,
            1,
            Default::default(),
        )
        .unwrap();
        if crate::backend::gpu::Gpu::open(true, crate::backend::gpu::ShaderReal::F64).is_ok() {
            eprintln!("skipped: a hardware adapter with f64 takes the run");
            return;
        }
        assert!(
            b.name().starts_with("cpu") && !b.name().contains("auto"),
            "{}",
            b.name()
        );
    }

    use super::*;

    /// `--precision auto` tries f64 only on hardware with 64-bit floats and
    /// a run of at least the trial threshold; everywhere else it is f32.
    #[test]
    fn auto_precision_falls_back_to_f32() {
        let n = AUTO_TRIAL_MIN_LANES;
        assert!(auto_trial(true, true, n));
        assert!(!auto_trial(false, true, n), "no f64 on the adapter");
        assert!(!auto_trial(true, false, n), "a software adapter");
        assert!(!auto_trial(true, true, n - 1), "a small run");
    }
}
