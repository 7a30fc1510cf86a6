//! A CSV file written line by line under a temporary name, and the one
//! spelling of a float cell.

use std::io::Write;
use std::path::{Path, PathBuf};

use super::atomic::AtomicFile;
use crate::error::{Error, Result};

/// A CSV file written line by line under a temporary name (the files of
/// one run are committed together, `outdir::commit_together`).
pub struct CsvLines {
    file: AtomicFile,
    line: String,
    path: PathBuf,
}

impl CsvLines {
    /// Starts `path` with the header line `header`.
    pub fn create(path: &Path, header: &str) -> Result<CsvLines> {
        CsvLines::start(path, header, false)
    }

    /// Starts `path` with the header line `header`, hashing it when
    /// `hashed` (see [`AtomicFile::create_hashed`]).
    pub fn start(path: &Path, header: &str, hashed: bool) -> Result<CsvLines> {
        let mut w = CsvLines {
            file: if hashed {
                AtomicFile::create_hashed(path)?
            } else {
                AtomicFile::create(path)?
            },
            line: String::with_capacity(512),
            path: path.into(),
        };
        w.line.push_str(header);
        w.end_line()?;
        Ok(w)
    }

    /// The line being built (empty after each `end_line`).
    pub fn line(&mut self) -> &mut String {
        &mut self.line
    }

    /// Ends the line and writes it.
    pub(crate) fn end_line(&mut self) -> Result<()> {
        self.line.push('\n');
        let r = self.file.writer().write_all(self.line.as_bytes());
        self.line.clear();
        r.map_err(|e| Error::io(&self.path, e))
    }

    /// Writes whole lines, already formatted.
    pub(crate) fn write_raw(&mut self, lines: &[u8]) -> Result<()> {
        self.file
            .writer()
            .write_all(lines)
            .map_err(|e| Error::io(&self.path, e))
    }

    /// The finished file, to be committed with the run's other files.
    pub fn into_file(self) -> AtomicFile {
        self.file
    }
}

/// A float cell: empty for NaN (not applicable, or no such event), else
/// the shortest text that reads back to the same f64
/// ([`super::float_text::push_f64`]).
pub(crate) fn push_f64(s: &mut String, v: f64) {
    let mut b = Vec::with_capacity(32);
    super::float_text::push_f64(&mut b, v);
    // The float text is ASCII.
    s.push_str(std::str::from_utf8(&b).unwrap_or_default());
}
