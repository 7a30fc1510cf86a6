//! `tswm`: parse, plan, run; one error line and exit code 2 for bad input.

use std::io::IsTerminal;
use std::path::Path;
use std::process::ExitCode;

use clap::Parser;
use tswm::backend::{self, Choice, CpuBackend};
use tswm::cli::{Cli, Command, LanesArgs};
use tswm::error::{Error, Result};
use tswm::gpu::{Gpu, GpuBackend};
use tswm::{check, output, runner};

fn main() -> ExitCode {
    quiet_mesa();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run {
            lanes,
            out,
            backend,
        } => run(&lanes, &out, backend),
        Command::Check { lanes } => check(&lanes),
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

fn run(lanes: &LanesArgs, out: &Path, choice: Choice) -> Result<()> {
    let plan = lanes.plan()?;
    let mut be = backend::open(
        choice,
        plan.source.lane_count(),
        plan.threads,
        plan.settings,
    )?;
    std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
    let csv = out.join("lanes.csv");
    let progress = std::io::stderr().is_terminal();
    let summary = runner::run(&plan.source, be.as_mut(), &csv, progress)?;
    let resolved = output::provenance(&plan.source, &be.name(), be.tolerance());
    output::write_atomic(&out.join("sweep.resolved.toml"), resolved.as_bytes())?;
    println!("{}", summary.line(&be.name(), &csv));
    Ok(())
}

fn check(lanes: &LanesArgs) -> Result<()> {
    let plan = lanes.plan()?;
    let cpu = CpuBackend::new(plan.threads, plan.settings)?;
    let cpu_name = backend::Backend::name(&cpu);
    let mut gpu = GpuBackend::new(Gpu::new(false)?, plan.settings);
    let progress = std::io::stderr().is_terminal();
    let report = check::compare(&plan.source, &mut gpu, cpu, progress)?;
    println!(
        "tswm check: {} lanes, {} against {cpu_name}",
        report.lanes,
        backend::Backend::name(&gpu),
    );
    print!("{}", report.text());
    if report.passes() {
        println!("PASS");
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
