//! The TSWM physics of docs/model.md sections 2 to 5: forces, the force
//! transfer function ψ, the equation of motion, the switching function φ
//! and the stick test. No integration here: the integrator calls these.
//!
//! Each formula is written once, in [`kernel`]; [`coefs`] composes them
//! into the equation of motion of W lanes at once, and the one-lane
//! functions here ([`motion`], [`phi`], ...) are its W = 1 case or call
//! the kernel with one lane's fields. The laws are declared in [`laws`];
//! [`friction`] turns a friction law into the wedge's tan ρ.
//!
//! The shader mirrors these files in `shaders/model/`, a file of the same
//! name for each it mirrors.

pub mod coefs;
pub mod friction;
pub mod kernel;
pub mod lane;
pub mod laws;
pub mod vmath;

pub use coefs::{motions, Coef, Coefs};
pub use friction::{
    branch_edges, branch_of, mu_at, mu_sliding, tan_small, FrictionTable, MAX_TABLES,
    MAX_TABLE_POINTS,
};
pub use kernel::{Motion, Motions};
pub use lane::Lane;
pub use laws::{agma_mu, agma_upper, FrictionKind, MotorKind, AGMA_JUMP_M_S};

use crate::lanewise::Lanewise;
use kernel::{load_term, motor_force_of, switching};

/// Motor force F1 at speed `v1`; zero once the motor is off.
#[inline]
pub(crate) fn motor_force(lane: &Lane, v1: f64, motor_on: bool) -> f64 {
    motor_force_of(
        lane.motor,
        motor_on,
        lane.f1,
        lane.v_sync,
        lane.sigma_k,
        lane.f_crit,
        v1,
    )
}

/// Switching function φ = F1/m1 − F2/(m2 tan γ): a-a when > 0, b-b when < 0.
#[inline]
pub fn phi(lane: &Lane, v1: f64, motor_on: bool) -> f64 {
    let load = load_term(lane.f2, lane.m2, lane.tan_g);
    switching(motor_force(lane, v1, motor_on), lane.m1, load)
}

/// The switch event's function, c·φ for a lane on side `side` (c) with
/// switching function `phi`, or 1 (never a switch) where the lane has no
/// load (`load`, F2/(m2 tan γ), is 0): φ = F1/m1 then changes sign only
/// where F1 does, at a Kloss motor's synchronous speed, a fixed point of
/// the motion (ẍ1 = F1/D = 0 there, on either side) that a lane
/// approaches and never crosses. A crossing located there would be
/// rounding (f32's speed does overshoot it), and the side stays.
#[inline(always)]
pub(crate) fn switch_value(side: f64, phi: f64, load: f64) -> f64 {
    if load == 0.0 {
        1.0
    } else {
        side * phi
    }
}

/// The contact side for φ: +1 (a-a) when φ >= 0, else −1 (b-b).
#[inline]
pub(crate) fn side_of(phi: f64) -> i32 {
    if phi >= 0.0 {
        1
    } else {
        -1
    }
}

/// The mode a lane slides in between events, frozen for a whole step:
/// contact side, direction, motor, and the friction law's branch.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Mode {
    /// Contact side c: +1 a-a, −1 b-b.
    pub side: i32,
    /// Direction of motion s.
    pub dir: i32,
    /// Motor force on.
    pub motor_on: bool,
    /// The friction law's branch ([`branch_of`]): for `agma` 1 above its
    /// branch speed (10 ft/min), else 0; for `table` the piece between
    /// two of its speeds; 0 for the laws of one piece. Frozen so a step's
    /// right-hand side is smooth: the law's jumps and kinks between
    /// branches are events.
    pub branch: u32,
}

/// Equation of motion in mode `mode` (side c, direction s) at speed `v1`:
/// [`motions`] of one lane.
#[inline]
pub fn motion(lane: &Lane, tables: &[FrictionTable], mode: Mode, v1: f64) -> Motion {
    let mut out = Motion::default();
    motions::<1>(
        &Coef::of(lane, mode).one(),
        &[lane],
        tables,
        &[v1],
        |_, m| out = m,
    );
    out
}

