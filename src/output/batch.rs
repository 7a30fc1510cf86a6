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

use std::sync::{Arc, OnceLock};

use arrow_array::builder::StringBuilder;
use arrow_array::{Array, ArrayRef, Float64Array, Int64Array, RecordBatch, StringArray};
use arrow_buffer::{BooleanBuffer, NullBuffer};
use arrow_schema::{DataType, Field, Schema, SchemaRef};

use crate::columns::{results, Cell, Kind};
use crate::error::{Error, Result};
use crate::integrator::LaneResult;
use crate::params::{Param, Params};

/// The columns of the results table, in order, with their kinds: the
/// parameters (docs/model.md section 9 order), then the result columns of
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

/// The Arrow type of a column of `kind`.
pub fn data_type(kind: Kind) -> DataType {
    match kind {
        Kind::Float => DataType::Float64,
        Kind::Int => DataType::Int64,
        Kind::Text => DataType::Utf8,
    }
}

/// The schema of the results table, in [`columns`]
/// order: floats and words nullable (an empty cell), counts never empty.
pub fn schema() -> SchemaRef {
    static SCHEMA: OnceLock<SchemaRef> = OnceLock::new();
    SCHEMA
        .get_or_init(|| {
            let fields: Vec<Field> = columns()
                .into_iter()
                .map(|(name, kind)| Field::new(name, data_type(kind), kind != Kind::Int))
                .collect();
            Arc::new(Schema::new(fields))
        })
        .clone()
}

/// A float column from its values, NaN as null.
pub fn floats(values: Vec<f64>) -> ArrayRef {
    let valid = BooleanBuffer::collect_bool(values.len(), |i| !values[i].is_nan());
    let nulls = (valid.count_set_bits() < values.len()).then(|| NullBuffer::new(valid));
    Arc::new(Float64Array::new(values.into(), nulls))
}

/// A column of a batch being filled.
enum Fill {
    F(Vec<f64>),
    I(Vec<i64>),
    S(StringBuilder),
}

impl Fill {
    fn of(kind: Kind, n: usize) -> Fill {
        match kind {
            Kind::Float => Fill::F(Vec::with_capacity(n)),
            Kind::Int => Fill::I(Vec::with_capacity(n)),
            Kind::Text => Fill::S(StringBuilder::with_capacity(n, n * 4)),
        }
    }

    fn finish(self) -> ArrayRef {
        match self {
            Fill::F(v) => floats(v),
            Fill::I(v) => Arc::new(Int64Array::from(v)),
            Fill::S(mut b) => Arc::new(b.finish()),
        }
    }

    /// Appends a word, "" as null.
    fn word(&mut self, w: &str) {
        if let Fill::S(b) = self {
            if w.is_empty() {
                b.append_null();
            } else {
                b.append_value(w);
            }
        }
    }
}

/// Appends rows `rows` of column `c` (of [`columns`])
/// of the lanes `first..` to `fill`.
fn fill_column(
    fill: &mut Fill,
    c: usize,
    rows: std::ops::Range<usize>,
    first: u64,
    params: &[Params],
    results_: &[LaneResult],
) {
    let np = Param::COLUMNS.len();
    if c < np {
        let ps = &params[rows];
        match (Param::COLUMNS[c], fill) {
            (Param::Num(k), Fill::F(v)) => v.extend(ps.iter().map(|p| p.get(k))),
            (Param::Motor, f) => ps.iter().for_each(|p| f.word(p.motor.name())),
            (Param::Friction, f) => ps.iter().for_each(|p| f.word(p.friction.name())),
            (Param::FrictionTable, f) => ps
                .iter()
                .for_each(|p| f.word(p.friction_table.as_ref().map_or("", |t| t.as_str()))),
            // Every parameter column is a float or a word.
            (_, _) => {}
        }
        return;
    }
    let cell = results()[c - np].cell;
    let cells = rows.map(|i| cell(first + i as u64, &results_[i]));
    match fill {
        Fill::F(v) => v.extend(cells.map(|x| x.number())),
        Fill::I(v) => v.extend(cells.map(|x| match x {
            Cell::I(x) => x as i64,
            x => x.number() as i64,
        })),
        f => cells.for_each(|x| f.word(x.word())),
    }
}

