//! One module per subcommand of `tswm`; `main` parses the command line and
//! calls one of them.

/// `print!` to standard output, where a reader that has gone (`tswm
/// devices | head -1`) is no error: the rest is not wanted, so it is
/// dropped, where `print!` would panic. Any other failure to write is
/// said on standard error.
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::commands::write_out(format_args!($($arg)*))
    };
}

/// `println!` as [`say!`] does it.
macro_rules! sayln {
    ($($arg:tt)*) => {
        $crate::commands::write_out(format_args!("{}\n", format_args!($($arg)*)))
    };
}

pub mod bench;
pub mod check;
pub mod devices;
pub mod merge;
pub mod report;
pub mod run;

/// Writes `text` to standard output for [`say!`] and [`sayln!`].
pub(crate) fn write_out(text: std::fmt::Arguments) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match out.write_fmt(text).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            eprintln!("tswm: could not write to standard output: {e}");
        }
        _ => {}
    }
}
