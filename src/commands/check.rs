//! `tswm check`: the same lanes on the CPU and the GPU, compared.

use std::io::IsTerminal;
use std::path::Path;

use crate::backend::gpu::{Gpu, GpuBackend};
use crate::backend::{self, CpuBackend};
use crate::cli::LanesArgs;
use crate::error::{Error, Result};
use crate::run::compare as check;

/// Runs `tswm check`; exit 1 (an error) when a bound is missed.
pub fn run(lanes: &LanesArgs, disagreements: Option<&Path>) -> Result<()> {
    let plan = lanes.plan()?;
    let cpu = CpuBackend::new(plan.threads, plan.settings)?;
    let cpu_name = backend::Backend::name(&cpu);
    let recompute = CpuBackend::new(plan.threads, plan.settings)?;
    let mut gpu = GpuBackend::with_cpu(Gpu::new(false)?, plan.settings, recompute);
    let report = match disagreements {
        None => check::Report::default(),
        Some(p) => {
            let f = std::fs::File::create(p).map_err(|e| Error::io(p, e))?;
            check::Report::writing_to(Box::new(std::io::BufWriter::new(f)))
                .map_err(|e| Error::io(p, e))?
        }
    };
    let progress = std::io::stderr().is_terminal();
    let report = check::compare(&plan.source, &mut gpu, cpu, progress, report)?;
    sayln!(
        "tswm check: {} lanes, {} against {cpu_name}",
        report.lanes,
        backend::Backend::name(&gpu),
    );
    say!("{}", report.text());
    if report.passes() {
        Ok(())
    } else {
        Err(Error::CheckFailed(
            "a bound was missed (see the table above)".into(),
        ))
    }
}
