//! The table of parameters: one row per parameter of docs/model.md section 9,
//! in its column order, then the gear terms of section 12. The enum [`Num`], [`Num::ALL`], [`Param::COLUMNS`]
//! and [`NUMERIC`] are generated from the rows by `parameter_table!`.
//!
//! Why over 400 lines: the rows and what reads them (ranges in words, the
//! guide's table) belong together; split, the one place that states each
//! parameter's facts would become two.

pub use crate::model::laws::{FrictionKind, MotorKind};

/// Which law a numeric parameter belongs to: set under another law it is
/// refused rather than ignored (a user who sets `mu` but forgets
/// `friction = "coulomb"` would otherwise get the paper law unnoticed).
/// A friction law's parameters are the rows that name it, and a lane
/// holds them in its law slots in the table's order ([`law_params`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Owner {
    /// Every lane uses it.
    All,
    /// These motor laws (a set of codes: [`motors`]).
    Motor(u32),
    /// These friction laws (a set of codes: [`frictions`]).
    Friction(u32),
    /// The laws that give a coefficient μ (`FrictionLaw::gives_coefficient`).
    Coefficient,
}

impl Owner {
    /// Whether lanes with these laws use the parameter.
    pub(crate) fn applies(self, motor: MotorKind, friction: FrictionKind) -> bool {
        match self {
            Owner::All => true,
            Owner::Motor(m) => m >> motor.code() & 1 == 1,
            Owner::Friction(f) => f >> friction.code() & 1 == 1,
            Owner::Coefficient => friction.gives_coefficient(),
        }
    }

    /// The law as a user writes it ("motor = kloss", "friction = coulomb
    /// or stribeck"); empty for `All`.
    pub fn law(self) -> String {
        let words = |w: Vec<&str>| match w.split_last() {
            Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
            _ => w.concat(),
        };
        match self {
            Owner::All => String::new(),
            Owner::Motor(m) => {
                let laws = MotorKind::ALL
                    .into_iter()
                    .filter(|k| m >> k.code() & 1 == 1);
                format!("motor = {}", words(laws.map(|k| k.name()).collect()))
            }
            Owner::Friction(f) => {
                let laws = FrictionKind::ALL
                    .into_iter()
                    .filter(|k| f >> k.code() & 1 == 1);
                format!("friction = {}", words(laws.map(|k| k.name()).collect()))
            }
            Owner::Coefficient => {
                let laws = FrictionKind::ALL
                    .into_iter()
                    .filter(|k| k.gives_coefficient());
                format!("friction = {}", words(laws.map(|k| k.name()).collect()))
            }
        }
    }
}

/// The set of motor laws an [`Owner::Motor`] holds, as a bit a code.
pub const fn motors(kinds: &[MotorKind]) -> u32 {
    let (mut set, mut i) = (0, 0);
    while i < kinds.len() {
        set |= 1 << kinds[i] as u8;
        i += 1;
    }
    set
}

/// The set of friction laws an [`Owner::Friction`] holds, as a bit a code.
pub const fn frictions(kinds: &[FrictionKind]) -> u32 {
    let (mut set, mut i) = (0, 0);
    while i < kinds.len() {
        set |= 1 << kinds[i] as u32;
        i += 1;
    }
    set
}

/// A friction law's parameters: the rows whose owner names the law, in
/// the table's order, which is the order of the lane's law slots
/// (`model::Lane::law`).
pub fn law_params(law: FrictionKind) -> &'static [Num] {
    static PARAMS: std::sync::OnceLock<Vec<Vec<Num>>> = std::sync::OnceLock::new();
    let all = PARAMS.get_or_init(|| {
        FrictionKind::ALL
            .map(|k| {
                Num::ALL
                    .into_iter()
                    .filter(
                        |n| matches!(n.def().owner, Owner::Friction(f) if f >> k.code() & 1 == 1),
                    )
                    .collect()
            })
            .to_vec()
    });
    &all[law as usize]
}

/// What an unset parameter takes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fallback {
    /// This value.
    Value(f64),
    /// The value of another parameter (`mu_static` defaults to `mu`).
    SameAs(Num),
    /// Nothing: the law that owns it needs it set.
    Required,
    /// Nothing, meaning "never" (`motor_off`).
    Never,
    /// Nothing: the quantity is given another way or not at all (a gear
    /// term, whose wedge counterpart has the default).
    NotSet,
}

