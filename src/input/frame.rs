//! A lane table held in memory as typed columns (Arrow record batches: a
//! pandas, polars or pyarrow table handed over by Python), one column a
//! parameter as in a lane table file: numbers (any integer type, f32 or
//! f64) or words (UTF-8), a null (or a float NaN, pandas' missing value)
//! meaning "not set".

use std::path::{Path, PathBuf};

use arrow_array::cast::AsArray;
use arrow_array::types::{
    Float32Type, Float64Type, Int16Type, Int32Type, Int64Type, Int8Type, UInt16Type, UInt32Type,
    UInt64Type, UInt8Type,
};
use arrow_array::{Array, RecordBatch};
use arrow_schema::{DataType, Schema};

use crate::error::{Error, Result};
use crate::params::{Param, Spec};

/// One column of a [`Frame`]: its parameter and its cells.
#[derive(Clone, Debug)]
enum Cells {
    /// Numbers; None (or NaN) is not set.
    Numbers(Vec<Option<f64>>),
    /// Words (or numbers as text); None is not set.
    Words(Vec<Option<String>>),
}

/// A lane table in memory: its name in errors, and its columns.
#[derive(Clone, Debug)]
pub struct Frame {
    name: PathBuf,
    columns: Vec<(Param, Cells)>,
    rows: u64,
}

impl Frame {
    /// The table of `batches` (all of `schema`), named `name` in errors:
    /// every column named as a parameter, each once, numbers or words.
    pub fn from_batches(name: &Path, schema: &Schema, batches: &[RecordBatch]) -> Result<Frame> {
        let bad = |param: Option<&str>, msg: String| Error::input(name, None, param, msg);
        let mut columns: Vec<(Param, Cells)> = Vec::new();
        for (i, field) in schema.fields().iter().enumerate() {
            let col = field.name();
            let p = Param::from_name(col).ok_or_else(|| {
                bad(
                    Some(col),
                    format!(
                        "unknown column{}; allowed: {}",
                        crate::error::did_you_mean(col, Param::COLUMNS.map(|p| p.name())),
                        Param::all_names()
                    ),
                )
            })?;
            if columns.iter().any(|(q, _)| *q == p) {
                return Err(bad(Some(col), "column appears twice".into()));
            }
            let mut cells = match field.data_type() {
                t if is_text(t) => Cells::Words(Vec::new()),
                t if is_number(t) => Cells::Numbers(Vec::new()),
                t => {
                    return Err(bad(
                        Some(col),
                        format!(
                            "holds {t}; allowed: numbers (any integer type, f32 or f64), or \
                             words (the laws, a friction table's name)"
                        ),
                    ))
                }
            };
            for b in batches {
                append(&mut cells, b.column(i).as_ref());
            }
            columns.push((p, cells));
        }
        let rows = batches.iter().map(|b| b.num_rows() as u64).sum();
        Ok(Frame {
            name: name.to_path_buf(),
            columns,
            rows,
        })
    }

    /// The table's name in errors.
    pub fn name(&self) -> &Path {
        &self.name
    }

    /// The parameters its columns give.
    pub fn params(&self) -> Vec<Param> {
        self.columns.iter().map(|(p, _)| *p).collect()
    }

    /// Rows (lanes).
    pub fn rows(&self) -> u64 {
        self.rows
    }

    /// Sets the cells of row `row` in `spec` (over its base); the error
    /// says which lane, parameter and what is allowed.
    pub(crate) fn set_row(&self, row: u64, spec: &mut Spec) -> Result<()> {
        let r = row as usize;
        for (p, cells) in &self.columns {
            let set = match cells {
                Cells::Numbers(v) => match (v[r], p) {
                    (Some(x), Param::Num(n)) if x.is_finite() => {
                        spec.set(*n, x);
                        Ok(())
                    }
                    (Some(x), _) if !x.is_nan() => spec.set_text(*p, &format!("{x}")),
                    _ => Ok(()),
                },
                Cells::Words(v) => match &v[r] {
                    Some(w) => spec.set_text(*p, w),
                    None => Ok(()),
                },
            };
            set.map_err(|m| {
                Error::input(&self.name, Some(format!("lane {row}")), Some(p.name()), m)
            })?;
        }
        Ok(())
    }
}

fn is_text(t: &DataType) -> bool {
    match t {
        DataType::Utf8 | DataType::LargeUtf8 | DataType::Utf8View => true,
        // A categorical column of words (what `tswm run` writes).
        DataType::Dictionary(_, v) => is_text(v),
        _ => false,
    }
}

fn is_number(t: &DataType) -> bool {
    t.is_integer() || matches!(t, DataType::Float32 | DataType::Float64)
}

/// Appends the cells of `a` (of the column's type) to `cells`.
fn append(cells: &mut Cells, a: &dyn Array) {
    match cells {
        Cells::Words(v) => match a.data_type() {
            DataType::Utf8 => v.extend(a.as_string::<i32>().iter().map(|w| w.map(String::from))),
            DataType::LargeUtf8 => {
                v.extend(a.as_string::<i64>().iter().map(|w| w.map(String::from)))
            }
            DataType::Dictionary(..) => {
                let d = a.as_any_dictionary();
                let mut words = Cells::Words(Vec::new());
                append(&mut words, d.values().as_ref());
                let Cells::Words(words) = words else {
                    unreachable!("built as words")
                };
                let keys = d.normalized_keys();
                v.extend((0..a.len()).map(|i| {
                    if a.is_valid(i) {
                        words[keys[i]].clone()
                    } else {
                        None
                    }
                }))
            }
            _ => v.extend(a.as_string_view().iter().map(|w| w.map(String::from))),
        },
        Cells::Numbers(v) => {
            macro_rules! numbers {
                ($($t:ty),*) => {
                    match a.data_type() {
                        $(t if t == &<$t as arrow_array::types::ArrowPrimitiveType>::DATA_TYPE => {
                            v.extend(a.as_primitive::<$t>().iter().map(|x| x.map(|x| x.to_f64())))
                        })*
                        _ => {}
                    }
                };
            }
            numbers!(
                Float64Type,
                Float32Type,
                Int64Type,
                Int32Type,
                Int16Type,
                Int8Type,
                UInt64Type,
                UInt32Type,
                UInt16Type,
                UInt8Type
            );
        }
    }
}

/// A number of any of the types a column may hold, as f64.
trait ToF64 {
    fn to_f64(self) -> f64;
}

macro_rules! to_f64 {
    ($($t:ty),*) => { $(impl ToF64 for $t { fn to_f64(self) -> f64 { self as f64 } })* };
}
to_f64!(f64, f32, i64, i32, i16, i8, u64, u32, u16, u8);
