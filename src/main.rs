//! `tswm`: parse the command line, run one command, and print one error
//! line (exit code 2 for bad input) when it fails.

use std::io::IsTerminal;
use std::process::ExitCode;

use clap::Parser;
use tswm::cli::{Cli, Command};
use tswm::commands;
use tswm::output::atomic::remove_partials_on_signal;

fn main() -> ExitCode {
    quiet_mesa();
    let cli = Cli::parse();
    // A forced vector width is read (and refused) before any command
    // writes anything.
    if let Err(why) = tswm::integrator::width::width() {
        let e = tswm::error::Error::Usage(why);
        eprintln!("tswm: error: {e}");
        return ExitCode::from(e.exit_code());
    }
    if let Err(e) = remove_partials_on_signal() {
        eprintln!("tswm: error: {e}");
        return ExitCode::from(e.exit_code());
    }
    let result = match &cli.command {
        Command::Run {
            lanes,
            out,
            backend,
            trace,
            trace_dt,
            no_report,
            shard,
            format,
        } => commands::run::run(commands::run::RunArgs {
            lanes,
            out,
            backend: *backend,
            trace,
            trace_dt: *trace_dt,
            report: !no_report,
            shard: shard.as_deref(),
            format: *format,
            progress: std::io::stderr().is_terminal(),
        }),
        Command::Merge {
            dirs,
            out,
            format,
            no_report,
        } => commands::merge::run(dirs, out, *format, !no_report),
        Command::Report { dir } => commands::report::run(dir),
        Command::Check {
            lanes,
            disagreements,
        } => commands::check::run(lanes, disagreements.as_deref()),
        Command::Devices => commands::devices::run(),
        Command::Bench { lanes, backend } => commands::bench::run(lanes, *backend),
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
