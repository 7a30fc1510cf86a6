//! A results table read back as Arrow batches of only the columns a
//! reader asks for: `lanes.parquet` through `parquet`'s Arrow reader with
//! a projection (the other columns' pages are never read), `lanes.csv`
//! with only the asked-for cells parsed. Errors name the file, the row
//! and the column.

use std::fs::File;
use std::path::Path;
use std::sync::Arc;

use ::parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use ::parquet::arrow::ProjectionMask;
use arrow_array::builder::{Float64Builder, Int64Builder, StringBuilder};
use arrow_array::{ArrayRef, RecordBatch};

use super::{columns, Format, Kind};
use crate::error::{Error, Result};
use crate::output::batch::data_type;

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

/// Reads the results table of `dir` (`lanes.csv` or `lanes.parquet`),
/// columns `names` only (in table order), handing `each` batches of rows
/// in order. Returns the table's path.
pub fn read_batches(
    dir: &Path,
    names: &[&str],
    mut each: impl FnMut(&RecordBatch) -> Result<()>,
) -> Result<std::path::PathBuf> {
    let format = Format::of_folder(dir)?;
    let path = dir.join(format.file_name());
    let table = columns();
    let wanted: Vec<(usize, &'static str, Kind)> = table
        .iter()
        .enumerate()
        .filter(|(_, c)| names.contains(&c.0))
        .map(|(i, c)| (i, c.0, c.1))
        .collect();
    match format {
        Format::Parquet => read_parquet(&path, &wanted, &mut each)?,
        Format::Csv => super::csv_read::read_csv(&path, &wanted, &mut each)?,
    }
    Ok(path)
}

/// The table, opened; an error naming it when it cannot be.
pub(super) fn open(path: &Path) -> Result<File> {
    File::open(path).map_err(|e| Error::input(path, None, None, format!("cannot read it: {e}")))
}

/// The columns asked for: their place in the table, name and kind.
pub(super) type Wanted = [(usize, &'static str, Kind)];

fn read_parquet(
    path: &Path,
    wanted: &Wanted,
    each: &mut impl FnMut(&RecordBatch) -> Result<()>,
) -> Result<()> {
    let bad = |m: String| Error::input(path, None, None, m);
    let b = ParquetRecordBatchReaderBuilder::try_new(open(path)?)
        .map_err(|e| bad(format!("not a Parquet file: {e}")))?;
    let descr = b.parquet_schema();
    let table = columns();
    let fields = descr.root_schema().get_fields();
    if fields.len() != table.len() || fields.iter().zip(&table).any(|(f, c)| f.name() != c.0) {
        return Err(not_ours(path));
    }
    let mask = ProjectionMask::roots(descr, wanted.iter().map(|w| w.0));
    let rd = b
        .with_projection(mask)
        .with_batch_size(BATCH_ROWS)
        .build()
        .map_err(|e| bad(format!("not a tswm table: {e}")))?;
    let mut rows = 0u64;
    for batch in rd {
        let batch = batch.map_err(|e| {
            Error::input(
                path,
                Some(format!("row {}", rows + 1)),
                None,
                format!("not a tswm table: {e}"),
            )
        })?;
        for ((_, name, kind), f) in wanted.iter().zip(batch.schema_ref().fields()) {
            if f.data_type() != &data_type(*kind) {
                return Err(Error::input(
                    path,
                    None,
                    Some(name),
                    format!(
                        "is {}, not {}; not a tswm table",
                        f.data_type(),
                        data_type(*kind)
                    ),
                ));
            }
        }
        rows += batch.num_rows() as u64;
        each(&batch)?;
    }
    Ok(())
}

/// One asked-for column of a CSV table, filling.
pub(super) enum Builder {
    F(Float64Builder),
    I(Int64Builder),
    S(StringBuilder),
}

impl Builder {
    /// An empty column of `kind`.
    pub(super) fn of(kind: Kind) -> Builder {
        match kind {
            Kind::Float => Builder::F(Float64Builder::with_capacity(BATCH_ROWS)),
            Kind::Int => Builder::I(Int64Builder::with_capacity(BATCH_ROWS)),
            Kind::Text => Builder::S(StringBuilder::with_capacity(BATCH_ROWS, BATCH_ROWS * 4)),
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
            Builder::S(b) if s.is_empty() => b.append_null(),
            Builder::S(b) => b.append_value(s),
        }
        Ok(())
    }

    /// The column so far, as an array; the builder starts again empty.
    pub(super) fn finish(&mut self) -> ArrayRef {
        match self {
            Builder::F(b) => Arc::new(b.finish()),
            Builder::I(b) => Arc::new(b.finish()),
            Builder::S(b) => Arc::new(b.finish()),
        }
    }
}
