//! Sweep files (TOML) and the lanes they stand for.
//!
//! A sweep is a `[base]` parameter set, optional grid axes (`[[grid]]`, a
//! Cartesian product), an optional tolerance study (`[sampling]` with
//! `[[tolerance]]` entries) and an optional `[friction_table]`.
//!
//! Lane order: grid points in row-major order (the first `[[grid]]` axis
//! varies slowest, the last fastest), and for each grid point the samples
//! 0..n of the study. Lane `i` is grid point `i / n`, sample `i % n`.
//! Sample `k` draws the same uniforms at every grid point (common random
//! numbers), so designs are compared under the same tolerances.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Deserialize;
use toml::Spanned;

use crate::error::{Error, Result};
use crate::model::FrictionTable;
use crate::params::{default_of, FrictionKind, MotorKind, Num, Param, Spec};
use crate::sampling::{Dist, Permutation, Uniforms};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SweepFile {
    #[serde(default)]
    base: BTreeMap<String, Spanned<toml::Value>>,
    #[serde(default)]
    grid: Vec<Spanned<AxisDef>>,
    sampling: Option<Spanned<SamplingDef>>,
    #[serde(default)]
    tolerance: Vec<Spanned<TolDef>>,
    friction_table: Option<Spanned<TableDef>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AxisDef {
    param: String,
    values: Option<Vec<f64>>,
    from: Option<f64>,
    to: Option<f64>,
    n: Option<i64>,
    scale: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SamplingDef {
    method: Method,
    n: i64,
    seed: u64,
}

/// How a tolerance study draws its samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// Independent draws.
    MonteCarlo,
    /// One sample in each of n equal-probability strata per parameter.
    LatinHypercube,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TolDef {
    param: String,
    dist: Dist,
    tol: Option<f64>,
    tol_rel: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TableDef {
    vs: Vec<f64>,
    mu: Vec<f64>,
}

/// One grid axis: a numeric parameter and its values.
#[derive(Clone, Debug)]
pub struct Axis {
    /// The parameter.
    pub param: Num,
    /// Its values.
    pub values: AxisValues,
}

/// An axis's values: a list, or a range computed value by value (so an
/// axis of 10^9 points costs no memory, and provenance keeps its form).
#[derive(Clone, Debug)]
pub enum AxisValues {
    /// `values = [...]`
    List(Vec<f64>),
    /// `from`, `to`, `n`, `scale`
    Range {
        /// First value.
        from: f64,
        /// Last value.
        to: f64,
        /// Number of values, >= 1.
        n: u64,
        /// Log-spaced.
        log: bool,
    },
}

impl Axis {
    /// Number of values (never 0: validation refuses empty axes).
    #[allow(clippy::len_without_is_empty)]
    pub fn len(&self) -> u64 {
        match &self.values {
            AxisValues::List(v) => v.len() as u64,
            AxisValues::Range { n, .. } => *n,
        }
    }

    /// Value `i` (< len).
    pub fn value(&self, i: u64) -> f64 {
        match &self.values {
            AxisValues::List(v) => v[i as usize],
            &AxisValues::Range { from, to, n, log } => {
                let frac = if n == 1 {
                    0.0
                } else {
                    i as f64 / (n - 1) as f64
                };
                if log {
                    (from.ln() + (to.ln() - from.ln()) * frac).exp()
                } else {
                    from + (to - from) * frac
                }
            }
        }
    }
}

/// One parameter of a tolerance study.
#[derive(Clone, Copy, Debug)]
pub struct Tolerance {
    /// The parameter.
    pub param: Num,
    /// Its distribution.
    pub dist: Dist,
    /// Half-width of the band, absolute (`tol`) ...
    pub tol: f64,
    /// ... or as a fraction of the nominal value (`tol_rel`).
    pub relative: bool,
}

/// A tolerance study.
#[derive(Clone, Debug)]
pub struct Study {
    /// Sampling method.
    pub method: Method,
    /// Samples per grid point.
    pub n: u64,
    /// Seed of the ChaCha8 stream.
    pub seed: u64,
    /// The varied parameters.
    pub params: Vec<Tolerance>,
    perms: Vec<Permutation>,
}

/// A parsed, validated sweep: a function from lane index to parameters.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// The base parameter set (unset values take MODEL.md defaults).
    pub base: Spec,
    /// Grid axes, slowest first.
    pub axes: Vec<Axis>,
    /// Optional tolerance study.
    pub study: Option<Study>,
    /// Optional friction table (for `friction = "table"`).
    pub table: Option<FrictionTable>,
}

fn line_of(text: &str, pos: usize) -> String {
    format!(
        "line {}",
        text[..pos.min(text.len())].matches('\n').count() + 1
    )
}

impl Sweep {
    /// Reads and validates a sweep file.
    pub fn from_file(path: &Path) -> Result<Sweep> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            Error::input(path, None, None, format!("cannot read the sweep file: {e}"))
        })?;
        Sweep::parse(path, &text)
    }

    /// Parses sweep-file text; `path` names it in errors.
    pub fn parse(path: &Path, text: &str) -> Result<Sweep> {
        let file: SweepFile = toml::from_str(text).map_err(|e| {
            let at = e.span().map(|s| line_of(text, s.start));
            Error::input(path, at, None, e.message().trim().replace('\n', " "))
        })?;
        let bad = |span: std::ops::Range<usize>, param: &str, msg: String| {
            Error::input(path, Some(line_of(text, span.start)), Some(param), msg)
        };

        let mut base = Spec::default();
        for (key, val) in &file.base {
            let span = val.span();
            let p = Param::from_name(key).ok_or_else(|| {
                bad(
                    span.clone(),
                    key,
                    format!("unknown parameter; allowed: {}", Param::all_names()),
                )
            })?;
            let text_form = match (p, val.get_ref()) {
                (Param::Num(_), toml::Value::Float(f)) => format!("{f:?}"),
                (Param::Num(_), toml::Value::Integer(i)) => i.to_string(),
                (Param::Num(_), v) => {
                    return Err(bad(
                        span,
                        key,
                        format!("expected a number, found {}", v.type_str()),
                    ))
                }
                (_, toml::Value::String(s)) => s.clone(),
                (_, v) => {
                    return Err(bad(
                        span,
                        key,
                        format!("expected a string, found {}", v.type_str()),
                    ))
                }
            };
            base.set_text(p, &text_form)
                .map_err(|m| bad(span, key, m))?;
        }

        let mut axes = Vec::new();
        for ax in &file.grid {
            let span = ax.span();
            let a = ax.get_ref();
            let param = numeric_param(&a.param).map_err(|m| bad(span.clone(), &a.param, m))?;
            let values = axis_values(a).map_err(|m| bad(span.clone(), &a.param, m))?;
            if axes.iter().any(|x: &Axis| x.param == param) {
                return Err(bad(span, &a.param, "appears on two grid axes".into()));
            }
            axes.push(Axis { param, values });
        }

        let table = match &file.friction_table {
            Some(t) => Some(
                FrictionTable::new(&t.get_ref().vs, &t.get_ref().mu)
                    .map_err(|m| bad(t.span(), "friction_table", m))?,
            ),
            None => None,
        };

        let study = match (&file.sampling, file.tolerance.is_empty()) {
            (None, true) => None,
            (None, false) => {
                return Err(bad(
                    file.tolerance[0].span(),
                    "tolerance",
                    "[[tolerance]] needs a [sampling] section (method, n, seed)".into(),
                ))
            }
            (Some(s), true) => {
                return Err(bad(
                    s.span(),
                    "sampling",
                    "[sampling] needs at least one [[tolerance]] entry".into(),
                ))
            }
            (Some(s), false) => {
                let sd = s.get_ref();
                if sd.n < 1 {
                    return Err(bad(s.span(), "n", format!("must be >= 1, got {}", sd.n)));
                }
                let mut params: Vec<Tolerance> = Vec::new();
                for t in &file.tolerance {
                    let span = t.span();
                    let td = t.get_ref();
                    let param =
                        numeric_param(&td.param).map_err(|m| bad(span.clone(), &td.param, m))?;
                    let (tol, relative) = match (td.tol, td.tol_rel) {
                        (Some(t), None) => (t, false),
                        (None, Some(t)) => (t, true),
                        _ => {
                            return Err(bad(
                                span,
                                &td.param,
                                "give exactly one of tol or tol_rel".into(),
                            ))
                        }
                    };
                    if !(tol.is_finite() && tol >= 0.0) {
                        return Err(bad(
                            span,
                            &td.param,
                            format!("tol must be finite and >= 0, got {tol}"),
                        ));
                    }
                    if params.iter().any(|x| x.param == param) {
                        return Err(bad(
                            span,
                            &td.param,
                            "appears in two [[tolerance]] entries".into(),
                        ));
                    }
                    if base.num[param as usize].is_none()
                        && default_of(param).is_none()
                        && !axes.iter().any(|a| a.param == param)
                    {
                        return Err(bad(
                            span,
                            &td.param,
                            "has no nominal value: set it in [base] or on a grid axis".into(),
                        ));
                    }
                    params.push(Tolerance {
                        param,
                        dist: td.dist,
                        tol,
                        relative,
                    });
                }
                let n = sd.n as u64;
                let perms = (0..params.len() as u64)
                    .map(|d| Permutation::new(n, sd.seed ^ (0xA5A5_0000_0000_0000 | d)))
                    .collect();
                Some(Study {
                    method: sd.method,
                    n,
                    seed: sd.seed,
                    params,
                    perms,
                })
            }
        };
        let sweep = Sweep {
            base,
            axes,
            study,
            table,
        };
        sweep
            .lane_count_checked()
            .map_err(|m| Error::input(path, None, None, m))?;
        Ok(sweep)
    }

    fn lane_count_checked(&self) -> std::result::Result<u64, String> {
        let mut n: u64 = self.study.as_ref().map_or(1, |s| s.n);
        for a in &self.axes {
            n = n
                .checked_mul(a.len())
                .ok_or("the sweep has more than 2^64 lanes")?;
        }
        Ok(n)
    }

    /// Number of lanes.
    pub fn lane_count(&self) -> u64 {
        self.lane_count_checked().unwrap_or(u64::MAX)
    }

    /// Samples per grid point (1 without a study).
    fn samples(&self) -> u64 {
        self.study.as_ref().map_or(1, |s| s.n)
    }

    /// The parameters of lane `i` (not yet validated).
    pub fn lane_spec(&self, i: u64, u: &mut Uniforms) -> Spec {
        let mut spec = self.base.clone();
        let n = self.samples();
        let (mut g, k) = (i / n, i % n);
        for a in self.axes.iter().rev() {
            let len = a.len();
            spec.set(a.param, a.value(g % len));
            g /= len;
        }
        if let Some(st) = &self.study {
            let dims = st.params.len() as u64;
            u.seek(k, dims);
            for (d, t) in st.params.iter().enumerate() {
                let r = u.next();
                let q = match st.method {
                    Method::MonteCarlo => r,
                    Method::LatinHypercube => (st.perms[d].apply(k) as f64 + r) / n as f64,
                };
                let nominal = spec.num[t.param as usize]
                    .or_else(|| default_of(t.param))
                    .unwrap_or(f64::NAN);
                let half = if t.relative {
                    t.tol * nominal.abs()
                } else {
                    t.tol
                };
                spec.set(t.param, nominal + half * t.dist.quantile(q));
            }
        }
        spec
    }

    /// A stream of uniforms for this sweep's study.
    pub fn uniforms(&self) -> Uniforms {
        Uniforms::new(self.study.as_ref().map_or(0, |s| s.seed))
    }

    /// The sweep as TOML with every lane's source spelled out: base with
    /// defaults resolved, axes as value lists, the study and the table.
    pub fn resolved_toml(&self) -> toml::Table {
        let mut t = toml::Table::new();
        // The base as set, plus the defaults of the laws it chooses; not
        // validated, since axes and samples may supply what it lacks.
        let mut base = toml::Table::new();
        let motor = self.base.motor.unwrap_or(MotorKind::Kloss);
        let friction = self.base.friction.unwrap_or(FrictionKind::Paper);
        base.insert("motor".into(), motor.name().into());
        base.insert("friction".into(), friction.name().into());
        for n in Num::ALL {
            let law_default = match n {
                Num::VSync | Num::VCrit | Num::FCrit => motor == MotorKind::Kloss,
                Num::FricA | Num::FricB | Num::FricC => friction == FrictionKind::Paper,
                _ => true,
            };
            let v = self.base.num[n as usize].or(if law_default { default_of(n) } else { None });
            if let Some(v) = v {
                base.insert(n.name().into(), v.into());
            }
        }
        t.insert("base".into(), base.into());
        let grid: Vec<toml::Value> = self
            .axes
            .iter()
            .map(|a| {
                let mut x = toml::Table::new();
                x.insert("param".into(), a.param.name().into());
                match &a.values {
                    &AxisValues::Range { from, to, n, log } => {
                        x.insert("from".into(), from.into());
                        x.insert("to".into(), to.into());
                        x.insert("n".into(), (n as i64).into());
                        x.insert("scale".into(), if log { "log" } else { "linear" }.into());
                    }
                    AxisValues::List(v) => {
                        x.insert("values".into(), floats(v));
                    }
                }
                x.into()
            })
            .collect();
        if !grid.is_empty() {
            t.insert("grid".into(), grid.into());
        }
        if let Some(st) = &self.study {
            let mut s = toml::Table::new();
            s.insert("method".into(), serde_name(&st.method));
            s.insert("n".into(), (st.n as i64).into());
            s.insert("seed".into(), toml::Value::Integer(st.seed as i64));
            t.insert("sampling".into(), s.into());
            let tols: Vec<toml::Value> = st
                .params
                .iter()
                .map(|p| {
                    let mut x = toml::Table::new();
                    x.insert("param".into(), p.param.name().into());
                    x.insert("dist".into(), serde_name(&p.dist));
                    x.insert(
                        if p.relative { "tol_rel" } else { "tol" }.into(),
                        p.tol.into(),
                    );
                    x.into()
                })
                .collect();
            t.insert("tolerance".into(), tols.into());
        }
        if let Some(tb) = &self.table {
            let mut x = toml::Table::new();
            x.insert("vs".into(), floats(&tb.vs[..tb.n]));
            x.insert("mu".into(), floats(&tb.mu[..tb.n]));
            t.insert("friction_table".into(), x.into());
        }
        t
    }
}

