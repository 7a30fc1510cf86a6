//! The command line: flags parsed by clap, then validated into a [`Plan`].

use std::path::PathBuf;

use clap::{Parser, Subcommand};

use crate::backend::{Choice, Precision};
use crate::error::{Error, Result};
use crate::input::lanes::Source;
use crate::input::sweep::TraceSpec;
use crate::integrator::Settings;
use crate::output::table::Format;
use crate::params::Num;
use crate::progress::Show;

/// Simulate thousands to millions of worm-drive (TSWM) variants.
#[derive(Parser, Debug)]
#[command(name = "tswm", version, about)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Where the lanes come from.
#[derive(clap::Args, Debug, Clone)]
pub struct LanesArgs {
    /// Sweep file (TOML). With --lanes it may give only `[base]`, its friction tables, `[trace]` and `[report]`.
    pub sweep: Option<PathBuf>,
    /// Explicit lane table (CSV, one lane a row, the parameters' names as columns).
    #[arg(long, value_name = "FILE.csv")]
    pub lanes: Option<PathBuf>,
    /// CPU threads (default: all cores).
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Per-step error tolerance of the f64 path, relative to max(1, |y|):
    /// default 1e-8 (results within 1e-6); 1e-12 gives reference-grade
    /// results (the reference lanes within 1e-9; 7e-11 measured), at about
    /// 5 times the steps.
    #[arg(long, value_name = "TOL", allow_hyphen_values = true)]
    pub tol: Option<f64>,
    /// The GPU's arithmetic: f32 (rows within 5e-5, each checked, the
    /// untrusted ones recomputed in f64), f64 (the CPU path's bound, 1e-6;
    /// refused on an adapter without 64-bit floats), or auto (f64 where
    /// the adapter has it and a trial finds it no slower, else f32; f64
    /// when --tol is given).
    #[arg(long, value_enum, default_value_t = Precision::Auto)]
    pub precision: Precision,
}

/// What `tswm run` does with the lanes (Python's `tswm.run` fills the
/// same struct).
#[derive(clap::Args, Debug, Clone)]
pub struct RunFlags {
    /// Output folder.
    #[arg(long, value_name = "DIR", default_value = "out")]
    pub out: PathBuf,
    /// Backend.
    #[arg(long, value_enum, default_value_t = Choice::Auto)]
    pub backend: Choice,
    /// Lanes to trace into DIR/traces.csv (overrides the sweep's `[trace]`).
    #[arg(long, value_delimiter = ',', value_name = "L1,L2,...")]
    pub trace: Vec<u64>,
    /// Interval between trace rows, s.
    #[arg(long, value_name = "DT")]
    pub trace_dt: Option<f64>,
    /// Do not write DIR/report.html.
    #[arg(long)]
    pub no_report: bool,
    /// Run only shard K (0-based) of N: a contiguous range of lanes, for
    /// a cluster's job array; join the shards with `tswm merge`.
    #[arg(long, value_name = "K/N", allow_hyphen_values = true)]
    pub shard: Option<String>,
    /// Format of the results table: lanes.csv or lanes.parquet.
    #[arg(long, value_enum, default_value_t = Format::Csv)]
    pub format: Format,
    /// Say what the run would cost (time, and the size of its table, from
    /// a trial of its lanes) and stop: nothing is run or written.
    #[arg(long)]
    pub dry_run: bool,
}

/// Subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Run a sweep and write DIR/lanes.csv, summary.csv, sweep.resolved.toml,
    /// report.html (and traces.csv for traced lanes, sensitivity.csv for a
    /// sensitivity design).
    Run {
        /// The lanes: a sweep file or a lane table.
        #[command(flatten)]
        lanes: LanesArgs,
        /// How to run them and where to write.
        #[command(flatten)]
        run: RunFlags,
    },
    /// Join the shard folders of one sweep into OUT: the table exactly as
    /// one run writes it, traces, summary.csv and report.html.
    Merge {
        /// Shard folders (`tswm run --shard K/N --out DIR`), each shard once.
        #[arg(value_name = "DIR", required = true)]
        dirs: Vec<PathBuf>,
        /// Output folder.
        #[arg(long, value_name = "OUT")]
        out: PathBuf,
        /// Format of the merged table.
        #[arg(long, value_enum, default_value_t = Format::Csv)]
        format: Format,
        /// Do not write OUT/report.html.
        #[arg(long)]
        no_report: bool,
    },
    /// Write DIR/report.html from the files of an existing output folder.
    Report {
        /// Output folder of `tswm run`.
        #[arg(value_name = "DIR")]
        dir: PathBuf,
    },
    /// Run the same lanes on the CPU and the GPU and compare (exit 1 when a bound is missed).
    Check {
        /// The lanes: a sweep file or a lane table.
        #[command(flatten)]
        lanes: LanesArgs,
        /// Write every disagreeing lane (lane, reason) to this CSV file.
        #[arg(long, value_name = "FILE.csv")]
        disagreements: Option<PathBuf>,
    },
    /// List GPU adapters and their limits.
    Devices,
    /// Integrate a sweep's lanes on a backend and print lanes/s, writing
    /// nothing (integration, the f32 check and recomputation; no table).
    Bench {
        /// The lanes: a sweep file or a lane table.
        #[command(flatten)]
        lanes: LanesArgs,
        /// Backend.
        #[arg(long, value_enum, default_value_t = Choice::Auto)]
        backend: Choice,
    },
}

