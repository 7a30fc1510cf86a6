//! `tswm`: parse, plan, run; one error line and exit code 2 for bad input.

use std::io::IsTerminal;
use std::process::ExitCode;

use clap::Parser;
use tswm::cli::{BackendChoice, Cli, Command};
use tswm::error::{Error, Result};
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
            backend,
        } => {
            let plan = lanes.plan()?;
            let mut be: Box<dyn Backend> = match backend {
                BackendChoice::Cpu | BackendChoice::Auto => {
                    Box::new(CpuBackend::new(plan.threads, plan.settings)?)
                }
                BackendChoice::Gpu => {
                    return Err(Error::Gpu(
                        "the GPU backend is not built yet; use --backend cpu".into(),
                    ))
                }
            };
            std::fs::create_dir_all(&out).map_err(|e| Error::io(&out, e))?;
            let resolved = match &plan.source {
                tswm::lanes::Source::Sweep { sweep, .. } => {
                    toml::to_string(&sweep.resolved_toml()).unwrap_or_default()
                }
                tswm::lanes::Source::Table { path, .. } => {
                    format!("# lanes from {}\n", path.display())
                }
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
        Command::Check { .. } => Err(Error::Gpu(
            "tswm check needs the GPU backend, which is not built yet".into(),
        )),
        Command::Devices => Err(Error::Gpu("the GPU backend is not built yet".into())),
    }
}
