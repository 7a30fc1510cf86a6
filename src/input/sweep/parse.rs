//! Reading a sweep file: its TOML form, and every check that can be made
//! before lanes are generated, each error naming the file, the line and
//! the key.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Deserialize;
use toml::Spanned;

use super::{Axis, AxisValues, Study, Sweep, Tolerance};
use crate::error::{did_you_mean, Error, Result};
use crate::input::sampling::{Dist, Permutation};
use crate::model::FrictionTable;
use crate::params::{Num, Param, Spec};

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
    trace: Option<Spanned<TraceDef>>,
    report: Option<Spanned<ReportDef>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ReportDef {
    title: Option<String>,
    #[serde(default)]
    axes: Vec<String>,
    #[serde(default)]
    results: Vec<String>,
    panels: Option<i64>,
    require: Option<String>,
    at_least: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TraceDef {
    lanes: Vec<u64>,
    dt: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AxisDef {
    param: Spanned<String>,
    values: Option<Spanned<Vec<f64>>>,
    from: Option<Spanned<f64>>,
    to: Option<Spanned<f64>>,
    n: Option<Spanned<i64>>,
    scale: Option<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SamplingDef {
    method: Method,
    n: Spanned<i64>,
    seed: Spanned<Seed>,
}

/// Largest seed: `sweep.resolved.toml` writes seeds as TOML integers,
/// which are signed 64-bit, and a seed must come back as it was given.
pub const MAX_SEED: u64 = i64::MAX as u64;

/// A seed as written, checked against [`MAX_SEED`] with its line.
struct Seed(i128);

impl<'de> Deserialize<'de> for Seed {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Seed, D::Error> {
        struct V;
        impl serde::de::Visitor<'_> for V {
            type Value = Seed;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                write!(f, "seed: an integer from 0 to {MAX_SEED}")
            }
            fn visit_i64<E>(self, v: i64) -> std::result::Result<Seed, E> {
                Ok(Seed(v as i128))
            }
            fn visit_u64<E>(self, v: u64) -> std::result::Result<Seed, E> {
                Ok(Seed(v as i128))
            }
        }
        d.deserialize_any(V)
    }
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
    param: Spanned<String>,
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
/// The TOML reader's error on one line; a duplicate key is named.
fn toml_error(path: &Path, text: &str, e: &toml::de::Error) -> Error {
    let at = e.span().map(|s| line_of(text, s.start));
    let msg = e.message().trim().replace('\n', " ");
    if msg.starts_with("duplicate key") {
        let key = e
            .span()
            .and_then(|s| text.get(s))
            .map(|k| k.trim().trim_matches(['"', '\'']))
            .unwrap_or("");
        return Error::input(
            path,
            at,
            Some(key),
            "duplicate key; each key may appear once in its table",
        );
    }
    Error::input(path, at, None, suggest_in(&msg))
}

/// The TOML reader's "unknown field `x`, expected one of `a`, `b`" (or
/// "unknown variant"), with a "did you mean" for a near miss.
fn suggest_in(msg: &str) -> String {
    for kind in ["unknown field `", "unknown variant `"] {
        let Some(rest) = msg.split(kind).nth(1) else {
            continue;
        };
        let Some((name, tail)) = rest.split_once('`') else {
            continue;
        };
        let candidates: Vec<&str> = tail.split('`').skip(1).step_by(2).collect();
        let hint = did_you_mean(name, candidates.iter().copied());
        if !hint.is_empty() {
            return msg.replacen(
                &format!("{kind}{name}`"),
                &format!("{kind}{name}`{hint}"),
                1,
            );
        }
    }
    msg.to_string()
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
        let file: SweepFile = toml::from_str(text).map_err(|e| toml_error(path, text, &e))?;
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
        let mut sweep = Sweep {
            base,
            axes,
            study,
            table,
            trace: None,
            report: Default::default(),
        };
        let total = sweep
            .lane_count_checked()
            .map_err(|m| Error::input(path, None, None, m))?;
        if let Some(t) = &file.trace {
            let d = t.get_ref();
            sweep.trace = Some(
                super::TraceSpec::new(d.lanes.clone(), d.dt, total)
                    .map_err(|m| at.bad(t.span(), "trace", m))?,
            );
        }
        if let Some(r) = &file.report {
            sweep.report = parse_report(r.get_ref(), &sweep.axes)
                .map_err(|(key, m)| at.bad(r.span(), key, m))?;
        }
        Ok(sweep)
    }
}

/// The `[report]` table, checked against the grid; an error names its key.
fn parse_report(
    d: &ReportDef,
    axes: &[Axis],
) -> std::result::Result<super::ReportSpec, (&'static str, String)> {
    let grid: Vec<&str> = axes.iter().map(|a| a.param.name()).collect();
    let mut chosen = Vec::new();
    for name in &d.axes {
        match axes.iter().find(|a| a.param.name() == name) {
            Some(a) if !chosen.contains(&a.param) => chosen.push(a.param),
            Some(_) => return Err(("report.axes", format!("`{name}` is given twice"))),
            None => {
                return Err((
                    "report.axes",
                    format!(
                        "`{name}` is not a grid parameter of this sweep; allowed: {}",
                        if grid.is_empty() {
                            "none (the sweep has no grid)".into()
                        } else {
                            grid.join(", ")
                        }
                    ),
                ))
            }
        }
    }
    if chosen.len() > 2 {
        return Err(("report.axes", "at most 2 axes (x, then y)".into()));
    }
    let allowed: Vec<&str> = crate::columns::number_columns().map(|c| c.name).collect();
    for r in &d.results {
        if !allowed.contains(&r.as_str()) {
            return Err((
                "report.results",
                format!(
                    "`{r}` is not a result number column; allowed: {}",
                    allowed.join(", ")
                ),
            ));
        }
    }
    let max = super::ReportSpec::MAX_PANELS;
    let panels = match d.panels {
        None => 0,
        Some(n) if n >= 1 && n as usize <= max => n as usize,
        Some(n) => {
            return Err((
                "report.panels",
                format!("{n} is out of range; allowed: 1 to {max}"),
            ))
        }
    };
    let require =
        match (&d.require, d.at_least) {
            (None, None) => None,
            (Some(r), Some(a)) => {
                Some(super::require::Requirement::parse(r, a).map_err(|m| ("report.require", m))?)
            }
            (Some(_), None) => {
                return Err((
                    "report.at_least",
                    "require needs at_least, the least share of lanes that must meet it, in (0, 1]"
                        .into(),
                ))
            }
            (None, Some(_)) => return Err((
                "report.require",
                "at_least needs require, the test it applies to (e.g. require = \"hold = held\")"
                    .into(),
            )),
        };
    Ok(super::ReportSpec {
        title: d.title.clone(),
        axes: chosen,
        results: d.results.clone(),
        panels,
        require,
    })
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
                format!(
                    "unknown parameter{}; allowed: {}",
                    did_you_mean(key, Param::COLUMNS.map(|p| p.name())),
                    Param::all_names()
                ),
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
        let a = ax.get_ref();
        // Errors point at the key concerned, else at the [[grid]] entry.
        let bad = |(span, m): (Option<std::ops::Range<usize>>, String)| {
            at.bad(span.unwrap_or(a.param.span()), a.param.get_ref(), m)
        };
        let param = numeric_param(a.param.get_ref()).map_err(|m| bad((None, m)))?;
        let values = axis_values(a).map_err(bad)?;
        if axes.iter().any(|x| x.param == param) {
            return Err(bad((None, "appears on two grid axes".into())));
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
    let n = *sd.n.get_ref();
    if n < 1 {
        return Err(at.bad(sd.n.span(), "n", format!("must be >= 1, got {n}")));
    }
    let seed = sd.seed.get_ref().0;
    if !(0..=MAX_SEED as i128).contains(&seed) {
        return Err(at.bad(
            sd.seed.span(),
            "seed",
            format!("must be an integer from 0 to {MAX_SEED} (so that sweep.resolved.toml gives it back), got {seed}"),
        ));
    }
    let seed = seed as u64;
    let mut params: Vec<Tolerance> = Vec::new();
    for t in &file.tolerance {
        let tol = parse_tolerance(at, t, base, axes)?;
        if params.iter().any(|x| x.param == tol.param) {
            return Err(at.bad(
                t.span(),
                t.get_ref().param.get_ref(),
                "appears in two [[tolerance]] entries".into(),
            ));
        }
        params.push(tol);
    }
    let n = n as u64;
    let perms = (0..params.len() as u64)
        .map(|d| Permutation::new(n, seed ^ (0xA5A5_0000_0000_0000 | d)))
        .collect();
    Ok(Some(Study {
        method: sd.method,
        n,
        seed,
        params,
        perms,
    }))
}

fn parse_tolerance(at: &At, t: &Spanned<TolDef>, base: &Spec, axes: &[Axis]) -> Result<Tolerance> {
    let span = t.span();
    let td = t.get_ref();
    let bad = |m: String| at.bad(span.clone(), td.param.get_ref(), m);
    let param = numeric_param(td.param.get_ref())
        .map_err(|m| at.bad(td.param.span(), td.param.get_ref(), m))?;
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
            "unknown parameter{}; allowed: {}",
            did_you_mean(name, Param::COLUMNS.map(|p| p.name())),
            Param::all_names()
        )),
    }
}

