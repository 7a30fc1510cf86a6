//! The results table on disk, in either format: `lanes.csv` (text, the
//! default) or `lanes.parquet` (typed columns, MODEL.md section 9 order,
//! empty cells as nulls). One row is a list of [`Cell`]s, built once
//! ([`row_cells`]) and written by either writer; either file reads back as
//! the same text records ([`RowReader`]), the float cells spelled as
//! `lanes.csv` spells them (the shortest text that reads back to the same
//! f64), so `merge` and `report` treat both alike and a CSV written from a
//! Parquet file is byte-identical to one written directly.

use std::borrow::Cow;
use std::fs::File;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use parquet::basic::{Compression, Repetition, Type as Physical};
use parquet::column::writer::{get_column_writer, get_typed_column_writer_mut, ColumnCloseResult};
use parquet::data_type::{ByteArray, ByteArrayType, DoubleType, Int64Type};
use parquet::file::properties::WriterProperties;
use parquet::file::reader::FileReader;
use parquet::file::serialized_reader::SerializedFileReader;
use parquet::file::writer::{SerializedFileWriter, SerializedPageWriter, TrackedWrite};
use parquet::record::Field;
use parquet::schema::types::Type;

use crate::columns::results;
pub use crate::columns::{Cell, Kind};
use crate::error::{Error, Result};
use crate::integrator::LaneResult;
use crate::output::csv_lines::{push_f64, CsvLines};
use crate::output::digest::{FileDigest, Hashing};
use crate::output::AtomicFile;
use crate::params::{Param, Params};

/// The format of the results table.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "lowercase")]
pub enum Format {
    /// `lanes.csv`.
    Csv,
    /// `lanes.parquet`.
    Parquet,
}

impl Format {
    /// The table's file name in an output folder.
    pub fn file_name(self) -> &'static str {
        match self {
            Format::Csv => "lanes.csv",
            Format::Parquet => "lanes.parquet",
        }
    }

    /// The other format's file name (an earlier run's, stale beside ours).
    pub fn other(self) -> Format {
        match self {
            Format::Csv => Format::Parquet,
            Format::Parquet => Format::Csv,
        }
    }

    /// The results table of the folder `dir`: `lanes.csv`, else
    /// `lanes.parquet`; an error naming the folder when neither is there.
    pub fn of_folder(dir: &Path) -> Result<Format> {
        for f in [Format::Csv, Format::Parquet] {
            if dir.join(f.file_name()).is_file() {
                return Ok(f);
            }
        }
        Err(Error::input(
            dir,
            None,
            None,
            "holds no lanes.csv or lanes.parquet; allowed: a folder written by `tswm run` or `tswm merge`",
        ))
    }
}

