//! The laws a lane may choose, each declared once: the motor's and the
//! friction's. A friction law is a row of [`FRICTION_LAWS`] (its word,
//! whether it gives a coefficient, its static friction, whether its slope
//! is unbounded at rest, the speed where it changes branch) and its μ(Vs)
//! below; its parameters are the rows of the parameter table whose owner
//! names it (`params::table`), held in the lane's law slots in the
//! table's column order ([`LAW_SLOTS`]).
//!
//! Everything else follows from the rows: the words files use, the codes
//! of the GPU's lane and the shader's `FRICTION_*` constants (generated,
//! `backend::gpu::shader`), a lane's static friction, its step grading
//! and its branch event, the guide's parameter table and the validation
//! messages. Adding a law means: a variant and a row here with its μ
//! function, its arm in `friction::mu_sliding`, its parameters' rows, and
//! its WGSL twin in `shaders/model/friction.wgsl`.

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

/// Which friction law acts on the contact surface: the index of its row
/// in [`FRICTION_LAWS`].
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
    /// The Stribeck curve: breakaway μs falling to Coulomb's μc, plus a
    /// viscous share.
    Stribeck = 4,
}

/// Most parameters one friction law holds in a lane (the lane's law
/// slots, in the CPU's and the GPU's lane alike).
pub const LAW_SLOTS: usize = 5;

/// Where a law's static friction μs (at breakaway) comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StaticMu {
    /// The sliding law's value at rest.
    AtRest,
    /// The parameter in this law slot (`mu_static`).
    Slot(usize),
    /// A constant of the law.
    Value(f64),
}

/// Whether a law is steep at rest, so that steps into a stop are graded
/// (docs/model.md section 8): its slope dμ/dVs is unbounded there, or its
/// curvature is (a power Vs^δ with 1 < δ < 2), which the step's error
/// estimate misreads just as badly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SteepAtRest {
    /// Never.
    No,
    /// Always.
    Yes,
    /// Unless the exponent δ in this law slot is a whole number (Vs^δ is
    /// then smooth at rest).
    UnlessWholeExponent(usize),
}

/// One friction law's declaration.
#[derive(Clone, Copy, Debug)]
pub struct FrictionLaw {
    /// The word files use (`friction = "agma"`).
    pub name: &'static str,
    /// Whether the law gives a friction coefficient μ (so the flank's
    /// pressure angle turns it into the wedge's tan ρ = μ / cos αn), not
    /// the friction angle itself.
    pub gives_coefficient: bool,
    /// Its static friction.
    pub static_mu: StaticMu,
    /// Whether its slope is unbounded at rest.
    pub steep: SteepAtRest,
    /// The sliding speed, m/s, where the law changes branch (and may
    /// jump): an event of the lanes that use it.
    pub branch_speed: Option<f64>,
}

/// The friction laws, indexed by [`FrictionKind`]'s code.
pub const FRICTION_LAWS: [FrictionLaw; 5] = [
    FrictionLaw {
        name: "paper",
        gives_coefficient: false,
        static_mu: StaticMu::AtRest,
        steep: SteepAtRest::Yes,
        branch_speed: None,
    },
    FrictionLaw {
        name: "coulomb",
        gives_coefficient: true,
        static_mu: StaticMu::Slot(1),
        steep: SteepAtRest::No,
        branch_speed: None,
    },
    FrictionLaw {
        name: "table",
        gives_coefficient: true,
        static_mu: StaticMu::AtRest,
        steep: SteepAtRest::No,
        branch_speed: None,
    },
    FrictionLaw {
        name: "agma",
        gives_coefficient: true,
        static_mu: StaticMu::Value(AGMA_MU_STATIC),
        steep: SteepAtRest::Yes,
        branch_speed: Some(AGMA_JUMP_M_S),
    },
    FrictionLaw {
        name: "stribeck",
        gives_coefficient: true,
        static_mu: StaticMu::Slot(1),
        steep: SteepAtRest::UnlessWholeExponent(3),
        branch_speed: None,
    },
];

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
    /// Every friction law, in code order.
    pub const ALL: [FrictionKind; FRICTION_LAWS.len()] = [
        FrictionKind::Paper,
        FrictionKind::Coulomb,
        FrictionKind::Table,
        FrictionKind::Agma,
        FrictionKind::Stribeck,
    ];
    /// The law's code in the GPU's lane (`FRICTION_*` in the shader).
    pub fn code(self) -> u32 {
        self as u32
    }

    /// The law's declaration.
    pub fn law(self) -> &'static FrictionLaw {
        &FRICTION_LAWS[self as usize]
    }

    /// The spelling used in files.
    pub fn name(self) -> &'static str {
        self.law().name
    }

    /// See [`FrictionLaw::gives_coefficient`].
    pub(crate) fn gives_coefficient(self) -> bool {
        self.law().gives_coefficient
    }
}

