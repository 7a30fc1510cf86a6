//! `tswm report DIR`: the report again, from the folder's files, with the
//! folder locked while it is written.

use std::path::{Path, PathBuf};

use crate::error::Result;
use crate::output::names::REPORT;
use crate::output::OutDir;

/// Writes `dir/report.html` again from the folder's files; its path.
pub fn rebuild(dir: &Path) -> Result<PathBuf> {
    let mut d = OutDir::open_existing(dir)?;
    crate::report::write(&mut d)?;
    Ok(d.join(REPORT))
}

/// Runs `tswm report`.
pub fn run(dir: &Path) -> Result<()> {
    let path = rebuild(dir)?;
    sayln!("tswm: wrote {}", path.display());
    Ok(())
}