/// The columns of the results table, in order, with their kinds: the
/// parameters (MODEL.md section 9 order), then the result columns of
/// [`crate::columns::RESULTS`].
pub fn columns() -> Vec<(&'static str, Kind)> {
    let mut c: Vec<(&'static str, Kind)> = Param::COLUMNS
        .iter()
        .map(|p| match p {
            Param::Num(_) => (p.name(), Kind::Float),
            _ => (p.name(), Kind::Text),
        })
        .collect();
    c.extend(results().iter().map(|r| (r.name, r.kind)));
    c
}

/// Lane `lane`'s row, in [`columns`] order, into `out` (cleared first).
pub fn row_cells(lane: u64, p: &Params, r: &LaneResult, out: &mut Vec<Cell>) {
    out.clear();
    for c in Param::COLUMNS {
        out.push(match c {
            Param::Motor => Cell::S(Cow::Borrowed(p.motor.name())),
            Param::Friction => Cell::S(Cow::Borrowed(p.friction.name())),
            Param::Num(n) => Cell::F(p.get(n)),
        });
    }
    out.extend(results().iter().map(|c| (c.cell)(lane, r)));
}

/// A row of `lanes.csv`, without its line end: the cells joined by
/// commas, floats as their shortest round-trip text, NaN as an empty cell.
fn push_csv_row(s: &mut String, cells: &[Cell]) {
    use std::fmt::Write as _;
    for (i, c) in cells.iter().enumerate() {
        if i > 0 {
            s.push(',');
        }
        match c {
            Cell::F(v) => push_f64(s, *v),
            Cell::I(v) => {
                let _ = write!(s, "{v}");
            }
            Cell::S(t) => s.push_str(t),
        }
    }
}

/// Writes rows to the results table in either format, under a temporary
/// name; committed with the run's other files.
pub enum LanesWriter {
    /// `lanes.csv`.
    Csv(CsvLines),
    /// `lanes.parquet`.
    Parquet(Box<ParquetLanes>),
}

impl LanesWriter {
    /// Starts the table `dir/lanes.{csv,parquet}`.
    /// `hashed`: the file's SHA-256 is computed as it is written (a
    /// shard's, for its manifest).
    pub fn create(dir: &Path, format: Format, hashed: bool) -> Result<LanesWriter> {
        let path = dir.join(format.file_name());
        Ok(match format {
            Format::Csv => {
                let header: Vec<&str> = columns().iter().map(|c| c.0).collect();
                LanesWriter::Csv(CsvLines::start(&path, &header.join(","), hashed)?)
            }
            Format::Parquet => LanesWriter::Parquet(Box::new(ParquetLanes::create(&path, hashed)?)),
        })
    }

    /// Appends a row of cells, in [`columns`] order.
    pub fn write_cells(&mut self, cells: &[Cell]) -> Result<()> {
        match self {
            LanesWriter::Csv(w) => {
                push_csv_row(w.line(), cells);
                w.end_line()
            }
            LanesWriter::Parquet(w) => w.write(cells, None),
        }
    }

    /// Appends the rows of lanes `first..first + params.len()`. CSV rows
    /// are formatted in parallel on `pool`, blocks of rows at a time, and
    /// written in lane order; Parquet rows go to the column buffers.
    pub fn write_lanes(
        &mut self,
        pool: &rayon::ThreadPool,
        first: u64,
        params: &[Params],
        results: &[LaneResult],
        cells: &mut Vec<Cell>,
    ) -> Result<()> {
        match self {
            LanesWriter::Csv(w) => {
                use rayon::prelude::*;
                // Blocks big enough that a task's overhead is nothing
                // beside formatting its rows, small enough to share a
                // chunk among every thread.
                const BLOCK: usize = 512;
                let blocks: Vec<String> = pool.install(|| {
                    params
                        .par_chunks(BLOCK)
                        .zip(results.par_chunks(BLOCK))
                        .enumerate()
                        .map(|(b, (ps, rs))| {
                            let mut s = String::with_capacity(ps.len() * 448);
                            let mut cells = Vec::with_capacity(64);
                            for (i, (p, r)) in ps.iter().zip(rs).enumerate() {
                                row_cells(first + (b * BLOCK + i) as u64, p, r, &mut cells);
                                push_csv_row(&mut s, &cells);
                                s.push('\n');
                            }
                            s
                        })
                        .collect()
                });
                for b in blocks {
                    w.write_raw(b.as_bytes())?;
                }
                Ok(())
            }
            LanesWriter::Parquet(w) => {
                for (i, (p, r)) in params.iter().zip(results).enumerate() {
                    row_cells(first + i as u64, p, r, cells);
                    w.write(cells, Some(pool))?;
                }
                Ok(())
            }
        }
    }

    /// Appends a row read back by a [`RowReader`]: `rec` its text, `cells`
    /// its cells as [`RowReader::read_cells`] typed them. A CSV row is
    /// copied as it was read (the same bytes as the shard's).
    pub fn write_row(&mut self, rec: &csv::ByteRecord, cells: &[Cell]) -> Result<()> {
        match self {
            LanesWriter::Csv(w) => {
                let s = w.line();
                for (i, f) in rec.iter().enumerate() {
                    if i > 0 {
                        s.push(',');
                    }
                    s.push_str(std::str::from_utf8(f).unwrap_or(""));
                }
                w.end_line()
            }
            LanesWriter::Parquet(w) => w.write(cells, None),
        }
    }

    /// The finished file, to be committed with the run's other files.
    pub fn into_file(self) -> Result<AtomicFile> {
        match self {
            LanesWriter::Csv(w) => Ok(w.into_file()),
            LanesWriter::Parquet(w) => w.finish(),
        }
    }
}

/// Rows buffered per row group: 64 Ki rows of ~60 columns is ~30 MB, and
/// row groups this size compress and scan well.
const ROW_GROUP: usize = 1 << 16;

/// One column's values of the row group being filled.
enum Buffer {
    Float(Vec<f64>, Vec<i16>),
    Int(Vec<i64>),
    Text(Vec<ByteArray>),
}

/// Encodes one column of a row group into memory; the buffers are left
/// empty for the next group.
fn encode_column(
    descr: parquet::schema::types::ColumnDescPtr,
    props: Arc<WriterProperties>,
    b: &mut Buffer,
) -> parquet::errors::Result<(bytes::Bytes, ColumnCloseResult)> {
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
            Buffer::Text(v) => {
                get_typed_column_writer_mut::<ByteArrayType>(&mut col)
                    .write_batch(v, None, None)?;
                v.clear();
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
                Kind::Text => Type::primitive_type_builder(name, Physical::BYTE_ARRAY)
                    .with_repetition(Repetition::REQUIRED)
                    .with_logical_type(Some(parquet::basic::LogicalType::String)),
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

fn parquet_error(path: &Path, e: parquet::errors::ParquetError) -> Error {
    Error::io(path, std::io::Error::other(e.to_string()))
}

impl ParquetLanes {
    fn create(path: &Path, hashed: bool) -> Result<ParquetLanes> {
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
                Kind::Text => Buffer::Text(Vec::new()),
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
    fn write(&mut self, cells: &[Cell], pool: Option<&rayon::ThreadPool>) -> Result<()> {
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
                (Buffer::Text(v), Cell::S(t)) => v.push(ByteArray::from(t.as_ref())),
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
        let encode = |(d, b): (parquet::schema::types::ColumnDescPtr, &mut Buffer)| {
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

    fn finish(mut self) -> Result<AtomicFile> {
        self.flush_group(None)?;
        let w = self.writer.take().expect("open");
        let inner = w.into_inner().map_err(|e| parquet_error(&self.path, e))?;
        self.file.restore_writer(inner);
        Ok(self.file)
    }
}

/// Reads a results table, either format, as text records (the header
/// first, through [`RowReader::header`]).
pub struct RowReader {
    path: PathBuf,
    header: csv::ByteRecord,
    inner: Inner,
    rows: u64,
}

enum Inner {
    Csv(csv::Reader<Hashing<File>>),
    Parquet(parquet::record::reader::RowIter<'static>),
}

impl RowReader {
    /// Opens the results table of `dir` (`lanes.csv` or `lanes.parquet`).
    pub fn open_folder(dir: &Path) -> Result<RowReader> {
        let f = Format::of_folder(dir)?;
        RowReader::open(&dir.join(f.file_name()), f)
    }

    /// Opens `path` in `format`.
    pub fn open(path: &Path, format: Format) -> Result<RowReader> {
        let bad = |m: String| Error::input(path, None, None, m);
        match format {
            Format::Csv => {
                let f = File::open(path).map_err(|e| bad(format!("cannot read it: {e}")))?;
                // Hashed as it is read: a merge checks a shard's table
                // against its manifest without reading it twice.
                let mut rd = csv::Reader::from_reader(Hashing::new(f));
                let header = rd
                    .byte_headers()
                    .map_err(|e| bad(format!("not a tswm table: {e}")))?
                    .clone();
                Ok(RowReader {
                    path: path.into(),
                    header,
                    inner: Inner::Csv(rd),
                    rows: 0,
                })
            }
            Format::Parquet => {
                let f = File::open(path).map_err(|e| bad(format!("cannot read it: {e}")))?;
                let rd = SerializedFileReader::new(f)
                    .map_err(|e| bad(format!("not a Parquet file: {e}")))?;
                let mut header = csv::ByteRecord::new();
                for field in rd.metadata().file_metadata().schema().get_fields() {
                    header.push_field(field.name().as_bytes());
                }
                Ok(RowReader {
                    path: path.into(),
                    header,
                    inner: Inner::Parquet(rd.into_iter()),
                    rows: 0,
                })
            }
        }
    }

    /// The size and SHA-256 of what was read so far of a CSV table (the
    /// whole file once [`RowReader::read`] has returned false); None for
    /// Parquet, which is not read as a stream of bytes.
    pub fn digest(&self) -> Option<FileDigest> {
        match &self.inner {
            Inner::Csv(rd) => rd.get_ref().digest(),
            Inner::Parquet(_) => None,
        }
    }

    /// Reads the next row into `cells`, typed by `kinds` (the table's
    /// columns): floats (empty: NaN), counts and words. Errors name the
    /// row and the column of a cell that is not of its column's kind; a
    /// row of another length is an error too. False at the end.
    pub fn read_cells(
        &mut self,
        rec: &mut csv::ByteRecord,
        kinds: &[(&'static str, Kind)],
        cells: &mut Vec<Cell>,
    ) -> Result<bool> {
        if !self.read(rec)? {
            return Ok(false);
        }
        let row = self.rows;
        let bad = |col: &str, m: String| {
            Error::input(&self.path, Some(format!("row {row}")), Some(col), m)
        };
        if rec.len() != kinds.len() {
            return Err(bad(
                "",
                format!(
                    "has {} cells, the table's header {}; not a tswm table",
                    rec.len(),
                    kinds.len()
                ),
            ));
        }
        cells.clear();
        for (&(name, kind), f) in kinds.iter().zip(rec.iter()) {
            let t =
                std::str::from_utf8(f).map_err(|_| bad(name, "is not valid UTF-8 text".into()))?;
            cells.push(match kind {
                Kind::Float if t.is_empty() => Cell::F(f64::NAN),
                Kind::Float => match t.parse::<f64>() {
                    Ok(v) if v.is_finite() => Cell::F(v),
                    _ => {
                        return Err(bad(
                            name,
                            format!("`{}` is not a finite number", crate::error::shown(t, 40)),
                        ))
                    }
                },
                Kind::Int => Cell::I(t.parse().map_err(|_| {
                    bad(
                        name,
                        format!("`{}` is not a whole number", crate::error::shown(t, 40)),
                    )
                })?),
                Kind::Text => Cell::S(Cow::Owned(t.to_string())),
            });
        }
        Ok(true)
    }

    /// The column names.
    pub fn header(&self) -> &csv::ByteRecord {
        &self.header
    }

    /// The file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Reads the next row into `rec`; false at the end.
    pub fn read(&mut self, rec: &mut csv::ByteRecord) -> Result<bool> {
        let path = &self.path;
        let more = match &mut self.inner {
            Inner::Csv(rd) => rd.read_byte_record(rec).map_err(|e| {
                let line = e.position().map(|p| format!("line {}", p.line()));
                Error::input(path, line, None, format!("not a tswm table: {e}"))
            })?,
            Inner::Parquet(it) => match it.next() {
                None => false,
                Some(row) => {
                    let row = row.map_err(|e| {
                        Error::input(
                            path,
                            Some(format!("row {}", self.rows + 1)),
                            None,
                            format!("not a tswm table: {e}"),
                        )
                    })?;
                    rec.clear();
                    let mut s = String::new();
                    for (_, f) in row.get_column_iter() {
                        s.clear();
                        match f {
                            Field::Null => {}
                            Field::Double(v) => push_f64(&mut s, *v),
                            Field::Long(v) => {
                                use std::fmt::Write as _;
                                let _ = write!(s, "{v}");
                            }
                            Field::Str(t) => s.push_str(t),
                            other => {
                                use std::fmt::Write as _;
                                let _ = write!(s, "{other}");
                            }
                        }
                        rec.push_field(s.as_bytes());
                    }
                    true
                }
            },
        };
        if more {
            self.rows += 1;
        }
        Ok(more)
    }
}