/// Stick test at rest (docs/model.md section 4): returns (sticks, T), where T is
/// the tangential force needed at rest; sign(T) is the direction of
/// departure when the lane does not stick.
#[inline]
pub(crate) fn stick_test(lane: &Lane, motor_on: bool) -> (bool, f64) {
    let f1 = motor_force(lane, 0.0, motor_on);
    let n = (lane.f2 * lane.cos_g - f1 * lane.sin_g).abs();
    let t = f1 * lane.cos_g + lane.f2 * lane.sin_g;
    (t.abs() <= lane.mu_s * n, t)
}

/// Mesh efficiency in the current mode: direct flow (c·s = +1, the worm
/// drives) −S2ẋ2/(S1ẋ1), inverse flow (c·s = −1, the wheel drives)
/// −S1ẋ1/(S2ẋ2). NaN when there is no power flow.
#[inline]
pub fn efficiency(lane: &Lane, m: &Motion, side: i32, dir: i32, v1: f64) -> f64 {
    let p1 = m.s1 * v1;
    let p2 = m.s2 * v1 * lane.tan_g;
    let (p_in, p_out) = if side * dir > 0 { (p1, p2) } else { (p2, p1) };
    if p_in == 0.0 {
        f64::NAN
    } else {
        -p_out / p_in
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Spec;

    fn paper() -> Lane {
        Lane::new(&Spec::default().resolve(&[]).unwrap(), &[])
    }

    #[test]
    fn kloss_is_zero_at_sync_and_peaks_at_crit() {
        let l = paper();
        assert_eq!(motor_force(&l, 3.35, true), 0.0);
        assert!((motor_force(&l, 2.07, true) - 4375.0).abs() < 1e-9);
        assert!(motor_force(&l, 3.5, true) < 0.0);
        assert_eq!(motor_force(&l, 1.0, false), 0.0);
    }

    #[test]
    fn psi_is_the_papers_kernel_and_s2_follows_phi() {
        let l = paper();
        let g = 0.1f64.atan();
        for (side, want_rho_sign) in [(1, 1.0), (-1, -1.0)] {
            let v = 1.0;
            let m = motion(
                &l,
                &[],
                Mode {
                    side,
                    dir: 1,
                    motor_on: true,
                    branch: 0,
                },
                v,
            );
            let rho = mu_at(&l, &[], v / l.cos_g).atan();
            let psi = -(g + want_rho_sign * rho).tan();
            assert!((m.s1 - psi * m.s2).abs() < 1e-9 * m.s1.abs().max(1.0));
            // S2 = −m1 m2 tanγ φ / D
            let s2 = -l.m1 * l.m2 * l.tan_g * phi(&l, v, true) / m.d;
            assert!((m.s2 - s2).abs() < 1e-9 * s2.abs().max(1.0));
        }
    }

    #[test]
    fn steady_efficiency_is_tan_ratio() {
        let l = paper();
        let v = 2.0;
        let m = motion(
            &l,
            &[],
            Mode {
                side: 1,
                dir: 1,
                motor_on: true,
                branch: 0,
            },
            v,
        );
        let rho = mu_at(&l, &[], v / l.cos_g).atan();
        let g = l.tan_g.atan();
        assert!((efficiency(&l, &m, 1, 1, v) - g.tan() / (g + rho).tan()).abs() < 1e-12);
        let m = motion(
            &l,
            &[],
            Mode {
                side: -1,
                dir: 1,
                motor_on: true,
                branch: 0,
            },
            v,
        );
        assert!((efficiency(&l, &m, -1, 1, v) - (g - rho).tan() / g.tan()).abs() < 1e-12);
        // Running backwards on the a-a side the wheel drives: inverse flow.
        let m = motion(
            &l,
            &[],
            Mode {
                side: 1,
                dir: -1,
                motor_on: false,
                branch: 0,
            },
            -v,
        );
        assert!((efficiency(&l, &m, 1, -1, -v) - (g - rho).tan() / g.tan()).abs() < 1e-12);
    }
}