/// A list of floats as a TOML array.
fn floats(v: &[f64]) -> toml::Value {
    toml::Value::Array(v.iter().map(|&x| x.into()).collect())
}

/// An enum's spelling in files, as its serde derive writes it (one source
/// of truth for the names).
fn serde_name<T: serde::Serialize>(v: &T) -> toml::Value {
    toml::Value::try_from(v).expect("unit enum variants serialize as strings")
}

fn numeric_param(name: &str) -> std::result::Result<Num, String> {
    match Param::from_name(name) {
        Some(Param::Num(n)) => Ok(n),
        Some(_) => Err("is a law selector, not a number; only numeric parameters can vary".into()),
        None => Err(format!(
            "unknown parameter; allowed: {}",
            Param::all_names()
        )),
    }
}

fn axis_values(a: &AxisDef) -> std::result::Result<AxisValues, String> {
    match (&a.values, a.from, a.to, a.n) {
        (Some(v), None, None, None) => {
            if a.scale.is_some() {
                return Err("scale applies to from/to/n, not to values".into());
            }
            if v.is_empty() {
                return Err("values is empty; give at least one value".into());
            }
            if let Some(x) = v.iter().find(|x| !x.is_finite()) {
                return Err(format!("value {x} is not finite"));
            }
            Ok(AxisValues::List(v.clone()))
        }
        (None, Some(from), Some(to), Some(n)) => {
            if n < 1 {
                return Err(format!("n must be >= 1, got {n}"));
            }
            if !from.is_finite() || !to.is_finite() {
                return Err("from and to must be finite".into());
            }
            let log = match a.scale.as_deref().unwrap_or("linear") {
                "linear" => false,
                "log" => true,
                s => return Err(format!("scale `{s}` is unknown; allowed: linear, log")),
            };
            if log && !(from > 0.0 && to > 0.0) {
                return Err("scale = \"log\" needs from > 0 and to > 0".into());
            }
            Ok(AxisValues::Range {
                from,
                to,
                n: n as u64,
                log,
            })
        }
        _ => Err("give either values = [...] or from, to and n (with optional scale)".into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(t: &str) -> Result<Sweep> {
        Sweep::parse(Path::new("s.toml"), t)
    }

    #[test]
    fn grid_is_row_major_first_axis_slowest() {
        let s = parse(
            "[[grid]]\nparam = \"f2\"\nvalues = [1, 2]\n[[grid]]\nparam = \"gamma_deg\"\nfrom = 5\nto = 15\nn = 3\n",
        )
        .unwrap();
        assert_eq!(s.lane_count(), 6);
        let mut u = s.uniforms();
        let got: Vec<(f64, f64)> = (0..6)
            .map(|i| {
                let sp = s.lane_spec(i, &mut u);
                (
                    sp.num[Num::F2 as usize].unwrap(),
                    sp.num[Num::GammaDeg as usize].unwrap(),
                )
            })
            .collect();
        assert_eq!(
            got,
            vec![
                (1.0, 5.0),
                (1.0, 10.0),
                (1.0, 15.0),
                (2.0, 5.0),
                (2.0, 10.0),
                (2.0, 15.0)
            ]
        );
    }

    /// sweep.resolved.toml stands for exactly the same lanes.
    #[test]
    fn resolved_sweep_gives_the_same_lanes() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("sweeps");
        for f in [
            "paper.toml",
            "efficiency_map.toml",
            "tolerance.toml",
            "million.toml",
        ] {
            let a = Sweep::from_file(&root.join(f)).unwrap();
            let text = toml::to_string(&a.resolved_toml()).unwrap();
            let b = Sweep::parse(Path::new("resolved"), &text)
                .unwrap_or_else(|e| panic!("{f}: {e}\n{text}"));
            assert_eq!(a.lane_count(), b.lane_count(), "{f}");
            let (mut ua, mut ub) = (a.uniforms(), b.uniforms());
            let n = a.lane_count();
            for i in (0..n).step_by((n / 500).max(1) as usize) {
                let pa = a.lane_spec(i, &mut ua).resolve(a.table.is_some()).unwrap();
                let pb = b.lane_spec(i, &mut ub).resolve(b.table.is_some()).unwrap();
                assert_eq!(format!("{pa:?}"), format!("{pb:?}"), "{f} lane {i}");
            }
        }
    }

    #[test]
    fn log_axis_hits_its_ends() {
        let s = parse("[[grid]]\nparam = \"mu\"\nfrom = 0.01\nto = 1\nn = 3\nscale = \"log\"\n")
            .unwrap();
        let v: Vec<f64> = (0..3).map(|i| s.axes[0].value(i)).collect();
        assert!(
            (v[0] - 0.01).abs() < 1e-15 && (v[1] - 0.1).abs() < 1e-15 && (v[2] - 1.0).abs() < 1e-14
        );
    }

    #[test]
    fn latin_hypercube_puts_one_sample_in_each_stratum() {
        let s = parse(
            "[sampling]\nmethod = \"latin_hypercube\"\nn = 50\nseed = 3\n\
             [[tolerance]]\nparam = \"m1\"\ndist = \"uniform\"\ntol = 50\n",
        )
        .unwrap();
        let mut u = s.uniforms();
        let mut hit = [0; 50];
        for i in 0..50 {
            let m1 = s.lane_spec(i, &mut u).num[Num::M1 as usize].unwrap();
            // uniform on 586 ± 50: stratum of width 100/50 = 2 kg
            hit[((m1 - 536.0) / 2.0) as usize] += 1;
        }
        assert!(hit.iter().all(|&h| h == 1), "{hit:?}");
    }
}
