//! What a run does with each chunk's batch. Every consumer of the batches
//! (the results table, the statistics of `summary.csv`, the report's
//! aggregates) is one [`Consumer`]; the run's sink holds them as a list
//! and feeds each the same batch, each a task of the writer threads
//! (which it may split further), and each puts what it made into the
//! run's [`Written`] at the end. A new output that reads the rows as a
//! run streams them is one more implementation and one more entry of the
//! list (`write.rs`, `run`).

use std::path::PathBuf;

use arrow_array::RecordBatch;

use super::summary::Summary;
use crate::error::Result;
use crate::output::batch::typed;
use crate::output::table::LanesWriter;
use crate::output::traces::TracesCsv;
use crate::output::AtomicFile;
use crate::report::Scan;
use crate::stats::Stats;

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

/// A consumer of a run's batches, in lane order.
pub(crate) trait Consumer: Send {
    /// Takes the batch of lanes `first..`; `pool` is the writer threads.
    fn batch(&mut self, first: u64, batch: &RecordBatch, pool: &rayon::ThreadPool) -> Result<()>;

    /// Puts what it wrote or gathered into `out`.
    fn finish(self: Box<Self>, out: &mut Written) -> Result<()>;
}

/// Feeds `batch` to every consumer, each a task on `pool`; the first
/// failure in the list's order, if any.
pub(crate) fn feed(
    consumers: &mut [Box<dyn Consumer>],
    first: u64,
    batch: &RecordBatch,
    pool: &rayon::ThreadPool,
) -> Result<()> {
    use rayon::prelude::*;
    let done: Vec<Result<()>> = pool.install(|| {
        consumers
            .par_iter_mut()
            .map(|c| c.batch(first, batch, pool))
            .collect()
    });
    done.into_iter().collect()
}

/// The results table.
impl Consumer for LanesWriter {
    fn batch(&mut self, _first: u64, b: &RecordBatch, pool: &rayon::ThreadPool) -> Result<()> {
        self.write_batch(pool, b)
    }

    fn finish(self: Box<Self>, out: &mut Written) -> Result<()> {
        out.lanes = Some(self.into_file()?);
        Ok(())
    }
}

/// `summary.csv` (and `sensitivity.csv` of a sensitivity design).
impl Consumer for Stats {
    fn batch(&mut self, first: u64, b: &RecordBatch, pool: &rayon::ThreadPool) -> Result<()> {
        self.add_batch(first, &typed(b)?, pool)
    }

    fn finish(self: Box<Self>, out: &mut Written) -> Result<()> {
        let (stats, sensitivity_seconds, boundaries) = self.finish_all()?;
        out.stats = stats;
        out.summary.sensitivity_seconds = sensitivity_seconds;
        out.summary.boundaries = boundaries;
        Ok(())
    }
}

/// The report's aggregates, and the table's path for their errors.
pub(crate) struct ReportScan(pub Scan, pub PathBuf);

impl Consumer for ReportScan {
    fn batch(&mut self, _first: u64, b: &RecordBatch, _pool: &rayon::ThreadPool) -> Result<()> {
        self.0.batch_of(&self.1, b)
    }

    fn finish(self: Box<Self>, out: &mut Written) -> Result<()> {
        out.scan = Some(self.0);
        Ok(())
    }
}
