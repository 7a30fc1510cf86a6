//! Partial parameter sets ([`Spec`]) and their resolution into a complete,
//! validated [`Params`], driven by the table of `table.rs` (gear terms
//! converted by `gear.rs` first).

use super::check::check;
pub use super::check::ParamError;
use super::gear;
use super::table::{FrictionKind, MotorKind, Num, Param, N_NUM};
use super::table_name::TableName;
use super::validated::{ParamColumns, Params};

/// A partial parameter set: `None` means "not set, the default applies".
#[derive(Clone, Debug, PartialEq)]
pub struct Spec {
    /// Numeric values, indexed by [`Num`].
    pub num: [Option<f64>; N_NUM],
    /// Motor law.
    pub motor: Option<MotorKind>,
    /// Friction law.
    pub friction: Option<FrictionKind>,
    /// Which named friction table (`friction = table`).
    pub friction_table: Option<TableName>,
}

impl Default for Spec {
    fn default() -> Self {
        Spec {
            num: [None; N_NUM],
            motor: None,
            friction: None,
            friction_table: None,
        }
    }
}

/// Parses a law selector by its serde spelling (the one source of names).
fn parse_law<T: serde::de::DeserializeOwned>(text: &str) -> Option<T> {
    T::deserialize(serde::de::value::StrDeserializer::<serde::de::value::Error>::new(text)).ok()
}

impl Spec {
    /// Sets a numeric parameter.
    pub fn set(&mut self, p: Num, v: f64) {
        self.num[p as usize] = Some(v);
    }

    /// Sets a parameter from its text form (a lane-table cell, say).
    /// Empty text leaves it unset. Errors say what is allowed.
    pub(crate) fn set_text(&mut self, p: Param, text: &str) -> Result<(), String> {
        let text = text.trim();
        if text.is_empty() {
            return Ok(());
        }
        // No number, law or table name holds a line break, so only a cell
        // that is refused is looked at for one (this runs for every cell).
        self.set_trimmed(p, text).map_err(|refused| {
            if text.contains(['\n', '\r']) {
                format!(
                    "`{}` holds a line break; a cell is one number or law name (is a quote left \
                     open?)",
                    crate::error::shown(text, 40)
                )
            } else {
                refused
            }
        })
    }

    /// [`Spec::set_text`] of a trimmed, non-empty cell.
    fn set_trimmed(&mut self, p: Param, text: &str) -> Result<(), String> {
        // Only an error needs the cell's words (this runs for every cell).
        let quoted = || crate::error::shown(text, 40);
        match p {
            Param::Motor => {
                self.motor = Some(parse_law(text).ok_or_else(|| {
                    let laws = MotorKind::ALL.map(MotorKind::name);
                    format!(
                        "`{}` is not a motor law{}; allowed: {}",
                        quoted(),
                        crate::error::did_you_mean(text, laws),
                        laws.join(", ")
                    )
                })?)
            }
            Param::Friction => {
                self.friction = Some(parse_law(text).ok_or_else(|| {
                    let laws = FrictionKind::ALL.map(FrictionKind::name);
                    format!(
                        "`{}` is not a friction law{}; allowed: {}",
                        quoted(),
                        crate::error::did_you_mean(text, laws),
                        laws.join(", ")
                    )
                })?)
            }
            Param::FrictionTable => self.friction_table = Some(TableName::new(text)?),
            Param::Num(n) => {
                let v: f64 = text
                    .parse()
                    .map_err(|_| format!("`{}` is not a number", quoted()))?;
                if !v.is_finite() {
                    return Err(format!(
                        "`{}` is not finite; a finite number is required",
                        quoted()
                    ));
                }
                self.set(n, v);
            }
        }
        Ok(())
    }

    /// Resolves defaults and validates, row by row of the table, after
    /// converting gear terms (docs/model.md section 12) into the wedge's.
    /// `tables`: the names of the run's friction tables (one unnamed, or
    /// the `[friction_table.NAME]`s), for `friction = "table"`.
    pub fn resolve(&self, tables: &[TableName]) -> Result<Params, ParamError> {
        let motor = self.motor.unwrap_or(MotorKind::Kloss);
        let friction = self.friction.unwrap_or(FrictionKind::Paper);
        if !gear::any(&self.num) {
            return self.resolve_wedge(motor, friction, tables);
        }
        let converted = gear::to_wedge(&self.num, motor, friction)?;
        let wedge = Spec {
            num: converted.num,
            ..self.clone()
        };
        let mut p = wedge
            .resolve_wedge(motor, friction, tables)
            .map_err(|e| converted.explain(e))?;
        p.r1 = converted.r1;
        p.r2 = converted.r2;
        Ok(p)
    }

