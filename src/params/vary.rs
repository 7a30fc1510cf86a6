//! A lane resolved once and then again and again with one numeric
//! parameter changed: a search's queries of one drive. Only the changed
//! parameter and those whose check reads it (a bound, an `at least`, a
//! default taken from it) are checked again, so a query costs a few
//! checks instead of the whole table; the values are those of
//! [`Spec::resolve_into`] with the parameter set, bit for bit.

use super::check::check;
use super::gear;
use super::resolve::{ParamError, Spec};
use super::table::{Fallback, FrictionKind, MotorKind, Num, N_NUM};
use super::table_name::TableName;
use super::validated::ParamColumns;

/// A lane with one numeric parameter left to set (see the module).
#[derive(Clone, Debug)]
pub struct Varying {
    p: Num,
    how: How,
}

// The large variant is the common one: boxing it would allocate a drive.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug)]
enum How {
    /// In wedge terms: the values of every parameter the changed one does
    /// not reach, checked once, and the values given to those it reaches
    /// (NaN where none is given), unchecked.
    Wedge {
        num: [f64; N_NUM],
        /// The parameters checked again, a bit each by [`Num`] index.
        again: u64,
        /// Those of them given a value.
        given: u64,
        motor: MotorKind,
        friction: FrictionKind,
        friction_table: Option<TableName>,
        table: usize,
    },
    /// Gear terms are converted as a whole: every query is resolved anew.
    Whole(Box<Spec>),
}

/// `p` and every parameter whose check reads one of them, a bit each by
/// [`Num`] index (a check reads only parameters before it in the table).
fn reached_from(p: Num) -> u64 {
    const _: () = assert!(N_NUM <= 64, "a parameter set is a bit each in a u64");
    let mut hit = [false; N_NUM];
    hit[p as usize] = true;
    for q in Num::ALL {
        let d = q.def();
        let reads = [d.below, d.above, d.at_least]
            .into_iter()
            .flatten()
            .chain(match d.default {
                Fallback::SameAs(r) => Some(r),
                _ => None,
            });
        if reads.into_iter().any(|r| hit[r as usize]) {
            hit[q as usize] = true;
        }
    }
    Num::ALL
        .into_iter()
        .filter(|q| hit[*q as usize])
        .fold(0, |m, q| m | 1 << q as usize)
}

impl Spec {
    /// This lane with `p` left to set by [`Varying::resolve_into`]; an
    /// error of a parameter that `p` does not reach is found here.
    pub(crate) fn varying(&self, p: Num, tables: &[TableName]) -> Result<Varying, ParamError> {
        let mut alone = [None; N_NUM];
        alone[p as usize] = Some(0.0);
        let how = if gear::any(&self.num) || gear::any(&alone) {
            How::Whole(Box::new(self.clone()))
        } else {
            let motor = self.motor.unwrap_or(MotorKind::Kloss);
            let friction = self.friction.unwrap_or(FrictionKind::Paper);
            let again = reached_from(p);
            let (mut num, mut given) = ([f64::NAN; N_NUM], 0);
            for q in Num::ALL {
                let set = self.num[q as usize];
                if again & 1 << q as usize == 0 {
                    num[q as usize] = check(q, set, motor, friction, &num)?;
                } else if let Some(v) = set {
                    num[q as usize] = v;
                    given |= 1 << q as usize;
                }
            }
            How::Wedge {
                num,
                again,
                given,
                motor,
                friction,
                friction_table: self.friction_table,
                table: self.table_index(friction, tables)?,
            }
        };
        Ok(Varying { p, how })
    }
}

impl Varying {
    /// The lane with its parameter at `x`, resolved and appended to `out`
    /// (nothing on an error), as [`Spec::resolve_into`] would.
    pub(crate) fn resolve_into(
        &self,
        x: f64,
        tables: &[TableName],
        out: &mut ParamColumns,
    ) -> Result<(), ParamError> {
        match &self.how {
            How::Whole(spec) => {
                let mut spec = (**spec).clone();
                spec.set(self.p, x);
                spec.resolve_into(tables, out)
            }
            How::Wedge {
                num: known,
                again,
                given,
                motor,
                friction,
                friction_table,
                table,
            } => {
                let mut num = *known;
                for q in Num::ALL
                    .into_iter()
                    .filter(|q| again & 1 << *q as usize != 0)
                {
                    let set = if q == self.p {
                        Some(x)
                    } else if given & 1 << q as usize != 0 {
                        Some(known[q as usize])
                    } else {
                        None
                    };
                    num[q as usize] = check(q, set, *motor, *friction, &num)?;
                }
                out.push_checked(&num, *motor, *friction, *friction_table, *table);
                Ok(())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every numeric parameter varied over values in and out of its range,
    /// on the paper's lane and on lanes of other laws: the same columns
    /// (bit for bit) or the same error as a whole resolution.
    #[test]
    fn a_varied_lane_resolves_as_a_whole_one_does() {
        let tables: [TableName; 0] = [];
        let mut laws = Vec::new();
        for m in MotorKind::ALL {
            for f in FrictionKind::ALL {
                let law = Spec {
                    motor: Some(m),
                    friction: Some(f),
                    ..Spec::default()
                };
                // And with values given to the parameters whose checks
                // read others (v_crit < v_sync, mu_static >= mu, t_max >
                // t_end, n_crit < n_sync), where the law uses them.
                let mut given = law.clone();
                for (p, v) in [
                    (Num::VCrit, 2.0),
                    (Num::MuStatic, 0.08),
                    (Num::TMax, 5.0),
                    (Num::NCrit, 900.0),
                ] {
                    let mut one = given.clone();
                    one.set(p, v);
                    if one.resolve_into(&[], &mut ParamColumns::default()).is_ok() {
                        given = one;
                    }
                }
                laws.push(law);
                laws.push(given);
            }
        }
        let xs = [
            -1.0, 0.0, 1e-3, 0.05, 0.3, 1.0, 3.0, 12.0, 100.0, 6000.0, 1e9,
        ];
        for base in &laws {
            for p in Num::ALL {
                let whole_at = |x: f64| {
                    let mut whole = base.clone();
                    whole.set(p, x);
                    let mut a = ParamColumns::default();
                    whole.resolve_into(&tables, &mut a).map(|()| a.params(0))
                };
                let v = match base.varying(p, &tables) {
                    Ok(v) => v,
                    Err(e) => {
                        // An error the parameter does not reach: every
                        // value of it fails as a whole lane.
                        for x in xs {
                            assert!(whole_at(x).is_err(), "{} = {x}: {e:?}", p.name());
                        }
                        continue;
                    }
                };
                for x in xs {
                    let mut b = ParamColumns::default();
                    let (ra, rb) = (whole_at(x), v.resolve_into(x, &tables, &mut b));
                    assert_eq!(ra.is_ok(), rb.is_ok(), "{} = {x}: {ra:?} {rb:?}", p.name());
                    if let Ok(pa) = ra {
                        let pb = b.params(0);
                        for q in Num::ALL {
                            let (u, w) = (pa.num[q as usize], pb.num[q as usize]);
                            assert!(
                                u.to_bits() == w.to_bits(),
                                "{} = {x}: {} {u} {w}",
                                p.name(),
                                q.name()
                            );
                        }
                        assert_eq!(
                            (pa.motor, pa.friction, pa.table),
                            (pb.motor, pb.friction, pb.table)
                        );
                    }
                }
            }
        }
    }
}
