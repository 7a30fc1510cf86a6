//! `tswm bench`: lanes/s of a backend on a sweep, nothing written.

use crate::backend::Choice;
use crate::cli::{LanesArgs, Plan};
use crate::error::Result;
use crate::progress::Show;
use crate::run;

/// Counts the lanes of each chunk and drops them (a search's row counts
/// the lanes its drive integrated).
struct Discard(u64);

impl run::Sink for Discard {
    type Output = u64;
    fn chunk(
        &mut self,
        _first: u64,
        params: &mut crate::params::ParamColumns,
        results: &[crate::integrator::LaneResult],
    ) -> Result<()> {
        self.0 += if results.iter().any(|r| r.search.is_some()) {
            results
                .iter()
                .filter_map(|r| r.search.map(|s| s.lanes as u64))
                .sum()
        } else {
            params.len() as u64
        };
        Ok(())
    }
    fn finish(self) -> Result<u64> {
        Ok(self.0)
    }
}

/// What `tswm bench` measured.
#[derive(Clone, Debug)]
pub struct Bench {
    /// Lanes integrated (a search's: every round's).
    pub lanes: u64,
    /// Seconds they took (generation and integration; the lanes' check
    /// before is not timed).
    pub seconds: f64,
    /// The backend, as the summary line names it.
    pub backend: String,
}

impl Bench {
    /// Lanes a second.
    pub fn rate(&self) -> f64 {
        self.lanes as f64 / self.seconds.max(1e-9)
    }
}

/// Integrates the lanes of `plan` on `choice`, writing nothing.
pub fn measure(plan: &Plan, choice: Choice, show: &Show) -> Result<Bench> {
    let total = plan.source.lane_count();
    let be = plan.backend(choice, total)?;
    // A search integrates its rounds as a run does.
    let mut be = run::search::around(be, &plan.source, (0, total))?;
    let start = std::time::Instant::now();
    let n = run::pipeline(&plan.source, be.as_mut(), show, Discard(0))?;
    Ok(Bench {
        lanes: n,
        seconds: start.elapsed().as_secs_f64(),
        backend: be.name(),
    })
}

/// Runs `tswm bench`.
pub fn run(lanes: &LanesArgs, choice: Choice) -> Result<()> {
    let b = measure(&lanes.plan()?, choice, &Show::default())?;
    sayln!(
        "tswm bench: {} lanes in {:.3} s ({:.0} lanes/s, {}); nothing written",
        b.lanes,
        b.seconds,
        b.rate(),
        b.backend
    );
    Ok(())
}
