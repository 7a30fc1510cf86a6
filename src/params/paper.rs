//! Which of the paper's drive (docs/model.md section 7) a run takes
//! because it leaves a value out: its masses, lead angle, load, time, the
//! Kloss motor and the paper's friction law are the defaults, and a sweep
//! that forgets its load silently simulates the paper's overhauling
//! +4774 N. The summary line, `sweep.resolved.toml` and the report say
//! which of them a run relies on.

use super::gear;
use super::table::{FrictionKind, MotorKind, Num, Owner, Param};

/// What a run gives: the parameters it sets anywhere (a `[base]` key, an
/// axis, a tolerance, a lane table's column), and whether its laws are
/// given and which motor laws its lanes may have.
pub struct Given {
    /// Parameters set somewhere (their gear forms count for the wedge's).
    pub params: Vec<Param>,
    /// Motor laws its lanes may have (the default `kloss` when not given).
    pub motors: Vec<MotorKind>,
}

impl Given {
    /// Whether `n` (or a gear term that gives it) is set.
    fn has(&self, n: Num) -> bool {
        self.params.iter().any(|&p| match p {
            Param::Num(q) => q == n || gear::gives(q) == Some(n),
            _ => false,
        })
    }
}

/// "m1 = 586 kg", "f2 = 4774 N".
fn value(n: Num) -> String {
    let def = n.def();
    let v = n.default_value().unwrap_or(f64::NAN);
    let unit = if def.unit.is_empty() {
        String::new()
    } else {
        format!(" {}", def.unit)
    };
    // Short: 586, 4774, 2.07; the lead angle atan(0.1) to four decimals.
    let text = format!("{v}");
    let text = if text.len() > 8 {
        format!("{v:.4}")
    } else {
        text
    };
    format!("{} = {text}{unit}", def.name)
}

/// The paper's drive's values the run takes because it leaves them out,
/// in words ("m1 = 586 kg", "motor = kloss", ...); none when it gives
/// them all.
pub fn paper_defaults(g: &Given) -> Vec<String> {
    let left_out = |n: Num| n.def().paper && !g.has(n);
    let of = |owner: Owner| -> Vec<String> {
        Num::ALL
            .into_iter()
            .filter(|&n| n.def().owner == owner && n != Num::TEnd && left_out(n))
            .map(value)
            .collect()
    };
    // In the order of the parameters: the drive, its motor, its friction,
    // then the time.
    let mut out = of(Owner::All);
    if !g.params.contains(&Param::Motor) {
        out.push(format!("motor = {}", MotorKind::Kloss.name()));
    }
    if g.motors.contains(&MotorKind::Kloss) {
        out.extend(of(Owner::Motor(super::table::motors(&[MotorKind::Kloss]))));
    }
    if !g.params.contains(&Param::Friction) {
        out.push(format!("friction = {}", FrictionKind::Paper.name()));
    }
    if left_out(Num::TEnd) {
        out.push(value(Num::TEnd));
    }
    out
}

/// How the summary line, `sweep.resolved.toml` and the report begin the
/// list of them.
pub(crate) const PHRASE: &str = "from the paper's drive (not given): ";

/// The words the summary line and the report use for them.
pub fn note(defaults: &[String]) -> String {
    format!("{PHRASE}{}", defaults.join(", "))
}
