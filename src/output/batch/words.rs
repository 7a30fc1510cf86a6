//! Word columns as Arrow dictionaries: the values are the column's
//! vocabulary in code order ([`crate::columns::Vocabulary`]: a status,
//! a contact, a law) and each row's key is its word's code, so a reader
//! compares small integers, not strings, and Parquet, pyarrow, polars and
//! DuckDB see a categorical column of the same words. `friction_table`,
//! whose words are the sweep's own table names, is keyed by the order
//! its names first appear in a batch.
//!
//! Batches read back from a file are keyed again here ([`canonical`]):
//! Parquet's reader keys a column by its pages' own dictionary.

use std::sync::Arc;

use arrow_array::cast::AsArray;
use arrow_array::types::Int16Type;
use arrow_array::{Array, ArrayRef, DictionaryArray, Int16Array, RecordBatch, StringArray};
use arrow_buffer::NullBuffer;
use arrow_schema::DataType;

use crate::columns::{result, Value, Vocabulary};
use crate::model::{FrictionKind, MotorKind};
use crate::params::Param;

/// The key type of a word column's dictionary.
pub type Key = Int16Type;

/// The Arrow type of a word column: UTF-8 words keyed by an i16 code.
pub fn word_type() -> DataType {
    DataType::Dictionary(Box::new(DataType::Int16), Box::new(DataType::Utf8))
}

crate::columns::vocabulary!(motor_words, MotorKind);
crate::columns::vocabulary!(friction_words, FrictionKind);

/// The vocabulary of word column `name`: the motor and friction laws,
/// a result column's own; None for `friction_table` (the sweep's names)
/// and for a column that is not a word column.
pub fn vocabulary(name: &str) -> Option<Vocabulary> {
    match Param::from_name(name) {
        Some(Param::Motor) => Some(motor_words),
        Some(Param::Friction) => Some(friction_words),
        Some(_) => None,
        None => match result(name)?.value {
            Value::W(_, words) => Some(words),
            _ => None,
        },
    }
}

/// The dictionary of `keys` (`valid`: which rows have a word) over
/// `words`.
pub fn dictionary(keys: Vec<i16>, valid: Option<NullBuffer>, words: &[&str]) -> ArrayRef {
    let values = Arc::new(StringArray::from_iter_values(words.iter()));
    Arc::new(DictionaryArray::<Key>::new(
        Int16Array::new(keys.into(), valid),
        values,
    ))
}

/// The key of a row with no word while a column is filled (a null once
/// finished; its key is then 0).
const NO_WORD: i16 = -1;

/// The error's words for `word`, which column `name`'s vocabulary `v`
/// lacks.
fn not_a_value(word: &str, name: &str, v: &[&str]) -> String {
    format!(
        "`{}` is not a value of {name}; allowed: {}",
        crate::error::shown(word, 40),
        v.join(", ")
    )
}

/// A word column being filled: keys of its vocabulary's codes, or of its
/// words in the order they first appear (`friction_table`).
pub struct WordKeys {
    /// The column's name (for an error).
    name: &'static str,
    /// The vocabulary, when the column has one.
    vocab: Option<&'static [&'static str]>,
    /// The words met so far, for a column without one.
    seen: Vec<String>,
    keys: Vec<i16>,
}

impl WordKeys {
    /// An empty column `name` with room for `n` rows.
    pub fn new(name: &'static str, n: usize) -> WordKeys {
        WordKeys {
            name,
            vocab: vocabulary(name).map(|v| v()),
            seen: Vec::new(),
            keys: Vec::with_capacity(n),
        }
    }

    /// Appends a row by its code (None: no word).
    #[inline]
    pub(crate) fn push_code(&mut self, code: Option<usize>) {
        self.keys.push(code.map_or(NO_WORD, |c| c as i16));
    }

    /// Appends a row by its word ("" or None: no word); the error's
    /// words when the column's vocabulary lacks it.
    pub fn push(&mut self, word: Option<&str>) -> std::result::Result<(), String> {
        let key = match word.filter(|w| !w.is_empty()) {
            None => NO_WORD,
            Some(w) => match self.vocab {
                Some(v) => match v.iter().position(|x| *x == w) {
                    Some(c) => c as i16,
                    None => return Err(not_a_value(w, self.name, v)),
                },
                None => match self.seen.iter().position(|x| x == w) {
                    Some(c) => c as i16,
                    None if self.seen.len() < i16::MAX as usize => {
                        self.seen.push(w.to_string());
                        (self.seen.len() - 1) as i16
                    }
                    None => return Err(format!("holds over {} different words", i16::MAX)),
                },
            },
        };
        self.keys.push(key);
        Ok(())
    }

