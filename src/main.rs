//! `tswm`: parse, plan, run; one error line and exit code 2 for bad input.

use std::io::IsTerminal;
use std::process::ExitCode;

use clap::Parser;
use tswm::check::Report;
use tswm::cli::{open_backend, Cli, Command};
use tswm::error::{Error, Result};
use tswm::gpu::{Gpu, GpuBackend};
use tswm::lanes::Source;
use tswm::runner::{self, Backend, CpuBackend};

fn main() -> ExitCode {
    let cli = Cli::parse();
    match real_main(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("tswm: error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}

fn real_main(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Run {
            lanes,
            out,
            backend: choice,
        } => {
            let plan = lanes.plan()?;
            let mut be = open_backend(choice, &plan)?;
            std::fs::create_dir_all(&out).map_err(|e| Error::io(&out, e))?;
            let resolved = match &plan.source {
                Source::Sweep { sweep, .. } => {
                    toml::to_string(&sweep.resolved_toml()).unwrap_or_default()
                }
                Source::Table { path, .. } => format!("# lanes from {}\n", path.display()),
            };
            let header = format!(
                "# tswm {} resolved sweep: every lane of lanes.csv follows from this file\n# backend: {}, tol: {:e}, lanes: {}\n",
                env!("CARGO_PKG_VERSION"),
                be.name(),
                plan.settings.tol,
                plan.source.lane_count()
            );
            let csv = out.join("lanes.csv");
            let summary = runner::run(
                &plan.source,
                be.as_mut(),
                &csv,
                std::io::stderr().is_terminal(),
            )?;
            tswm::output::write_atomic(
                &out.join("sweep.resolved.toml"),
                format!("{header}{resolved}").as_bytes(),
            )?;
            println!("{}", summary.line(&be.name(), &csv));
            Ok(())
        }
        Command::Check { lanes } => {
            let plan = lanes.plan()?;
            let mut cpu = CpuBackend::new(plan.threads, plan.settings)?;
            let mut gpu = GpuBackend::new(Gpu::new(false)?, plan.settings);
            let table = plan.source.friction_table().copied();
            let mut reader = plan.source.reader()?;
            let (mut params, mut rc, mut rg) = (Vec::new(), Vec::new(), Vec::new());
            let mut report = Report::default();
            let mut first = 0;
            loop {
                params.clear();
                reader.fill(gpu.chunk_lanes(), &mut params)?;
                if params.is_empty() {
                    break;
                }
                cpu.run_chunk(first, &params, table.as_ref(), &mut rc)?;
                gpu.run_chunk(first, &params, table.as_ref(), &mut rg)?;
                report.add(first, &rc, &rg);
                first += params.len() as u64;
            }
            println!(
                "tswm check: {} lanes, {} against {}",
                report.lanes,
                gpu.name(),
                cpu.name()
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
        Command::Devices => {
            let list = tswm::gpu::adapters();
            if list.is_empty() {
                println!(
                    "no GPU adapters found (install a Vulkan driver, e.g. mesa-vulkan-drivers)"
                );
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
    }
}
