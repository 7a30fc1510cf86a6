//! `tswm check`: the same lanes on the CPU and the GPU, compared.

use std::path::Path;

use crate::backend::gpu::{Gpu, GpuBackend};
use crate::backend::{self, CpuBackend};
use crate::cli::{LanesArgs, Plan};
use crate::error::{Error, Result};
use crate::progress::Show;
use crate::run::compare as check;

/// What `tswm check` found: the comparison, and the two paths compared.
pub struct Checked {
    /// The comparison, lane by lane.
    pub report: check::Report,
    /// The GPU backend, named.
    pub gpu: String,
    /// The CPU backend, named.
    pub cpu: String,
}

/// Runs the lanes of `plan` on the GPU and on the f64 CPU path and
/// compares them (every disagreeing lane to `disagreements`, when given).
pub fn compare(plan: &Plan, disagreements: Option<&Path>, show: &Show) -> Result<Checked> {
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
    let report = check::compare(&plan.source, &mut gpu, cpu, show, report)?;
    Ok(Checked {
        report,
        gpu: backend::Backend::name(&gpu),
        cpu: cpu_name,
    })
}

/// Runs `tswm check`; exit 1 (an error) when a bound is missed.
pub fn run(lanes: &LanesArgs, disagreements: Option<&Path>, show: &Show) -> Result<()> {
    let Checked { report, gpu, cpu } = compare(&lanes.plan()?, disagreements, show)?;
    sayln!("tswm check: {} lanes, {gpu} against {cpu}", report.lanes);
    say!("{}", report.text());
    if report.passes() {
        Ok(())
    } else {
        Err(Error::CheckFailed(
            "a bound was missed (see the table above)".into(),
        ))
    }
}
