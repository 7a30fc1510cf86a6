//! A results table read back as Arrow batches of only the columns a
//! reader asks for, whichever its format ([`super::TableFormat::read`]).

use std::path::{Path, PathBuf};

use arrow_array::RecordBatch;

use super::reading::{not_ours, Wanted};
use super::{Format, Kind};
use crate::error::Result;
use crate::output::batch::columns_for;

/// Reads the results table of `dir` (`lanes.csv` or `lanes.parquet`),
/// columns `names` only (in table order), handing `each` batches of rows
/// in order. Returns the table's path.
pub fn read_batches(
    dir: &Path,
    names: &[&str],
    mut each: impl FnMut(&RecordBatch) -> Result<()>,
) -> Result<PathBuf> {
    let format = Format::of_folder(dir)?;
    let path = dir.join(format.file_name());
    // A search's columns are asked for only of a search's table.
    let search = names
        .iter()
        .any(|n| crate::columns::SEARCH.iter().any(|c| c.name == *n));
    let wanted: Vec<(usize, &'static str, Kind)> = columns_for(search)
        .into_iter()
        .enumerate()
        .filter(|(_, c)| names.contains(&c.0))
        .map(|(i, c)| (i, c.0, c.1))
        .collect();
    format.table().read(&path, &wanted, &mut each)?;
    Ok(path)
}

/// Reads every column of the table `path` in `format` (a search's table
/// when `search`; another table is refused as not this version's),
/// handing `each` batches of rows in order (a merge).
pub fn read_table(
    path: &Path,
    format: Format,
    search: bool,
    mut each: impl FnMut(&RecordBatch) -> Result<()>,
) -> Result<()> {
    if format.table().width(path)? != columns_for(search).len() {
        return Err(not_ours(path));
    }
    let wanted: Vec<(usize, &'static str, Kind)> = columns_for(search)
        .into_iter()
        .enumerate()
        .map(|(i, c)| (i, c.0, c.1))
        .collect();
    format.table().read(path, &wanted as &Wanted, &mut each)
}

/// The names of the columns of the results table of `dir`, in table
/// order: a search run's table has the search's columns after the others.
pub fn folder_columns(dir: &Path) -> Result<Vec<&'static str>> {
    let format = Format::of_folder(dir)?;
    let width = format.table().width(&dir.join(format.file_name()))?;
    let search = width == columns_for(true).len();
    Ok(columns_for(search).into_iter().map(|c| c.0).collect())
}
