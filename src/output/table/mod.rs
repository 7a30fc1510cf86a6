//! The results table on disk, in either format: `lanes.csv` (text, the
//! default) or `lanes.parquet` (typed columns, docs/model.md section 9 order,
//! empty cells as nulls). A run's rows come as batches of columns
//! ([`crate::output::batch`]), written by either writer; a table is read
//! back as batches of the columns a reader asks for ([`read_batches`],
//! the report), or as the same text records whichever its format
//! ([`RowReader`], a merge: the float cells spelled as `lanes.csv` spells
//! them, so a CSV written from a Parquet file is byte-identical to one
//! written directly).

mod batches;
mod csv_read;
mod csv_rows;
mod parquet;
mod reader;
mod reading;

use std::path::Path;

pub use self::batches::{folder_columns, read_batches};
pub use self::csv_rows::CsvBlocks;
pub use self::parquet::{ParquetLanes, ROW_GROUP};
pub use crate::columns::{Cell, Kind};
use crate::error::{Error, Result};
use crate::output::atomic::AtomicFile;
use crate::output::batch;
pub use crate::output::batch::columns;
use crate::output::csv_lines::CsvLines;
use crate::output::names;
use arrow_array::RecordBatch;
pub use reader::RowReader;

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
            Format::Csv => names::LANES_CSV,
            Format::Parquet => names::LANES_PARQUET,
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

/// Writes rows to the results table in either format, under a temporary
/// name; committed with the run's other files.
pub enum LanesWriter {
    /// `lanes.csv`, and the buffers its blocks of rows are formatted in.
    Csv(CsvLines, CsvBlocks),
    /// `lanes.parquet`, the rows given as cells not yet written, and
    /// whether it is a search's table.
    Parquet(Box<ParquetLanes>, Vec<Cell>, bool),
}

/// The bytes the rows of `batch` take in a table of `format` (no
/// header), as its writer writes them: CSV rows formatted on `pool`, or
/// the batch encoded with `lanes.parquet`'s settings in memory, less the
/// bytes of an empty file (for the estimate of a run's disk).
pub fn rows_bytes(format: Format, pool: &rayon::ThreadPool, batch: &RecordBatch) -> Result<u64> {
    match format {
        Format::Csv => {
            let mut bytes = 0u64;
            CsvBlocks::default().format(pool, batch, |text| {
                bytes += text.len() as u64;
                Ok(())
            })?;
            Ok(bytes)
        }
        Format::Parquet => {
            let search = batch::is_search(
                &batch
                    .schema()
                    .fields()
                    .iter()
                    .map(|f| f.name().as_str())
                    .collect::<Vec<_>>(),
            );
            let size = |b: Option<&RecordBatch>| -> Result<u64> {
                let mut w = ::parquet::arrow::ArrowWriter::try_new(
                    Vec::new(),
                    batch::schema_for(search),
                    Some(parquet::writer_properties(search)),
                )
                .map_err(|e| Error::Internal(format!("estimating lanes.parquet: {e}")))?;
                if let Some(b) = b {
                    w.write(b)
                        .map_err(|e| Error::Internal(format!("estimating lanes.parquet: {e}")))?;
                }
                let v = w
                    .into_inner()
                    .map_err(|e| Error::Internal(format!("estimating lanes.parquet: {e}")))?;
                Ok(v.len() as u64)
            };
            Ok(size(Some(batch))?.saturating_sub(size(None)?))
        }
    }
}

/// Rows given as cells (a merge's) gathered into one batch for Parquet.
const CELL_ROWS: usize = 8192;

impl LanesWriter {
    /// Starts the table `dir/lanes.{csv,parquet}`.
    /// `hashed`: the file's SHA-256 is computed as it is written (a
    /// shard's, for its manifest).
    /// `search`: a search run's table, with the search's columns.
    pub fn create(dir: &Path, format: Format, hashed: bool, search: bool) -> Result<LanesWriter> {
        let path = dir.join(format.file_name());
        Ok(match format {
            Format::Csv => {
                let header: Vec<&str> = batch::columns_for(search).iter().map(|c| c.0).collect();
                LanesWriter::Csv(
                    CsvLines::start(&path, &header.join(","), hashed)?,
                    CsvBlocks::default(),
                )
            }
            Format::Parquet => LanesWriter::Parquet(
                Box::new(ParquetLanes::create(&path, hashed, search)?),
                Vec::new(),
                search,
            ),
        })
    }

    /// Appends the rows of a batch of the run: CSV rows formatted in
    /// parallel on `pool`, blocks of rows at a time, and written in lane
    /// order; Parquet columns encoded in parallel.
    pub fn write_batch(&mut self, pool: &rayon::ThreadPool, b: &RecordBatch) -> Result<()> {
        match self {
            LanesWriter::Csv(w, blocks) => blocks.format(pool, b, |text| w.write_raw(text)),
            LanesWriter::Parquet(w, ..) => w.write(b, Some(pool)),
        }
    }

    /// Appends a row read back by a [`RowReader`]: `rec` its text, `cells`
    /// its cells as [`RowReader::read_cells`] typed them. A CSV row is
    /// copied as it was read (the same bytes as the shard's).
    pub fn write_row(&mut self, rec: &csv::ByteRecord, cells: &[Cell]) -> Result<()> {
        match self {
            LanesWriter::Csv(w, _) => {
                let s = w.line();
                for (i, f) in rec.iter().enumerate() {
                    if i > 0 {
                        s.push(',');
                    }
                    s.push_str(std::str::from_utf8(f).unwrap_or(""));
                }
                w.end_line()
            }
            LanesWriter::Parquet(w, rows, search) => {
                rows.extend_from_slice(cells);
                if rows.len() >= CELL_ROWS * cells.len() {
                    w.write(&batch::from_cells(rows, *search)?, None)?;
                    rows.clear();
                }
                Ok(())
            }
        }
    }

    /// The finished file, to be committed with the run's other files.
    pub fn into_file(self) -> Result<AtomicFile> {
        match self {
            LanesWriter::Csv(w, _) => Ok(w.into_file()),
            LanesWriter::Parquet(mut w, rows, search) => {
                if !rows.is_empty() {
                    w.write(&batch::from_cells(&rows, search)?, None)?;
                }
                w.finish()
            }
        }
    }
}