    /// The column so far; the builder starts again empty (keeping its
    /// vocabulary).
    pub fn finish(&mut self) -> ArrayRef {
        let mut keys = std::mem::take(&mut self.keys);
        let valid = super::build::nulls_where(&keys, |k| k == NO_WORD);
        if valid.is_some() {
            keys.iter_mut()
                .filter(|k| **k == NO_WORD)
                .for_each(|k| *k = 0);
        }
        let seen = std::mem::take(&mut self.seen);
        match self.vocab {
            Some(v) => dictionary(keys, valid, v),
            None => {
                let words: Vec<&str> = seen.iter().map(String::as_str).collect();
                dictionary(keys, valid, &words)
            }
        }
    }
}

/// Column `name` of a batch read back (words as UTF-8 of any width or as
/// a dictionary), as this version keys it: the vocabulary's codes, or
/// the order of first appearance. The error's words when a word is not
/// the column's.
pub fn canonical(name: &'static str, a: &ArrayRef) -> std::result::Result<ArrayRef, String> {
    let vocab = vocabulary(name).map(|v| v());
    if let Some(d) = a.as_any().downcast_ref::<DictionaryArray<Key>>() {
        let values = d.values().as_string_opt::<i32>();
        if let (Some(v), Some(values)) = (vocab, values) {
            if values.null_count() == 0
                && values.len() == v.len()
                && values.iter().zip(v).all(|(a, b)| a == Some(*b))
            {
                return Ok(a.clone());
            }
            // Keyed otherwise (a Parquet reader's keys): each dictionary
            // word's code found once, then the keys mapped.
            let mut code = Vec::with_capacity(values.len());
            for x in values.iter() {
                code.push(match x.filter(|x| !x.is_empty()) {
                    None => NO_WORD,
                    Some(x) => match v.iter().position(|w| *w == x) {
                        Some(c) => c as i16,
                        None => return Err(not_a_value(x, name, v)),
                    },
                });
            }
            let keys: Vec<i16> = (0..d.len())
                .map(|i| {
                    if d.is_valid(i) {
                        code[d.keys().value(i) as usize]
                    } else {
                        NO_WORD
                    }
                })
                .collect();
            let mut w = WordKeys::new(name, 0);
            w.keys = keys;
            return Ok(w.finish());
        }
    }
    let mut w = WordKeys::new(name, a.len());
    let push_all = |w: &mut WordKeys, it: &mut dyn Iterator<Item = Option<&str>>| {
        for x in it {
            w.push(x)?;
        }
        Ok::<(), String>(())
    };
    match a.data_type() {
        DataType::Utf8 => push_all(&mut w, &mut a.as_string::<i32>().iter())?,
        DataType::LargeUtf8 => push_all(&mut w, &mut a.as_string::<i64>().iter())?,
        DataType::Utf8View => push_all(&mut w, &mut a.as_string_view().iter())?,
        DataType::Dictionary(_, v) if v.as_ref() == &DataType::Utf8 => {
            let d = a.as_any_dictionary();
            let values = d.values().as_string::<i32>();
            let keys = d.normalized_keys();
            let mut it = (0..a.len()).map(|i| {
                (a.is_valid(i) && values.is_valid(keys[i])).then(|| values.value(keys[i]))
            });
            push_all(&mut w, &mut it)?
        }
        t => return Err(format!("is {t}, not words")),
    }
    Ok(w.finish())
}

/// `batch` with each word column keyed as [`canonical`] keys it (the
/// other columns as they are). The error names the column.
pub fn canonical_batch(batch: RecordBatch) -> std::result::Result<RecordBatch, (String, String)> {
    let schema = batch.schema();
    let mut cols = Vec::with_capacity(batch.num_columns());
    let mut changed = false;
    for (f, a) in schema.fields().iter().zip(batch.columns()) {
        if f.data_type() == &word_type() {
            let name = word_column_name(f.name())
                .ok_or_else(|| (f.name().clone(), "is not a word column".into()))?;
            let c = canonical(name, a).map_err(|m| (f.name().clone(), m))?;
            changed |= !Arc::ptr_eq(&c, a);
            cols.push(c);
        } else {
            cols.push(a.clone());
        }
    }
    if !changed {
        return Ok(batch);
    }
    RecordBatch::try_new(schema, cols).map_err(|e| (String::new(), e.to_string()))
}

