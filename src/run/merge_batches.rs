//! A shard's rows read as Arrow batches, whichever its table's format,
//! for a merge: the file's SHA-256 checked against the manifest first,
//! then each batch checked (the schema, and the lane numbers in order
//! within the shard's range) and handed on, so no value of a Parquet
//! shard is formatted as text and parsed back, and a CSV shard's cells
//! are parsed once, by the reader the report uses.

use arrow_array::{Array, Int64Array, RecordBatch};

use super::verify::{all_rows_read, refused, Part};
use crate::columns::LANE;
use crate::error::{Error, Result};
use crate::output::batch::columns_for;
use crate::output::digest::file_digest;
use crate::output::table::read_table;

/// Streams shard `p`'s batches (lanes from `next` on) into
/// `each(first lane, batch)`, checking each, once the file's SHA-256 is
/// the one its manifest records. Returns the next lane.
pub(super) fn merge_part(
    p: &Part,
    search: bool,
    mut next: u64,
    mut each: impl FnMut(u64, &RecordBatch) -> Result<()>,
) -> Result<u64> {
    let format = p.m.format;
    let name = format.file_name();
    let path = p.dir.join(name);
    if file_digest(&path)?.sha256 != p.m.files[name].sha256 {
        return Err(refused(
            &p.dir,
            &p.m,
            format!("{name} is changed: its SHA-256 is not the one the manifest records"),
        ));
    }
    let kinds = columns_for(search);
    if format.table().width(&path)? != kinds.len() {
        return Err(Error::input(
            &path,
            Some("line 1".into()),
            None,
            "its columns are not those of this tswm version's table; run the shard again",
        ));
    }
    let bad = |m: String| Error::input(&path, None, None, m);
    let lane_col = kinds.iter().position(|c| c.0 == LANE).unwrap_or(0);
    read_table(&path, format, search, |b| {
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
        each(next, b)?;
        next += b.num_rows() as u64;
        Ok(())
    })?;
    all_rows_read(p, name, next)
}