/// Rows filled at a time, every column of a group over them before the
/// next: the lanes' parameters and end states (a few hundred bytes a
/// lane) stay in cache while their cells are copied out column by column.
const FILL_ROWS: usize = 1024;

/// The batch of lanes `first..first + params.len()`: the columns split
/// among `pool`'s threads, each filling its columns a block of rows at a
/// time.
pub fn from_lanes(
    first: u64,
    params: &[Params],
    results_: &[LaneResult],
    pool: &rayon::ThreadPool,
) -> Result<RecordBatch> {
    use rayon::prelude::*;
    let schema = schema();
    let kinds: Vec<Kind> = columns().iter().map(|c| c.1).collect();
    let n = params.len();
    // Every `groups`-th column a group: parameters and results (whose
    // cells cost more) shared evenly.
    let groups = pool.current_num_threads().clamp(1, kinds.len());
    let filled: Vec<Vec<(usize, Fill)>> = pool.install(|| {
        (0..groups)
            .into_par_iter()
            .map(|g| {
                let mut fills: Vec<(usize, Fill)> = (g..kinds.len())
                    .step_by(groups)
                    .map(|c| (c, Fill::of(kinds[c], n)))
                    .collect();
                for start in (0..n).step_by(FILL_ROWS) {
                    let rows = start..(start + FILL_ROWS).min(n);
                    for (c, f) in fills.iter_mut() {
                        fill_column(f, *c, rows.clone(), first, params, results_);
                    }
                }
                fills
            })
            .collect()
    });
    let mut all: Vec<(usize, Fill)> = filled.into_iter().flatten().collect();
    all.sort_by_key(|f| f.0);
    let cols: Vec<ArrayRef> = all.into_iter().map(|f| f.1.finish()).collect();
    RecordBatch::try_new(schema, cols).map_err(|e| Error::Internal(format!("results batch: {e}")))
}

/// The batch of rows given as cells, row after row, in
/// [`columns`] order (a merge's rows read back).
pub fn from_cells(cells: &[Cell]) -> Result<RecordBatch> {
    let schema = schema();
    let w = schema.fields().len();
    let n = cells.len() / w;
    let at = |c: usize| (0..n).map(move |r| &cells[r * w + c]);
    let cols: Vec<ArrayRef> = schema
        .fields()
        .iter()
        .enumerate()
        .map(|(c, f)| match f.data_type() {
            DataType::Float64 => floats(at(c).map(Cell::number).collect()),
            DataType::Int64 => Arc::new(
                at(c)
                    .map(|x| match x {
                        Cell::I(v) => *v as i64,
                        x => x.number() as i64,
                    })
                    .collect::<Int64Array>(),
            ) as ArrayRef,
            _ => Arc::new(
                at(c)
                    .map(|x| Some(x.word()).filter(|w| !w.is_empty()))
                    .collect::<StringArray>(),
            ),
        })
        .collect();
    RecordBatch::try_new(schema, cols).map_err(|e| Error::Internal(format!("results batch: {e}")))
}

/// One column of a batch, typed.
#[derive(Clone, Copy)]
pub enum Col<'a> {
    /// Floats; a null is an empty cell.
    F(&'a Float64Array),
    /// Counts.
    I(&'a Int64Array),
    /// Words; a null is an empty cell.
    S(&'a StringArray),
}

impl<'a> Col<'a> {
    /// The column as one of the three types a results table has.
    pub fn of(a: &'a dyn Array) -> Option<Col<'a>> {
        let any = a.as_any();
        any.downcast_ref::<Float64Array>()
            .map(Col::F)
            .or_else(|| any.downcast_ref::<Int64Array>().map(Col::I))
            .or_else(|| any.downcast_ref::<StringArray>().map(Col::S))
    }

    /// Rows.
    pub fn len(&self) -> usize {
        match self {
            Col::F(a) => a.len(),
            Col::I(a) => a.len(),
            Col::S(a) => a.len(),
        }
    }

    /// Whether the column has no rows.
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

    /// Row `i` as a word ("" for an empty cell or a number).
    #[inline]
    pub fn word(&self, i: usize) -> &'a str {
        match self {
            Col::S(a) if a.is_valid(i) => a.value(i),
            _ => "",
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
            Col::S(_) => return self.word(i).to_string(),
        }
        String::from_utf8(b).unwrap_or_default()
    }
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
