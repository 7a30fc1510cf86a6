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
            // The (motor, friction) of each word of the axis, the lane's
            // other law held.
            let laws: Vec<(MotorKind, FrictionKind)> = match a.param {
                Param::Motor => MotorKind::ALL
                    .into_iter()
                    .filter(|m| words.iter().any(|w| w == m.name()))
                    .map(|m| (m, friction))
                    .collect(),
                Param::Friction => FrictionKind::ALL
                    .into_iter()
                    .filter(|f| words.iter().any(|w| w == f.name()))
                    .map(|f| (motor, f))
                    .collect(),
                _ => continue,
            };
            for n in crate::params::Num::ALL {
                let owner = n.def().owner;
                if spec.num[n as usize].is_some()
                    && !owner.applies(motor, friction)
                    && laws.iter().any(|&(m, f)| owner.applies(m, f))
                {
                    spec.num[n as usize] = None;
                }
            }
            let table = |f: FrictionKind| f == FrictionKind::Table;
            if a.param == Param::Friction && !table(friction) && laws.iter().any(|&(_, f)| table(f))
            {
                spec.friction_table = None;
            }
        }
    }
}
