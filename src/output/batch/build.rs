//! A run's batches built from its lanes: the parameter columns are the
//! chunk's own (moved in, not copied), the result columns are filled from
//! the lanes' end states a block of rows at a time, and the number
//! buffers are kept from batch to batch.

use std::sync::Arc;

use arrow_array::{ArrayRef, Float64Array, Int64Array, RecordBatch};
use arrow_buffer::{BooleanBuffer, NullBuffer, ScalarBuffer};

use super::{schema_for, WordKeys};
use crate::columns::{results_for, Column, Kind, Value};
use crate::error::{Error, Result};
use crate::integrator::LaneResult;
use crate::params::{Param, ParamColumns};

/// A float column over `values`, NaN as null.
pub(super) fn float_array(values: ScalarBuffer<f64>) -> ArrayRef {
    let nulls = nan_nulls(&values);
    Arc::new(Float64Array::new(values, nulls))
}

/// Where `values` hold NaN, as nulls: none for a column without NaN, all
/// for a column of NaN (a parameter that no lane's law uses, a result no
/// lane has).
fn nan_nulls(values: &[f64]) -> Option<NullBuffer> {
    nulls_where(values, |v| v.is_nan())
}

/// The rows of `values` where `empty` holds, as nulls: none, all, or a
/// mask; counted first (as a vector) so that only a mixed column is
/// walked value by value.
pub(super) fn nulls_where<T: Copy>(values: &[T], empty: impl Fn(T) -> bool) -> Option<NullBuffer> {
    let n: usize = values.iter().map(|&v| usize::from(empty(v))).sum();
    match n {
        0 => None,
        n if n == values.len() => Some(NullBuffer::new_null(n)),
        _ => Some(NullBuffer::new(BooleanBuffer::collect_bool(
            values.len(),
            |i| !empty(values[i]),
        ))),
    }
}

/// The word column `name` of `values` (a parameter's law or table, one
/// a lane), each keyed by `code` (None: by its word, `word`).
fn words_of<T>(
    name: &'static str,
    values: &[T],
    code: Option<fn(&T) -> usize>,
    word: impl Fn(&T) -> &str,
) -> ArrayRef {
    let mut w = WordKeys::new(name, values.len());
    match code {
        Some(code) => values.iter().for_each(|v| w.push_code(Some(code(v)))),
        // A table's name is one of the sweep's: it has no other error.
        None => values.iter().for_each(|v| {
            let _ = w.push(Some(word(v)));
        }),
    }
    w.finish()
}

/// A result column of a batch being filled.
enum Fill {
    F(Vec<f64>),
    I(Vec<i64>),
    S(WordKeys),
}

impl Fill {
    fn finish(self) -> ArrayRef {
        match self {
            Fill::F(v) => float_array(v.into()),
            Fill::I(v) => Arc::new(Int64Array::from(v)),
            Fill::S(mut w) => w.finish(),
        }
    }

    /// Appends rows `rows` of the result column `col` of the lanes
    /// `first..`, whose end states are `results_`.
    fn results(
        &mut self,
        col: &Column,
        rows: std::ops::Range<usize>,
        first: u64,
        results_: &[LaneResult],
    ) {
        let rs = &results_[rows.clone()];
        match (col.value, self) {
            (Value::F(_, block), Fill::F(v)) => block(rs, v),
            (Value::I(_, block), Fill::I(v)) => block(rs, v),
            (Value::Lane, Fill::I(v)) => v.extend(rows.map(|i| (first + i as u64) as i64)),
            (Value::W(code, _), Fill::S(w)) => rs.iter().for_each(|r| w.push_code(code(r))),
            // A column's fill has its value's type (`Column::kind`).
            (_, _) => {}
        }
    }
}

/// Rows filled at a time, every column of a group over them before the
/// next: the lanes' end states (a few hundred bytes a lane) stay in cache
/// while their cells are copied out column by column.
const FILL_ROWS: usize = 1024;

/// Builds a run's batches: the parameter columns are the chunk's own
/// (moved into the batch, not copied), the result columns are filled from
/// the end states, and the number buffers come back
/// ([`Builder::recycle`]) once a batch is written, so that after the
/// first chunks nothing is allocated for them.
#[derive(Default)]
pub struct Builder {
    floats: Vec<Vec<f64>>,
    ints: Vec<Vec<i64>>,
    /// Builds a search run's batches (its columns after the results).
    search: bool,
}

impl Builder {
    /// A builder of a search run's batches (`search`) or another's.
    pub(crate) fn for_run(search: bool) -> Builder {
        Builder {
            search,
            ..Builder::default()
        }
    }

