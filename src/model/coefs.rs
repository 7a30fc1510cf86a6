//! The right-hand side's constants of W lanes in their modes
//! ([`Coefs`], one column a constant, so that a loop over the lanes is a
//! loop over vector elements) and the equation of motion of W lanes at
//! once ([`motions`]): the kernel's formulas composed once. The one-lane
//! path is its W = 1 case ([`super::motion`]).

use super::friction::{mu_sliding, tan_series, FrictionTable, TAN_SERIES_MAX};
use super::kernel::{
    load_term, motion_parts, motor_force_of, paper_rho, sliding_speed, switching, Motion,
};
use super::laws::{FrictionKind, MotorKind};
use super::{switch_value, Lane, Mode};
use crate::lanewise::by_lane;

crate::lanewise_scalar!(MotorKind = MotorKind::Kloss);

crate::lanewise_struct! {
    /// A lane's constants in its mode, as the right-hand side reads them.
    #[derive(Clone, Copy, Debug)]
    pub struct Coef, Coefs {
        /// Direction of motion s of the mode.
        pub dir: f64,
        /// Contact side c of the mode.
        pub side: f64,
        /// c s: the sign of tan ρ in ψ.
        pub sd: f64,
        /// The mode's branch of the friction law (`Mode::branch`).
        pub branch: u32,
        /// 1 / cos γ.
        pub inv_cos_g: f64,
        /// tan γ.
        pub tan_g: f64,
        /// Mass of body 1, kg.
        pub m1: f64,
        /// Mass of body 2, kg.
        pub m2: f64,
        /// The load F2, N.
        pub f2: f64,
        /// The paper law's a, b and c (its law slots; read only for its lanes).
        pub fa: f64,
        /// See `fa`.
        pub fb: f64,
        /// See `fa`.
        pub fc: f64,
        /// The motor's law.
        pub motor: MotorKind,
        /// The motor is on in the mode.
        pub motor_on: bool,

        /// A constant motor's force, N.
        pub f1: f64,
        /// The Kloss law's synchronous speed, critical slip and force.
        pub v_sync: f64,
        /// See `v_sync`.
        pub sigma_k: f64,
        /// See `v_sync`.
        pub f_crit: f64,
        /// F2/(m2 tan γ), the switching function's constant part.
        pub load: f64,
        /// The lane's friction law is not the paper's (its μ comes from
        /// `mu_sliding`, lane by lane).
        pub other: bool,
    }
}

impl Coef {
    /// The constants of `lane` in `mode`.
    #[inline(always)]
    pub fn of(lane: &Lane, mode: Mode) -> Coef {
        Coef {
            dir: mode.dir as f64,
            side: mode.side as f64,
            sd: (mode.side * mode.dir) as f64,
            branch: mode.branch,
            inv_cos_g: lane.inv_cos_g,
            tan_g: lane.tan_g,
            m1: lane.m1,
            m2: lane.m2,
            f2: lane.f2,
            fa: lane.law[0],
            fb: lane.law[1],
            fc: lane.law[2],
            motor: lane.motor,
            motor_on: mode.motor_on,

            f1: lane.f1,
            v_sync: lane.v_sync,
            sigma_k: lane.sigma_k,
            f_crit: lane.f_crit,
            load: load_term(lane.f2, lane.m2, lane.tan_g),
            other: lane.friction != FrictionKind::Paper,
        }
    }
}

impl<const W: usize> Coefs<W> {
    /// The constants of `lane` in `mode`, lane by lane.
    #[inline(always)]
    pub fn of(lane: &[&Lane; W], mode: &[Mode; W]) -> Coefs<W> {
        let mut c = Coefs::zero();
        for j in 0..W {
            c.set_lane(j, Coef::of(lane[j], mode[j]));
        }
        c
    }

    /// Lane j's motor force at speed `v`.
    #[inline(always)]
    pub(crate) fn motor_force(&self, j: usize, v: f64) -> f64 {
        motor_force_of(
            self.motor[j],
            self.motor_on[j],
            self.f1[j],
            self.v_sync[j],
            self.sigma_k[j],
            self.f_crit[j],
            v,
        )
    }

    /// The switch event's function c·φ of each lane whose motor force is
    /// `f1` (at the speed φ is wanted at).
    #[inline(always)]
    pub(crate) fn switch_values(&self, f1: &[f64; W]) -> [f64; W] {
        by_lane(|j| {
            let phi = switching(f1[j], self.m1[j], self.load[j]);
            switch_value(self.side[j], phi, self.load[j])
        })
    }
}

/// The equation of motion of W lanes at speeds `v`, each in its mode (its
/// constants `c`): the motor force, the sliding speed, the friction law
/// and [`motion_parts`], as loops over the lanes that compile to vector
/// instructions; `each(j, motion)` takes lane j's. Per lane the
/// arithmetic is the same whatever W and the lanes beside it, so a lane's
/// bits do not depend on them. (A closure, not an array of motions: what
/// `each` does not read, such as D or ψ, is never computed.)
#[inline(always)]
pub fn motions<const W: usize>(
    c: &Coefs<W>,
    lane: &[&Lane; W],
    tables: &[FrictionTable],
    v: &[f64; W],
    mut each: impl FnMut(usize, Motion),
) {
    let vs: [f64; W] = by_lane(|j| sliding_speed(c.dir[j], v[j], c.inv_cos_g[j]));
    let mut rho = [0.0; W];
    let mut mu = [0.0; W];
    // The paper law's pow only where a lane has it.
    if c.other.iter().any(|o| !o) {
        for j in 0..W {
            rho[j] = paper_rho(c.fa[j], c.fb[j], c.fc[j], vs[j]);
            mu[j] = tan_series(rho[j]);
        }
    }
    // The rare lanes off the vector's path: another law, or a friction
    // angle past the series' range (`tan_small`'s rule). Whether there is
    // one is a vector fold; the loop that branches lane by lane runs only
    // then.
    let rare = (0..W).fold(false, |r, j| {
        r | c.other[j] | (rho[j].abs() > TAN_SERIES_MAX)
    });
    if rare {
        for j in 0..W {
            if c.other[j] {
                // Signed: past a rest a table reads its line (`mu_sliding`).
                let at = c.dir[j] * v[j] * c.inv_cos_g[j];
                mu[j] = mu_sliding(lane[j], tables, at, c.branch[j]);
            } else if rho[j].abs() > TAN_SERIES_MAX {
                mu[j] = rho[j].tan();
            }
        }
    }
    for j in 0..W {
        let f1 = c.motor_force(j, v[j]);
        let t = c.sd[j] * mu[j];
        each(
            j,
            motion_parts(f1, t, c.tan_g[j], c.m1[j], c.m2[j], c.f2[j]),
        );
    }
}