/// A validated run.
pub struct Plan {
    /// The lanes.
    pub source: Source,
    /// CPU threads (0: all).
    pub threads: usize,
    /// Integration settings of the CPU path.
    pub settings: Settings,
    /// The GPU's arithmetic.
    pub precision: Precision,
}

impl Plan {
    /// Opens the backend `choice` for a run of `lanes` of these lanes, at
    /// this plan's threads, settings and GPU precision
    /// ([`crate::backend::open`]).
    pub fn backend(&self, choice: Choice, lanes: u64) -> Result<Box<dyn crate::backend::Backend>> {
        crate::backend::open(choice, self.precision, lanes, self.threads, self.settings)
    }
}

/// Most rows the sampling interval of a run's traces may give (about
/// 1 GB of `traces.csv`); each event adds two rows beyond them, at most
/// 2 × `max_events` a lane.
pub(crate) const MAX_TRACE_ROWS: u64 = 10_000_000;

/// The traces a run writes: `--trace` and `--trace-dt` over the sweep
/// file's `[trace]` table; None when no lane is traced. A request for
/// more than [`MAX_TRACE_ROWS`] rows is refused with the smallest
/// interval that fits.
pub(crate) fn trace_plan(
    lanes: &[u64],
    dt: Option<f64>,
    source: &Source,
) -> Result<Option<TraceSpec>> {
    let spec = trace_spec(lanes, dt, source)?;
    if let Some(s) = &spec {
        check_trace_rows(s, source)?;
    }
    Ok(spec)
}

/// Rows a traced lane gets by default (`--trace` without `--trace-dt`):
/// its interval is the longest traced lane's time over this, rounded down
/// to 1, 2 or 5 times a power of ten.
pub(crate) const DEFAULT_TRACE_ROWS: f64 = 1000.0;

/// The default interval of a trace whose longest lane runs `horizon` s:
/// horizon / [`DEFAULT_TRACE_ROWS`] rounded down to 1, 2 or 5 × 10^k.
pub(crate) fn default_trace_dt(horizon: f64) -> f64 {
    let raw = horizon / DEFAULT_TRACE_ROWS;
    let p = 10f64.powf(raw.log10().floor());
    let m = [5.0, 2.0, 1.0]
        .into_iter()
        .find(|&m| m * p <= raw * (1.0 + 1e-12))
        .unwrap_or(1.0);
    m * p
}

/// Where the traced lanes stop at the latest: t_max, or t_end.
fn horizons(lanes: &[u64], source: &Source) -> Result<Vec<f64>> {
    Ok(source
        .lanes_at(lanes)?
        .iter()
        .map(|p| {
            let (te, tm) = (p.get(Num::TEnd), p.get(Num::TMax));
            if tm.is_nan() {
                te
            } else {
                te.max(tm)
            }
        })
        .collect())
}

/// The rows a trace of lanes running to `horizons` (s) gets every `dt`.
fn trace_rows(horizons: &[f64], dt: f64) -> f64 {
    horizons.iter().map(|h| (h / dt).floor() + 1.0).sum()
}

fn check_trace_rows(spec: &TraceSpec, source: &Source) -> Result<()> {
    let horizons = horizons(&spec.lanes, source)?;
    let max = MAX_TRACE_ROWS as f64;
    let rows = trace_rows(&horizons, spec.dt);
    if rows <= max {
        return Ok(());
    }
    // The smallest interval that fits, rounded up to two digits.
    let total: f64 = horizons.iter().sum();
    let raw = total / (max - horizons.len() as f64).max(1.0);
    let unit = 10f64.powf(raw.log10().floor() - 1.0);
    let mut dt = (raw / unit).ceil() * unit;
    while trace_rows(&horizons, dt) > max {
        dt += unit;
    }
    Err(Error::Usage(format!(
        "trace dt: {} s gives {rows:.3e} rows for {} traced lanes, over the limit of {} rows \
         (about 1 GB of traces.csv); allowed: a dt of at least {} s, or fewer traced lanes",
        spec.dt,
        spec.lanes.len(),
        MAX_TRACE_ROWS,
        crate::report::axis::number(dt, unit)
    )))
}

