//! Reading the cells of a CSV file the report reads: columns found by
//! name, numbers checked to be numbers, each error one line naming the
//! file, line and column.

use std::path::Path;

use crate::error::{Error, Result};

pub(super) fn open_csv(path: &Path) -> Result<csv::Reader<std::fs::File>> {
    csv::Reader::from_path(path)
        .map_err(|e| Error::input(path, None, None, format!("cannot read it: {e}")))
}

pub(super) fn bad_row(path: &Path, e: csv::Error) -> Error {
    let line = e.position().map(|p| format!("line {}", p.line()));
    Error::input(path, line, None, format!("not a tswm table: {e}"))
}

pub(super) fn column(path: &Path, head: &csv::ByteRecord, name: &str) -> Result<usize> {
    head.iter()
        .position(|h| h == name.as_bytes())
        .ok_or_else(|| Error::input(path, Some("line 1".into()), Some(name), "column missing"))
}

/// A number cell of a CSV record: empty is NaN, anything else must be a
/// finite number (else an error naming the line and column).
pub(super) fn num(path: &Path, rec: &csv::ByteRecord, i: usize, name: &str) -> Result<f64> {
    let t = rec.get(i).unwrap_or(b"");
    if t.is_empty() {
        return Ok(f64::NAN);
    }
    match std::str::from_utf8(t)
        .ok()
        .and_then(|s| s.parse::<f64>().ok())
    {
        Some(v) if v.is_finite() => Ok(v),
        _ => Err(Error::input(
            path,
            rec.position().map(|p| format!("line {}", p.line())),
            Some(name),
            format!(
                "`{}` is not a finite number; not a tswm table",
                crate::error::shown(&String::from_utf8_lossy(t), 40)
            ),
        )),
    }
}

pub(super) fn text(rec: &csv::ByteRecord, i: usize) -> String {
    String::from_utf8_lossy(rec.get(i).unwrap_or(b"")).into_owned()
}

/// A number column of a batch by name, as f64 (an integer column
/// converted; NaN where empty, not a number, or the column is missing).
pub(super) fn numbers(b: &arrow_array::RecordBatch, name: &str) -> Vec<f64> {
    use arrow_array::{Array, Float64Array, Int64Array};
    let n = b.num_rows();
    let Some(a) = b.column_by_name(name) else {
        return vec![f64::NAN; n];
    };
    if let Some(x) = a.as_any().downcast_ref::<Float64Array>() {
        return (0..n)
            .map(|r| if x.is_valid(r) { x.value(r) } else { f64::NAN })
            .collect();
    }
    if let Some(x) = a.as_any().downcast_ref::<Int64Array>() {
        return (0..n)
            .map(|r| {
                if x.is_valid(r) {
                    x.value(r) as f64
                } else {
                    f64::NAN
                }
            })
            .collect();
    }
    vec![f64::NAN; n]
}
