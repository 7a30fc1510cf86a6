//! `lanes.parquet`: the results table as typed columns (DOUBLE and UTF-8
//! nullable: an empty cell is a null; INT64), written from the run's
//! Arrow batches with `parquet`'s Arrow column writers: LZ4 (`LZ4_RAW`) pages,
//! dictionary-encoded words, min/max statistics per column chunk
//! and page, and the Arrow schema in the footer for Arrow readers. Row
//! groups of [`ROW_GROUP`] rows; each group's columns encoded in
//! parallel, then spliced into the file in schema order (the same bytes
//! either way). The column writers take the rows [`STRIDE`] at a time
//! whatever the batches' sizes: they cut pages where a call's rows end,
//! so a run, a merge of its shards and a run on more threads write the
//! same bytes.

use std::path::{Path, PathBuf};

use ::parquet::arrow::arrow_writer::{
    compute_leaves, ArrowColumnWriter, ArrowRowGroupWriterFactory, ArrowWriter,
};
use ::parquet::basic::Compression;
use ::parquet::file::properties::{EnabledStatistics, WriterProperties};
use ::parquet::file::writer::SerializedFileWriter;
use ::parquet::schema::types::ColumnPath;
use arrow_array::{ArrayRef, RecordBatch};
use arrow_schema::FieldRef;

use super::Kind;
use crate::error::{Error, Result};
use crate::output::atomic::{AtomicFile, FileWriter};

/// Rows a row group: big enough to compress and scan well, small enough
/// that a reader holds one in a few tens of MB.
pub const ROW_GROUP: usize = 1 << 17;

/// Rows the column writers are handed at a time (a divisor of
/// [`ROW_GROUP`]): rows of batches cut elsewhere are joined or split to
/// it, so that pages end at the same rows however the table's batches
/// were cut.
const STRIDE: usize = 1 << 13;
const _: () = assert!(ROW_GROUP.is_multiple_of(STRIDE));

/// `lanes.parquet`, written a row group at a time (bounded memory).
pub struct ParquetLanes {
    file: AtomicFile,
    /// The table's schema (a search's has its columns).
    schema: arrow_schema::SchemaRef,
    path: PathBuf,
    writer: Option<SerializedFileWriter<FileWriter>>,
    factory: ArrowRowGroupWriterFactory,
    /// The current row group's column writers (one per column).
    cols: Vec<ArrowColumnWriter>,
    rows: usize,
    groups: usize,
    /// Rows waiting for a whole [`STRIDE`] (pieces of batches).
    pending: Vec<RecordBatch>,
    pending_rows: usize,
}

/// The writer's settings of `lanes.parquet` (also what the estimate of a
/// run's disk writes its trial rows with).
pub(crate) fn writer_properties(search: bool) -> WriterProperties {
    let mut props = WriterProperties::builder()
        // LZ4_RAW: about a fifth cheaper to encode than Snappy, for a
        // file of about the same size; pyarrow, pandas, polars and DuckDB
        // read it (docs/outputs.md's snippets run in a test).
        .set_compression(Compression::LZ4_RAW)
        // Words by dictionary (a handful of words a column); numbers
        // plain: a result takes a new value nearly every lane, and a
        // dictionary of a million floats costs more than it saves
        // (a fixed parameter's run of one value LZ4 packs anyway).
        .set_dictionary_enabled(false)
        .set_statistics_enabled(EnabledStatistics::Page)
        .set_max_row_group_row_count(Some(ROW_GROUP))
        .set_created_by(format!("tswm {}", env!("CARGO_PKG_VERSION")));
    for (name, kind) in crate::output::batch::columns_for(search) {
        if kind == Kind::Text {
            props = props.set_column_dictionary_enabled(ColumnPath::from(name), true);
        }
    }
    props.build()
}

pub(super) fn parquet_error(path: &Path, e: ::parquet::errors::ParquetError) -> Error {
    Error::io(path, std::io::Error::other(e.to_string()))
}

impl ParquetLanes {
    pub(super) fn create(path: &Path, hashed: bool, search: bool) -> Result<ParquetLanes> {
        let mut file = if hashed {
            AtomicFile::create_hashed(path)?
        } else {
            AtomicFile::create(path)?
        };
        let props = writer_properties(search);
        let pe = |e| parquet_error(path, e);
        let schema = crate::output::batch::schema_for(search);
        let (writer, factory) =
            ArrowWriter::try_new(file.take_writer(), schema.clone(), Some(props))
                .and_then(ArrowWriter::into_serialized_writer)
                .map_err(pe)?;
        let cols = factory.create_column_writers(0).map_err(pe)?;
        Ok(ParquetLanes {
            file,
            schema,
            path: path.to_path_buf(),
            writer: Some(writer),
            factory,
            cols,
            rows: 0,
            groups: 0,
            pending: Vec::new(),
            pending_rows: 0,
        })
    }

