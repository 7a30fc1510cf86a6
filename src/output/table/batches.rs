//! A results table read back as Arrow batches of only the columns a
//! reader asks for: `lanes.parquet` through `parquet`'s Arrow reader with
//! a projection (the other columns' pages are never read), `lanes.csv`
//! with only the asked-for cells parsed. Errors name the file, the row
//! and the column.

use std::path::Path;

use ::parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use ::parquet::arrow::ProjectionMask;
use arrow_array::RecordBatch;

use super::reading::{not_ours, open, Wanted};
use super::{columns, Format, Kind};
use crate::error::{Error, Result};
use crate::output::batch::{columns_for, data_type};

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
    // A search's columns are asked for only of a search's table.
    let search = names
        .iter()
        .any(|n| crate::columns::SEARCH.iter().any(|c| c.name == *n));
    let table = columns_for(search);
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

/// The names of the columns of the results table of `dir`, in table
/// order: a search run's table has the search's columns after the others.
pub fn folder_columns(dir: &Path) -> Result<Vec<&'static str>> {
    let format = Format::of_folder(dir)?;
    let path = dir.join(format.file_name());
    let width = match format {
        Format::Parquet => ParquetRecordBatchReaderBuilder::try_new(open(&path)?)
            .map_err(|e| Error::input(&path, None, None, format!("not a Parquet file: {e}")))?
            .parquet_schema()
            .root_schema()
            .get_fields()
            .len(),
        Format::Csv => {
            let mut rd = csv::ReaderBuilder::new()
                .has_headers(false)
                .from_reader(open(&path)?);
            let mut rec = csv::ByteRecord::new();
            rd.read_byte_record(&mut rec)
                .map_err(|e| Error::input(&path, Some("line 1".into()), None, e.to_string()))?;
            rec.len()
        }
    };
    let search = width == columns_for(true).len();
    Ok(columns_for(search).into_iter().map(|c| c.0).collect())
}

fn read_parquet(
    path: &Path,
    wanted: &Wanted,
    each: &mut impl FnMut(&RecordBatch) -> Result<()>,
) -> Result<()> {
    let bad = |m: String| Error::input(path, None, None, m);
    let b = ParquetRecordBatchReaderBuilder::try_new(open(path)?)
        .map_err(|e| bad(format!("not a Parquet file: {e}")))?;
    let descr = b.parquet_schema();
    let fields = descr.root_schema().get_fields();
    let table = columns_for(fields.len() > columns().len());
    if fields.len() != table.len() || fields.iter().zip(&table).any(|(f, c)| f.name() != c.0) {
        return Err(not_ours(path));
    }
    let mask = ProjectionMask::roots(descr, wanted.iter().map(|w| w.0));
    let rd = b
        .with_projection(mask)
        .with_batch_size(super::reading::BATCH_ROWS)
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
        let batch = crate::output::batch::canonical_batch(batch).map_err(|(col, m)| {
            Error::input(path, Some(format!("rows {}..", rows + 1)), Some(&col), m)
        })?;
        rows += batch.num_rows() as u64;
        each(&batch)?;
    }
    Ok(())
}
