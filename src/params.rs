//! Lane parameters: the names of MODEL.md section 9, partial specifications
//! (what a sweep file, an axis or a lane-table row sets) and their resolution
//! into a validated, complete [`Params`].
//!
//! One name per parameter is used everywhere: TOML keys, lane-table columns
//! and the parameter columns of `lanes.csv`.

use std::fmt;

/// Which motor law drives body 1.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MotorKind {
    /// Kloss characteristic of an induction motor (`v_sync`, `v_crit`, `f_crit`).
    Kloss,
    /// A constant force `f1`.
    Constant,
}

/// Which friction law acts on the contact surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FrictionKind {
    /// The paper's fit ρ[deg] = 1/(a Vs^b + c).
    Paper,
    /// Constant μ, with an optional static `mu_static`.
    Coulomb,
    /// μ(Vs) from the sweep's friction table, interpolated linearly.
    Table,
}

impl MotorKind {
    /// The spelling used in files.
    pub fn name(self) -> &'static str {
        match self {
            MotorKind::Kloss => "kloss",
            MotorKind::Constant => "constant",
        }
    }
    fn parse(s: &str) -> Option<Self> {
        match s {
            "kloss" => Some(MotorKind::Kloss),
            "constant" => Some(MotorKind::Constant),
            _ => None,
        }
    }
}

impl FrictionKind {
    /// The spelling used in files.
    pub fn name(self) -> &'static str {
        match self {
            FrictionKind::Paper => "paper",
            FrictionKind::Coulomb => "coulomb",
            FrictionKind::Table => "table",
        }
    }
    fn parse(s: &str) -> Option<Self> {
        match s {
            "paper" => Some(FrictionKind::Paper),
            "coulomb" => Some(FrictionKind::Coulomb),
            "table" => Some(FrictionKind::Table),
            _ => None,
        }
    }
}

/// The numeric parameters, in the order of MODEL.md section 9.
///
/// The discriminant indexes [`Spec::num`] and [`Params::num`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(usize)]
pub enum Num {
    M1,
    M2,
    GammaDeg,
    F2,
    VSync,
    VCrit,
    FCrit,
    F1,
    MotorOff,
    FricA,
    FricB,
    FricC,
    Mu,
    MuStatic,
    X10,
    V10,
    TEnd,
}

/// Number of numeric parameters.
pub const N_NUM: usize = 17;

impl Num {
    /// All numeric parameters in index order.
    pub const ALL: [Num; N_NUM] = [
        Num::M1,
        Num::M2,
        Num::GammaDeg,
        Num::F2,
        Num::VSync,
        Num::VCrit,
        Num::FCrit,
        Num::F1,
        Num::MotorOff,
        Num::FricA,
        Num::FricB,
        Num::FricC,
        Num::Mu,
        Num::MuStatic,
        Num::X10,
        Num::V10,
        Num::TEnd,
    ];

    /// The parameter's one name.
    pub fn name(self) -> &'static str {
        match self {
            Num::M1 => "m1",
            Num::M2 => "m2",
            Num::GammaDeg => "gamma_deg",
            Num::F2 => "f2",
            Num::VSync => "v_sync",
            Num::VCrit => "v_crit",
            Num::FCrit => "f_crit",
            Num::F1 => "f1",
            Num::MotorOff => "motor_off",
            Num::FricA => "fric_a",
            Num::FricB => "fric_b",
            Num::FricC => "fric_c",
            Num::Mu => "mu",
            Num::MuStatic => "mu_static",
            Num::X10 => "x1_0",
            Num::V10 => "v1_0",
            Num::TEnd => "t_end",
        }
    }

    /// Looks a numeric parameter up by name.
    pub fn from_name(name: &str) -> Option<Num> {
        Num::ALL.iter().copied().find(|p| p.name() == name)
    }
}

/// Any parameter: numeric, or one of the two law selectors.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Param {
    /// A numeric parameter.
    Num(Num),
    /// `motor`
    Motor,
    /// `friction`
    Friction,
}

