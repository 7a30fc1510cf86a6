//! `lanes.parquet`: the results table as typed columns (DOUBLE and UTF-8
//! nullable: an empty cell is a null; INT64), Snappy-compressed, written a row group at a time with
//! each group's columns encoded in parallel.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use ::parquet::basic::{Compression, Repetition, Type as Physical};
use ::parquet::column::writer::{
    get_column_writer, get_typed_column_writer_mut, ColumnCloseResult,
};
use ::parquet::data_type::{ByteArray, ByteArrayType, DoubleType, Int64Type};
use ::parquet::file::properties::WriterProperties;
use ::parquet::file::writer::{SerializedFileWriter, SerializedPageWriter, TrackedWrite};
use ::parquet::schema::types::Type;

use super::{columns, Cell, Kind};
use crate::error::{Error, Result};
use crate::output::atomic::AtomicFile;

/// Rows buffered per row group: 64 Ki rows of ~60 columns is ~30 MB, and
/// row groups this size compress and scan well.
const ROW_GROUP: usize = 1 << 16;

/// One column's values of the row group being filled.
enum Buffer {
    Float(Vec<f64>, Vec<i16>),
    Int(Vec<i64>),
    /// Words, and their definition levels (0: an empty cell, a null).
    Text(Vec<ByteArray>, Vec<i16>),
}

/// Encodes one column of a row group into memory; the buffers are left
/// empty for the next group.
fn encode_column(
    descr: ::parquet::schema::types::ColumnDescPtr,
    props: Arc<WriterProperties>,
    b: &mut Buffer,
) -> ::parquet::errors::Result<(bytes::Bytes, ColumnCloseResult)> {
    let mut sink = TrackedWrite::new(Vec::new());
    let close = {
        let pages = Box::new(SerializedPageWriter::new(&mut sink));
        let mut col = get_column_writer(descr, props, pages);
        match b {
            Buffer::Float(v, def) => {
                get_typed_column_writer_mut::<DoubleType>(&mut col).write_batch(
                    v,
                    Some(def),
                    None,
                )?;
                v.clear();
                def.clear();
            }
            Buffer::Int(v) => {
                get_typed_column_writer_mut::<Int64Type>(&mut col).write_batch(v, None, None)?;
                v.clear();
            }
            Buffer::Text(v, def) => {
                get_typed_column_writer_mut::<ByteArrayType>(&mut col).write_batch(
                    v,
                    Some(def),
                    None,
                )?;
                v.clear();
                def.clear();
            }
        }
        col.close()?
    };
    Ok((bytes::Bytes::from(sink.into_inner()?), close))
}

/// `lanes.parquet`, written a row group at a time (bounded memory).
pub struct ParquetLanes {
    file: AtomicFile,
    path: PathBuf,
    writer: Option<SerializedFileWriter<crate::output::atomic::FileWriter>>,
    bufs: Vec<Buffer>,
    rows: usize,
}

/// The Parquet schema of the results table.
fn schema() -> Result<Type> {
    let fields = columns()
        .into_iter()
        .map(|(name, kind)| {
            let b = match kind {
                Kind::Float => Type::primitive_type_builder(name, Physical::DOUBLE)
                    .with_repetition(Repetition::OPTIONAL),
                Kind::Int => Type::primitive_type_builder(name, Physical::INT64)
                    .with_repetition(Repetition::REQUIRED),
                // An empty word (no `hold`, no table) is a null, as an
                // empty number is.
                Kind::Text => Type::primitive_type_builder(name, Physical::BYTE_ARRAY)
                    .with_repetition(Repetition::OPTIONAL)
                    .with_logical_type(Some(::parquet::basic::LogicalType::String)),
            };
            b.build().map(Arc::new)
        })
        .collect::<std::result::Result<Vec<_>, _>>()
        .map_err(|e| Error::Internal(format!("parquet schema: {e}")))?;
    Type::group_type_builder("tswm_lanes")
        .with_fields(fields)
        .build()
        .map_err(|e| Error::Internal(format!("parquet schema: {e}")))
}

pub(super) fn parquet_error(path: &Path, e: ::parquet::errors::ParquetError) -> Error {
    Error::io(path, std::io::Error::other(e.to_string()))
}

