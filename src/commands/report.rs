//! `tswm report DIR`: the report again, from the folder's files, with the
//! folder locked while it is written.

use std::path::Path;

use crate::error::Result;
use crate::output::names::REPORT;
use crate::output::OutDir;

/// Runs `tswm report`.
pub fn run(dir: &Path) -> Result<()> {
    let mut d = OutDir::open_existing(dir)?;
    crate::report::write(&mut d)?;
    sayln!("tswm: wrote {}", d.join(REPORT).display());
    Ok(())
}