    /// [`Spec::resolve`], appending the lane to `out` (nothing on an
    /// error): a lane in wedge terms goes from its checked values straight
    /// into the columns, with no parameter set in between.
    pub(crate) fn resolve_into(
        &self,
        tables: &[TableName],
        out: &mut ParamColumns,
    ) -> Result<(), ParamError> {
        let motor = self.motor.unwrap_or(MotorKind::Kloss);
        let friction = self.friction.unwrap_or(FrictionKind::Paper);
        if gear::any(&self.num) {
            out.push(&self.resolve(tables)?);
            return Ok(());
        }
        let mut num = [f64::NAN; N_NUM];
        self.check_wedge(motor, friction, &mut num)?;
        let table = self.table_index(friction, tables)?;
        out.push_checked(&num, motor, friction, self.friction_table, table);
        Ok(())
    }

    /// [`Spec::resolve`] once every value is in wedge terms.
    fn resolve_wedge(
        &self,
        motor: MotorKind,
        friction: FrictionKind,
        tables: &[TableName],
    ) -> Result<Params, ParamError> {
        let mut num = [f64::NAN; N_NUM];
        self.check_wedge(motor, friction, &mut num)?;
        let table = self.table_index(friction, tables)?;
        Ok(Params {
            num,
            motor,
            friction,
            friction_table: self.friction_table,
            table,
            r1: f64::NAN,
            r2: f64::NAN,
        })
    }

    /// Every numeric value checked, in table order, into `num`.
    #[inline]
    fn check_wedge(
        &self,
        motor: MotorKind,
        friction: FrictionKind,
        num: &mut [f64; N_NUM],
    ) -> Result<(), ParamError> {
        for p in Num::ALL {
            num[p as usize] = check(p, self.num[p as usize], motor, friction, num)?;
        }
        Ok(())
    }

    /// The lane's friction table among the run's: the one it names, or
    /// the only one.
    pub(super) fn table_index(
        &self,
        friction: FrictionKind,
        tables: &[TableName],
    ) -> Result<usize, ParamError> {
        let err = |param, msg: String| Err(ParamError { param, msg });
        let list = || {
            tables
                .iter()
                .map(|t| t.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        };
        if friction != FrictionKind::Table {
            return match self.friction_table {
                Some(_) => err(
                    "friction_table",
                    format!(
                        "is set but not used by friction = {}; it belongs to friction = table",
                        friction.name()
                    ),
                ),
                None => Ok(0),
            };
        }
        match (self.friction_table, tables) {
            (_, []) => err(
                "friction",
                "= table needs a [friction_table] in the sweep file".into(),
            ),
            (None, [_]) => Ok(0),
            (None, _) => err(
                "friction_table",
                format!(
                    "is required: the sweep has several friction tables; allowed: {}",
                    list()
                ),
            ),
            (Some(name), _) => match tables.iter().position(|t| *t == name) {
                Some(i) => Ok(i),
                None if tables == [TableName::UNNAMED] => err(
                    "friction_table",
                    format!(
                        "names `{name}`, but the sweep's one [friction_table] has no name; name it \
                         [friction_table.{name}] or leave friction_table out"
                    ),
                ),
                None => err(
                    "friction_table",
                    format!(
                        "`{name}` is not a friction table of the sweep; allowed: {}",
                        list()
                    ),
                ),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_the_paper_design() {
        let p = Spec::default().resolve(&[]).unwrap();
        assert_eq!(p.get(Num::M1), 586.0);
        assert!((p.get(Num::GammaDeg).to_radians().tan() - 0.1).abs() < 1e-15);
        assert!(p.get(Num::Mu).is_nan());
        assert!(p.get(Num::MotorOff).is_nan());
    }

    #[test]
    fn coulomb_static_defaults_to_mu() {
        let mut s = Spec {
            friction: Some(FrictionKind::Coulomb),
            ..Default::default()
        };
        s.set(Num::Mu, 0.05);
        let p = s.resolve(&[]).unwrap();
        assert_eq!(p.get(Num::MuStatic), 0.05);
        assert!(p.get(Num::FricA).is_nan());
    }

    #[test]
    fn errors_name_the_range() {
        let mut s = Spec::default();
        s.set(Num::VCrit, 3.4);
        let e = s.resolve(&[]).unwrap_err();
        assert_eq!(e.param, "v_crit");
        assert_eq!(e.msg, "must be >= 0 m/s and < v_sync = 3.35, got 3.4");
        let mut s = Spec::default();
        s.set(Num::GammaDeg, 1e-9);
        assert_eq!(
            s.resolve(&[]).unwrap_err().msg,
            "must be in [0.5, 85] deg (worm lead angles; towards 0 or 90 deg the \
             efficiencies lose meaning), got 0.000000001"
        );
    }
}