impl Param {
    /// Every parameter in the column order of MODEL.md section 9.
    pub const COLUMNS: [Param; N_NUM + 2] = [
        Param::Num(Num::M1),
        Param::Num(Num::M2),
        Param::Num(Num::GammaDeg),
        Param::Num(Num::F2),
        Param::Motor,
        Param::Num(Num::VSync),
        Param::Num(Num::VCrit),
        Param::Num(Num::FCrit),
        Param::Num(Num::F1),
        Param::Num(Num::MotorOff),
        Param::Friction,
        Param::Num(Num::FricA),
        Param::Num(Num::FricB),
        Param::Num(Num::FricC),
        Param::Num(Num::Mu),
        Param::Num(Num::MuStatic),
        Param::Num(Num::X10),
        Param::Num(Num::V10),
        Param::Num(Num::TEnd),
    ];

    /// The parameter's one name.
    pub fn name(self) -> &'static str {
        match self {
            Param::Num(n) => n.name(),
            Param::Motor => "motor",
            Param::Friction => "friction",
        }
    }

    /// Looks a parameter up by name.
    pub fn from_name(name: &str) -> Option<Param> {
        Param::COLUMNS.iter().copied().find(|p| p.name() == name)
    }

    /// All names, comma separated, for error messages.
    pub fn all_names() -> String {
        Param::COLUMNS
            .iter()
            .map(|p| p.name())
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// A partial parameter set: `None` means "not set, the default applies".
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Spec {
    /// Numeric values, indexed by [`Num`].
    pub num: [Option<f64>; N_NUM],
    /// Motor law.
    pub motor: Option<MotorKind>,
    /// Friction law.
    pub friction: Option<FrictionKind>,
}

impl Spec {
    /// Sets a numeric parameter.
    pub fn set(&mut self, p: Num, v: f64) {
        self.num[p as usize] = Some(v);
    }

    /// Sets a parameter from its text form (a lane-table cell, say).
    /// Empty text leaves it unset. Errors say what is allowed.
    pub fn set_text(&mut self, p: Param, text: &str) -> Result<(), String> {
        let text = text.trim();
        if text.is_empty() {
            return Ok(());
        }
        match p {
            Param::Motor => {
                self.motor = Some(MotorKind::parse(text).ok_or_else(|| {
                    format!("`{text}` is not a motor law; allowed: kloss, constant")
                })?)
            }
            Param::Friction => {
                self.friction = Some(FrictionKind::parse(text).ok_or_else(|| {
                    format!("`{text}` is not a friction law; allowed: paper, coulomb, table")
                })?)
            }
            Param::Num(n) => {
                let v: f64 = text
                    .parse()
                    .map_err(|_| format!("`{text}` is not a number"))?;
                if !v.is_finite() {
                    return Err(format!(
                        "`{text}` is not finite; a finite number is required"
                    ));
                }
                self.set(n, v);
            }
        }
        Ok(())
    }

    /// `other`'s set values replace this spec's.
    pub fn overlay(&mut self, other: &Spec) {
        for i in 0..N_NUM {
            if other.num[i].is_some() {
                self.num[i] = other.num[i];
            }
        }
        if other.motor.is_some() {
            self.motor = other.motor;
        }
        if other.friction.is_some() {
            self.friction = other.friction;
        }
    }

    /// Resolves defaults and validates. `has_table` says whether the sweep
    /// carries a friction table (required by `friction = "table"`).
    pub fn resolve(&self, has_table: bool) -> Result<Params, ParamError> {
        resolve(self, has_table)
    }
}

/// A parameter that fails validation: which one, and what is allowed.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamError {
    /// The parameter's name.
    pub param: &'static str,
    /// What is wrong and what is allowed.
    pub msg: String,
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.param, self.msg)
    }
}

