//! `lanes.parquet` as a [`TableFormat`]: written by [`ParquetLanes`],
//! read back through `parquet`'s Arrow reader with a projection (the
//! other columns' pages are never read).

use std::path::Path;

use ::parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use ::parquet::arrow::ProjectionMask;
use arrow_array::RecordBatch;

use super::parquet::writer_properties;
use super::reading::{not_ours, open, Wanted, BATCH_ROWS};
use super::{columns, ParquetLanes, TableFormat, TableWriter};
use crate::error::{Error, Result};
use crate::output::atomic::AtomicFile;
use crate::output::batch::{self, columns_for, data_type};
use crate::output::names;

/// The Parquet results table.
pub(super) struct ParquetTable;

impl TableFormat for ParquetTable {
    fn file_name(&self) -> &'static str {
        names::LANES_PARQUET
    }

    fn create(&self, path: &Path, hashed: bool, search: bool) -> Result<Box<dyn TableWriter>> {
        Ok(Box::new(ParquetLanes::create(path, hashed, search)?))
    }

    fn read(
        &self,
        path: &Path,
        wanted: &Wanted,
        each: &mut dyn FnMut(&RecordBatch) -> Result<()>,
    ) -> Result<()> {
        read_parquet(path, wanted, each)
    }

    fn width(&self, path: &Path) -> Result<usize> {
        Ok(ParquetRecordBatchReaderBuilder::try_new(open(path)?)
            .map_err(|e| Error::input(path, None, None, format!("not a Parquet file: {e}")))?
            .parquet_schema()
            .root_schema()
            .get_fields()
            .len())
    }

    /// The batch encoded with `lanes.parquet`'s settings in memory, less
    /// the bytes of an empty file.
    fn rows_bytes(&self, _pool: &rayon::ThreadPool, b: &RecordBatch) -> Result<u64> {
        let schema = b.schema();
        let names: Vec<&str> = schema.fields().iter().map(|f| f.name().as_str()).collect();
        let search = batch::is_search(&names);
        let size = |b: Option<&RecordBatch>| -> Result<u64> {
            let e = |e| Error::Internal(format!("estimating lanes.parquet: {e}"));
            let mut w = ::parquet::arrow::ArrowWriter::try_new(
                Vec::new(),
                batch::schema_for(search),
                Some(writer_properties(search)),
            )
            .map_err(e)?;
            if let Some(b) = b {
                w.write(b).map_err(e)?;
            }
            Ok(w.into_inner().map_err(e)?.len() as u64)
        };
        Ok(size(Some(b))?.saturating_sub(size(None)?))
    }
}

impl TableWriter for ParquetLanes {
    fn write_batch(&mut self, pool: &rayon::ThreadPool, b: &RecordBatch) -> Result<()> {
        self.write(b, Some(pool))
    }

    fn finish(self: Box<Self>) -> Result<AtomicFile> {
        (*self).finish()
    }
}

fn read_parquet(
    path: &Path,
    wanted: &Wanted,
    each: &mut dyn FnMut(&RecordBatch) -> Result<()>,
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
        let batch = batch::canonical_batch(batch).map_err(|(col, m)| {
            Error::input(path, Some(format!("rows {}..", rows + 1)), Some(&col), m)
        })?;
        rows += batch.num_rows() as u64;
        each(&batch)?;
    }
    Ok(())
}