    /// An empty column `name` of `kind` with room for `n` rows.
    fn fill(&mut self, name: &'static str, kind: Kind, n: usize) -> Fill {
        fn room<T>(mut v: Vec<T>, n: usize) -> Vec<T> {
            v.clear();
            v.reserve(n);
            v
        }
        match kind {
            Kind::Float => Fill::F(room(self.floats.pop().unwrap_or_default(), n)),
            Kind::Int => Fill::I(room(self.ints.pop().unwrap_or_default(), n)),
            Kind::Text => Fill::S(WordKeys::new(name, n)),
        }
    }

    /// The batch of lanes `first..first + params.len()`: the numeric
    /// parameters' columns taken out of `params` into the batch as they
    /// are ([`Builder::recycle`] puts them back), the words and the
    /// results filled on `pool`'s threads, a group of columns a thread,
    /// a block of rows at a time.
    pub fn build(
        &mut self,
        first: u64,
        params: &mut ParamColumns,
        results_: &[LaneResult],
        pool: &rayon::ThreadPool,
    ) -> Result<RecordBatch> {
        use rayon::prelude::*;
        let n = params.len();
        let np = Param::COLUMNS.len();
        let mut cols: Vec<Option<ArrayRef>> = Param::COLUMNS
            .iter()
            .map(|p| {
                Some(match p {
                    Param::Num(k) => float_array(params.take_num(*k).into()),
                    Param::Motor => {
                        words_of(p.name(), params.motors(), Some(|m| *m as usize), |m| {
                            m.name()
                        })
                    }
                    Param::Friction => {
                        words_of(p.name(), params.frictions(), Some(|f| *f as usize), |f| {
                            f.name()
                        })
                    }
                    Param::FrictionTable => {
                        words_of(p.name(), params.friction_tables(), None, |t| {
                            t.as_ref().map_or("", |t| t.as_str())
                        })
                    }
                })
            })
            .collect();
        let results = results_for(self.search);
        // Every `groups`-th result column a group.
        let groups = pool.current_num_threads().clamp(1, results.len());
        let mut filled: Vec<Vec<(usize, Fill)>> = (0..groups)
            .map(|g| {
                (g..results.len())
                    .step_by(groups)
                    .map(|c| (c, self.fill(results[c].name, results[c].kind(), n)))
                    .collect()
            })
            .collect();
        pool.install(|| {
            filled.par_iter_mut().for_each(|fills| {
                for start in (0..n).step_by(FILL_ROWS) {
                    let rows = start..(start + FILL_ROWS).min(n);
                    for (c, f) in fills.iter_mut() {
                        f.results(results[*c], rows.clone(), first, results_);
                    }
                }
            })
        });
        cols.resize(np + results.len(), None);
        for (c, f) in filled.into_iter().flatten() {
            cols[np + c] = Some(f.finish());
        }
        let cols = cols.into_iter().map(|c| c.expect("every column filled"));
        RecordBatch::try_new(schema_for(self.search), cols.collect())
            .map_err(|e| Error::Internal(format!("results batch: {e}")))
    }

    /// Takes back the number buffers of `batch` (built by
    /// [`Builder::build`] from `params`, and no longer shared): the
    /// parameters' columns to `params`, as they were, the results' to be
    /// filled again. A buffer still shared elsewhere is copied back or
    /// left to its other owner.
    pub fn recycle(&mut self, batch: RecordBatch, params: &mut ParamColumns) {
        let results = results_for(self.search);
        let (_, cols, _) = batch.into_parts();
        for (c, a) in cols.into_iter().enumerate() {
            let param = Param::COLUMNS.get(c).copied();
            let data = a.to_data();
            drop(a);
            let Some(buffer) = data.buffers().first().cloned() else {
                continue;
            };
            drop(data);
            match (param, results.get(c.wrapping_sub(Param::COLUMNS.len()))) {
                (Some(Param::Num(k)), _) => params.put_num(
                    k,
                    buffer
                        .into_vec()
                        .unwrap_or_else(|b| b.typed_data::<f64>().to_vec()),
                ),
                (None, Some(r)) => match r.kind() {
                    Kind::Float => self.floats.extend(buffer.into_vec().ok()),
                    Kind::Int => self.ints.extend(buffer.into_vec().ok()),
                    Kind::Text => {}
                },
                _ => {}
            }
        }
    }
}

/// The batch of lanes `first..first + params.len()` (their parameters
/// copied), built on `pool`.
pub fn from_lanes(
    first: u64,
    params: &ParamColumns,
    results_: &[LaneResult],
    pool: &rayon::ThreadPool,
) -> Result<RecordBatch> {
    let search = results_.first().is_some_and(|r| r.search.is_some());
    Builder::for_run(search).build(first, &mut params.clone(), results_, pool)
}