/// A complete, validated parameter set. Numeric values that the chosen laws
/// do not use are NaN (written as empty cells).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    /// Numeric values, indexed by [`Num`].
    pub num: [f64; N_NUM],
    /// Motor law.
    pub motor: MotorKind,
    /// Friction law.
    pub friction: FrictionKind,
}

impl Params {
    /// A numeric value (NaN when not applicable).
    #[inline]
    pub fn get(&self, p: Num) -> f64 {
        self.num[p as usize]
    }
}

/// Defaults of MODEL.md section 9 (the paper's design, case 1 load).
pub fn default_of(p: Num) -> Option<f64> {
    Some(match p {
        Num::M1 => 586.0,
        Num::M2 => 10275.0,
        Num::GammaDeg => 5.710593137499643, // atan(0.1)
        Num::F2 => 4774.0,
        Num::VSync => 3.35,
        Num::VCrit => 2.07,
        Num::FCrit => 4375.0,
        Num::FricA => 0.174,
        Num::FricB => 0.612,
        Num::FricC => 0.14,
        Num::X10 => 0.0,
        Num::V10 => 0.0,
        Num::TEnd => 2.0,
        Num::F1 | Num::MotorOff | Num::Mu | Num::MuStatic => return None,
    })
}

fn err(param: Num, msg: impl Into<String>) -> ParamError {
    ParamError {
        param: param.name(),
        msg: msg.into(),
    }
}

