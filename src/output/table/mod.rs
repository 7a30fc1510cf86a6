//! The results table on disk: `lanes.csv` (text, the default) or
//! `lanes.parquet` (typed columns, docs/model.md section 9 order, empty
//! cells as nulls). Each format is one [`TableFormat`]: its file, its
//! writer of the run's Arrow batches ([`crate::output::batch`]) and its
//! reader of batches of the columns asked for, listed once in
//! [`Format::table`]. Everything else (a run, a merge, the report, the
//! estimate of a run's disk, Python) goes through [`LanesWriter`] and
//! [`read_batches`], whatever the format.

mod batches;
mod csv_read;
mod csv_rows;
mod csv_table;
mod parquet;
mod parquet_table;
mod reading;

use std::path::Path;

pub use self::batches::{folder_columns, read_batches, read_table};
pub use self::csv_rows::CsvBlocks;
pub use self::parquet::{ParquetLanes, ROW_GROUP};
pub use self::reading::Wanted;
pub use crate::columns::{Cell, Kind};
use crate::error::{Error, Result};
use crate::output::atomic::AtomicFile;
pub use crate::output::batch::columns;
use arrow_array::RecordBatch;
use clap::ValueEnum;

/// The format of the results table: the word a user gives (`--format`,
/// a shard's manifest); what each does is its [`TableFormat`].
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

/// One format of the results table: its file, its writer and its reader.
/// A new format is a variant of [`Format`], an implementation of this
/// trait in a file of its own, and its arm of [`Format::table`].
pub trait TableFormat: Sync {
    /// The table's file name in an output folder.
    fn file_name(&self) -> &'static str;

    /// Starts writing the table `path` under a temporary name (committed
    /// with the run's other files). `hashed`: its SHA-256 is computed as
    /// it is written (a shard's, for its manifest); `search`: a search
    /// run's table, with the search's columns.
    fn create(&self, path: &Path, hashed: bool, search: bool) -> Result<Box<dyn TableWriter>>;

    /// Reads the table `path`, the columns `wanted` only, handing `each`
    /// batches of rows in order; word columns keyed by their words'
    /// codes ([`crate::output::batch::canonical`]). Errors name the file,
    /// the row and the column.
    fn read(
        &self,
        path: &Path,
        wanted: &Wanted,
        each: &mut dyn FnMut(&RecordBatch) -> Result<()>,
    ) -> Result<()>;

    /// The number of columns of the table `path` (a search's table has
    /// more).
    fn width(&self, path: &Path) -> Result<usize>;

    /// The bytes the rows of `batch` take in a table of this format (no
    /// header), as its writer writes them, for the estimate of a run's
    /// disk.
    fn rows_bytes(&self, pool: &rayon::ThreadPool, batch: &RecordBatch) -> Result<u64>;
}

/// A results table being written, batch by batch.
pub trait TableWriter: Send {
    /// Appends the rows of `batch`, in lane order; `pool` the threads
    /// that format or encode them.
    fn write_batch(&mut self, pool: &rayon::ThreadPool, batch: &RecordBatch) -> Result<()>;

    /// The finished file, to be committed with the run's other files.
    fn finish(self: Box<Self>) -> Result<AtomicFile>;
}

impl Format {
    /// What the format does: the one place each format is registered.
    pub fn table(self) -> &'static dyn TableFormat {
        match self {
            Format::Csv => &csv_table::CsvTable,
            Format::Parquet => &parquet_table::ParquetTable,
        }
    }

    /// The table's file name in an output folder.
    pub fn file_name(self) -> &'static str {
        self.table().file_name()
    }

    /// The results table of the folder `dir`, the first format whose file
    /// is there; an error naming the folder when none is.
    pub(crate) fn of_folder(dir: &Path) -> Result<Format> {
        let all = Format::value_variants();
        if let Some(f) = all.iter().find(|f| dir.join(f.file_name()).is_file()) {
            return Ok(*f);
        }
        let names: Vec<&str> = all.iter().map(|f| f.file_name()).collect();
        Err(Error::input(
            dir,
            None,
            None,
            format!(
                "holds no {}; allowed: a folder written by `tswm run` or `tswm merge`",
                names.join(" or ")
            ),
        ))
    }
}

/// The bytes the rows of `batch` take in a table of `format` (no
/// header), as its writer writes them (for the estimate of a run's disk).
pub(crate) fn rows_bytes(
    format: Format,
    pool: &rayon::ThreadPool,
    batch: &RecordBatch,
) -> Result<u64> {
    format.table().rows_bytes(pool, batch)
}

/// Writes a run's batches to the results table, in its format, under a
/// temporary name; committed with the run's other files.
pub struct LanesWriter(Box<dyn TableWriter>);

impl LanesWriter {
    /// Starts the table `dir/lanes.{csv,parquet}` (see
    /// [`TableFormat::create`]).
    pub fn create(dir: &Path, format: Format, hashed: bool, search: bool) -> Result<LanesWriter> {
        let t = format.table();
        Ok(LanesWriter(t.create(
            &dir.join(t.file_name()),
            hashed,
            search,
        )?))
    }

    /// Appends the rows of a batch of the run, in lane order.
    pub fn write_batch(&mut self, pool: &rayon::ThreadPool, b: &RecordBatch) -> Result<()> {
        self.0.write_batch(pool, b)
    }

    /// The finished file, to be committed with the run's other files.
    pub fn into_file(self) -> Result<AtomicFile> {
        self.0.finish()
    }
}