/// One end of a parameter's allowed range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bound {
    /// No bound on this side.
    None,
    /// The value itself is allowed.
    Closed(f64),
    /// Only values strictly beyond it.
    Open(f64),
}

/// One row of the table: everything about a numeric parameter.
#[derive(Clone, Copy, Debug)]
pub struct Def {
    /// The one name: TOML key, lane-table column, `lanes.csv` column.
    pub name: &'static str,
    /// Unit ("" for none).
    pub unit: &'static str,
    /// What it is, for the guide.
    pub meaning: &'static str,
    /// Value when unset.
    pub default: Fallback,
    /// The law that uses it.
    pub owner: Owner,
    /// Lowest allowed value.
    pub lo: Bound,
    /// Highest allowed value.
    pub hi: Bound,
    /// A parameter it must stay strictly below (`v_crit < v_sync`).
    pub below: Option<Num>,
    /// A parameter it must be at least (`mu_static >= mu`).
    pub at_least: Option<Num>,
    /// A parameter it must stay strictly above (`t_max > t_end`).
    pub above: Option<Num>,
    /// Only whole numbers (tooth counts).
    pub integer: bool,
    /// Why the range is what it is, when that is not obvious.
    pub why: &'static str,
    /// Its default is the paper's drive's value (docs/model.md section 7),
    /// not a neutral one: a run that leaves it out says so.
    pub paper: bool,
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
    /// `friction_table`: which of the sweep's named friction tables.
    FrictionTable,
}

