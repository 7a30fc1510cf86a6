//! A lane's validated parameters into the constants the integrator reads
//! ([`Lane::new`]): the parameters are this module's to read, the
//! [`Lane`] the model's.

use super::table::{law_params, Num};
use super::validated::LaneParams;
use crate::model::laws::{StaticMu, SteepAtRest, LAW_SLOTS};
use crate::model::{mu_at, FrictionTable, Lane, MotorKind};

impl Lane {
    /// Derives a lane's constants from validated parameters.
    pub fn new(p: &impl LaneParams, tables: &[FrictionTable]) -> Lane {
        let g = p.get(Num::GammaDeg).to_radians();
        let inv_cos_an = match p.get(Num::AlphaNDeg) {
            a if a.is_nan() => 1.0,
            a => 1.0 / a.to_radians().cos(),
        };
        let nan_to = |v: f64, d: f64| if v.is_nan() { d } else { v };
        let (motor, v_sync, sigma_k, f_crit, f1) = match p.motor() {
            MotorKind::Kloss => {
                let vs = p.get(Num::VSync);
                (
                    MotorKind::Kloss,
                    vs,
                    (vs - p.get(Num::VCrit)) / vs,
                    p.get(Num::FCrit),
                    0.0,
                )
            }
            MotorKind::Constant => (MotorKind::Constant, 1.0, 1.0, 0.0, p.get(Num::F1)),
        };
        let mut lane = Lane {
            m1: p.get(Num::M1),
            m2: p.get(Num::M2),
            tan_g: g.tan(),
            sin_g: g.sin(),
            cos_g: g.cos(),
            inv_cos_g: 1.0 / g.cos(),
            f2: p.get(Num::F2),
            motor,
            v_sync,
            sigma_k,
            f_crit,
            f1,
            motor_off: nan_to(p.get(Num::MotorOff), f64::INFINITY),
            friction: p.friction(),
            table: p.table() as u32,
            inv_cos_an,
            law: [0.0; LAW_SLOTS],
            mu_s: 0.0,
            steep: false,
            branch_speed: f64::INFINITY,
            x1_0: p.get(Num::X10),
            v1_0: p.get(Num::V10),
            t_end: p.get(Num::TEnd),
            t_max: nan_to(p.get(Num::TMax), p.get(Num::TEnd)),
        };
        // The law's declaration says the rest.
        let law = p.friction().law();
        for (slot, &n) in lane.law.iter_mut().zip(law_params(p.friction())) {
            *slot = p.get(n);
        }
        lane.mu_s = match law.static_mu {
            StaticMu::AtRest => mu_at(&lane, tables, 0.0),
            StaticMu::Slot(i) => lane.law[i] * inv_cos_an,
            StaticMu::Value(mu) => mu * inv_cos_an,
        };
        lane.steep = match law.steep {
            SteepAtRest::No => false,
            SteepAtRest::Yes => true,
            SteepAtRest::UnlessWholeExponent(i) => lane.law[i].fract() != 0.0,
        };
        lane.branch_speed = law.branch_speed.unwrap_or(f64::INFINITY);
        lane
    }
}
