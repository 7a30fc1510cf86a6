//! What the table's two readers share: opening the table, the error for
//! a table of another version, the columns asked for, and a column of a
//! CSV table being filled from its cells' text.

use std::fs::File;
use std::path::Path;
use std::sync::Arc;

use arrow_array::builder::{Float64Builder, Int64Builder};
use arrow_array::ArrayRef;

use super::Kind;
use crate::error::{Error, Result};
use crate::output::batch::WordKeys;

/// Rows a batch read back.
pub(super) const BATCH_ROWS: usize = 1 << 16;

/// The error for a table whose header is not this version's.
pub(super) fn not_ours(path: &Path) -> Error {
    Error::input(
        path,
        Some("line 1".into()),
        None,
        "its columns are not those of this tswm version's table; run it again",
    )
}

/// The table, opened; an error naming it when it cannot be.
pub(super) fn open(path: &Path) -> Result<File> {
    File::open(path).map_err(|e| Error::input(path, None, None, format!("cannot read it: {e}")))
}

/// The columns asked for: their place in the table, name and kind.
pub type Wanted = [(usize, &'static str, Kind)];

/// One asked-for column of a CSV table, filling.
pub(super) enum Builder {
    F(Float64Builder),
    I(Int64Builder),
    S(WordKeys),
}

impl Builder {
    /// An empty column `name` of `kind`.
    pub(super) fn of(name: &'static str, kind: Kind) -> Builder {
        match kind {
            Kind::Float => Builder::F(Float64Builder::with_capacity(BATCH_ROWS)),
            Kind::Int => Builder::I(Int64Builder::with_capacity(BATCH_ROWS)),
            Kind::Text => Builder::S(WordKeys::new(name, BATCH_ROWS)),
        }
    }

    /// Appends cell `t`; the error's words when it is not of the kind.
    pub(super) fn push(&mut self, t: &[u8]) -> std::result::Result<(), String> {
        let s = std::str::from_utf8(t).map_err(|_| "is not valid UTF-8 text".to_string())?;
        let shown = || crate::error::shown(s, 40);
        match self {
            Builder::F(b) if s.is_empty() => b.append_null(),
            Builder::F(b) => match s.parse::<f64>() {
                Ok(v) if v.is_finite() => b.append_value(v),
                _ => return Err(format!("`{}` is not a finite number", shown())),
            },
            Builder::I(b) => match s.parse::<u64>() {
                Ok(v) => b.append_value(v as i64),
                _ => return Err(format!("`{}` is not a whole number", shown())),
            },
            Builder::S(b) => b.push(Some(s))?,
        }
        Ok(())
    }

    /// The column so far, as an array; the builder starts again empty.
    pub(super) fn finish(&mut self) -> ArrayRef {
        match self {
            Builder::F(b) => Arc::new(b.finish()),
            Builder::I(b) => Arc::new(b.finish()),
            Builder::S(b) => b.finish(),
        }
    }
}
