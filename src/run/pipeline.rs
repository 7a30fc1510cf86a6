//! Runs a lane source through a backend, chunk by chunk, and hands each
//! chunk's results, in lane order, to a [`Sink`] on its own thread: the
//! results table for `tswm run`, the CPU comparison for `tswm check`.
//!
//! Three stages overlap: a producer thread generates and validates the
//! next chunk of lanes, the calling thread runs the backend on the current
//! one, and the sink's thread consumes the previous one. Chunk buffers
//! circulate between them, so after the first few chunks nothing is
//! allocated and memory stays bounded whatever the sweep's size.

use crate::backend::Backend;
use crate::error::{Error, Result};
use crate::input::lanes::Source;
use crate::integrator::LaneResult;
use crate::params::ParamColumns;
use crate::progress::{Phase, Show};

/// What consumes each chunk's results, in lane order.
pub trait Sink: Send {
    /// What the sink gives back when every chunk is in.
    type Output: Send;
    /// Lanes `first..first + params.len()` with their results; `params`
    /// may be lent out meanwhile (to a batch of the results table) but
    /// holds the same lanes when the call returns.
    fn chunk(
        &mut self,
        first: u64,
        params: &mut ParamColumns,
        results: &[LaneResult],
    ) -> Result<()>;
    /// Called after the last chunk.
    fn finish(self) -> Result<Self::Output>;
}

/// A chunk on its way: its first lane, its lanes and their results.
type Batch = (u64, ParamColumns, Vec<LaneResult>);

/// Runs every lane of `source` through `backend` into `sink`, chunk by
/// chunk, in lane order.
pub fn pipeline<S: Sink>(
    source: &Source,
    backend: &mut dyn Backend,
    show: &Show,
    sink: S,
) -> Result<S::Output> {
    pipeline_range(source, (0, source.lane_count()), backend, show, sink)
}

/// Where a pipeline's time went, s: the backend integrating its chunks,
/// and the sink consuming them (writing, for a run). Each stage runs on
/// its own thread, so the larger sets the pace.
#[derive(Clone, Copy, Debug, Default)]
pub struct Busy {
    /// In the backend.
    pub integrating: f64,
    /// In the sink.
    pub sinking: f64,
}

/// Runs lanes `start..end` of `source` through `backend` into `sink`,
/// chunk by chunk, in lane order.
pub fn pipeline_range<S: Sink>(
    source: &Source,
    range: (u64, u64),
    backend: &mut dyn Backend,
    show: &Show,
    sink: S,
) -> Result<S::Output> {
    pipeline_timed(source, range, backend, show, sink).map(|o| o.0)
}

/// The producer: chunks of lanes from `reader` (lanes `first..`), in
/// buffers given back when free, until the end, an error or a closed
/// channel (the run stopped).
fn produce(
    reader: &mut crate::input::lanes::RunLanes<'_>,
    mut first: u64,
    chunk: usize,
    recycled: std::sync::mpsc::Receiver<Batch>,
    to_backend: std::sync::mpsc::SyncSender<Result<Batch>>,
) {
    loop {
        let (_, mut params, results) = recycled.try_recv().unwrap_or_else(|_| {
            (
                0,
                ParamColumns::with_capacity(chunk),
                Vec::with_capacity(chunk),
            )
        });
        params.clear();
        if let Err(e) = reader.fill(chunk, &mut params) {
            let _ = to_backend.send(Err(e));
            return;
        }
        let n = params.len() as u64;
        if n == 0 || to_backend.send(Ok((first, params, results))).is_err() {
            return;
        }
        first += n;
    }
}

/// The sink's thread: every chunk into `sink`, its buffers given back;
/// what the sink gives back, and the seconds it was busy.
fn consume<S: Sink>(
    mut sink: S,
    from_backend: std::sync::mpsc::Receiver<Batch>,
    recycle: std::sync::mpsc::SyncSender<Batch>,
) -> Result<(S::Output, f64)> {
    use std::time::Instant;
    let mut busy = 0.0;
    for (first, mut params, results) in from_backend {
        let t = Instant::now();
        sink.chunk(first, &mut params, &results)?;
        busy += t.elapsed().as_secs_f64();
        let _ = recycle.send((0, params, results));
    }
    let t = Instant::now();
    let out = sink.finish()?;
    Ok((out, busy + t.elapsed().as_secs_f64()))
}

/// [`pipeline_range`], with the time each stage was busy.
pub(crate) fn pipeline_timed<S: Sink>(
    source: &Source,
    (start, end): (u64, u64),
    backend: &mut dyn Backend,
    show: &Show,
    sink: S,
) -> Result<(S::Output, Busy)> {
    use std::time::Instant;
    let tables = source.friction_tables().tables.clone();
    let bar = show.bar(Phase::Running, true, end - start, "");
    backend.show_on(&bar);
    let chunk = backend.chunk_lanes().max(1);
    let mut reader = source.run_lanes(start, end)?;

    const IN_FLIGHT: usize = 1;
    let (to_backend, from_producer) = std::sync::mpsc::sync_channel::<Result<Batch>>(IN_FLIGHT);
    let (to_sink, from_backend) = std::sync::mpsc::sync_channel::<Batch>(IN_FLIGHT);
    let (recycle, recycled) = std::sync::mpsc::sync_channel::<Batch>(2 * IN_FLIGHT + 2);

    let mut busy = Busy::default();
    let outcome = std::thread::scope(|scope| -> Result<(S::Output, f64)> {
        scope.spawn(move || produce(&mut reader, start, chunk, recycled, to_backend));
        let consumer = scope.spawn(move || consume(sink, from_backend, recycle));
        let mut failure = None;
        for batch in &from_producer {
            let (first, mut params, mut results) =
                match batch.and_then(|b| show.check().map(|()| b)) {
                    Ok(b) => b,
                    Err(e) => {
                        failure = Some(e);
                        break;
                    }
                };
            let t = Instant::now();
            if let Err(e) = backend.run_rows(first, &mut params, &tables, &mut results) {
                failure = Some(e);
                break;
            }
            busy.integrating += t.elapsed().as_secs_f64();
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
    let (out, sinking) = outcome?;
    busy.sinking = sinking;
    Ok((out, busy))
}
