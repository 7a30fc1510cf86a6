//! A lane's constants as the integrator reads them: fixed size, the laws
//! as their enums, trigonometry done once. Built from a lane's validated
//! parameters by `Lane::new` (in `params`, which owns the parameters).

use super::laws::{FrictionKind, MotorKind, LAW_SLOTS};

/// A lane's constants in the form the integrator uses.
///
/// The GPU's twin is `GpuLane` in `src/backend/gpu/layout.rs` and `Lane`
/// in the shader (a test holds their layouts together).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lane {
    /// Mass of body 1 (the worm's side), kg.
    pub m1: f64,
    /// Mass of body 2 (the wheel's side), kg.
    pub m2: f64,
    /// tan γ of the lead angle γ.
    pub tan_g: f64,
    /// sin γ.
    pub sin_g: f64,
    /// cos γ.
    pub cos_g: f64,
    /// 1 / cos γ
    pub inv_cos_g: f64,
    /// The load F2 on body 2, N.
    pub f2: f64,
    /// The motor's law.
    pub motor: MotorKind,
    /// The Kloss law's synchronous speed, m/s (1 for a constant motor).
    pub v_sync: f64,
    /// critical slip σk
    pub sigma_k: f64,
    /// The Kloss law's largest force, N.
    pub f_crit: f64,
    /// A constant motor's force, N (0 for Kloss).
    pub f1: f64,
    /// time the motor is cut; +inf for never
    pub motor_off: f64,
    /// The friction law.
    pub friction: FrictionKind,
    /// Which of the run's friction tables (`friction = table`).
    pub table: u32,
    /// 1 / cos αn: a coefficient law's μ becomes the wedge's tan ρ = μ / cos αn.
    pub inv_cos_an: f64,
    /// The friction law's parameters, in the parameter table's column
    /// order (the paper law's a, b, c; coulomb's μ, μs; ...); unused
    /// slots are 0.
    pub law: [f64; LAW_SLOTS],
    /// static tan ρs for every law (μs / cos αn, or tan ρ(0))
    pub mu_s: f64,
    /// The law's slope is unbounded at rest, so steps into a stop are
    /// graded (`laws::SteepAtRest`).
    pub steep: bool,
    /// The sliding speed, m/s, where the law changes branch; +inf for a
    /// law with one branch.
    pub branch_speed: f64,
    /// Position x1 at t = 0, m.
    pub x1_0: f64,
    /// Speed ẋ1 at t = 0, m/s.
    pub v1_0: f64,
    /// End of the run, s.
    pub t_end: f64,
    /// Latest end of a lane still coasting at t_end with its motor cut
    /// (docs/model.md section 10); t_end when unset (no running on).
    pub t_max: f64,
}

impl Lane {
    /// Whether the motor is cut before t_end: only then does the lane
    /// answer "does it hold?" (docs/model.md section 10).
    #[inline]
    pub(crate) fn motor_cut(&self) -> bool {
        self.motor_off < self.t_end
    }

    /// Whether sliding speed `vs` is above the law's branch speed (on
    /// its upper branch); always false for a law with one branch.
    #[inline]
    pub(crate) fn above_branch(&self, vs: f64) -> bool {
        vs > self.branch_speed
    }

    /// The direction the motor drives body 1 (+1 or −1): +x1 for `kloss`,
    /// the sign of `f1` for `constant`; None for a constant motor with
    /// f1 = 0 (no motor). docs/model.md section 10, "Does the motor drive it?".
    #[inline]
    pub(crate) fn motor_direction(&self) -> Option<f64> {
        match self.motor {
            MotorKind::Kloss => Some(1.0),
            _ if self.f1 > 0.0 => Some(1.0),
            _ if self.f1 < 0.0 => Some(-1.0),
            _ => None,
        }
    }
}
