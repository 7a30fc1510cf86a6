//! A lane's validated parameters into the constants the integrator reads
//! ([`Lane::new`]): the parameters are this module's to read, the
//! [`Lane`] the model's.

use super::table::Num;
use super::validated::LaneParams;
use crate::model::friction::AGMA_MU_STATIC;
use crate::model::{mu_sliding, FrictionKind, FrictionTable, Lane, MotorKind};

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
            fric_a: nan_to(p.get(Num::FricA), 0.0),
            fric_b: nan_to(p.get(Num::FricB), 1.0),
            fric_c: nan_to(p.get(Num::FricC), 1.0),
            mu: nan_to(p.get(Num::Mu), 0.0) * inv_cos_an,
            mu_s: 0.0,
            x1_0: p.get(Num::X10),
            v1_0: p.get(Num::V10),
            t_end: p.get(Num::TEnd),
            t_max: nan_to(p.get(Num::TMax), p.get(Num::TEnd)),
        };
        lane.mu_s = match p.friction() {
            FrictionKind::Coulomb => p.get(Num::MuStatic) * inv_cos_an,
            FrictionKind::Agma => AGMA_MU_STATIC * inv_cos_an,
            _ => mu_sliding(&lane, tables, 0.0, false),
        };
        lane
    }
}
