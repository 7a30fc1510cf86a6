//! Word axes over laws: each lane takes the parameters its own law uses.

use super::{AxisValues, Sweep};
use crate::params::{FrictionKind, MotorKind, Param, Spec};

impl Sweep {
    /// On a word axis over laws (`motor`, `friction`), each lane takes the
    /// parameters its own law uses: a parameter that some word of the
    /// axis uses (`mu` beside `friction = ["coulomb", "agma"]`, `f1`
    /// beside `motor = ["kloss", "constant"]`) is left out of the lanes
    /// whose law does not use it. One a word of no axis uses stays, and
    /// is refused as set but not used.
    pub(super) fn keep_own_law_params(&self, spec: &mut Spec) {
        for a in &self.axes {
            let AxisValues::Words(words) = &a.values else {
                continue;
            };
            let motor = spec.motor.unwrap_or(MotorKind::Kloss);
            let friction = spec.friction.unwrap_or(FrictionKind::Paper);
            // Whether some word of the axis, the lane's other law held,
            // satisfies `uses` (no allocation: this runs for every lane).
            let some_word = |uses: &dyn Fn(MotorKind, FrictionKind) -> bool| match a.param {
                Param::Motor => motors_on(words).any(|m| uses(m, friction)),
                Param::Friction => frictions_on(words).any(|f| uses(motor, f)),
                _ => false,
            };
            for n in crate::params::Num::ALL {
                let owner = n.def().owner;
                if spec.num[n as usize].is_some()
                    && !owner.applies(motor, friction)
                    && some_word(&|m, f| owner.applies(m, f))
                {
                    spec.num[n as usize] = None;
                }
            }
            let table = |f: FrictionKind| f == FrictionKind::Table;
            if a.param == Param::Friction && !table(friction) && some_word(&|_, f| table(f)) {
                spec.friction_table = None;
            }
        }
    }
}

/// The motor laws among an axis's words.
pub(super) fn motors_on(words: &[String]) -> impl Iterator<Item = MotorKind> + '_ {
    MotorKind::ALL
        .into_iter()
        .filter(|m| words.iter().any(|w| w == m.name()))
}

/// The friction laws among an axis's words.
pub(super) fn frictions_on(words: &[String]) -> impl Iterator<Item = FrictionKind> + '_ {
    FrictionKind::ALL
        .into_iter()
        .filter(|f| words.iter().any(|w| w == f.name()))
}
