//! A Parquet shard's rows read as the Arrow batches they were written
//! as, for a merge into a Parquet table: checked column by column (the
//! schema, and the lane numbers in order within the shard's range), and
//! handed on as batches, so no value is formatted as text and parsed back.

use std::fs::File;

use arrow_array::{Array, Int64Array, RecordBatch, RecordBatchReader};
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;

use super::verify::{all_rows_read, refused, Part};
use crate::columns::LANE;
use crate::error::{Error, Result};
use crate::output::batch::schema_for;
use crate::output::digest::file_digest;

/// Rows a batch read from a shard holds at most.
const BATCH_ROWS: usize = 8192;

/// Streams Parquet shard `p`'s batches (lanes from `next` on) into
/// `each(first lane, batch)`, checking each, once the file's SHA-256 is
/// the one its manifest records. Returns the next lane.
pub(super) fn merge_parquet_part(
    p: &Part,
    search: bool,
    mut next: u64,
    mut each: impl FnMut(u64, &RecordBatch) -> Result<()>,
) -> Result<u64> {
    let name = p.m.format.file_name();
    let path = p.dir.join(name);
    if file_digest(&path)?.sha256 != p.m.files[name].sha256 {
        return Err(refused(
            &p.dir,
            &p.m,
            format!("{name} is changed: its SHA-256 is not the one the manifest records"),
        ));
    }
    let bad = |m: String| Error::input(&path, None, None, m);
    let file = File::open(&path).map_err(|e| bad(format!("cannot read it: {e}")))?;
    let reader = ParquetRecordBatchReaderBuilder::try_new(file)
        .and_then(|b| b.with_batch_size(BATCH_ROWS).build())
        .map_err(|e| bad(format!("not a Parquet file: {e}")))?;
    let want = schema_for(search);
    let ours = reader.schema();
    let same = ours.fields().len() == want.fields().len()
        && ours
            .fields()
            .iter()
            .zip(want.fields())
            .all(|(a, b)| a.name() == b.name() && a.data_type() == b.data_type());
    if !same {
        return Err(Error::input(
            &path,
            Some("line 1".into()),
            None,
            "its columns are not those of this tswm version's table; run the shard again",
        ));
    }
    let lane_col = want.index_of(LANE).unwrap_or(0);
    for batch in reader {
        let b = batch.map_err(|e| bad(format!("cannot read it: {e}")))?;
        let lanes = b
            .column(lane_col)
            .as_any()
            .downcast_ref::<Int64Array>()
            .filter(|a| a.null_count() == 0)
            .ok_or_else(|| {
                bad(format!(
                    "its column {LANE} is not a whole number on every row"
                ))
            })?;
        for (i, &lane) in lanes.values().iter().enumerate() {
            if u64::try_from(lane) != Ok(next + i as u64) || next + i as u64 >= p.m.lane_end {
                let at = next + i as u64;
                return Err(Error::input(
                    &path,
                    Some(format!("row {}", at - p.m.lane_start + 1)),
                    Some(LANE),
                    format!(
                        "expected lane {at} (shard {}/{} holds lanes {}..{}); run the shard again",
                        p.m.shard, p.m.shards, p.m.lane_start, p.m.lane_end
                    ),
                ));
            }
        }
        // Keyed as a run keys its word columns (a Parquet reader keys
        // them by the pages' own dictionary).
        let b = crate::output::batch::canonical_batch(b).map_err(|(col, m)| {
            Error::input(
                &path,
                Some(format!("row {}", next - p.m.lane_start + 1)),
                Some(&col),
                m,
            )
        })?;
        each(next, &b)?;
        next += b.num_rows() as u64;
    }
    all_rows_read(p, name, next)
}
