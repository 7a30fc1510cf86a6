//! The drive in gear terms (docs/model.md section 12): catalogue geometry,
//! inertias, torques and shaft speeds, converted once, when a lane is
//! resolved, into the wedge's parameters. Body 1 moves on the worm's pitch
//! circle (radius R1) and body 2 on the wheel's (R2), so kinetic energy and
//! power carry over one to one:
//!
//! ```text
//! R1 = d1 / 2,  R2 = z2 m_x / 2,  tan γ = z1 m_x / d1   (or r1, r2 beside gamma_deg)
//! m1 = j1 / R1²,  m2 = j2 / R2²,  f1 = t1 / R1,  f2 = t2 / R2
//! v = 2π n / 60 · R1 (v_sync, v_crit, v1_0),  f_crit = t_crit / R1
//! ```
//!
//! Each quantity is given one way: both forms of one (`j1` and `m1`), a
//! gear term without a geometry, part of a catalogue geometry or of a
//! Kloss motor in gear terms are refused, each with one line.

use super::check::{check, ParamError};
use super::table::{FrictionKind, MotorKind, Num, N_NUM};

/// The gear terms, in table order.
pub(crate) const GEAR: [Num; 14] = [
    Num::D1,
    Num::Z1,
    Num::Z2,
    Num::MX,
    Num::R1,
    Num::R2,
    Num::J1,
    Num::J2,
    Num::T1,
    Num::T2,
    Num::NSync,
    Num::NCrit,
    Num::TCrit,
    Num::N10,
];

/// The catalogue geometry: all four or none.
const CATALOGUE: [Num; 4] = [Num::D1, Num::Z1, Num::Z2, Num::MX];
/// The Kloss motor in gear terms: all three or none.
const KLOSS: [Num; 3] = [Num::NSync, Num::NCrit, Num::TCrit];

/// Which pitch radius a conversion divides or multiplies by.
#[derive(Clone, Copy)]
enum Radius {
    R1,
    R2,
}

/// How a gear term becomes its wedge counterpart.
#[derive(Clone, Copy)]
enum Rule {
    /// An inertia: m = j / R².
    Inertia,
    /// A torque: f = t / R.
    Torque,
    /// A shaft speed in rpm: v = 2π n / 60 · R.
    Speed,
}

/// One conversion: (gear term, wedge parameter, radius, rule, formula).
const PAIRS: [(Num, Num, Radius, Rule, &str); 8] = [
    (Num::J1, Num::M1, Radius::R1, Rule::Inertia, "j1 / R1^2"),
    (Num::J2, Num::M2, Radius::R2, Rule::Inertia, "j2 / R2^2"),
    (Num::T1, Num::F1, Radius::R1, Rule::Torque, "t1 / R1"),
    (Num::T2, Num::F2, Radius::R2, Rule::Torque, "t2 / R2"),
    (
        Num::NSync,
        Num::VSync,
        Radius::R1,
        Rule::Speed,
        "2 pi n_sync / 60 R1",
    ),
    (
        Num::NCrit,
        Num::VCrit,
        Radius::R1,
        Rule::Speed,
        "2 pi n_crit / 60 R1",
    ),
    (
        Num::TCrit,
        Num::FCrit,
        Radius::R1,
        Rule::Torque,
        "t_crit / R1",
    ),
    (
        Num::N10,
        Num::V10,
        Radius::R1,
        Rule::Speed,
        "2 pi n1_0 / 60 R1",
    ),
];

/// Whether a wedge parameter has a gear form (it is then left unset, not
/// defaulted, where a sweep uses gear terms).
pub(crate) fn has_gear_form(p: Num) -> bool {
    p == Num::GammaDeg || PAIRS.iter().any(|&(_, w, ..)| w == p)
}

/// The wedge parameter a gear term gives (`t2` gives `f2`; each part of
/// the catalogue geometry, `gamma_deg`), if any.
pub fn gives(g: Num) -> Option<Num> {
    if CATALOGUE.contains(&g) {
        return Some(Num::GammaDeg);
    }
    PAIRS.iter().find(|&&(t, ..)| t == g).map(|&(_, w, ..)| w)
}

/// rad/s in one rpm.
pub(crate) const RAD_S_PER_RPM: f64 = std::f64::consts::PI / 30.0;

