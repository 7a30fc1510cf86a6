//! One module per subcommand of `tswm`; `main` parses the command line and
//! calls one of them.

pub mod bench;
pub mod check;
pub mod devices;
pub mod merge;
pub mod report;
pub mod run;
