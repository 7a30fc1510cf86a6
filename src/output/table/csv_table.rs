//! `lanes.csv` as a [`TableFormat`]: rows formatted from the batches in
//! parallel (`csv_rows.rs`), read back by column (`csv_read.rs`).

use std::path::Path;

use arrow_array::RecordBatch;

use super::reading::{open, Wanted};
use super::{CsvBlocks, TableFormat, TableWriter};
use crate::error::{Error, Result};
use crate::output::atomic::AtomicFile;
use crate::output::batch;
use crate::output::csv_lines::CsvLines;
use crate::output::names;

/// The CSV results table.
pub(super) struct CsvTable;

/// `lanes.csv` being written, and the buffers its blocks of rows are
/// formatted in.
struct CsvWriter(CsvLines, CsvBlocks);

impl TableFormat for CsvTable {
    fn file_name(&self) -> &'static str {
        names::LANES_CSV
    }

    fn create(&self, path: &Path, hashed: bool, search: bool) -> Result<Box<dyn TableWriter>> {
        let header: Vec<&str> = batch::columns_for(search).iter().map(|c| c.0).collect();
        Ok(Box::new(CsvWriter(
            CsvLines::start(path, &header.join(","), hashed)?,
            CsvBlocks::default(),
        )))
    }

    fn read(
        &self,
        path: &Path,
        wanted: &Wanted,
        each: &mut dyn FnMut(&RecordBatch) -> Result<()>,
    ) -> Result<()> {
        super::csv_read::read_csv(path, wanted, &mut |b: &RecordBatch| each(b))
    }

    fn width(&self, path: &Path) -> Result<usize> {
        let mut rd = csv::ReaderBuilder::new()
            .has_headers(false)
            .from_reader(open(path)?);
        let mut rec = csv::ByteRecord::new();
        rd.read_byte_record(&mut rec)
            .map_err(|e| Error::input(path, Some("line 1".into()), None, e.to_string()))?;
        Ok(rec.len())
    }

    fn rows_bytes(&self, pool: &rayon::ThreadPool, batch: &RecordBatch) -> Result<u64> {
        let mut bytes = 0u64;
        CsvBlocks::default().format(pool, batch, |text| {
            bytes += text.len() as u64;
            Ok(())
        })?;
        Ok(bytes)
    }
}

impl TableWriter for CsvWriter {
    fn write_batch(&mut self, pool: &rayon::ThreadPool, b: &RecordBatch) -> Result<()> {
        let CsvWriter(w, blocks) = self;
        blocks.format(pool, b, |text| w.write_raw(text))
    }

    fn finish(self: Box<Self>) -> Result<AtomicFile> {
        Ok(self.0.into_file())
    }
}
