//! A design requirement written in a sweep (`[report] require = "hold =
//! held"`, `at_least = 0.99`): a test on one result column that a share
//! of drives must pass. The report states, per value of the first grid
//! axis, whether the share is met with 95 % confidence.

use crate::columns::{result, Cell, Kind, Summary};

/// A comparison of a number column with a value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    /// `<`
    Lt,
    /// `<=`
    Le,
    /// `>`
    Gt,
    /// `>=`
    Ge,
}

impl Op {
    fn text(self) -> &'static str {
        match self {
            Op::Lt => "<",
            Op::Le => "<=",
            Op::Gt => ">",
            Op::Ge => ">=",
        }
    }
}

/// What a lane's cell must be.
#[derive(Clone, Debug, PartialEq)]
pub enum Test {
    /// A word column equals this word.
    Word(String),
    /// A number column compares so with this value (an empty cell fails).
    Number(Op, f64),
}

/// A requirement: a column, its test, and the least share of lanes that
/// must pass it.
#[derive(Clone, Debug, PartialEq)]
pub struct Requirement {
    /// The result column tested.
    pub column: &'static str,
    /// The test.
    pub test: Test,
    /// Least share of lanes that must pass, in (0, 1].
    pub at_least: f64,
}

impl Requirement {
    /// Parses `text` ("hold = held", "eta_direct >= 0.8") with its share;
    /// errors say what is allowed.
    pub fn parse(text: &str, at_least: f64) -> Result<Requirement, String> {
        if !(at_least > 0.0 && at_least <= 1.0) {
            return Err(format!(
                "at_least must be a share in (0, 1], got {at_least}"
            ));
        }
        let allowed = "allowed: `COLUMN = WORD` for a word column (hold, contact_end, status) \
                       or `COLUMN >= X` (also >, <=, <) for a result number column";
        let ops = [
            (">=", Some(Op::Ge)),
            ("<=", Some(Op::Le)),
            ("==", None),
            (">", Some(Op::Gt)),
            ("<", Some(Op::Lt)),
            ("=", None),
        ];
        let (at, op, len) = ops
            .iter()
            .filter_map(|(s, op)| text.find(s).map(|i| (i, *op, s.len())))
            .min_by_key(|x| x.0)
            .ok_or_else(|| format!("`{}` has no comparison; {allowed}", shown(text)))?;
        let (name, value) = (text[..at].trim(), text[at + len..].trim());
        let col = result(name)
            .ok_or_else(|| format!("`{}` is not a result column; {allowed}", shown(name)))?;
        let test = match (col.kind(), col.summary, op) {
            (Kind::Text, Summary::Shares(_), None) => {
                let words = col.vocabulary().unwrap_or_default();
                if !words.contains(&value) {
                    return Err(format!(
                        "`{}` is not a value of {}; allowed: {}",
                        shown(value),
                        col.name,
                        words.join(", ")
                    ));
                }
                Test::Word(value.to_string())
            }
            (Kind::Float | Kind::Int, Summary::Numbers, Some(op)) => {
                let v: f64 = value
                    .parse()
                    .map_err(|_| format!("`{}` is not a number; {allowed}", shown(value)))?;
                if !v.is_finite() {
                    return Err(format!("`{}` is not finite", shown(value)));
                }
                Test::Number(op, v)
            }
            _ => return Err(format!("`{}` cannot be tested so; {allowed}", shown(text))),
        };
        Ok(Requirement {
            column: col.name,
            test,
            at_least,
        })
    }

    /// Whether a lane whose cell of [`Requirement::column`] is `cell`
    /// passes.
    pub fn passes(&self, cell: &Cell) -> bool {
        self.passes_value(cell.word(), cell.number())
    }

    /// Whether a lane whose cell in the column is `word` (a word column)
    /// or `x` (a number column) passes.
    pub(crate) fn passes_value(&self, word: &str, x: f64) -> bool {
        match &self.test {
            Test::Word(w) => word == w,
            Test::Number(op, v) => match op {
                Op::Lt => x < *v,
                Op::Le => x <= *v,
                Op::Gt => x > *v,
                Op::Ge => x >= *v,
            },
        }
    }

    /// The test as written in the sweep, normalised ("hold = held").
    pub fn text(&self) -> String {
        match &self.test {
            Test::Word(w) => format!("{} = {w}", self.column),
            Test::Number(op, v) => format!("{} {} {v}", self.column, op.text()),
        }
    }
}

fn shown(s: &str) -> String {
    crate::error::shown(s, 40)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn requirements_parse_and_test() {
        let r = Requirement::parse("hold = held", 0.99).unwrap();
        assert_eq!(r.column, "hold");
        assert!(r.passes(&Cell::S("held".into())));
        assert!(!r.passes(&Cell::S("".into())));
        let r = Requirement::parse(" eta_direct>=0.8", 0.9).unwrap();
        assert!(r.passes(&Cell::F(0.8)) && !r.passes(&Cell::F(f64::NAN)));
        assert_eq!(r.text(), "eta_direct >= 0.8");
        for bad in [
            "hold = stuck",
            "mass >= 1",
            "hold >= 1",
            "eta_direct = 1",
            "eta_direct",
        ] {
            assert!(Requirement::parse(bad, 0.9).is_err(), "{bad}");
        }
        assert!(Requirement::parse("hold = held", 1.5).is_err());
    }
}
