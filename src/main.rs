//! `tswm`: parse, plan, run; one error line and exit code 2 for bad input.

use std::io::{IsTerminal, Write};
use std::path::Path;
use std::process::ExitCode;

use clap::Parser;
use tswm::backend::{self, Choice, CpuBackend};
use tswm::cli::{Cli, Command, LanesArgs};
use tswm::error::{Error, Result};
use tswm::gpu::{Gpu, GpuBackend};
use tswm::outdir::{commit_together, remove_partials_on_signal, AtomicFile, OutDir};
use tswm::{check, output, runner};

fn main() -> ExitCode {
    quiet_mesa();
    let cli = Cli::parse();
    if let Err(e) = remove_partials_on_signal() {
        eprintln!("tswm: error: {e}");
        return ExitCode::from(e.exit_code());
    }
    let result = match cli.command {
        Command::Run {
            lanes,
            out,
            backend,
            trace,
            trace_dt,
            no_report,
        } => run(&lanes, &out, backend, &trace, trace_dt, !no_report),
        Command::Report { dir } => report(&dir),
        Command::Check {
            lanes,
            disagreements,
        } => check(&lanes, disagreements.as_deref()),
        Command::Devices => devices(),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("tswm: error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}

/// Without XDG_RUNTIME_DIR, Mesa's Vulkan drivers print an error line while
/// probing for a Wayland display that compute never needs. Set here, before
/// any thread starts, since the environment is not safe to change later.
fn quiet_mesa() {
    if std::env::var_os("XDG_RUNTIME_DIR").is_none() {
        std::env::set_var("XDG_RUNTIME_DIR", std::env::temp_dir());
    }
}

fn run(
    lanes: &LanesArgs,
    out: &Path,
    choice: Choice,
    trace: &[u64],
    trace_dt: Option<f64>,
    with_report: bool,
) -> Result<()> {
    let plan = lanes.plan()?;
    let trace = tswm::cli::trace_plan(trace, trace_dt, &plan.source)?;
    let mut be = backend::open(
        choice,
        plan.source.lane_count(),
        plan.threads,
        plan.settings,
    )?;
    let dir = OutDir::open(out)?;
    let csv = dir.join("lanes.csv");
    let progress = std::io::stderr().is_terminal();
    let written = runner::run(&plan.source, be.as_mut(), &csv, trace.as_ref(), progress)?;
    let mut resolved = AtomicFile::create(&dir.join("sweep.resolved.toml"))?;
    let text = output::provenance(
        &plan.source,
        &be.name(),
        be.tolerance(),
        written.summary.seconds,
    );
    resolved
        .writer()
        .write_all(text.as_bytes())
        .map_err(|e| Error::io(&dir.join("sweep.resolved.toml"), e))?;
    // lanes.csv last: its appearance means the run is complete. A run
    // without traces removes an earlier run's traces.csv, which would not
    // belong to it; the report is built from the committed files, so an
    // earlier run's report goes with the old results.
    let mut files = vec![resolved, written.stats];
    files.extend(written.traces.map(|t| t.into_file()));
    files.push(written.lanes.into_file());
    commit_together(files, &[&dir.join("traces.csv"), &dir.join("report.html")])?;
    let mut line = written.summary.line(&be.name(), &csv);
    if with_report {
        let start = std::time::Instant::now();
        tswm::report::write(dir.path())?;
        line.push_str(&format!(
            "; report.html in {:.2} s",
            start.elapsed().as_secs_f64()
        ));
    }
    println!("{line}");
    Ok(())
}

fn report(dir: &Path) -> Result<()> {
    tswm::report::write(dir)?;
    println!("tswm: wrote {}", dir.join("report.html").display());
    Ok(())
}

fn check(lanes: &LanesArgs, disagreements: Option<&Path>) -> Result<()> {
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
    println!(
        "tswm check: {} lanes, {} against {cpu_name}",
        report.lanes,
        backend::Backend::name(&gpu),
    );
    print!("{}", report.text());
    if report.passes() {
        Ok(())
    } else {
        Err(Error::CheckFailed(
            "a bound was missed (see the table above)".into(),
        ))
    }
}

fn devices() -> Result<()> {
    let list = tswm::gpu::adapters();
    if list.is_empty() {
        println!("no GPU adapters found (install a Vulkan driver, e.g. mesa-vulkan-drivers)");
    }
    for a in list {
        let l = &a.limits;
        println!(
            "{} ({:?}, {:?}, driver {} {})\n  max_storage_buffer_binding_size {} B, max_buffer_size {} B, \
             max_compute_workgroups_per_dimension {}, max_compute_invocations_per_workgroup {}",
            a.info.name,
            a.info.device_type,
            a.info.backend,
            a.info.driver,
            a.info.driver_info,
            l.max_storage_buffer_binding_size,
            l.max_buffer_size,
            l.max_compute_workgroups_per_dimension,
            l.max_compute_invocations_per_workgroup
        );
    }
    Ok(())
}
