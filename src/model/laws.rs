//! The laws a lane may choose, one enum each: the motor's and the
//! friction's. Files spell them by [`MotorKind::name`] and
//! [`FrictionKind::name`]; the GPU's lane carries them as the codes
//! [`MotorKind::code`] and [`FrictionKind::code`] (its only integer
//! encoding, the shader's `MOTOR_*` and `FRICTION_*` constants).

/// Which motor law drives body 1.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
// A byte, as the mode's `motor_on` is: a loop over lanes selects the
// motor force on both with masks of one width (a u32 here costs the
// vector code at eight lanes a seventh of its speed).
#[repr(u8)]
pub enum MotorKind {
    /// Kloss characteristic of an induction motor (`v_sync`, `v_crit`, `f_crit`).
    Kloss = 0,
    /// A constant force `f1`.
    Constant = 1,
}

/// Which friction law acts on the contact surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
#[repr(u32)]
pub enum FrictionKind {
    /// The paper's fit: rho in degrees = 1/(a Vs^b + c).
    Paper = 0,
    /// Constant μ, with an optional static `mu_static`.
    Coulomb = 1,
    /// μ(Vs) from one of the sweep's friction tables, interpolated linearly.
    Table = 2,
    /// AGMA's curve for a hardened steel worm on a bronze wheel.
    Agma = 3,
}

impl MotorKind {
    /// Every motor law.
    pub const ALL: [MotorKind; 2] = [MotorKind::Kloss, MotorKind::Constant];
    /// The law's code in the GPU's lane (`MOTOR_*` in the shader).
    pub fn code(self) -> u32 {
        self as u8 as u32
    }

    /// The spelling used in files.
    pub fn name(self) -> &'static str {
        match self {
            MotorKind::Kloss => "kloss",
            MotorKind::Constant => "constant",
        }
    }
}

impl FrictionKind {
    /// Every friction law.
    pub const ALL: [FrictionKind; 4] = [
        FrictionKind::Paper,
        FrictionKind::Coulomb,
        FrictionKind::Table,
        FrictionKind::Agma,
    ];
    /// The law's code in the GPU's lane (`FRICTION_*` in the shader).
    pub fn code(self) -> u32 {
        self as u32
    }

    /// The spelling used in files.
    pub fn name(self) -> &'static str {
        match self {
            FrictionKind::Paper => "paper",
            FrictionKind::Coulomb => "coulomb",
            FrictionKind::Table => "table",
            FrictionKind::Agma => "agma",
        }
    }

    /// Whether the law gives a friction coefficient μ (so the flank's
    /// pressure angle turns it into the wedge's tan ρ = μ / cos αn), not
    /// the friction angle itself.
    pub fn gives_coefficient(self) -> bool {
        self != FrictionKind::Paper
    }

    /// Whether the law's derivative dρ/dVs is unbounded at rest (the
    /// paper and agma laws), so that steps into a stop are graded.
    pub fn steep_at_rest(self) -> bool {
        matches!(self, FrictionKind::Paper | FrictionKind::Agma)
    }
}