impl ParquetLanes {
    pub(super) fn create(path: &Path, hashed: bool) -> Result<ParquetLanes> {
        let mut file = if hashed {
            AtomicFile::create_hashed(path)?
        } else {
            AtomicFile::create(path)?
        };
        let props = WriterProperties::builder()
            // Snappy: fast, and read by every Parquet reader.
            .set_compression(Compression::SNAPPY)
            .set_created_by(format!("tswm {}", env!("CARGO_PKG_VERSION")))
            .build();
        let writer =
            SerializedFileWriter::new(file.take_writer(), Arc::new(schema()?), Arc::new(props))
                .map_err(|e| parquet_error(path, e))?;
        let bufs = columns()
            .iter()
            .map(|(_, k)| match k {
                Kind::Float => Buffer::Float(Vec::new(), Vec::new()),
                Kind::Int => Buffer::Int(Vec::new()),
                Kind::Text => Buffer::Text(Vec::new(), Vec::new()),
            })
            .collect();
        Ok(ParquetLanes {
            file,
            path: path.to_path_buf(),
            writer: Some(writer),
            bufs,
            rows: 0,
        })
    }

    /// Appends a row to the column buffers, and writes them as a row
    /// group when it is full (its columns encoded on `pool` when given).
    pub(super) fn write(&mut self, cells: &[Cell], pool: Option<&rayon::ThreadPool>) -> Result<()> {
        for (b, c) in self.bufs.iter_mut().zip(cells) {
            match (b, c) {
                (Buffer::Float(v, def), Cell::F(x)) => {
                    if x.is_nan() {
                        def.push(0);
                    } else {
                        def.push(1);
                        v.push(*x);
                    }
                }
                (Buffer::Int(v), Cell::I(x)) => v.push(*x as i64),
                (Buffer::Text(v, def), Cell::S(t)) => {
                    if t.is_empty() {
                        def.push(0);
                    } else {
                        def.push(1);
                        v.push(ByteArray::from(t.as_ref()));
                    }
                }
                _ => return Err(Error::Internal("a cell of the wrong kind".into())),
            }
        }
        self.rows += 1;
        if self.rows == ROW_GROUP {
            self.flush_group(pool)?;
        }
        Ok(())
    }

    /// Writes the buffered rows as a row group. Its columns are encoded
    /// and compressed each into a buffer of its own, in parallel on
    /// `pool` when given (the encoder is most of Parquet's cost), then
    /// spliced into the file in schema order: the same bytes either way.
    fn flush_group(&mut self, pool: Option<&rayon::ThreadPool>) -> Result<()> {
        use rayon::prelude::*;
        if self.rows == 0 {
            return Ok(());
        }
        let path = &self.path;
        let w = self.writer.as_mut().expect("open");
        let descr = w.schema_descr();
        let jobs: Vec<_> = self
            .bufs
            .iter_mut()
            .enumerate()
            .map(|(i, b)| (descr.column(i), b))
            .collect();
        let props = w.properties();
        let encode = |(d, b): (::parquet::schema::types::ColumnDescPtr, &mut Buffer)| {
            encode_column(d, props.clone(), b)
        };
        let chunks: Vec<_> = match pool {
            Some(pool) => pool.install(|| jobs.into_par_iter().map(encode).collect()),
            None => jobs.into_iter().map(encode).collect(),
        };
        let mut rg = w.next_row_group().map_err(|e| parquet_error(path, e))?;
        for c in chunks {
            let (data, close) = c.map_err(|e| parquet_error(path, e))?;
            rg.append_column(&data, close)
                .map_err(|e| parquet_error(path, e))?;
        }
        rg.close().map_err(|e| parquet_error(path, e))?;
        self.rows = 0;
        Ok(())
    }

    pub(super) fn finish(mut self) -> Result<AtomicFile> {
        self.flush_group(None)?;
        let w = self.writer.take().expect("open");
        let inner = w.into_inner().map_err(|e| parquet_error(&self.path, e))?;
        self.file.restore_writer(inner);
        Ok(self.file)
    }
}