    /// Appends a batch's rows, its columns encoded in parallel on `pool`
    /// [`STRIDE`] rows at a time; a row group is written whenever
    /// [`ROW_GROUP`] rows are in.
    pub(super) fn write(
        &mut self,
        batch: &RecordBatch,
        pool: Option<&rayon::ThreadPool>,
    ) -> Result<()> {
        let mut at = 0;
        while at < batch.num_rows() {
            let n = (STRIDE - self.pending_rows).min(batch.num_rows() - at);
            let piece = batch.slice(at, n);
            at += n;
            if n == STRIDE {
                self.put(&piece, pool)?;
            } else {
                self.pending.push(piece);
                self.pending_rows += n;
                if self.pending_rows == STRIDE {
                    self.put_pending(pool)?;
                }
            }
        }
        Ok(())
    }

    /// Encodes the waiting rows as one piece.
    fn put_pending(&mut self, pool: Option<&rayon::ThreadPool>) -> Result<()> {
        if self.pending_rows == 0 {
            return Ok(());
        }
        let joined =
            arrow_select::concat::concat_batches(&self.schema, &self.pending).map_err(|e| {
                Error::Internal(format!("joining rows for {}: {e}", self.path.display()))
            })?;
        self.pending.clear();
        self.pending_rows = 0;
        self.put(&joined, pool)
    }

    /// Encodes `piece` (at most the rest of the row group).
    fn put(&mut self, piece: &RecordBatch, pool: Option<&rayon::ThreadPool>) -> Result<()> {
        let piece = without_empty_null_masks(piece)
            .map_err(|e| Error::Internal(format!("rows for {}: {e}", self.path.display())))?;
        self.encode(&piece, pool)?;
        self.rows += piece.num_rows();
        if self.rows == ROW_GROUP {
            self.flush_group(pool)?;
        }
        Ok(())
    }

    /// Encodes the columns of `batch` into the row group's writers.
    fn encode(&mut self, batch: &RecordBatch, pool: Option<&rayon::ThreadPool>) -> Result<()> {
        use rayon::prelude::*;
        let schema = self.schema.clone();
        let one = |((w, a), f): ((&mut ArrowColumnWriter, &ArrayRef), &FieldRef)| {
            for leaf in compute_leaves(f, a)? {
                w.write(&leaf)?;
            }
            Ok(())
        };
        let jobs: Vec<_> = self
            .cols
            .iter_mut()
            .zip(batch.columns())
            .zip(schema.fields())
            .collect();
        match pool {
            Some(pool) => pool.install(|| jobs.into_par_iter().try_for_each(one)),
            None => jobs.into_iter().try_for_each(one),
        }
        .map_err(|e| parquet_error(&self.path, e))
    }

    /// Writes the row group's columns to the file and starts the next:
    /// the columns' last pages encoded in parallel on `pool`, then
    /// appended in schema order.
    fn flush_group(&mut self, pool: Option<&rayon::ThreadPool>) -> Result<()> {
        use rayon::prelude::*;
        if self.rows == 0 {
            return Ok(());
        }
        let pe = |e| parquet_error(&self.path, e);
        self.groups += 1;
        let next = self
            .factory
            .create_column_writers(self.groups)
            .map_err(pe)?;
        let cols = std::mem::replace(&mut self.cols, next);
        let chunks: Vec<_> = match pool {
            Some(pool) => pool.install(|| cols.into_par_iter().map(|c| c.close()).collect()),
            None => cols.into_iter().map(|c| c.close()).collect(),
        };
        let w = self.writer.as_mut().expect("open");
        let mut rg = w.next_row_group().map_err(pe)?;
        for c in chunks {
            c.and_then(|chunk| chunk.append_to_row_group(&mut rg))
                .map_err(pe)?;
        }
        rg.close().map_err(pe)?;
        self.rows = 0;
        Ok(())
    }

    pub(super) fn finish(mut self) -> Result<AtomicFile> {
        self.put_pending(None)?;
        self.flush_group(None)?;
        let w = self.writer.take().expect("open");
        let inner = w.into_inner().map_err(|e| parquet_error(&self.path, e))?;
        self.file.restore_writer(inner);
        Ok(self.file)
    }
}

/// `batch` with no null mask on a column that has no null: a column
/// writer takes another path for a column with a mask than without (its
/// pages end elsewhere), and whether a piece of rows has one depends on
/// the batch it was cut from.
fn without_empty_null_masks(
    batch: &RecordBatch,
) -> std::result::Result<RecordBatch, arrow_schema::ArrowError> {
    let empty_mask = |a: &ArrayRef| a.nulls().is_some_and(|n| n.null_count() == 0);
    if !batch.columns().iter().any(empty_mask) {
        return Ok(batch.clone());
    }
    let cols = batch
        .columns()
        .iter()
        .map(|a| {
            if empty_mask(a) {
                Ok(arrow_array::make_array(
                    a.to_data().into_builder().nulls(None).build()?,
                ))
            } else {
                Ok(a.clone())
            }
        })
        .collect::<std::result::Result<Vec<_>, arrow_schema::ArrowError>>()?;
    RecordBatch::try_new(batch.schema(), cols)
}
