//! What a run gives of the paper's drive (docs/model.md section 7): the
//! parameters its sweep or lane table sets, and the motor laws its lanes
//! may take, for [`crate::params::paper::paper_defaults`].

use super::lanes::Source;
use crate::params::Spec;

impl Source {
    /// What the run gives of the paper's drive (docs/model.md section
    /// 7): the parameters set anywhere (a sweep's `[base]` keys, axes and
    /// tolerances; a lane table's columns and the `[base]` under it) and
    /// the motor laws its lanes may take, for
    /// [`crate::params::paper::paper_defaults`]. A lane table's own
    /// `motor` column leaves the Kloss motor's values unnamed (which rows
    /// use it is not read here).
    pub fn given(&self) -> crate::params::paper::Given {
        use crate::params::{MotorKind, Param};
        let set_in = |base: &Spec| -> Vec<Param> {
            let mut v: Vec<Param> = crate::params::Num::ALL
                .into_iter()
                .filter(|&n| base.num[n as usize].is_some())
                .map(Param::Num)
                .collect();
            v.extend(base.motor.map(|_| Param::Motor));
            v.extend(base.friction.map(|_| Param::Friction));
            v
        };
        let (params, motors) = match self {
            Source::Sweep { sweep, .. } => {
                let mut params = set_in(&sweep.base);
                params.extend(
                    sweep
                        .key_lines
                        .iter()
                        .filter_map(|(n, _)| Param::from_name(n)),
                );
                let motors = match sweep.axes.iter().find(|a| a.param == Param::Motor) {
                    Some(a) => (0..a.len())
                        .filter_map(|i| MotorKind::ALL.into_iter().find(|m| m.name() == a.text(i)))
                        .collect(),
                    None => vec![sweep.base.motor.unwrap_or(MotorKind::Kloss)],
                };
                (params, motors)
            }
            Source::Table { table, base, .. } => {
                let mut params = set_in(base);
                params.extend(table.params());
                let motors = if params.contains(&Param::Motor) && base.motor.is_none() {
                    Vec::new()
                } else {
                    vec![base.motor.unwrap_or(MotorKind::Kloss)]
                };
                (params, motors)
            }
        };
        // A search sets its parameter.
        let mut params = params;
        params.extend(self.search().map(|s| crate::params::Param::Num(s.param)));
        crate::params::paper::Given { params, motors }
    }
}