/// Builds the enum, the column order and [`NUMERIC`] from the rows, so
/// none of them can disagree with the table.
macro_rules! parameter_table {
    (@rows [$($v:ident $def:tt)*] [$($col:expr,)*]) => {
        /// The numeric parameters, in the order of docs/model.md section 9.
        /// The discriminant indexes [`NUMERIC`], `Spec::num` and `Params::num`.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        #[repr(usize)]
        pub enum Num { $(#[doc = concat!("The parameter `", stringify!($v), "` (its file name and meaning are in [`NUMERIC`]).")] $v,)* }
        /// Number of numeric parameters.
        pub const N_NUM: usize = [$(Num::$v),*].len();
        impl Num {
            /// All numeric parameters in index order.
            pub const ALL: [Num; N_NUM] = [$(Num::$v),*];
        }
        /// The rows of the numeric parameters, indexed by [`Num`].
        pub const NUMERIC: [Def; N_NUM] = [$(Def $def),*];
        impl Param {
            /// Every parameter in the column order of docs/model.md section 9.
            pub const COLUMNS: [Param; N_NUM + 3] = [$($col),*];
        }
    };
    (@rows [$($n:tt)*] [$($c:tt)*] num $v:ident $def:tt $($rest:tt)*) => {
        parameter_table!(@rows [$($n)* $v $def] [$($c)* Param::Num(Num::$v),] $($rest)*);
    };
    (@rows [$($n:tt)*] [$($c:tt)*] selector $v:ident $($rest:tt)*) => {
        parameter_table!(@rows [$($n)*] [$($c)* Param::$v,] $($rest)*);
    };
    ($($rows:tt)*) => { parameter_table!(@rows [] [] $($rows)*); };
}

/// A row's fields that most parameters leave at their usual value.
const ROW: Def = Def {
    name: "",
    unit: "",
    meaning: "",
    default: Fallback::Required,
    owner: Owner::All,
    lo: Bound::None,
    hi: Bound::None,
    below: None,
    at_least: None,
    above: None,
    integer: false,
    why: "",
    paper: false,
};

parameter_table! {
    num M1 { name: "m1", unit: "kg", meaning: "reduced mass of the worm side",
        default: Fallback::Value(586.0), lo: Bound::Closed(1e-3), hi: Bound::Closed(1e9),
        why: "a physical reduced mass", paper: true, ..ROW }
    num M2 { name: "m2", unit: "kg", meaning: "reduced mass of the wheel side",
        default: Fallback::Value(10275.0), lo: Bound::Closed(1e-3), hi: Bound::Closed(1e9),
        why: "a physical reduced mass", paper: true, ..ROW }
    num GammaDeg { name: "gamma_deg", unit: "deg", meaning: "lead angle",
        default: Fallback::Value(5.710593137499643), // atan(0.1)
        lo: Bound::Closed(0.5), hi: Bound::Closed(85.0),
        why: "worm lead angles; towards 0 or 90 deg the efficiencies lose meaning", paper: true, ..ROW }
    num F2 { name: "f2", unit: "N", meaning: "load on body 2 (+ overhauling, - resisting)",
        default: Fallback::Value(4774.0), paper: true, ..ROW }
    selector Motor
    num VSync { name: "v_sync", unit: "m/s", meaning: "Kloss motor: synchronous speed",
        default: Fallback::Value(3.35), owner: Owner::Motor(motors(&[MotorKind::Kloss])), lo: Bound::Open(0.0),
        hi: Bound::Closed(100.0), why: "sliding speeds of real drives", paper: true, ..ROW }
    num VCrit { name: "v_crit", unit: "m/s", meaning: "Kloss motor: speed at the peak force",
        default: Fallback::Value(2.07), owner: Owner::Motor(motors(&[MotorKind::Kloss])), lo: Bound::Closed(0.0),
        below: Some(Num::VSync), paper: true, ..ROW }
    num FCrit { name: "f_crit", unit: "N", meaning: "Kloss motor: peak force",
        default: Fallback::Value(4375.0), owner: Owner::Motor(motors(&[MotorKind::Kloss])), lo: Bound::Open(0.0), paper: true, ..ROW }
    num F1 { name: "f1", unit: "N", meaning: "force of a constant motor",
        owner: Owner::Motor(motors(&[MotorKind::Constant])), ..ROW }
    num MotorOff { name: "motor_off", unit: "s", meaning: "motor force 0 from this time",
        default: Fallback::Never, lo: Bound::Closed(0.0), why: "or unset for never", ..ROW }
    selector Friction
    selector FrictionTable
    num FricA { name: "fric_a", unit: "", meaning: "paper law rho[deg] = 1/(a Vs^b + c)",
        default: Fallback::Value(0.174), owner: Owner::Friction(frictions(&[FrictionKind::Paper])), lo: Bound::Closed(0.0),
        hi: Bound::Closed(100.0), ..ROW }
    num FricB { name: "fric_b", unit: "", meaning: "paper law exponent b",
        default: Fallback::Value(0.612), owner: Owner::Friction(frictions(&[FrictionKind::Paper])), lo: Bound::Open(0.0),
        hi: Bound::Closed(5.0), ..ROW }
    num FricC { name: "fric_c", unit: "", meaning: "paper law c = 1/rho(0)",
        default: Fallback::Value(0.14), owner: Owner::Friction(frictions(&[FrictionKind::Paper])),
        lo: Bound::Open(1.0 / 90.0), hi: Bound::Closed(100.0),
        why: "1/90: rho(0) = 1/c deg < 90 deg", ..ROW }
    num Mu { name: "mu", unit: "", meaning: "sliding (Coulomb) friction coefficient",
        owner: Owner::Friction(frictions(&[FrictionKind::Coulomb, FrictionKind::Stribeck])),
        lo: Bound::Closed(0.0), hi: Bound::Closed(10.0), ..ROW }
    num MuStatic { name: "mu_static", unit: "", meaning: "static (breakaway) coefficient",
        default: Fallback::SameAs(Num::Mu),
        owner: Owner::Friction(frictions(&[FrictionKind::Coulomb, FrictionKind::Stribeck])),
        at_least: Some(Num::Mu), hi: Bound::Closed(10.0),
        why: "static friction below sliding friction would stop a departing lane at once",
        ..ROW }
    num VStribeck { name: "v_stribeck", unit: "m/s", meaning: "Stribeck speed v_st",
        owner: Owner::Friction(frictions(&[FrictionKind::Stribeck])), lo: Bound::Open(0.0),
        hi: Bound::Closed(100.0), why: "sliding speeds of real drives", ..ROW }
    num StribeckExp { name: "stribeck_exp", unit: "", meaning: "Stribeck exponent δ",
        default: Fallback::Value(2.0), owner: Owner::Friction(frictions(&[FrictionKind::Stribeck])),
        lo: Bound::Closed(0.5), hi: Bound::Closed(2.0), ..ROW }
    num MuViscous { name: "mu_viscous", unit: "s/m",
        meaning: "viscous share kv of μ (μ grows by kv Vs)",
        default: Fallback::Value(0.0), owner: Owner::Friction(frictions(&[FrictionKind::Stribeck])),
        lo: Bound::Closed(0.0), hi: Bound::Closed(10.0), ..ROW }
    num AlphaNDeg { name: "alpha_n_deg", unit: "deg",
        meaning: "normal pressure angle of the thread flank",
        default: Fallback::Value(0.0), owner: Owner::Coefficient, lo: Bound::Closed(0.0),
        hi: Bound::Open(45.0),
        why: "flank angles of worm threads; the paper law's fit already holds the flank", ..ROW }
    num X10 { name: "x1_0", unit: "m", meaning: "initial position of body 1",
        default: Fallback::Value(0.0), lo: Bound::Closed(-1e6), hi: Bound::Closed(1e6), ..ROW }
    num V10 { name: "v1_0", unit: "m/s", meaning: "initial speed of body 1",
        default: Fallback::Value(0.0), lo: Bound::Closed(-100.0), hi: Bound::Closed(100.0),
        why: "sliding speeds of real drives", ..ROW }
    num TEnd { name: "t_end", unit: "s", meaning: "simulated time",
        default: Fallback::Value(2.0), lo: Bound::Open(0.0), hi: Bound::Closed(1e5), paper: true, ..ROW }
    num TMax { name: "t_max", unit: "s",
        meaning: "a lane still coasting at t_end after its motor is cut runs on to this time at most",
        default: Fallback::Never, hi: Bound::Closed(1e6), above: Some(Num::TEnd),
        why: "or unset: the run ends at t_end", ..ROW }
    num D1 { name: "d1", unit: "m", meaning: "worm pitch diameter",
        default: Fallback::NotSet, lo: Bound::Open(0.0), hi: Bound::Closed(10.0), ..ROW }
    num Z1 { name: "z1", unit: "", meaning: "worm starts (threads)",
        default: Fallback::NotSet, lo: Bound::Closed(1.0), hi: Bound::Closed(20.0), integer: true,
        ..ROW }
    num Z2 { name: "z2", unit: "", meaning: "wheel teeth",
        default: Fallback::NotSet, lo: Bound::Closed(1.0), hi: Bound::Closed(2000.0),
        integer: true, ..ROW }
    num MX { name: "m_x", unit: "m", meaning: "axial module (the wheel's transverse module)",
        default: Fallback::NotSet, lo: Bound::Open(0.0), hi: Bound::Closed(1.0), ..ROW }
    num R1 { name: "r1", unit: "m", meaning: "worm pitch radius (with r2 and gamma_deg)",
        default: Fallback::NotSet, lo: Bound::Open(0.0), hi: Bound::Closed(10.0), ..ROW }
    num R2 { name: "r2", unit: "m", meaning: "wheel pitch radius (with r1 and gamma_deg)",
        default: Fallback::NotSet, lo: Bound::Open(0.0), hi: Bound::Closed(10.0), ..ROW }
    num J1 { name: "j1", unit: "kg m^2",
        meaning: "inertia turning with the worm (rotor, coupling, worm)",
        default: Fallback::NotSet, lo: Bound::Open(0.0), hi: Bound::Closed(1e9), ..ROW }
    num J2 { name: "j2", unit: "kg m^2",
        meaning: "inertia turning with the wheel (wheel, output, load)",
        default: Fallback::NotSet, lo: Bound::Open(0.0), hi: Bound::Closed(1e9), ..ROW }
    num T1 { name: "t1", unit: "N m", meaning: "torque of a constant motor on the worm shaft",
        default: Fallback::NotSet, owner: Owner::Motor(motors(&[MotorKind::Constant])), ..ROW }
    num T2 { name: "t2", unit: "N m",
        meaning: "load torque on the wheel shaft (+ overhauling, - resisting)",
        default: Fallback::NotSet, ..ROW }
    num NSync { name: "n_sync", unit: "rpm",
        meaning: "Kloss motor: synchronous speed",
        default: Fallback::NotSet, owner: Owner::Motor(motors(&[MotorKind::Kloss])), lo: Bound::Open(0.0),
        hi: Bound::Closed(1e5), ..ROW }
    num NCrit { name: "n_crit", unit: "rpm",
        meaning: "Kloss motor: speed at the breakdown torque",
        default: Fallback::NotSet, owner: Owner::Motor(motors(&[MotorKind::Kloss])), lo: Bound::Closed(0.0),
        below: Some(Num::NSync), ..ROW }
    num TCrit { name: "t_crit", unit: "N m",
        meaning: "Kloss motor: breakdown torque",
        default: Fallback::NotSet, owner: Owner::Motor(motors(&[MotorKind::Kloss])), lo: Bound::Open(0.0), ..ROW }
    num N10 { name: "n1_0", unit: "rpm", meaning: "initial worm speed",
        default: Fallback::NotSet, lo: Bound::Closed(-1e5), hi: Bound::Closed(1e5), ..ROW }
}

impl Num {
    /// The parameter's row.
    pub fn def(self) -> &'static Def {
        &NUMERIC[self as usize]
    }

    /// The parameter's one name.
    pub fn name(self) -> &'static str {
        self.def().name
    }

    /// Looks a numeric parameter up by name.
    pub(crate) fn from_name(name: &str) -> Option<Num> {
        Num::ALL.into_iter().find(|p| p.name() == name)
    }

    /// The default value, if it has one of its own.
    pub(crate) fn default_value(self) -> Option<f64> {
        match self.def().default {
            Fallback::Value(v) => Some(v),
            _ => None,
        }
    }
}

