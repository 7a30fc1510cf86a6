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
    keep_freed_memory();
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => return usage_error(e),
    };
    // A forced vector width is read (and refused) before any command
    // writes anything.
    if let Err(why) = tswm::integrator::width::width() {
        return fail(&tswm::error::Error::Usage(why));
    }
    if let Err(e) = remove_partials_on_signal() {
        return fail(&e);
    }
    let result = match &cli.command {
        Command::Run { lanes, run } => commands::run::run(lanes, run, &terminal()),
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
        } => commands::check::run(lanes, disagreements.as_deref(), &terminal()),
        Command::Devices => commands::devices::run(),
        Command::Bench { lanes, backend } => commands::bench::run(lanes, *backend),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => fail(&e),
    }
}

/// Progress shown as bars on stderr when it is a terminal.
fn terminal() -> tswm::progress::Show {
    tswm::progress::Show::terminal(std::io::stderr().is_terminal())
}

/// Prints the one error line, every control character in it (a file
/// name's newline or escape sequence) escaped, and gives the exit code.
fn fail(e: &tswm::error::Error) -> ExitCode {
    eprintln!("tswm: error: {}", tswm::error::one_line(&e.to_string()));
    ExitCode::from(e.exit_code())
}

/// A command line clap refuses: its first line, as one `tswm: error:`
/// line with exit code 2 (help and version print as clap writes them).
fn usage_error(e: clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion)
        || e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
    {
        let _ = e.print();
        return ExitCode::from(if e.use_stderr() { 2 } else { 0 });
    }
    let text = e.render().to_string();
    // The first paragraph: the error and what clap lists under it (the
    // missing arguments, the possible values).
    let first: Vec<&str> = text
        .lines()
        .map(str::trim)
        .skip_while(|l| l.is_empty())
        .take_while(|l| !l.is_empty())
        .collect();
    let first = first.join(" ");
    let first = first.strip_prefix("error: ").unwrap_or(&first);
    let usage = text
        .lines()
        .map(str::trim)
        .find_map(|l| l.strip_prefix("Usage: "))
        .map(|u| format!("; usage: {u}"))
        .unwrap_or_default();
    fail(&tswm::error::Error::Usage(format!("{first}{usage}")))
}

/// Keeps memory the process frees for its next allocations instead of
/// giving it back to the system at once: a run allocates and frees the
/// same buffers every chunk (a batch's columns, the Parquet encoders'
/// pages of a megabyte), and glibc would otherwise map and unmap them
/// each time, paying a page fault for every 4 KiB touched again (a sixth
/// of a Parquet run's time on 10^6 cheap lanes). Memory stays bounded:
/// what is kept is what the chunks need anyway.
fn keep_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only sets allocator parameters, before any thread starts.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 32 << 20);
        libc::mallopt(libc::M_TRIM_THRESHOLD, 256 << 20);
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