/// ft/min in one m/s: the `agma` law is stated in ft/min.
pub const FT_PER_MIN_PER_M_PER_S: f64 = 196.850_393_700_787_4;
/// The `agma` law's static coefficient μs.
pub(crate) const AGMA_MU_STATIC: f64 = 0.150;
/// Sliding speed, ft/min, where the `agma` curve changes branch (and jumps
/// by 2 %).
pub const AGMA_JUMP_FT_MIN: f64 = 10.0;
/// Lower branch (0 < Vs <= 10 ft/min): μ = A exp(−B Vs^E).
pub const AGMA_LOW_A: f64 = 0.124;
/// See [`AGMA_LOW_A`].
pub const AGMA_LOW_B: f64 = 0.074;
/// See [`AGMA_LOW_A`].
pub const AGMA_LOW_E: f64 = 0.645;
/// Upper branch (Vs > 10 ft/min): μ = A exp(−B Vs^E) + C.
pub const AGMA_HIGH_A: f64 = 0.103;
/// See [`AGMA_HIGH_A`].
pub const AGMA_HIGH_B: f64 = 0.110;
/// See [`AGMA_HIGH_A`].
pub const AGMA_HIGH_E: f64 = 0.450;
/// See [`AGMA_HIGH_A`].
pub const AGMA_HIGH_C: f64 = 0.012;
/// [`AGMA_JUMP_FT_MIN`] in m/s (0.0508).
pub const AGMA_JUMP_M_S: f64 = AGMA_JUMP_FT_MIN / FT_PER_MIN_PER_M_PER_S;

/// The `agma` law's sliding μ at `vs` (m/s) on the branch `upper` (Vs
/// above 10 ft/min) or the lower one. Inside a step the branch is frozen
/// (the mode's), so the right-hand side stays smooth and the jump is
/// located as an event; [`agma_upper`] says which branch a speed is on.
#[inline]
pub fn agma_mu(vs: f64, upper: bool) -> f64 {
    let v = vs.max(0.0) * FT_PER_MIN_PER_M_PER_S;
    if upper {
        AGMA_HIGH_A * (-AGMA_HIGH_B * v.powf(AGMA_HIGH_E)).exp() + AGMA_HIGH_C
    } else {
        AGMA_LOW_A * (-AGMA_LOW_B * v.powf(AGMA_LOW_E)).exp()
    }
}

/// Whether sliding speed `vs` (m/s) is on the `agma` law's upper branch.
#[inline]
pub fn agma_upper(vs: f64) -> bool {
    vs > AGMA_JUMP_M_S
}

/// The `stribeck` law's μ at sliding speed `vs` (m/s) from its slots
/// (μc, μs, v_st, δ, kv): μc + (μs − μc) exp(−(Vs/v_st)^δ) + kv Vs.
#[inline]
pub(crate) fn stribeck_mu(s: &[f64; LAW_SLOTS], vs: f64) -> f64 {
    let [mu_c, mu_s, v_st, delta, kv] = *s;
    mu_c + (mu_s - mu_c) * (-(vs / v_st).powf(delta)).exp() + kv * vs
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_index_the_declarations() {
        for (i, k) in FrictionKind::ALL.into_iter().enumerate() {
            assert_eq!(k.code() as usize, i);
            assert_eq!(k.name(), FRICTION_LAWS[i].name);
        }
    }

    /// docs/model.md section 5's check values, to 7 digits.
    #[test]
    fn stribeck_law_gives_the_models_check_values() {
        let s = [0.04, 0.10, 0.1, 2.0, 0.002];
        for (vs, want) in [
            (0.05, 0.0868280),
            (0.1, 0.0622728),
            (1.0, 0.0420000),
            (5.0, 0.05),
        ] {
            assert!((stribeck_mu(&s, vs) - want).abs() < 5e-8, "{vs} m/s");
        }
        assert_eq!(stribeck_mu(&s, 0.0), 0.10);
    }

    /// The table of docs/model.md section 5, to 1e-5.
    #[test]
    fn agma_law_gives_the_model_table() {
        let rows: [(f64, bool, f64); 10] = [
            (0.01, false, 0.11058),
            (0.0508, false, 0.08944),
            (0.0508, true, 0.08754),
            (0.1, true, 0.07964),
            (0.5, true, 0.05526),
            (1.0, true, 0.04349),
            (2.0, true, 0.03241),
            (5.0, true, 0.02093),
            (10.0, true, 0.01565),
            (20.0, true, 0.01307),
        ];
        for (vs, upper, want) in rows {
            let mu = agma_mu(vs, upper);
            assert!((mu - want).abs() < 1e-5, "{vs} m/s: {mu} (want {want})");
            if vs != 0.0508 {
                assert_eq!(agma_upper(vs), upper, "{vs} m/s");
            }
        }
        // 10 ft/min is 0.0508 m/s, on the lower branch; just above, the upper.
        assert!((AGMA_JUMP_M_S - 0.0508).abs() < 1e-12);
        assert!(!agma_upper(AGMA_JUMP_M_S) && agma_upper(AGMA_JUMP_M_S * (1.0 + 1e-12)));
        // The jump is 2 %.
        let (lo, hi) = (agma_mu(AGMA_JUMP_M_S, false), agma_mu(AGMA_JUMP_M_S, true));
        assert!(((lo - hi) / lo - 0.0213).abs() < 1e-3);
    }
}
