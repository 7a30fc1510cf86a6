//! The name of a friction table (`[friction_table.bronze]`, chosen per
//! lane by `friction_table = "bronze"`), held inline so parameter sets stay
//! `Copy` and a million lanes cost no allocation; and a run's tables by
//! name ([`FrictionTables`]).

use std::fmt;

use crate::model::FrictionTable;

/// Longest table name, bytes.
pub const MAX_NAME: usize = 31;

/// A friction table's name: a letter, then letters, digits, `_` or `-`, at
/// most [`MAX_NAME`] of them; empty for the unnamed `[friction_table]`.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct TableName {
    len: u8,
    bytes: [u8; MAX_NAME],
}

impl TableName {
    /// The unnamed table's name.
    pub const UNNAMED: TableName = TableName {
        len: 0,
        bytes: [0; MAX_NAME],
    };

    /// A name, checked; the error says what is allowed.
    pub fn new(text: &str) -> Result<TableName, String> {
        let ok_start = text.chars().next().is_some_and(|c| c.is_ascii_alphabetic());
        let ok_rest = text
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
        if !ok_start || !ok_rest || text.len() > MAX_NAME {
            return Err(format!(
                "`{}` is not a friction table name; allowed: a letter, then letters, digits, _ \
                 or -, at most {MAX_NAME} in all",
                crate::error::shown(text, 40)
            ));
        }
        let mut bytes = [0; MAX_NAME];
        bytes[..text.len()].copy_from_slice(text.as_bytes());
        Ok(TableName {
            len: text.len() as u8,
            bytes,
        })
    }

    /// The name as written.
    pub fn as_str(&self) -> &str {
        // Only ASCII was ever copied in.
        std::str::from_utf8(&self.bytes[..self.len as usize]).unwrap_or("")
    }
}

impl fmt::Display for TableName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl fmt::Debug for TableName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:?}", self.as_str())
    }
}

/// The friction tables of a run, each with its name (one unnamed table
/// for a sweep's plain `[friction_table]`); a lane picks one by index.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrictionTables {
    /// The names, in the sweep file's order.
    pub names: Vec<TableName>,
    /// The tables, in the same order.
    pub tables: Vec<FrictionTable>,
}

impl FrictionTables {
    /// Whether the run has no table.
    pub fn is_empty(&self) -> bool {
        self.tables.is_empty()
    }

    /// Whether the run's one table is the unnamed `[friction_table]`.
    pub(crate) fn unnamed(&self) -> bool {
        self.names == [TableName::UNNAMED]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_bad_ones_say_what_is_allowed() {
        assert_eq!(
            TableName::new("cast_iron-2").unwrap().as_str(),
            "cast_iron-2"
        );
        for bad in ["", "2bronze", "bronze alloy", "bronzé", &"x".repeat(32)] {
            let e = TableName::new(bad).unwrap_err();
            assert!(e.contains("allowed: a letter"), "{bad}: {e}");
        }
        assert_eq!(TableName::new(&"x".repeat(31)).unwrap().as_str().len(), 31);
    }
}