/// A lane's values with its gear terms converted: the wedge's values set
/// beside the gear terms it was given, the pitch radii, and where each
/// converted value came from (for errors).
pub(super) struct Converted {
    /// The values, gear terms kept, wedge values set.
    pub num: [Option<f64>; N_NUM],
    /// Pitch radius of the worm, m.
    pub r1: f64,
    /// Pitch radius of the wheel, m.
    pub r2: f64,
    /// For a converted wedge parameter: the gear terms it came from and
    /// its formula.
    from: [Option<(&'static str, &'static str)>; N_NUM],
}

/// Whether any gear term is given (the common case, none, costs a few
/// comparisons per lane).
#[inline]
pub(super) fn any(given: &[Option<f64>; N_NUM]) -> bool {
    GEAR.iter().any(|&g| given[g as usize].is_some())
}

fn bad(param: &'static str, msg: String) -> ParamError {
    ParamError { param, msg }
}

/// Names, comma separated: "d1, z1, z2, m_x".
fn names(ps: &[Num]) -> String {
    ps.iter().map(|p| p.name()).collect::<Vec<_>>().join(", ")
}

/// The values a lane was given, by [`Num`] index (None: not set).
type Given = [Option<f64>; N_NUM];

/// Converts the given gear terms (each first validated by its own row)
/// into wedge terms, refusing a quantity given twice or given in part.
pub(super) fn to_wedge(
    given: &Given,
    motor: MotorKind,
    friction: FrictionKind,
) -> Result<Converted, ParamError> {
    let set = |p: Num| given[p as usize].is_some();
    kloss_complete(given, motor)?;
    // Each value by its own row (range, whole numbers, the law it
    // belongs to), before any conversion hides it.
    let mut num = [f64::NAN; N_NUM];
    for g in GEAR {
        num[g as usize] = check(g, given[g as usize], motor, friction, &num)?;
    }
    let mut out = *given;
    let mut from = [None; N_NUM];
    let (r1, r2) = geometry(given, &num, &mut out, &mut from)?;
    for (gear, wedge, radius, rule, formula) in PAIRS {
        let Some(value) = given[gear as usize] else {
            continue;
        };
        if set(wedge) {
            return Err(bad(
                gear.name(),
                format!(
                    "{} is given too, the same quantity; give {} (gear terms) or {} (wedge terms), \
                     not both",
                    wedge.name(),
                    gear.name(),
                    wedge.name()
                ),
            ));
        }
        if r1.is_nan() {
            return Err(bad(
                gear.name(),
                "needs the drive's geometry: d1, z1, z2 and m_x, or r1 and r2 (with gamma_deg)"
                    .into(),
            ));
        }
        let r = match radius {
            Radius::R1 => r1,
            Radius::R2 => r2,
        };
        out[wedge as usize] = Some(match rule {
            Rule::Inertia => value / (r * r),
            Rule::Torque => value / r,
            Rule::Speed => value * RAD_S_PER_RPM * r,
        });
        from[wedge as usize] = Some((gear.name(), formula));
    }
    // A quantity given twice or in part is said first; then what is
    // missing.
    if !r1.is_nan() {
        drive_complete(given, motor)?;
    }
    Ok(Converted {
        num: out,
        r1,
        r2,
        from,
    })
}

/// A drive given in gear terms is given whole: its inertias (j1 and j2,
/// or m1 and m2) and its motor (a Kloss motor's n_sync, n_crit and t_crit
/// or v_sync, v_crit and f_crit; a constant motor's t1 or f1, which its
/// own row requires), unless the motor is cut from the start. The wedge's
/// defaults are the paper's drive (586 kg, 10,275 kg, a 3.35 m/s motor):
/// taken silently, they would be another drive's numbers.
fn drive_complete(given: &Given, motor: MotorKind) -> Result<(), ParamError> {
    let set = |p: Num| given[p as usize].is_some();
    for (gear, wedge, unit) in [(Num::J1, Num::M1, "worm"), (Num::J2, Num::M2, "wheel")] {
        if !set(gear) && !set(wedge) {
            return Err(bad(
                gear.name(),
                format!(
                    "is missing: a drive in gear terms needs the inertia on the {unit} shaft, {} \
                     in kg m^2 (or {} in kg); the defaults are the paper's drive, not yours",
                    gear.name(),
                    wedge.name()
                ),
            ));
        }
    }
    let cut_at_start = given[Num::MotorOff as usize] == Some(0.0);
    let wedge_kloss = [Num::VSync, Num::VCrit, Num::FCrit];
    let any_motor = KLOSS.iter().chain(&wedge_kloss).any(|&p| set(p));
    if motor == MotorKind::Kloss && !any_motor && !cut_at_start {
        return Err(bad(
            "motor",
            "is missing: a drive in gear terms needs its motor: n_sync, n_crit and t_crit (a Kloss \
             motor), or motor = \"constant\" with t1; the defaults are the paper's 3.35 m/s motor, \
             not yours"
                .into(),
        ));
    }
    Ok(())
}