/// The static name of word column `name` (a parameter's or a result's).
fn word_column_name(name: &str) -> Option<&'static str> {
    Param::from_name(name)
        .map(|p| p.name())
        .or_else(|| result(name).map(|c| c.name))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::batch::Col;

    #[test]
    fn words_are_keyed_by_their_codes_and_read_back_the_same() {
        let mut w = WordKeys::new("status", 4);
        for x in [Some("ok"), None, Some("max_steps"), Some("")] {
            w.push(x).unwrap();
        }
        let a = w.finish();
        let d = a.as_any().downcast_ref::<DictionaryArray<Key>>().unwrap();
        let words = crate::columns::status_words();
        assert_eq!(
            d.keys().value(0) as usize,
            words.iter().position(|w| *w == "ok").unwrap()
        );
        assert_eq!(
            d.keys().value(2) as usize,
            words.iter().position(|w| *w == "max_steps").unwrap()
        );
        assert_eq!(d.null_count(), 2);
        assert!(WordKeys::new("status", 1).push(Some("fine")).is_err());
        // Keyed differently (as a Parquet reader keys it), the same words.
        let other: ArrayRef = Arc::new(
            vec![Some("max_steps"), None, Some("ok"), Some("max_steps")]
                .into_iter()
                .collect::<DictionaryArray<Key>>(),
        );
        let c = canonical("status", &other).unwrap();
        let c = c.as_any().downcast_ref::<DictionaryArray<Key>>().unwrap();
        let read: Vec<Option<&str>> = (0..4)
            .map(|i| c.is_valid(i).then(|| words[c.keys().value(i) as usize]))
            .collect();
        assert_eq!(
            read,
            [Some("max_steps"), None, Some("ok"), Some("max_steps")]
        );
        assert!(Arc::ptr_eq(&canonical("status", &a).unwrap(), &a));
        let odd: ArrayRef = Arc::new(
            vec![Some("ok"), Some("fine")]
                .into_iter()
                .collect::<DictionaryArray<Key>>(),
        );
        assert!(canonical("status", &odd).unwrap_err().contains("`fine`"));
        let plain: ArrayRef = Arc::new(StringArray::from(vec![Some("max_steps"), None]));
        let c = canonical("status", &plain).unwrap();
        assert_eq!(Col::of(&c).unwrap().word(0), "max_steps");
    }

    /// A code is a variant's place in its enum's `ALL` (what `as usize`
    /// gives only when `ALL` lists the variants in declaration order).
    #[test]
    fn codes_are_places_in_the_vocabulary() {
        use crate::integrator::{Contact, Drive, Hold, RowPath, SearchStatus, Side, Status};
        macro_rules! in_order {
            ($($t:ty),*) => {$(
                assert!(<$t>::ALL.iter().enumerate().all(|(i, w)| *w as usize == i), stringify!($t));
            )*};
        }
        in_order!(
            Status,
            Contact,
            Hold,
            Drive,
            Side,
            SearchStatus,
            MotorKind,
            FrictionKind
        );
        for (i, p) in RowPath::every().enumerate() {
            assert_eq!(p.code(), i);
            assert_eq!(RowPath::words()[i], p.name());
        }
        assert_eq!(RowPath::Refined.name(), "cpu:refined");
        let words = vocabulary("friction").unwrap()();
        assert_eq!(words.len(), FrictionKind::ALL.len());
        assert!(vocabulary("friction_table").is_none() && vocabulary("x1_end").is_none());
    }

    #[test]
    fn table_names_are_keyed_by_first_appearance() {
        let mut w = WordKeys::new("friction_table", 4);
        for x in ["b", "a", "b", ""] {
            w.push(Some(x)).unwrap();
        }
        let a = w.finish();
        let d = a.as_any().downcast_ref::<DictionaryArray<Key>>().unwrap();
        assert_eq!(d.keys().values()[..3], [0, 1, 0]);
        assert_eq!(d.values().as_string::<i32>().value(1), "a");
        assert!(d.is_null(3));
    }
}