/// An axis's values; an error names the span of the key concerned.
fn axis_values(
    a: &AxisDef,
) -> std::result::Result<AxisValues, (Option<std::ops::Range<usize>>, String)> {
    let get = |x: &Option<Spanned<f64>>| x.as_ref().map(|v| *v.get_ref());
    match (&a.values, &a.from, &a.to, &a.n) {
        (Some(v), None, None, None) => {
            if let Some(sc) = &a.scale {
                return Err((
                    Some(sc.span()),
                    "scale applies to from/to/n, not to values".into(),
                ));
            }
            let span = Some(v.span());
            let v = v.get_ref();
            if v.is_empty() {
                return Err((span, "values is empty; give at least one value".into()));
            }
            if let Some(x) = v.iter().find(|x| !x.is_finite()) {
                return Err((span, format!("value {x} is not finite")));
            }
            Ok(AxisValues::List(v.clone()))
        }
        (None, Some(from), Some(to), Some(n)) => {
            if *n.get_ref() < 1 {
                return Err((
                    Some(n.span()),
                    format!("n must be >= 1, got {}", n.get_ref()),
                ));
            }
            for x in [from, to] {
                if !x.get_ref().is_finite() {
                    return Err((Some(x.span()), "from and to must be finite".into()));
                }
            }
            let log = match &a.scale {
                None => false,
                Some(sc) => match sc.get_ref().as_str() {
                    "linear" => false,
                    "log" => true,
                    s => {
                        return Err((
                            Some(sc.span()),
                            format!("scale `{s}` is unknown; allowed: linear, log"),
                        ))
                    }
                },
            };
            let (from, to) = (get(&a.from).unwrap_or(0.0), get(&a.to).unwrap_or(0.0));
            if log && !(from > 0.0 && to > 0.0) {
                return Err((
                    Some(a.scale.as_ref().map_or(0..0, |s| s.span())),
                    "scale = \"log\" needs from > 0 and to > 0".into(),
                ));
            }
            Ok(AxisValues::Range {
                from,
                to,
                n: *n.get_ref() as u64,
                log,
            })
        }
        _ => Err((
            None,
            "give either values = [...] or from, to and n (with optional scale)".into(),
        )),
    }
}
