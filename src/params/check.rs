//! One parameter's value checked against its row of the table: its law,
//! its range, and its relations to the parameters before it; and the
//! error that says which parameter and what is allowed. Shared by the
//! resolution of a lane (`resolve`) and of its gear terms (`gear`).

use std::fmt;

use super::table::{Bound, Fallback, FrictionKind, MotorKind, Num, N_NUM};

/// A parameter that fails validation: which one, and what is allowed.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamError {
    /// The parameter's name.
    pub param: &'static str,
    /// What is wrong and what is allowed.
    pub msg: String,
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.param, self.msg)
    }
}

/// One parameter's value (NaN when its law does not use it) from the
/// value `set` (None: unset), given the ones before it in table order.
/// Inlined: a lane checks every parameter, and the call cost as much as
/// the checks of a parameter its law leaves out.
#[inline(always)]
pub fn check(
    p: Num,
    set: Option<f64>,
    motor: MotorKind,
    friction: FrictionKind,
    num: &[f64; N_NUM],
) -> Result<f64, ParamError> {
    let def = p.def();
    let err = |msg: String| ParamError {
        param: def.name,
        msg,
    };
    if let Some(v) = set.filter(|v| !v.is_finite()) {
        return Err(err(format!(
            "{v} is not finite; a finite number is required"
        )));
    }
    if !def.owner.applies(motor, friction) {
        return match set {
            Some(_) => Err(err(format!(
                "is set but not used by motor = {}, friction = {}; it belongs to {}",
                motor.name(),
                friction.name(),
                def.owner.law()
            ))),
            None => Ok(f64::NAN),
        };
    }
    let v = match (set, def.default) {
        (Some(v), _) => v,
        (None, Fallback::Value(d)) => d,
        (None, Fallback::SameAs(q)) => num[q as usize],
        (None, Fallback::Never | Fallback::NotSet) => return Ok(f64::NAN),
        (None, Fallback::Required) => {
            return Err(err(format!(
                "is required by {}: give it a value (beside an axis over laws, the lanes of \
                 the other laws leave it out)",
                def.owner.law()
            )))
        }
    };
    // Only an error needs the words (this runs for every lane).
    let why = || {
        if def.why.is_empty() {
            String::new()
        } else {
            format!(" ({})", def.why)
        }
    };
    if !def.in_range(v) {
        let why = why();
        return Err(err(format!("must be {}{why}, got {v}", def.range_text())));
    }
    if let Some(q) = def.below.filter(|&q| !(v < num[q as usize])) {
        let b = num[q as usize];
        let lo = match def.lo {
            Bound::None => String::new(),
            _ => format!("{} and ", def.range_text()),
        };
        return Err(err(format!("must be {lo}< {} = {b}, got {v}", q.name())));
    }
    if let Some(q) = def.above.filter(|&q| !(v > num[q as usize])) {
        let b = num[q as usize];
        return Err(err(format!(
            "must be > {} = {b} and {}, got {v}",
            q.name(),
            def.range_text()
        )));
    }
    if let Some(q) = def.at_least.filter(|&q| !(v >= num[q as usize])) {
        let b = num[q as usize];
        let why = why();
        return Err(err(format!("must be >= {} = {b}{why}, got {v}", q.name())));
    }
    Ok(v)
}
