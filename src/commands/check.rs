//! `tswm check`: the same lanes on the CPU and the GPU, compared.

use std::path::Path;

use crate::backend::gpu::{Gpu, GpuBackend, ShaderReal};
use crate::backend::{self, CpuBackend, Precision};
use crate::cli::{LanesArgs, Plan};
use crate::error::{Error, Result};
use crate::input::lanes::Source;
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
    /// What was compared, when not the run's own lanes (a search's first
    /// round).
    pub note: Option<String>,
}

/// Runs the lanes of `plan` on the GPU and on the f64 CPU path and
/// compares them (every disagreeing lane to `disagreements`, when given).
/// The GPU runs in f64 with `--precision f64` (its rows held to the CPU
/// path's bound), else in f32.
pub fn compare(plan: &Plan, disagreements: Option<&Path>, show: &Show) -> Result<Checked> {
    let real = match plan.precision {
        Precision::F64 => ShaderReal::F64,
        Precision::F32 | Precision::Auto => ShaderReal::F32,
    };
    // The f64 GPU path runs at the settings the reference runs at
    // (`layout::f64_settings`), so that what is compared is the path, not
    // two tolerances.
    let reference = match real {
        ShaderReal::F64 => crate::backend::gpu::layout::f64_settings(&plan.settings),
        ShaderReal::F32 => plan.settings,
    };
    let cpu = CpuBackend::new(plan.threads, reference)?;
    let cpu_name = backend::Backend::name(&cpu);
    let recompute = CpuBackend::new(plan.threads, plan.settings)?;
    let mut gpu = GpuBackend::with_cpu(Gpu::open(false, real)?, plan.settings, recompute);
    let mut report = match disagreements {
        None => check::Report::default(),
        Some(p) => {
            let f = std::fs::File::create(p).map_err(|e| Error::io(p, e))?;
            check::Report::writing_to(Box::new(std::io::BufWriter::new(f)))
                .map_err(|e| Error::io(p, e))?
        }
    };
    // A search's later rounds follow its results; its first round is
    // lanes like any other's.
    let (first, note) = match &plan.source {
        Source::Sweep { sweep, file } => match (sweep.first_round(), &sweep.search) {
            (Some(sw), Some(s)) => (
                Some(Source::Sweep {
                    sweep: sw,
                    file: file.clone(),
                }),
                Some(format!(
                    "a search's rounds follow its results: compared its first round ({} points \
                     of {} from {} to {} for each drive)",
                    crate::input::sweep::search::FIRST_ROUND_POINTS,
                    s.param.name(),
                    s.from,
                    s.to
                )),
            ),
            _ => (None, None),
        },
        Source::Table {
            search: Some(_), ..
        } => (
            None,
            Some("a lane table's search: compared the table's rows as given".into()),
        ),
        Source::Table { .. } => (None, None),
    };
    report.f64_rows = real == ShaderReal::F64;
    let source = first.as_ref().unwrap_or(&plan.source);
    let report = check::compare(source, &mut gpu, cpu, show, report)?;
    Ok(Checked {
        report,
        gpu: backend::Backend::name(&gpu),
        cpu: cpu_name,
        note,
    })
}

/// `plan` with the GPU arithmetic `--precision` names: a check compares
/// the path it names (f32 unless f64), whatever `--tol` the CPU reference
/// runs at ([`LanesArgs::asked_precision`] is a run's choice).
pub fn checked_plan(plan: Plan, precision: Precision) -> Plan {
    Plan { precision, ..plan }
}

/// Runs `tswm check`; exit 1 (an error) when a bound is missed.
pub fn run(lanes: &LanesArgs, disagreements: Option<&Path>, show: &Show) -> Result<()> {
    let Checked {
        report,
        gpu,
        cpu,
        note,
    } = compare(
        &checked_plan(lanes.plan()?, lanes.precision),
        disagreements,
        show,
    )?;
    sayln!("tswm check: {} lanes, {gpu} against {cpu}", report.lanes);
    if let Some(n) = note {
        sayln!("({n})");
    }
    say!("{}", report.text());
    if report.passes() {
        Ok(())
    } else {
        Err(Error::CheckFailed(
            "a bound was missed (see the table above)".into(),
        ))
    }
}
