//! The command line: flags parsed by clap, then validated into a [`Plan`].

use std::path::PathBuf;

use clap::{Parser, Subcommand, ValueEnum};

use crate::error::{Error, Result};
use crate::gpu::{Gpu, GpuBackend};
use crate::integrator::Settings;
use crate::lanes::Source;
use crate::runner::{Backend, CpuBackend};

/// Simulate thousands to millions of worm-drive (TSWM) variants.
#[derive(Parser, Debug)]
#[command(name = "tswm", version, about)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Which backend integrates the lanes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum BackendChoice {
    /// A hardware GPU if there is one, else the faster of CPU and software GPU.
    Auto,
    /// The f64 CPU path.
    Cpu,
    /// The f32 WGSL path on the best adapter.
    Gpu,
}

/// Where the lanes come from.
#[derive(clap::Args, Debug, Clone)]
pub struct LanesArgs {
    /// Sweep file (TOML). With --lanes it may give only [base] and [friction_table].
    pub sweep: Option<PathBuf>,
    /// Explicit lane table (CSV, one lane a row, MODEL.md parameter names as columns).
    #[arg(long, value_name = "FILE.csv")]
    pub lanes: Option<PathBuf>,
    /// CPU threads (default: all cores).
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
}

/// Subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Run a sweep and write DIR/lanes.csv and DIR/sweep.resolved.toml.
    Run {
        #[command(flatten)]
        lanes: LanesArgs,
        /// Output folder.
        #[arg(long, value_name = "DIR", default_value = "out")]
        out: PathBuf,
        /// Backend.
        #[arg(long, value_enum, default_value_t = BackendChoice::Auto)]
        backend: BackendChoice,
    },
    /// Run the same lanes on the CPU and the GPU and compare (exit 1 when a bound is missed).
    Check {
        #[command(flatten)]
        lanes: LanesArgs,
    },
    /// List GPU adapters and their limits.
    Devices,
}

/// A validated run.
pub struct Plan {
    /// The lanes.
    pub source: Source,
    /// CPU threads (0: all).
    pub threads: usize,
    /// Integration settings of the CPU path.
    pub settings: Settings,
}

impl LanesArgs {
    /// Validates the lane arguments into a plan (reads and checks every lane).
    pub fn plan(&self) -> Result<Plan> {
        let source =
            match (&self.sweep, &self.lanes) {
                (None, None) => return Err(Error::Usage(
                    "name a sweep file (tswm run SWEEP.toml) or a lane table (--lanes FILE.csv)"
                        .into(),
                )),
                (Some(s), None) => {
                    let src = Source::sweep(s)?;
                    src.validate()?;
                    src
                }
                (s, Some(l)) => Source::table(l, s.as_deref())?,
            };
        if self.threads == Some(0) {
            return Err(Error::Usage("--threads must be >= 1".into()));
        }
        Ok(Plan {
            source,
            threads: self.threads.unwrap_or(0),
            settings: Settings::default(),
        })
    }
}

/// Below this many lanes `auto` runs on the CPU without a trial: opening a
/// software adapter and compiling its pipeline costs more than it can save.
pub const AUTO_TRIAL_MIN_LANES: u64 = 20_000;

/// Lanes of the `auto` trial.
const AUTO_TRIAL_LANES: usize = 4096;

/// Opens the backend a run asked for.
///
/// `auto`: a hardware GPU when there is one; else, for sweeps of at least
/// [`AUTO_TRIAL_MIN_LANES`] lanes with a software adapter present, the
/// faster of the CPU path and that adapter on a trial of 4096 paper-like
/// lanes run on both; else the CPU path.
pub fn open_backend(choice: BackendChoice, plan: &Plan) -> Result<Box<dyn Backend>> {
    let cpu = || -> Result<Box<dyn Backend>> {
        Ok(Box::new(CpuBackend::new(plan.threads, plan.settings)?))
    };
    match choice {
        BackendChoice::Cpu => cpu(),
        BackendChoice::Gpu => Ok(Box::new(GpuBackend::new(Gpu::new(false)?, plan.settings))),
        BackendChoice::Auto => {
            if let Ok(gpu) = Gpu::new(true) {
                return Ok(Box::new(GpuBackend::new(gpu, plan.settings)));
            }
            if plan.source.lane_count() < AUTO_TRIAL_MIN_LANES {
                return cpu();
            }
            let Ok(soft) = Gpu::new(false) else {
                return cpu();
            };
            let mut c = CpuBackend::new(plan.threads, plan.settings)?;
            let mut g = GpuBackend::new(soft, plan.settings);
            let trial: Vec<_> = crate::testmodels::paper_like(AUTO_TRIAL_LANES, 7)
                .iter()
                .map(|s| s.resolve(false).expect("paper-like lanes are valid"))
                .collect();
            let mut out = Vec::new();
            let rate = |b: &mut dyn Backend, out: &mut Vec<_>| -> Result<f64> {
                let t = std::time::Instant::now();
                b.run_chunk(0, &trial, None, out)?;
                Ok(trial.len() as f64 / t.elapsed().as_secs_f64())
            };
            let rc = rate(&mut c, &mut out)?;
            let rg = match rate(&mut g, &mut out) {
                Ok(r) => r,
                Err(_) => return Ok(Box::new(c)),
            };
            Ok(if rg > rc {
                Box::new(Auto {
                    inner: Box::new(g),
                    why: format!("auto: {rg:.0} vs cpu {rc:.0} lanes/s in a trial"),
                })
            } else {
                Box::new(Auto {
                    inner: Box::new(c),
                    why: format!("auto: {rc:.0} vs software gpu {rg:.0} lanes/s in a trial"),
                })
            })
        }
    }
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
    fn chunk_lanes(&self) -> usize {
        self.inner.chunk_lanes()
    }
    fn run_chunk(
        &mut self,
        first: u64,
        lanes: &[crate::params::Params],
        table: Option<&crate::model::FrictionTable>,
        out: &mut Vec<crate::integrator::LaneResult>,
    ) -> Result<()> {
        self.inner.run_chunk(first, lanes, table, out)
    }
}
