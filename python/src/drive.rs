//! Running the engine from Python's thread: the work runs on a thread of
//! its own while the caller's thread, the interpreter released (so other
//! Python threads run), wakes a few times a second to pass Ctrl-C on (the
//! work stops at its next block or chunk, nothing committed) and to hand
//! the progress to a callback (the Python package's progress bar).

use std::sync::mpsc;
use std::time::Duration;

use pyo3::prelude::*;

use tswm::progress::{Phase, Show, Watch};

use crate::failure;

/// How often the caller's thread wakes while the work runs.
const TICK: Duration = Duration::from_millis(100);

/// Runs `work` with a [`Show`] that watches it; `progress(phase, done,
/// total)` is called every [`TICK`] (phase "checking" or "running").
/// A KeyboardInterrupt (or an error of the callback) stops the work and
/// is raised once it has stopped.
pub fn drive<T: Send + 'static>(
    py: Python<'_>,
    progress: Option<Bound<'_, PyAny>>,
    work: impl FnOnce(Show) -> tswm::error::Result<T> + Send + 'static,
) -> PyResult<T> {
    let watch = Watch::new();
    let show = Show {
        terminal: false,
        watch: Some(watch.clone()),
    };
    let (tx, rx) = mpsc::channel();
    // Waited on with the interpreter released, from this thread only.
    let rx = std::sync::Mutex::new(rx);
    let worker = std::thread::Builder::new()
        .name("tswm-run".into())
        .spawn(move || {
            let r = work(show);
            let _ = tx.send(());
            r
        })
        .map_err(|e| failure(tswm::error::Error::Internal(format!("a thread: {e}"))))?;
    let finish = |py: Python<'_>, worker: std::thread::JoinHandle<tswm::error::Result<T>>| {
        py.detach(move || worker.join()).map_err(|_| {
            failure(tswm::error::Error::Internal(
                "the run's thread panicked".into(),
            ))
        })
    };
    loop {
        let done = py.detach(|| {
            let rx = rx.lock().unwrap_or_else(|e| e.into_inner());
            !matches!(rx.recv_timeout(TICK), Err(mpsc::RecvTimeoutError::Timeout))
        });
        if done {
            return finish(py, worker)?.map_err(failure);
        }
        let said = py.check_signals().and_then(|()| match &progress {
            Some(cb) => {
                let (phase, done, total) = watch.state();
                let phase = match phase {
                    Phase::Checking => "checking",
                    Phase::Running => "running",
                    Phase::Idle => "",
                };
                cb.call1((phase, done, total)).map(|_| ())
            }
            None => Ok(()),
        });
        if let Err(e) = said {
            // Ctrl-C, or the callback failed: stop the work, wait for it
            // (its files are removed as it unwinds), then raise.
            watch.stop();
            let _ = finish(py, worker)?;
            return Err(e);
        }
    }
}
