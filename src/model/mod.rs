//! The TSWM physics of docs/model.md sections 2 to 5: forces, the force transfer
//! function ψ, the equation of motion, the switching function φ and the
//! stick test. No integration here: the integrator calls these.
//!
//! Keep in sync with the shader's section `src/model/` in
//! `shaders/tswm.wgsl` (functions of the same names, same order); the
//! friction laws are in [`friction`].

pub mod friction;
pub mod vmath;

use crate::params::{FrictionKind, LaneParams, MotorKind, Num};
pub use friction::{
    agma_mu, agma_upper, mu_at, mu_sliding, tan_small, FrictionTable, FrictionTables,
    AGMA_JUMP_M_S, MAX_TABLES, MAX_TABLE_POINTS,
};

/// A lane's constants in the form the integrator uses: fixed size, laws as
/// codes, trigonometry done once.
///
/// Keep in sync with `GpuLane` in `src/backend/gpu/layout.rs` and `Lane` in the shader.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lane {
    pub m1: f64,
    pub m2: f64,
    pub tan_g: f64,
    pub sin_g: f64,
    pub cos_g: f64,
    /// 1 / cos γ
    pub inv_cos_g: f64,
    pub f2: f64,
    /// 0 = kloss, 1 = constant
    pub motor: u32,
    pub v_sync: f64,
    /// critical slip σk
    pub sigma_k: f64,
    pub f_crit: f64,
    pub f1: f64,
    /// time the motor is cut; +inf for never
    pub motor_off: f64,
    /// 0 = paper, 1 = coulomb, 2 = table, 3 = agma
    pub friction: u32,
    /// Which of the run's friction tables (`friction = table`).
    pub table: u32,
    /// 1 / cos αn: a coefficient law's μ becomes the wedge's tan ρ = μ / cos αn.
    pub inv_cos_an: f64,
    pub fric_a: f64,
    pub fric_b: f64,
    pub fric_c: f64,
    /// coulomb's tan ρ = μ / cos αn
    pub mu: f64,
    /// static tan ρs for every law (μs / cos αn, or tan ρ(0))
    pub mu_s: f64,
    pub x1_0: f64,
    pub v1_0: f64,
    pub t_end: f64,
    /// Latest end of a lane still coasting at t_end with its motor cut
    /// (docs/model.md section 10); t_end when unset (no running on).
    pub t_max: f64,
    /// Pitch radii R1, R2 (m) of a lane given in gear terms (docs/model.md
    /// section 12), for its shaft speeds; NaN without a geometry. The
    /// integrator never reads them.
    pub r1: f64,
    pub r2: f64,
}

/// Motor law codes shared with the shader (a test reads the shader's
/// constants and compares).
pub const MOTOR_KLOSS: u32 = 0;
/// Constant motor force.
pub const MOTOR_CONSTANT: u32 = 1;
/// Friction law codes shared with the shader.
pub const FRICTION_PAPER: u32 = 0;
/// Constant μ.
pub const FRICTION_COULOMB: u32 = 1;
/// Tabulated μ(Vs).
pub const FRICTION_TABLE: u32 = 2;
/// AGMA's curve for a steel worm on a bronze wheel.
pub const FRICTION_AGMA: u32 = 3;

impl Lane {
    /// Whether the motor is cut before t_end: only then does the lane
    /// answer "does it hold?" (docs/model.md section 10).
    #[inline]
    pub fn motor_cut(&self) -> bool {
        self.motor_off < self.t_end
    }

    /// The direction the motor drives body 1 (+1 or −1): +x1 for `kloss`,
    /// the sign of `f1` for `constant`; None for a constant motor with
    /// f1 = 0 (no motor). docs/model.md section 10, "Does the motor drive it?".
    #[inline]
    pub fn motor_direction(&self) -> Option<f64> {
        match self.motor {
            MOTOR_KLOSS => Some(1.0),
            _ if self.f1 > 0.0 => Some(1.0),
            _ if self.f1 < 0.0 => Some(-1.0),
            _ => None,
        }
    }

    /// Derives a lane's constants from validated parameters.
    pub fn new(p: &impl LaneParams, tables: &[FrictionTable]) -> Lane {
        let g = p.get(Num::GammaDeg).to_radians();
        let inv_cos_an = match p.get(Num::AlphaNDeg) {
            a if a.is_nan() => 1.0,
            a => 1.0 / a.to_radians().cos(),
        };
        let (r1, r2) = p.radii();
        let nan_to = |v: f64, d: f64| if v.is_nan() { d } else { v };
        let (motor, v_sync, sigma_k, f_crit, f1) = match p.motor() {
            MotorKind::Kloss => {
                let vs = p.get(Num::VSync);
                (
                    MOTOR_KLOSS,
                    vs,
                    (vs - p.get(Num::VCrit)) / vs,
                    p.get(Num::FCrit),
                    0.0,
                )
            }
            MotorKind::Constant => (MOTOR_CONSTANT, 1.0, 1.0, 0.0, p.get(Num::F1)),
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
            friction: match p.friction() {
                FrictionKind::Paper => FRICTION_PAPER,
                FrictionKind::Coulomb => FRICTION_COULOMB,
                FrictionKind::Table => FRICTION_TABLE,
                FrictionKind::Agma => FRICTION_AGMA,
            },
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
            r1,
            r2,
        };
        lane.mu_s = match p.friction() {
            FrictionKind::Coulomb => p.get(Num::MuStatic) * inv_cos_an,
            FrictionKind::Agma => friction::AGMA_MU_STATIC * inv_cos_an,
            _ => mu_sliding(&lane, tables, 0.0, false),
        };
        lane
    }
}

