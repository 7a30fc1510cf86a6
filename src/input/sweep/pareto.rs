//! `[report] pareto`: the trade-offs between two or three result number
//! columns, each to be made as large (`max`) or as small (`min`) as it
//! can: the designs that no other design beats on every one of them.
//!
//! ```toml
//! # fragment
//! [report]
//! pareto = ["max eta_direct_ss", "max lock_margin_deg"]
//! ```
//!
//! A bare column name means `max`.

/// One objective of a Pareto front: a result number column and its
/// direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Objective {
    /// The result column.
    pub column: &'static str,
    /// Larger is better (`max`), else smaller (`min`).
    pub max: bool,
}

/// Fewest and most objectives.
pub(crate) const OBJECTIVES: (usize, usize) = (2, 3);

impl Objective {
    /// Its text, as the sweep file and `sweep.resolved.toml` write it.
    pub fn text(&self) -> String {
        format!("{} {}", if self.max { "max" } else { "min" }, self.column)
    }

    /// `v` as a value to make as large as possible.
    pub(crate) fn gain(&self, v: f64) -> f64 {
        if self.max {
            v
        } else {
            -v
        }
    }
}

/// The objectives of `[report] pareto`; the error says what is allowed.
pub fn parse(items: &[String]) -> Result<Vec<Objective>, String> {
    let (fewest, most) = OBJECTIVES;
    if !(fewest..=most).contains(&items.len()) {
        return Err(format!(
            "has {} entries; allowed: {fewest} or {most} result columns, each \"max NAME\" or \
             \"min NAME\"",
            items.len()
        ));
    }
    let allowed: Vec<&'static str> = crate::columns::number_columns().map(|c| c.name).collect();
    let mut out: Vec<Objective> = Vec::new();
    for item in items {
        let words: Vec<&str> = item.split_whitespace().collect();
        let (max, name) = match words.as_slice() {
            [name] => (true, *name),
            ["max", name] => (true, *name),
            ["min", name] => (false, *name),
            _ => {
                return Err(format!(
                    "`{}` is not an objective; allowed: \"max NAME\" or \"min NAME\" (NAME a \
                     result number column)",
                    crate::error::shown(item, 40)
                ))
            }
        };
        let column = allowed.iter().find(|c| **c == name).ok_or_else(|| {
            format!(
                "`{}` is not a result number column{}; allowed: {}",
                crate::error::shown(name, 40),
                crate::error::did_you_mean(name, allowed.iter().copied()),
                allowed.join(", ")
            )
        })?;
        if out.iter().any(|o| o.column == *column) {
            return Err(format!("names {column} twice; each column once"));
        }
        out.push(Objective { column, max });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn objectives_read_with_their_directions() {
        let o = parse(&["eta_direct_ss".into(), "min lock_margin_deg".into()]).unwrap();
        assert_eq!(o[0].text(), "max eta_direct_ss");
        assert_eq!(o[1].text(), "min lock_margin_deg");
        assert_eq!(o[1].gain(2.0), -2.0);
        for bad in [
            vec!["eta_direct_ss"],
            vec!["eta_direct_ss", "hold"],
            vec!["eta_direct_ss", "most lock_margin_deg"],
            vec!["eta_direct_ss", "max eta_direct_ss"],
            vec!["a", "b", "c", "d"],
        ] {
            let items: Vec<String> = bad.iter().map(|s| s.to_string()).collect();
            assert!(parse(&items).is_err(), "{bad:?}");
        }
    }
}