fn resolve(spec: &Spec, has_table: bool) -> Result<Params, ParamError> {
    let motor = spec.motor.unwrap_or(MotorKind::Kloss);
    let friction = spec.friction.unwrap_or(FrictionKind::Paper);
    let mut num = [f64::NAN; N_NUM];
    for p in Num::ALL {
        let set = spec.num[p as usize];
        if let Some(v) = set {
            if !v.is_finite() {
                return Err(err(
                    p,
                    format!("{v} is not finite; a finite number is required"),
                ));
            }
        }
        // A value the chosen law does not use is refused rather than
        // ignored: a user who sets `mu` but forgets `friction = "coulomb"`
        // would otherwise get the paper law without noticing.
        let owner: Option<(&str, bool)> = match p {
            Num::VSync | Num::VCrit | Num::FCrit => {
                Some(("motor = kloss", motor == MotorKind::Kloss))
            }
            Num::F1 => Some(("motor = constant", motor == MotorKind::Constant)),
            Num::FricA | Num::FricB | Num::FricC => {
                Some(("friction = paper", friction == FrictionKind::Paper))
            }
            Num::Mu | Num::MuStatic => {
                Some(("friction = coulomb", friction == FrictionKind::Coulomb))
            }
            _ => None,
        };
        let applies = owner.is_none_or(|(_, used)| used);
        if !applies {
            if set.is_some() {
                let (who, _) = owner.unwrap();
                return Err(err(
                    p,
                    format!(
                        "is set but not used by motor = {}, friction = {}; it belongs to {who}",
                        motor.name(),
                        friction.name()
                    ),
                ));
            }
            continue;
        }
        let default = if p == Num::MuStatic {
            spec.num[Num::Mu as usize]
        } else {
            default_of(p)
        };
        num[p as usize] = set.or(default).unwrap_or(f64::NAN);
    }
    let g = |p: Num| num[p as usize];
    let positive = |p: Num| -> Result<(), ParamError> {
        if g(p) > 0.0 {
            Ok(())
        } else {
            Err(err(p, format!("must be > 0, got {}", g(p))))
        }
    };
    positive(Num::M1)?;
    positive(Num::M2)?;
    let gamma = g(Num::GammaDeg);
    if !(gamma > 0.0 && gamma < 90.0) {
        return Err(err(
            Num::GammaDeg,
            format!("must be in (0, 90) deg, got {gamma}"),
        ));
    }
    match motor {
        MotorKind::Kloss => {
            positive(Num::VSync)?;
            let (vs, vc) = (g(Num::VSync), g(Num::VCrit));
            if !(vc >= 0.0 && vc < vs) {
                return Err(err(
                    Num::VCrit,
                    format!("must be >= 0 and < v_sync = {vs}, got {vc}"),
                ));
            }
            positive(Num::FCrit)?;
        }
        MotorKind::Constant => {
            if g(Num::F1).is_nan() {
                return Err(err(
                    Num::F1,
                    "is required by motor = constant (a force in N)",
                ));
            }
        }
    }
    let off = g(Num::MotorOff);
    if off < 0.0 {
        return Err(err(
            Num::MotorOff,
            format!("must be >= 0 s (or unset for never), got {off}"),
        ));
    }
    match friction {
        FrictionKind::Paper => {
            let (a, b, c) = (g(Num::FricA), g(Num::FricB), g(Num::FricC));
            if !(a >= 0.0) {
                return Err(err(Num::FricA, format!("must be >= 0, got {a}")));
            }
            if !(b > 0.0) {
                return Err(err(Num::FricB, format!("must be > 0, got {b}")));
            }
            // rho(0) = 1/c degrees must stay below 90 deg.
            if !(c > 1.0 / 90.0) {
                return Err(err(
                    Num::FricC,
                    format!("must be > 1/90 (rho(0) = 1/c deg < 90 deg), got {c}"),
                ));
            }
        }
        FrictionKind::Coulomb => {
            let mu = g(Num::Mu);
            if mu.is_nan() {
                return Err(err(
                    Num::Mu,
                    "is required by friction = coulomb (a coefficient >= 0)",
                ));
            }
            if mu < 0.0 {
                return Err(err(Num::Mu, format!("must be >= 0, got {mu}")));
            }
            let mus = g(Num::MuStatic);
            // Static friction below sliding friction would make a lane that
            // leaves rest decelerate at once and stop again, forever.
            if mus < mu {
                return Err(err(
                    Num::MuStatic,
                    format!("must be >= mu = {mu}, got {mus}"),
                ));
            }
        }
        FrictionKind::Table => {
            if !has_table {
                return Err(ParamError {
                    param: "friction",
                    msg: "= table needs a [friction_table] in the sweep file".into(),
                });
            }
        }
    }
    let t_end = g(Num::TEnd);
    if !(t_end > 0.0) {
        return Err(err(Num::TEnd, format!("must be > 0 s, got {t_end}")));
    }
    Ok(Params {
        num,
        motor,
        friction,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_follow_model_md_order() {
        let names: Vec<_> = Param::COLUMNS.iter().map(|p| p.name()).collect();
        assert_eq!(
            names.join(","),
            "m1,m2,gamma_deg,f2,motor,v_sync,v_crit,f_crit,f1,motor_off,friction,\
             fric_a,fric_b,fric_c,mu,mu_static,x1_0,v1_0,t_end"
        );
        for p in Param::COLUMNS {
            assert_eq!(Param::from_name(p.name()), Some(p));
        }
        for (i, p) in Num::ALL.iter().enumerate() {
            assert_eq!(*p as usize, i);
        }
    }

    #[test]
    fn defaults_are_the_paper_design() {
        let p = Spec::default().resolve(false).unwrap();
        assert_eq!(p.get(Num::M1), 586.0);
        assert!((p.get(Num::GammaDeg).to_radians().tan() - 0.1).abs() < 1e-15);
        assert!(p.get(Num::Mu).is_nan());
        assert!(p.get(Num::MotorOff).is_nan());
    }

    #[test]
    fn coulomb_static_defaults_to_mu() {
        let mut s = Spec {
            friction: Some(FrictionKind::Coulomb),
            ..Default::default()
        };
        s.set(Num::Mu, 0.05);
        let p = s.resolve(false).unwrap();
        assert_eq!(p.get(Num::MuStatic), 0.05);
        assert!(p.get(Num::FricA).is_nan());
    }
}