/// Motor force F1 at speed `v1`; zero once the motor is off.
#[inline]
pub fn motor_force(lane: &Lane, v1: f64, motor_on: bool) -> f64 {
    if !motor_on {
        return 0.0;
    }
    if lane.motor == MOTOR_CONSTANT {
        return lane.f1;
    }
    // Kloss in the form 2 f σ σk / (σ² + σk²): finite at σ = 0, negative
    // above synchronous speed (generator braking).
    let sigma = (lane.v_sync - v1) / lane.v_sync;
    let sk = lane.sigma_k;
    2.0 * lane.f_crit * sigma * sk / (sigma * sigma + sk * sk)
}

/// Switching function φ = F1/m1 − F2/(m2 tan γ): a-a when > 0, b-b when < 0.
#[inline]
pub fn phi(lane: &Lane, v1: f64, motor_on: bool) -> f64 {
    motor_force(lane, v1, motor_on) / lane.m1 - lane.f2 / (lane.m2 * lane.tan_g)
}

/// The contact side for φ: +1 (a-a) when φ >= 0, else −1 (b-b).
#[inline]
pub fn side_of(phi: f64) -> i32 {
    if phi >= 0.0 {
        1
    } else {
        -1
    }
}

/// The mode a lane slides in between events, frozen for a whole step:
/// contact side, direction, motor, and the `agma` law's branch.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Mode {
    /// Contact side c: +1 a-a, −1 b-b.
    pub side: i32,
    /// Direction of motion s.
    pub dir: i32,
    /// Motor force on.
    pub motor_on: bool,
    /// The `agma` law's upper branch (Vs above 10 ft/min); false for the
    /// other laws. Frozen so a step's right-hand side is smooth: the jump
    /// between the branches is an event.
    pub upper: bool,
}

/// What the equation of motion gives in one mode at one speed.
#[derive(Clone, Copy, Debug)]
pub struct Motion {
    /// ẍ1
    pub acc: f64,
    /// D = m1 − ψ m2 tan γ; the mode is inconsistent when D <= 0.
    pub d: f64,
    /// motor force F1
    pub f1: f64,
    /// contact reactions S1, S2
    pub s1: f64,
    pub s2: f64,
}

/// Equation of motion in mode `mode` (side c, direction s) at speed `v1`.
///
/// ψ = −tan(γ + c s ρ) = −p/q by the tangent sum, with p = tan γ + c s μ and
/// q = 1 − tan γ c s μ; multiplying through by q leaves one division on the
/// path to ẍ1. The sliding speed is taken as max(s·v1, 0): inside a step
/// the mode is frozen, and past a rest event this keeps the right-hand side
/// finite and continuous for root finding.
#[inline]
pub fn motion(lane: &Lane, tables: &[FrictionTable], mode: Mode, v1: f64) -> Motion {
    let f1 = motor_force(lane, v1, mode.motor_on);
    let vs = (mode.dir as f64 * v1).max(0.0) * lane.inv_cos_g;
    let t = (mode.side * mode.dir) as f64 * mu_sliding(lane, tables, vs, mode.upper);
    motion_parts(f1, t, lane.tan_g, lane.m1, lane.m2, lane.f2)
}

/// The motion from the motor force `f1` and the signed tan ρ `t`: the
/// arithmetic `motion` and the stepper's lanes share.
#[inline(always)]
pub fn motion_parts(f1: f64, t: f64, tan_g: f64, m1: f64, m2: f64, f2: f64) -> Motion {
    let p = tan_g + t;
    let q = 1.0 - tan_g * t;
    // D·q = m1 q + p m2 tan γ
    let dq = m1 * q + p * m2 * tan_g;
    let acc = (f1 * q + p * f2) / dq;
    Motion {
        acc,
        d: dq / q,
        f1,
        s1: f1 - m1 * acc,
        s2: f2 - m2 * tan_g * acc,
    }
}

/// Stick test at rest (docs/model.md section 4): returns (sticks, T), where T is
/// the tangential force needed at rest; sign(T) is the direction of
/// departure when the lane does not stick.
#[inline]
pub fn stick_test(lane: &Lane, motor_on: bool) -> (bool, f64) {
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
                    upper: false,
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
                upper: false,
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
                upper: false,
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
                upper: false,
            },
            -v,
        );
        assert!((efficiency(&l, &m, 1, -1, -v) - (g - rho).tan() / g.tan()).abs() < 1e-12);
    }
}
