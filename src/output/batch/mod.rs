//! A chunk's results as columns: an Arrow [`RecordBatch`] with one typed
//! array per column of the results table (f64, i64 and UTF-8; an empty
//! cell is a null), built once from the lanes' parameters and end states.
//! Every consumer reads it: the CSV and Parquet writers, `summary.csv`,
//! the report's aggregates; and it is what pandas, polars, DuckDB and
//! pyarrow exchange without copies.
//!
//! A consumer reads a batch's columns typed ([`Col`]), in order
//! ([`typed`]) or by name ([`Columns`]: a batch read back from a file may
//! hold only the columns its reader asked for).

mod build;
mod words;

use std::sync::{Arc, OnceLock};

pub use build::{from_lanes, Builder};
pub use words::{canonical, canonical_batch, vocabulary, word_type, Key, WordKeys};

use arrow_array::{
    Array, ArrayRef, DictionaryArray, Float64Array, Int64Array, RecordBatch, StringArray,
};
use arrow_schema::{DataType, Field, Schema, SchemaRef};

use crate::columns::{results_for, Kind};
use crate::error::{Error, Result};
use crate::params::Param;

/// The columns of the results table, in order, with their kinds: the
/// parameters (docs/model.md section 9 order), then the result columns of
/// [`crate::columns::RESULTS`].
pub fn columns() -> Vec<(&'static str, Kind)> {
    columns_for(false)
}

