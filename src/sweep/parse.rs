//! Reading a sweep file: its TOML form, and every check that can be made
//! before lanes are generated, each error naming the file, the line and
//! the key.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Deserialize;
use toml::Spanned;

use super::{Axis, AxisValues, Study, Sweep, Tolerance};
use crate::error::{Error, Result};
use crate::model::FrictionTable;
use crate::params::{Num, Param, Spec};
use crate::sampling::{Dist, Permutation};

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
        let at = At { path, text };
        let base = parse_base(&at, &file.base)?;
        let axes = parse_axes(&at, &file.grid)?;
        let table = match &file.friction_table {
            Some(t) => Some(
                FrictionTable::new(&t.get_ref().vs, &t.get_ref().mu)
                    .map_err(|m| at.bad(t.span(), "friction_table", m))?,
            ),
            None => None,
        };
        let study = parse_study(&at, &file, &base, &axes)?;
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
}

/// A sweep file's text, to turn spans into "line N" in errors.
struct At<'a> {
    path: &'a Path,
    text: &'a str,
}

impl At<'_> {
    fn bad(&self, span: std::ops::Range<usize>, param: &str, msg: String) -> Error {
        Error::input(
            self.path,
            Some(line_of(self.text, span.start)),
            Some(param),
            msg,
        )
    }
}

fn parse_base(at: &At, keys: &BTreeMap<String, Spanned<toml::Value>>) -> Result<Spec> {
    let mut base = Spec::default();
    for (key, val) in keys {
        let span = val.span();
        let p = Param::from_name(key).ok_or_else(|| {
            at.bad(
                span.clone(),
                key,
                format!("unknown parameter; allowed: {}", Param::all_names()),
            )
        })?;
        let text_form = match (p, val.get_ref()) {
            (Param::Num(_), toml::Value::Float(f)) => format!("{f:?}"),
            (Param::Num(_), toml::Value::Integer(i)) => i.to_string(),
            (Param::Num(_), v) => {
                return Err(at.bad(
                    span,
                    key,
                    format!("expected a number, found {}", v.type_str()),
                ))
            }
            (_, toml::Value::String(s)) => s.clone(),
            (_, v) => {
                return Err(at.bad(
                    span,
                    key,
                    format!("expected a string, found {}", v.type_str()),
                ))
            }
        };
        base.set_text(p, &text_form)
            .map_err(|m| at.bad(span, key, m))?;
    }
    Ok(base)
}

fn parse_axes(at: &At, grid: &[Spanned<AxisDef>]) -> Result<Vec<Axis>> {
    let mut axes: Vec<Axis> = Vec::new();
    for ax in grid {
        let span = ax.span();
        let a = ax.get_ref();
        let param = numeric_param(&a.param).map_err(|m| at.bad(span.clone(), &a.param, m))?;
        let values = axis_values(a).map_err(|m| at.bad(span.clone(), &a.param, m))?;
        if axes.iter().any(|x| x.param == param) {
            return Err(at.bad(span, &a.param, "appears on two grid axes".into()));
        }
        axes.push(Axis { param, values });
    }
    Ok(axes)
}

fn parse_study(at: &At, file: &SweepFile, base: &Spec, axes: &[Axis]) -> Result<Option<Study>> {
    let s = match (&file.sampling, file.tolerance.first()) {
        (None, None) => return Ok(None),
        (None, Some(t)) => {
            return Err(at.bad(
                t.span(),
                "tolerance",
                "[[tolerance]] needs a [sampling] section (method, n, seed)".into(),
            ))
        }
        (Some(s), None) => {
            return Err(at.bad(
                s.span(),
                "sampling",
                "[sampling] needs at least one [[tolerance]] entry".into(),
            ))
        }
        (Some(s), Some(_)) => s,
    };
    let sd = s.get_ref();
    if sd.n < 1 {
        return Err(at.bad(s.span(), "n", format!("must be >= 1, got {}", sd.n)));
    }
    let mut params: Vec<Tolerance> = Vec::new();
    for t in &file.tolerance {
        let tol = parse_tolerance(at, t, base, axes)?;
        if params.iter().any(|x| x.param == tol.param) {
            return Err(at.bad(
                t.span(),
                &t.get_ref().param,
                "appears in two [[tolerance]] entries".into(),
            ));
        }
        params.push(tol);
    }
    let n = sd.n as u64;
    let perms = (0..params.len() as u64)
        .map(|d| Permutation::new(n, sd.seed ^ (0xA5A5_0000_0000_0000 | d)))
        .collect();
    Ok(Some(Study {
        method: sd.method,
        n,
        seed: sd.seed,
        params,
        perms,
    }))
}

fn parse_tolerance(at: &At, t: &Spanned<TolDef>, base: &Spec, axes: &[Axis]) -> Result<Tolerance> {
    let span = t.span();
    let td = t.get_ref();
    let bad = |m: String| at.bad(span.clone(), &td.param, m);
    let param = numeric_param(&td.param).map_err(bad)?;
    let (tol, relative) = match (td.tol, td.tol_rel) {
        (Some(t), None) => (t, false),
        (None, Some(t)) => (t, true),
        _ => return Err(bad("give exactly one of tol or tol_rel".into())),
    };
    if !(tol.is_finite() && tol >= 0.0) {
        return Err(bad(format!("tol must be finite and >= 0, got {tol}")));
    }
    if base.num[param as usize].is_none()
        && param.default_value().is_none()
        && !axes.iter().any(|a| a.param == param)
    {
        return Err(bad(
            "has no nominal value: set it in [base] or on a grid axis".into(),
        ));
    }
    Ok(Tolerance {
        param,
        dist: td.dist,
        tol,
        relative,
    })
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
