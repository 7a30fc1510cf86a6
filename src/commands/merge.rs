//! `tswm merge`: shard folders joined into one (see [`crate::run::merge`]).

use std::path::{Path, PathBuf};

use crate::error::Result;
use crate::output::table::Format;

/// Runs `tswm merge`; prints its summary line.
pub fn run(dirs: &[PathBuf], out: &Path, format: Format, report: bool) -> Result<()> {
    let merged = crate::run::merge::merge(dirs, out, format, report)?;
    sayln!("{}", merged.line());
    Ok(())
}