impl Param {
    /// The parameter's one name.
    pub fn name(self) -> &'static str {
        match self {
            Param::Num(n) => n.name(),
            Param::Motor => "motor",
            Param::Friction => "friction",
            Param::FrictionTable => "friction_table",
        }
    }

    /// Looks a parameter up by name.
    pub(crate) fn from_name(name: &str) -> Option<Param> {
        Param::COLUMNS.into_iter().find(|p| p.name() == name)
    }

    /// All names, comma separated, for error messages.
    pub(crate) fn all_names() -> String {
        Param::COLUMNS.map(|p| p.name()).join(", ")
    }
}

impl Bound {
    fn admits_above(self, v: f64) -> bool {
        match self {
            Bound::None => true,
            Bound::Closed(b) => v >= b,
            Bound::Open(b) => v > b,
        }
    }
    fn admits_below(self, v: f64) -> bool {
        match self {
            Bound::None => true,
            Bound::Closed(b) => v <= b,
            Bound::Open(b) => v < b,
        }
    }
}

/// A bound as a person writes it: 1e9, 1e-3, 0.5, 85.
fn num_text(b: f64) -> String {
    if b != 0.0 && !(1e-2..1e5).contains(&b.abs()) {
        format!("{b:e}")
    } else if format!("{b}").len() > 8 {
        // 1/90: six decimals say enough.
        format!("{b:.6}")
    } else {
        format!("{b}")
    }
}