/// The columns of a run's results table: [`columns`], and for a search
/// the columns of [`crate::columns::SEARCH`] after them.
pub(crate) fn columns_for(search: bool) -> Vec<(&'static str, Kind)> {
    let mut c: Vec<(&'static str, Kind)> = Param::COLUMNS
        .iter()
        .map(|p| match p {
            Param::Num(_) => (p.name(), Kind::Float),
            _ => (p.name(), Kind::Text),
        })
        .collect();
    c.extend(results_for(search).iter().map(|r| (r.name, r.kind())));
    c
}

/// The Arrow type of a column of `kind`.
pub(crate) fn data_type(kind: Kind) -> DataType {
    match kind {
        Kind::Float => DataType::Float64,
        Kind::Int => DataType::Int64,
        Kind::Text => word_type(),
    }
}

/// The schema of the results table, in [`columns`]
/// order: floats and words nullable (an empty cell), counts never empty.
pub fn schema() -> SchemaRef {
    schema_for(false)
}

/// The schema of a run's results table ([`columns_for`]).
pub(crate) fn schema_for(search: bool) -> SchemaRef {
    static SCHEMAS: [OnceLock<SchemaRef>; 2] = [OnceLock::new(), OnceLock::new()];
    SCHEMAS[search as usize]
        .get_or_init(|| {
            let fields: Vec<Field> = columns_for(search)
                .into_iter()
                .map(|(name, kind)| Field::new(name, data_type(kind), kind != Kind::Int))
                .collect();
            Arc::new(Schema::new(fields))
        })
        .clone()
}

/// Whether a batch (or a table's header) holds a search's columns.
pub(crate) fn is_search(names: &[&str]) -> bool {
    names.contains(&crate::columns::SEARCH_STATUS)
}

/// A float column from its values, NaN as null.
pub fn floats(values: Vec<f64>) -> ArrayRef {
    build::float_array(values.into())
}

/// One column of a batch, typed.
#[derive(Clone, Copy)]
pub enum Col<'a> {
    /// Floats; a null is an empty cell.
    F(&'a Float64Array),
    /// Counts.
    I(&'a Int64Array),
    /// Words: a dictionary (its keys the words' codes) and its words; a
    /// null is an empty cell.
    S(&'a DictionaryArray<Key>, &'a StringArray),
}

impl<'a> Col<'a> {
    /// The column as one of the three types a results table has.
    pub fn of(a: &'a dyn Array) -> Option<Col<'a>> {
        let any = a.as_any();
        any.downcast_ref::<Float64Array>()
            .map(Col::F)
            .or_else(|| any.downcast_ref::<Int64Array>().map(Col::I))
            .or_else(|| {
                let d = any.downcast_ref::<DictionaryArray<Key>>()?;
                Some(Col::S(
                    d,
                    d.values().as_any().downcast_ref::<StringArray>()?,
                ))
            })
    }

    /// Rows.
    pub fn len(&self) -> usize {
        match self {
            Col::F(a) => a.len(),
            Col::I(a) => a.len(),
            Col::S(a, _) => a.len(),
        }
    }

    /// Whether the column has no rows (clippy asks for it beside `len`).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Row `i` as a number: a float (NaN for an empty cell), a count as
    /// f64, a word NaN.
    #[inline]
    pub fn number(&self, i: usize) -> f64 {
        match self {
            Col::F(a) if a.is_valid(i) => a.value(i),
            Col::I(a) => a.value(i) as f64,
            _ => f64::NAN,
        }
    }

    /// Rows `rows` as numbers, as [`Col::number`] reads them (NaN for an
    /// empty cell): the column's own values where it has no empty cell.
    pub fn numbers(&self, rows: std::ops::Range<usize>) -> std::borrow::Cow<'a, [f64]> {
        match self {
            Col::F(a) if a.null_count() == 0 => std::borrow::Cow::Borrowed(&a.values()[rows]),
            Col::F(a) if a.null_count() == a.len() => vec![f64::NAN; rows.len()].into(),
            _ => rows.map(|i| self.number(i)).collect(),
        }
    }

    /// Row `i` as a word ("" for an empty cell or a number).
    #[inline]
    pub fn word(&self, i: usize) -> &'a str {
        match self {
            Col::S(a, words) if a.is_valid(i) => words.value(a.keys().value(i) as usize),
            _ => "",
        }
    }

    /// Row `i`'s word code (None for an empty cell or a number): its
    /// place in the column's vocabulary
    /// ([`crate::columns::Vocabulary`]), the key of every batch `tswm`
    /// builds or reads back ([`canonical`]).
    #[inline]
    pub fn code(&self, i: usize) -> Option<usize> {
        match self {
            Col::S(a, _) if a.is_valid(i) => Some(a.keys().value(i) as usize),
            _ => None,
        }
    }

    /// Row `i` as a count (None for a float or word column).
    #[inline]
    pub fn count(&self, i: usize) -> Option<i64> {
        match self {
            Col::I(a) => Some(a.value(i)),
            _ => None,
        }
    }

    /// Row `i` as `lanes.csv` spells it.
    pub fn text(&self, i: usize) -> String {
        let mut b = Vec::new();
        match self {
            Col::F(a) => {
                if a.is_valid(i) {
                    super::float_text::push_f64(&mut b, a.value(i));
                }
            }
            Col::I(a) => b.extend_from_slice(a.value(i).to_string().as_bytes()),
            Col::S(..) => return self.word(i).to_string(),
        }
        String::from_utf8(b).unwrap_or_default()
    }
}

/// The ends of the runs of rows `rows` over which every word column of
/// `cols` holds one word (the same word, or empty throughout): the rows
/// of a run need their words read once. Ascending, the last
/// `rows.end`; number columns are left out.
pub(crate) fn word_runs(cols: &[Col<'_>], rows: std::ops::Range<usize>) -> Vec<usize> {
    let mut ends: Vec<usize> = Vec::new();
    for c in cols {
        if let Col::S(a, _) = c {
            ends.extend(word_run_ends(a, rows.clone()));
        }
    }
    ends.push(rows.end);
    ends.sort_unstable();
    ends.dedup();
    ends.retain(|&e| e > rows.start);
    ends
}

/// The ends of the runs of one word in `a` over `rows` (the last one,
/// `rows.end`, left out): where the key or the validity changes (one key
/// is one word: the keys of a results batch are its words' codes).
fn word_run_ends(a: &DictionaryArray<Key>, rows: std::ops::Range<usize>) -> Vec<usize> {
    let keys = a.keys().values();
    (rows.start + 1..rows.end)
        .filter(|&i| {
            a.is_valid(i) != a.is_valid(i - 1) || (a.is_valid(i) && keys[i] != keys[i - 1])
        })
        .collect()
}

/// The columns of a batch, found by name.
pub struct Columns<'a> {
    batch: &'a RecordBatch,
}

impl<'a> Columns<'a> {
    /// The columns of `batch`.
    pub fn new(batch: &'a RecordBatch) -> Columns<'a> {
        Columns { batch }
    }

    /// The column named `name`, when the batch holds it as one of the
    /// results table's types.
    pub fn get(&self, name: &str) -> Option<Col<'a>> {
        let i = self.batch.schema_ref().index_of(name).ok()?;
        Col::of(self.batch.column(i).as_ref())
    }
}

/// Every column of `batch`, typed, in its order; an error for a column of
/// another type.
pub fn typed(batch: &RecordBatch) -> Result<Vec<Col<'_>>> {
    batch
        .columns()
        .iter()
        .zip(batch.schema_ref().fields())
        .map(|(a, f)| {
            Col::of(a.as_ref()).ok_or_else(|| {
                Error::Internal(format!(
                    "column {} is {}, not a results type",
                    f.name(),
                    a.data_type()
                ))
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand_core::{Rng, SeedableRng};

    /// `word_runs` against its definition: a run ends where some word
    /// column's cell differs from the row before's, on random columns of
    /// words of equal and unequal length, empty cells and nulls, over
    /// random ranges.
    #[test]
    fn word_runs_end_where_a_word_changes() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
        let words = [
            None,
            Some("aa"),
            Some("bb"),
            Some("stick"),
            Some("ok"),
            Some(""),
        ];
        for case in 0..2000 {
            let n = 1 + (rng.next_u64() % 200) as usize;
            let columns: Vec<DictionaryArray<Key>> = (0..1 + rng.next_u64() % 3)
                .map(|_| {
                    let mut w = words[(rng.next_u64() % 6) as usize];
                    (0..n)
                        .map(|_| {
                            if rng.next_u64() % 16 == 0 {
                                w = words[(rng.next_u64() % 6) as usize];
                            }
                            w
                        })
                        .collect()
                })
                .collect();
            let mut cols: Vec<Col<'_>> = columns.iter().map(|c| Col::of(c).unwrap()).collect();
            let numbers = Float64Array::from(vec![1.0; n]);
            cols.push(Col::F(&numbers));
            let a = (rng.next_u64() as usize) % n;
            let b = a + 1 + (rng.next_u64() as usize) % (n - a);
            fn cell(c: &DictionaryArray<Key>, i: usize) -> Option<&str> {
                let words = c.values().as_any().downcast_ref::<StringArray>().unwrap();
                c.is_valid(i)
                    .then(|| words.value(c.keys().value(i) as usize))
            }
            let mut want: Vec<usize> = (a + 1..b)
                .filter(|&i| columns.iter().any(|c| cell(c, i) != cell(c, i - 1)))
                .collect();
            want.push(b);
            assert_eq!(word_runs(&cols, a..b), want, "case {case}, rows {a}..{b}");
        }
    }
}