/// A Kloss motor in gear terms is given whole: n_sync, n_crit and t_crit.
fn kloss_complete(given: &Given, motor: MotorKind) -> Result<(), ParamError> {
    let kloss: Vec<Num> = KLOSS
        .into_iter()
        .filter(|&p| given[p as usize].is_some())
        .collect();
    let partial = motor == MotorKind::Kloss && !kloss.is_empty();
    match KLOSS.iter().find(|&&p| given[p as usize].is_none()) {
        Some(&missing) if partial => Err(bad(
            missing.name(),
            format!(
                "is missing: a Kloss motor in gear terms needs n_sync, n_crit and t_crit together \
                 (given: {})",
                names(&kloss)
            ),
        )),
        _ => Ok(()),
    }
}

/// The pitch radii (NaN without a geometry): the catalogue's four terms,
/// which also fix γ (set in `out`), or the two radii beside gamma_deg.
fn geometry(
    given: &Given,
    num: &[f64; N_NUM],
    out: &mut Given,
    from: &mut [Option<(&'static str, &'static str)>; N_NUM],
) -> Result<(f64, f64), ParamError> {
    let set = |p: Num| given[p as usize].is_some();
    let v = |p: Num| num[p as usize];
    let catalogue: Vec<Num> = CATALOGUE.into_iter().filter(|&p| set(p)).collect();
    let radii = set(Num::R1) || set(Num::R2);
    if !catalogue.is_empty() {
        if let Some(&missing) = CATALOGUE.iter().find(|&&p| !set(p)) {
            return Err(bad(
                missing.name(),
                format!(
                    "is missing: the geometry in catalogue terms needs all of d1, z1, z2 and m_x \
                     (given: {})",
                    names(&catalogue)
                ),
            ));
        }
        if radii {
            return Err(bad(
                if set(Num::R1) { "r1" } else { "r2" },
                "gives the geometry a second time: give d1, z1, z2 and m_x, or r1 and r2 with \
                 gamma_deg, not both"
                    .into(),
            ));
        }
        if set(Num::GammaDeg) {
            return Err(bad(
                "gamma_deg",
                "is given twice: d1, z1 and m_x fix the lead angle (tan gamma = z1 m_x / d1); \
                 leave gamma_deg out, or give r1 and r2 with gamma_deg instead"
                    .into(),
            ));
        }
        let tan_g = v(Num::Z1) * v(Num::MX) / v(Num::D1);
        out[Num::GammaDeg as usize] = Some(tan_g.atan().to_degrees());
        from[Num::GammaDeg as usize] = Some(("d1, z1, m_x", "atan(z1 m_x / d1)"));
        return Ok((v(Num::D1) / 2.0, v(Num::Z2) * v(Num::MX) / 2.0));
    }
    if !radii {
        return Ok((f64::NAN, f64::NAN));
    }
    for (p, q) in [(Num::R1, Num::R2), (Num::R2, Num::R1)] {
        if !set(p) {
            return Err(bad(
                p.name(),
                format!(
                    "is missing: {} gives one pitch radius; the geometry in radii needs r1 and r2 \
                     (with gamma_deg)",
                    q.name()
                ),
            ));
        }
    }
    Ok((v(Num::R1), v(Num::R2)))
}

impl Converted {
    /// An error on a converted wedge value, told in the terms the user
    /// gave: "j1: gives m1 = j1 / R1^2, and m1 must be ...".
    pub(crate) fn explain(&self, e: ParamError) -> ParamError {
        let Some(wedge) = Num::from_name(e.param) else {
            return e;
        };
        match self.from[wedge as usize] {
            Some((source, formula)) => ParamError {
                param: source,
                msg: format!("gives {} = {formula}, and {} {}", e.param, e.param, e.msg),
            },
            None => e,
        }
    }
}

/// A shaft speed in rpm from a pitch-circle speed `v` (m/s) on radius `r`.
#[inline]
pub fn rpm(v: f64, r: f64) -> f64 {
    v / r / RAD_S_PER_RPM
}