fn trace_spec(lanes: &[u64], dt: Option<f64>, source: &Source) -> Result<Option<TraceSpec>> {
    let from_file = source.trace().cloned();
    let (lanes, dt) = match (lanes.is_empty(), dt, from_file) {
        (true, None, file) => return Ok(file),
        (true, Some(dt), Some(file)) => (file.lanes, dt),
        (true, Some(_), None) => {
            return Err(Error::Usage(
                "--trace-dt: needs lanes to trace (--trace L1,L2,... or [trace] lanes)".into(),
            ))
        }
        (false, Some(dt), _) => (lanes.to_vec(), dt),
        (false, None, Some(file)) => (lanes.to_vec(), file.dt),
        (false, None, None) => {
            // No interval given: about a thousand rows a lane.
            let spec = TraceSpec::new(lanes.to_vec(), 1.0, source.lane_count())
                .map_err(|m| Error::Usage(format!("--trace: {m}")))?;
            let longest = horizons(&spec.lanes, source)?
                .into_iter()
                .fold(0.0, f64::max);
            (spec.lanes, default_trace_dt(longest))
        }
    };
    TraceSpec::new(lanes, dt, source.lane_count())
        .map(Some)
        .map_err(|m| Error::Usage(format!("--trace: {m}")))
}

/// The tightest `--tol`: a step's error estimate a few hundred times f64's
/// resolution, which the step control still reads.
pub(crate) const MIN_TOL: f64 = 1e-13;
/// The loosest `--tol`: past it the error estimate of a result (bound
/// 1e-6) would send most lanes to a second run.
pub(crate) const MAX_TOL: f64 = 1e-4;

/// Most CPU threads a run may ask for. Lanes are independent and
/// CPU-bound, so threads beyond the hardware's add no speed, only a stack
/// each; 1024 is above the hardware threads of any one machine this tool
/// runs on, and far below where thread creation itself fails.
pub const MAX_THREADS: usize = 1024;

impl LanesArgs {
    /// Validates the lane arguments into a plan (reads and checks every lane).
    pub fn plan(&self) -> Result<Plan> {
        self.plan_part(&|n, _| (0, n), &Show::default())
    }

    /// [`LanesArgs::plan`] for a run of part of a sweep's lanes (`part`
    /// gives a shard's range from the lane count): only those lanes are
    /// checked, shown by `show` (a bar on a terminal when they are many).
    pub fn plan_part(&self, part: &dyn Fn(u64, u64) -> (u64, u64), show: &Show) -> Result<Plan> {
        let (threads, settings) = self.settings()?;
        let source = Source::open_part(self.sweep.as_deref(), self.lanes.as_deref(), part, show)?;
        Ok(Plan {
            source,
            threads,
            settings,
            precision: self.asked_precision(),
        })
    }

    /// The GPU arithmetic these arguments ask for: `--precision`, but f64
    /// where it is `auto` and `--tol` is given. A tolerance is the f64
    /// path's (the f32 path keeps its own, 1e-6, and its rows are within
    /// 5e-5), and `--backend auto` picks the f32 path of a software
    /// adapter where a trial finds it faster: `--tol 1e-12` ran 150,000
    /// lanes in f32 there, 2.4e-6 from a CPU run, without a word.
    pub fn asked_precision(&self) -> Precision {
        match (self.tol, self.precision) {
            (Some(_), Precision::Auto) => Precision::F64,
            (_, p) => p,
        }
    }

    /// The threads (0: all cores) and integration settings these
    /// arguments ask for, checked.
    pub fn settings(&self) -> Result<(usize, Settings)> {
        match self.threads {
            Some(0) => return Err(Error::Usage("--threads must be >= 1".into())),
            Some(n) if n > MAX_THREADS => {
                let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
                return Err(Error::Usage(format!(
                    "--threads: {n} is too many; allowed: 1 to {MAX_THREADS} \
                     (this machine runs {cores} at once; more only cost memory)"
                )));
            }
            _ => {}
        }
        let mut settings = Settings::default();
        if let Some(tol) = self.tol {
            if !(MIN_TOL..=MAX_TOL).contains(&tol) {
                return Err(Error::Usage(format!(
                    "--tol: {tol:e} is not allowed; allowed: {MIN_TOL:e} to {MAX_TOL:e} (the f64 path's \
                     per-step tolerance; 1e-8 by default)"
                )));
            }
            settings.tol = tol;
        }
        Ok((self.threads.unwrap_or(0), settings))
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_default_trace_interval_is_a_round_thousandth_of_the_longest_lane() {
        use super::default_trace_dt as d;
        assert_eq!(d(2.0), 0.002);
        assert_eq!(d(5.0), 0.005);
        assert_eq!(d(3.0), 0.002);
        assert_eq!(d(1e-4), 1e-7);
        assert_eq!(d(7.0), 0.005);
        assert_eq!(d(10.0), 0.01);
    }
}