impl Def {
    /// Whether `v` lies in the row's own range (and is whole, for a count).
    pub(crate) fn in_range(&self, v: f64) -> bool {
        self.lo.admits_above(v) && self.hi.admits_below(v) && (!self.integer || v.fract() == 0.0)
    }

    /// The range in words: "> 0 kg", "in (0, 90) deg", ">= 0 s", "a whole
    /// number in [1, 20]"; empty when any number is allowed.
    pub(crate) fn range_text(&self) -> String {
        let range = self.bounds_text();
        if self.integer {
            format!("a whole number {range}")
        } else {
            range
        }
    }

    fn bounds_text(&self) -> String {
        let unit = if self.unit.is_empty() {
            String::new()
        } else {
            format!(" {}", self.unit)
        };
        match (self.lo, self.hi) {
            (Bound::None, Bound::None) => String::new(),
            (lo, Bound::None) => match lo {
                Bound::Closed(b) => format!(">= {}{unit}", num_text(b)),
                Bound::Open(b) => format!("> {}{unit}", num_text(b)),
                Bound::None => unreachable!(),
            },
            (Bound::None, hi) => match hi {
                Bound::Closed(b) => format!("<= {}{unit}", num_text(b)),
                Bound::Open(b) => format!("< {}{unit}", num_text(b)),
                Bound::None => unreachable!(),
            },
            (lo, hi) => {
                let (l, a) = match lo {
                    Bound::Closed(b) => ('[', b),
                    Bound::Open(b) => ('(', b),
                    Bound::None => unreachable!(),
                };
                let (r, b) = match hi {
                    Bound::Closed(b) => (']', b),
                    Bound::Open(b) => (')', b),
                    Bound::None => unreachable!(),
                };
                format!("in {l}{}, {}{r}{unit}", num_text(a), num_text(b))
            }
        }
    }
}

