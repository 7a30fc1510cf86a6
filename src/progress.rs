//! How a command shows how far it has got: a bar on stderr where that is
//! a terminal (the lanes of a run, and the check of a large sweep's lanes
//! before it), and a [`Watch`] for a caller on another thread (Python's
//! `tswm.run`, which draws its own bar and may ask the command to stop).

use std::sync::atomic::{AtomicBool, AtomicU64, AtomicU8, Ordering};
use std::sync::Arc;

use crate::error::{Error, Result};

/// What a command is doing, as a [`Watch`] reports it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Not started, or between phases.
    Idle,
    /// Checking every lane before anything is written.
    Checking,
    /// Running the lanes.
    Running,
}

/// Where a command's work stands, read from another thread, and that
/// thread's request to stop: the command stops at its next chunk or
/// block of lanes with [`Error::Stopped`], its files uncommitted.
#[derive(Debug, Default)]
pub struct Watch {
    stop: AtomicBool,
    phase: AtomicU8,
    done: AtomicU64,
    total: AtomicU64,
}

impl Watch {
    /// A new watch, shared.
    pub fn new() -> Arc<Watch> {
        Arc::new(Watch::default())
    }

    /// Asks the command to stop.
    pub fn stop(&self) {
        self.stop.store(true, Ordering::Relaxed);
    }

    /// Whether a stop was asked for.
    pub(crate) fn stopping(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }

    /// The phase, the lanes done in it and its lanes in all.
    pub fn state(&self) -> (Phase, u64, u64) {
        let phase = match self.phase.load(Ordering::Relaxed) {
            1 => Phase::Checking,
            2 => Phase::Running,
            _ => Phase::Idle,
        };
        (
            phase,
            self.done.load(Ordering::Relaxed),
            self.total.load(Ordering::Relaxed),
        )
    }

    fn start(&self, phase: Phase, total: u64) {
        self.done.store(0, Ordering::Relaxed);
        self.total.store(total, Ordering::Relaxed);
        self.phase.store(phase as u8, Ordering::Relaxed);
    }
}

/// How a command shows its progress: a bar on stderr when `terminal`,
/// and the `watch` of a caller, if any.
#[derive(Clone, Debug, Default)]
pub struct Show {
    /// Draw bars on stderr (it is a terminal).
    pub terminal: bool,
    /// A caller's watch.
    pub watch: Option<Arc<Watch>>,
}

impl Show {
    /// Bars on stderr when `terminal`, no watch.
    pub fn terminal(terminal: bool) -> Show {
        Show {
            terminal,
            watch: None,
        }
    }

    /// [`Error::Stopped`] when the watch asked for a stop.
    pub fn check(&self) -> Result<()> {
        match &self.watch {
            Some(w) if w.stopping() => Err(Error::Stopped),
            _ => Ok(()),
        }
    }

    /// A bar over `total` lanes of `phase`, named by `what` ("" for the
    /// run's own), drawn only when `draw` (and stderr is a terminal).
    pub fn bar(&self, phase: Phase, draw: bool, total: u64, what: &str) -> Bar {
        if let Some(w) = &self.watch {
            w.start(phase, total);
        }
        Bar {
            bar: bar(self.terminal && draw, total, what),
            watch: self.watch.clone(),
        }
    }
}

/// A progress bar in use (see [`Show::bar`]); a clone is the same bar.
#[derive(Clone)]
pub struct Bar {
    bar: indicatif::ProgressBar,
    watch: Option<Arc<Watch>>,
}

impl Bar {
    /// Lanes done so far.
    pub(crate) fn set_position(&self, done: u64) {
        self.bar.set_position(done);
        if let Some(w) = &self.watch {
            w.done.store(done, Ordering::Relaxed);
        }
    }

    /// `n` more lanes done.
    pub(crate) fn inc(&self, n: u64) {
        self.bar.inc(n);
        if let Some(w) = &self.watch {
            w.done.fetch_add(n, Ordering::Relaxed);
        }
    }

    /// Counts drives, not lanes, with `msg` saying how far the rounds have
    /// got (a search: its rounds and the lanes they integrated).
    pub(crate) fn count_drives(&self, msg: String) {
        self.bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{bar:40} {pos}/{len} drives searched, {msg}, eta {eta}",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        self.bar.set_message(msg);
    }

    /// Says how far a search's rounds have got (see [`Bar::count_drives`]).
    pub(crate) fn set_message(&self, msg: String) {
        self.bar.set_message(msg);
    }

    /// Takes the bar off the terminal.
    pub(crate) fn finish_and_clear(&self) {
        self.bar.finish_and_clear();
        if let Some(w) = &self.watch {
            w.phase.store(Phase::Idle as u8, Ordering::Relaxed);
        }
    }
}

/// A bar over `total` lanes, named by `what` ("" for the run's own);
/// hidden unless `show`.
fn bar(show: bool, total: u64, what: &str) -> indicatif::ProgressBar {
    let bar = if show {
        indicatif::ProgressBar::with_draw_target(
            Some(total),
            indicatif::ProgressDrawTarget::stderr(),
        )
    } else {
        indicatif::ProgressBar::hidden()
    };
    let prefix = if what.is_empty() {
        String::new()
    } else {
        format!("{what}: ")
    };
    bar.set_style(
        indicatif::ProgressStyle::with_template(&format!(
            "{prefix}{{bar:40}} {{pos}}/{{len}} lanes, {{per_sec}}, eta {{eta}}"
        ))
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_watch_sees_the_bar_and_stops_the_command() {
        let w = Watch::new();
        let show = Show {
            terminal: false,
            watch: Some(w.clone()),
        };
        assert!(show.check().is_ok());
        let b = show.bar(Phase::Running, true, 100, "");
        b.inc(30);
        b.set_position(40);
        assert_eq!(w.state(), (Phase::Running, 40, 100));
        b.finish_and_clear();
        assert_eq!(w.state().0, Phase::Idle);
        w.stop();
        assert!(matches!(show.check(), Err(Error::Stopped)));
    }
}
