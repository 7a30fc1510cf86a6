//! What a run's lanes are given as: a sweep, as a file or as its text
//! (Python's `tswm.run` takes a TOML string or a dict), and a lane table,
//! as a CSV file or as columns in memory (a pandas, polars or pyarrow
//! table).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::error::Result;
use crate::input::frame::Frame;

/// A sweep: a file, or its text given directly (Python's `tswm.run`),
/// named in errors.
#[derive(Clone, Copy, Debug)]
pub enum SweepIn<'a> {
    /// A sweep file.
    File(&'a Path),
    /// A sweep's text, and the name its errors give it.
    Text {
        /// The name.
        name: &'a Path,
        /// The TOML text.
        text: &'a str,
    },
}

impl SweepIn<'_> {
    /// The name its errors give it.
    pub fn name(&self) -> &Path {
        match self {
            SweepIn::File(p) => p,
            SweepIn::Text { name, .. } => name,
        }
    }

    /// Its text.
    pub(crate) fn text(&self) -> Result<String> {
        match self {
            SweepIn::File(p) => crate::input::sweep::read_text(p),
            SweepIn::Text { text, .. } => Ok(text.to_string()),
        }
    }
}

/// A lane table: a CSV file, or columns in memory.
#[derive(Clone, Debug)]
pub enum TableIn {
    /// A lane table file (CSV).
    File(PathBuf),
    /// A table in memory (Python's pandas, polars or pyarrow table).
    Frame(Arc<Frame>),
}

impl TableIn {
    /// The parameters its columns name (a file's header read; none where
    /// it cannot be read: the lane check reports that).
    pub fn params(&self) -> Vec<crate::params::Param> {
        match self {
            TableIn::File(path) => csv::Reader::from_path(path)
                .and_then(|mut r| r.headers().cloned())
                .map(|h| {
                    h.iter()
                        .filter_map(|n| crate::params::Param::from_name(n.trim()))
                        .collect()
                })
                .unwrap_or_default(),
            TableIn::Frame(f) => f.params(),
        }
    }

    /// The name its errors give it.
    pub fn name(&self) -> &Path {
        match self {
            TableIn::File(p) => p,
            TableIn::Frame(f) => f.name(),
        }
    }
}