/// The parameter table of `docs/guide.md`, rendered from the rows (a test
/// keeps the guide equal to it).
#[cfg(test)]
pub(crate) fn guide_table() -> String {
    let mut s =
        String::from("| name | unit | meaning | default | allowed |\n|---|---|---|---|---|\n");
    for p in Param::COLUMNS {
        let row = match p {
            Param::Motor => {
                let laws = MotorKind::ALL.map(|k| format!("`{}`", k.name())).join(", ");
                format!("| `motor` | | motor law | `kloss` | {laws} |")
            }
            Param::Friction => {
                let laws = FrictionKind::ALL
                    .map(|k| format!("`{}`", k.name()))
                    .join(", ");
                format!("| `friction` | | friction law | `paper` | {laws} |")
            }
            Param::FrictionTable => "| `friction_table` | | which named friction table \
                 (friction = table) | the only table | a `[friction_table.NAME]` of the sweep |"
                .to_string(),
            Param::Num(n) => {
                let d = n.def();
                let default = match d.default {
                    Fallback::Value(v) => format!("{v}"),
                    Fallback::SameAs(q) => format!("= `{}`", q.name()),
                    Fallback::Required => format!("required by {}", d.owner.law()),
                    Fallback::Never => "never".into(),
                    Fallback::NotSet => "not set".into(),
                };
                let mut allowed = d.range_text();
                if let Some(q) = d.below {
                    allowed += &format!(", < `{}`", q.name());
                }
                if let Some(q) = d.above {
                    allowed = format!("> `{}`, {}", q.name(), d.range_text());
                }
                if let Some(q) = d.at_least {
                    allowed += &format!(">= `{}`", q.name());
                    if d.hi != Bound::None {
                        allowed = format!(">= `{}`, {}", q.name(), d.range_text());
                    }
                }
                if allowed.is_empty() {
                    allowed = "any finite number".into();
                }
                let law = match d.owner {
                    Owner::All => String::new(),
                    o => format!(" ({})", o.law()),
                };
                format!(
                    "| `{}` | {} | {}{law} | {default} | {allowed} |",
                    d.name, d.unit, d.meaning
                )
            }
        };
        s += &row;
        s.push('\n');
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_follow_model_md_order() {
        let names: Vec<_> = Param::COLUMNS.iter().map(|p| p.name()).collect();
        assert_eq!(
            names.join(","),
            "m1,m2,gamma_deg,f2,motor,v_sync,v_crit,f_crit,f1,motor_off,friction,friction_table,\
             fric_a,fric_b,fric_c,mu,mu_static,v_stribeck,stribeck_exp,mu_viscous,alpha_n_deg,x1_0,v1_0,t_end,t_max,\
             d1,z1,z2,m_x,r1,r2,j1,j2,t1,t2,n_sync,n_crit,t_crit,n1_0"
        );
        for p in Param::COLUMNS {
            assert_eq!(Param::from_name(p.name()), Some(p));
        }
        for (i, p) in Num::ALL.iter().enumerate() {
            assert_eq!(*p as usize, i);
        }
    }

    /// The guide's table is the table.
    #[test]
    fn the_guides_parameter_table_is_the_table() {
        let guide = include_str!("../../docs/guide.md");
        let want = guide_table();
        assert!(
            guide.contains(&want),
            "docs/guide.md's parameter table differs; it should read:\n{want}"
        );
    }

    /// Each law's parameters fit the lane's slots, and the laws' words
    /// read as a person writes them.
    #[test]
    fn law_params_fit_the_slots() {
        for k in FrictionKind::ALL {
            assert!(
                law_params(k).len() <= crate::model::laws::LAW_SLOTS,
                "{}",
                k.name()
            );
        }
        assert_eq!(
            law_params(FrictionKind::Paper),
            [Num::FricA, Num::FricB, Num::FricC]
        );
        assert_eq!(Num::Mu.def().owner.law(), "friction = coulomb or stribeck");
        assert_eq!(
            law_params(FrictionKind::Stribeck),
            [
                Num::Mu,
                Num::MuStatic,
                Num::VStribeck,
                Num::StribeckExp,
                Num::MuViscous
            ]
        );
        assert_eq!(Num::FCrit.def().owner.law(), "motor = kloss");
        assert_eq!(
            Num::AlphaNDeg.def().owner.law(),
            "friction = coulomb, table, agma or stribeck"
        );
    }

    #[test]
    fn ranges_read_as_written() {
        assert_eq!(Num::M1.def().range_text(), "in [1e-3, 1e9] kg");
        assert_eq!(Num::GammaDeg.def().range_text(), "in [0.5, 85] deg");
        assert_eq!(Num::MotorOff.def().range_text(), ">= 0 s");
        assert!(Num::GammaDeg.def().in_range(45.0));
        assert!(!Num::GammaDeg.def().in_range(90.0));
        assert!(!Num::V10.def().in_range(1e39));
        assert!(!Num::M1.def().in_range(f64::NAN));
    }
}
