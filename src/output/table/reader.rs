//! Reading a results table back, either format, as text records: float
//! cells spelled as `lanes.csv` spells them, so `merge` and `report` treat
//! both alike; and typed cells for a reader that checks them.

use std::borrow::Cow;
use std::fs::File;
use std::path::{Path, PathBuf};

use ::parquet::basic::Type as Physical;
use ::parquet::column::reader::get_typed_column_reader;
use ::parquet::data_type::{ByteArray, ByteArrayType, DoubleType, Int64Type};
use ::parquet::file::reader::FileReader;
use ::parquet::file::serialized_reader::SerializedFileReader;

use super::{Cell, Format, Kind};
use crate::error::{Error, Result};
use crate::output::csv_lines::push_f64;
use crate::output::digest::{FileDigest, Hashing};

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
    Parquet(ParquetRows),
}

/// A Parquet table read a row group at a time, column by column with the
/// typed column readers (a row of `Field`s per lane costs an allocation a
/// cell), then handed out row by row.
struct ParquetRows {
    file: SerializedFileReader<File>,
    /// The next row group to read.
    group: usize,
    /// The current group's columns.
    cols: Vec<Column>,
    /// Rows of the current group, and the next one to hand out.
    rows: usize,
    next: usize,
}

/// One column of a row group: its values (present cells only), its
/// definition levels (empty for a column that is never null) and the next
/// value's index.
enum Column {
    Double(Vec<f64>, Vec<i16>, usize),
    Long(Vec<i64>, Vec<i16>, usize),
    Bytes(Vec<ByteArray>, Vec<i16>, usize),
}

/// The `n` values of one column chunk, with their definition levels when
/// the column may hold nulls (empty otherwise).
fn read_column<T: ::parquet::data_type::DataType>(
    col: ::parquet::column::reader::ColumnReader,
    n: usize,
    nullable: bool,
) -> ::parquet::errors::Result<(Vec<T::T>, Vec<i16>)> {
    let (mut v, mut def) = (Vec::with_capacity(n), Vec::new());
    get_typed_column_reader::<T>(col).read_records(
        n,
        nullable.then_some(&mut def),
        None,
        &mut v,
    )?;
    Ok((v, def))
}

impl ParquetRows {
    /// Reads row group `self.group` into `self.cols`; false past the last.
    fn load(&mut self) -> ::parquet::errors::Result<bool> {
        if self.group >= self.file.num_row_groups() {
            return Ok(false);
        }
        let rg = self.file.get_row_group(self.group)?;
        let n = rg.metadata().num_rows() as usize;
        self.cols.clear();
        for i in 0..rg.num_columns() {
            let descr = rg.metadata().column(i).column_descr_ptr();
            let nullable = descr.max_def_level() > 0;
            let col = rg.get_column_reader(i)?;
            self.cols.push(match descr.physical_type() {
                Physical::DOUBLE => {
                    let (v, def) = read_column::<DoubleType>(col, n, nullable)?;
                    Column::Double(v, def, 0)
                }
                Physical::INT64 => {
                    let (v, def) = read_column::<Int64Type>(col, n, nullable)?;
                    Column::Long(v, def, 0)
                }
                Physical::BYTE_ARRAY => {
                    let (v, def) = read_column::<ByteArrayType>(col, n, nullable)?;
                    Column::Bytes(v, def, 0)
                }
                t => {
                    return Err(::parquet::errors::ParquetError::General(format!(
                        "column {} is {t}, which no tswm table has",
                        descr.name()
                    )))
                }
            });
        }
        self.group += 1;
        self.rows = n;
        self.next = 0;
        Ok(true)
    }

    /// Writes the next row's cells into `rec` as `lanes.csv` spells them;
    /// false at the end.
    fn read(
        &mut self,
        rec: &mut csv::ByteRecord,
        s: &mut String,
    ) -> ::parquet::errors::Result<bool> {
        while self.next == self.rows {
            if !self.load()? {
                return Ok(false);
            }
        }
        let row = self.next;
        self.next += 1;
        rec.clear();
        let short = || ::parquet::errors::ParquetError::General("a column ends early".into());
        for c in &mut self.cols {
            s.clear();
            // A cell is present where its definition level is 1 (or the
            // column is never null).
            let present = |def: &Vec<i16>| def.is_empty() || def.get(row) == Some(&1);
            match c {
                Column::Double(v, def, k) => {
                    if present(def) {
                        push_f64(s, *v.get(*k).ok_or_else(short)?);
                        *k += 1;
                    }
                }
                Column::Long(v, def, k) => {
                    if present(def) {
                        use std::fmt::Write as _;
                        let _ = write!(s, "{}", v.get(*k).ok_or_else(short)?);
                        *k += 1;
                    }
                }
                Column::Bytes(v, def, k) => {
                    if present(def) {
                        rec.push_field(v.get(*k).ok_or_else(short)?.data());
                        *k += 1;
                        continue;
                    }
                }
            }
            rec.push_field(s.as_bytes());
        }
        Ok(true)
    }
}

impl RowReader {
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
                    inner: Inner::Parquet(ParquetRows {
                        file: rd,
                        group: 0,
                        cols: Vec::new(),
                        rows: 0,
                        next: 0,
                    }),
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
            Inner::Parquet(p) => {
                let mut s = String::new();
                p.read(rec, &mut s).map_err(|e| {
                    Error::input(
                        path,
                        Some(format!("row {}", self.rows + 1)),
                        None,
                        format!("not a tswm table: {e}"),
                    )
                })?
            }
        };
        if more {
            self.rows += 1;
        }
        Ok(more)
    }
}
