//! `tswm bench`: lanes/s of a backend on a sweep, nothing written.

use crate::backend::{self, Choice};
use crate::cli::LanesArgs;
use crate::error::Result;
use crate::run;

/// Counts the lanes of each chunk and drops them.
struct Discard(u64);

impl run::Sink for Discard {
    type Output = u64;
    fn chunk(
        &mut self,
        _first: u64,
        params: &mut crate::params::ParamColumns,
        _results: &[crate::integrator::LaneResult],
    ) -> Result<()> {
        self.0 += params.len() as u64;
        Ok(())
    }
    fn finish(self) -> Result<u64> {
        Ok(self.0)
    }
}

/// Runs `tswm bench`.
pub fn run(lanes: &LanesArgs, choice: Choice) -> Result<()> {
    let plan = lanes.plan()?;
    let mut be = backend::open(
        choice,
        plan.source.lane_count(),
        plan.threads,
        plan.settings,
    )?;
    let start = std::time::Instant::now();
    let n = run::pipeline(&plan.source, be.as_mut(), false, Discard(0))?;
    let s = start.elapsed().as_secs_f64();
    sayln!(
        "tswm bench: {n} lanes in {s:.3} s ({:.0} lanes/s, {}); nothing written",
        n as f64 / s.max(1e-9),
        be.name()
    );
    Ok(())
}
