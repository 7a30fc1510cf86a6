//! What a run will cost, from a short trial before it: its time and the
//! size of its results table. Said before every run of more than
//! [`ESTIMATE_FROM`] lanes, and by `tswm run --dry-run` (which then runs
//! nothing and writes nothing).
//!
//! The trial integrates up to [`TRIAL_MAX`] of the run's lanes on the
//! run's own backend (a sweep's lanes spread evenly over the run, so a
//! grid's far corners are in it; a lane table's first rows, read without
//! reading the rest), builds their rows and formats them as the table's
//! writer does. The run takes about the larger of the two times scaled
//! to its lanes (its pipeline overlaps integration and writing), and its
//! table about the trial's bytes a row times its rows; the other files
//! (`summary.csv`, the report, `sweep.resolved.toml`) are small beside it.

use crate::backend::Backend;
use crate::error::Result;
use crate::input::lanes::Source;
use crate::output::batch;
use crate::output::table::{rows_bytes, Format};
use crate::params::ParamColumns;

/// Runs of more lanes than this say their estimate before they start.
pub const ESTIMATE_FROM: u64 = 10_000_000;

/// Most lanes of a trial.
pub const TRIAL_MAX: u64 = 1 << 16;

/// Fewest lanes of a trial (all of a smaller run).
pub(crate) const TRIAL_MIN: u64 = 4096;

/// A run's estimated cost.
#[derive(Clone, Debug)]
pub struct Estimate {
    /// Lanes the run integrates.
    pub lanes: u64,
    /// Lanes of the trial.
    pub trial: u64,
    /// The trial's integration, s.
    pub integrate_s: f64,
    /// The trial's building and formatting of rows, s.
    pub write_s: f64,
    /// The trial's rows in the table's format, bytes.
    pub trial_bytes: u64,
    /// The table's format.
    pub format: Format,
    /// The backend, named.
    pub backend: String,
}

impl Estimate {
    /// The run's time, s: the larger of integration and writing, scaled.
    pub fn seconds(&self) -> f64 {
        self.integrate_s.max(self.write_s) * self.scale()
    }

    /// The results table's size, bytes.
    pub(crate) fn table_bytes(&self) -> f64 {
        self.trial_bytes as f64 * self.scale()
    }

    fn scale(&self) -> f64 {
        self.lanes as f64 / self.trial.max(1) as f64
    }

    /// The line said before the run (or by `--dry-run`).
    pub fn line(&self) -> String {
        format!(
            "tswm: estimate for {} lanes: about {} and {} of {} (from a trial of {} of them on \
             {}: {:.0} lanes/s integrated, {:.0} rows/s written; the other files are small)",
            self.lanes,
            duration(self.seconds()),
            size(self.table_bytes()),
            self.format.file_name(),
            self.trial,
            self.backend,
            self.trial as f64 / self.integrate_s.max(1e-9),
            self.trial as f64 / self.write_s.max(1e-9),
        )
    }
}

/// "40 s", "12 min", "3.1 h".
fn duration(s: f64) -> String {
    if s < 90.0 {
        format!("{s:.0} s")
    } else if s < 5400.0 {
        format!("{:.0} min", s / 60.0)
    } else {
        format!("{:.1} h", s / 3600.0)
    }
}

/// "850 MB", "1.7 GB".
fn size(bytes: f64) -> String {
    if bytes < 1e9 {
        format!("{:.0} MB", (bytes / 1e6).max(1.0))
    } else {
        format!("{:.1} GB", bytes / 1e9)
    }
}

/// Estimates the run of lanes `range` of `source` on `be`, writing its
/// table in `format` with `threads` threads (0: every core).
pub fn estimate(
    source: &Source,
    be: &mut dyn Backend,
    threads: usize,
    format: Format,
    range: (u64, u64),
) -> Result<Estimate> {
    let (start, end) = range;
    let n = end - start;
    let k = n.min((be.chunk_lanes() as u64).clamp(TRIAL_MIN, TRIAL_MAX));
    let idx: Vec<u64> = match source {
        // Spread over the run: lane start + i n / k.
        Source::Sweep { .. } => (0..k)
            .map(|i| start + (i as u128 * n as u128 / k.max(1) as u128) as u64)
            .collect(),
        // A table's first rows: reading further would read the table.
        Source::Table { .. } => (start..start + k).collect(),
    };
    let lanes: ParamColumns = source.lanes_at(&idx)?.into_iter().collect();
    let tables = source.friction_tables().tables.clone();
    let mut results = Vec::new();
    let t = std::time::Instant::now();
    be.run_chunk(start, &lanes, &tables, &mut results)?;
    let integrate_s = t.elapsed().as_secs_f64();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| crate::error::Error::Internal(format!("a thread pool: {e}")))?;
    let t = std::time::Instant::now();
    let b = batch::from_lanes(start, &lanes, &results, &pool)?;
    let trial_bytes = rows_bytes(format, &pool, &b)?;
    let write_s = t.elapsed().as_secs_f64();
    Ok(Estimate {
        lanes: n,
        trial: k,
        integrate_s,
        write_s,
        trial_bytes,
        format,
        backend: be.name(),
    })
}
