//! A sweep file's TOML form, as serde reads it (with spans, so errors
//! name their line); every check beyond its shape is in `parse`.

use std::collections::BTreeMap;

use serde::Deserialize;
use toml::Spanned;

use std::path::Path;

use crate::error::Error;
use crate::input::sampling::Dist;
use crate::params::Param;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SweepFile {
    #[serde(default)]
    pub(super) base: BTreeMap<String, Spanned<toml::Value>>,
    #[serde(default)]
    pub(super) grid: Vec<Spanned<AxisDef>>,
    pub(super) sampling: Option<Spanned<SamplingDef>>,
    pub(super) sensitivity: Option<Spanned<SensitivityDef>>,
    #[serde(default)]
    pub(super) tolerance: Vec<Spanned<TolDef>>,
    pub(super) friction_table: Option<Spanned<toml::Table>>,
    pub(super) trace: Option<Spanned<TraceDef>>,
    pub(super) report: Option<Spanned<ReportDef>>,
    pub(super) search: Option<Spanned<SearchDef>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SearchDef {
    pub(super) param: Spanned<String>,
    pub(super) from: Spanned<f64>,
    pub(super) to: Spanned<f64>,
    pub(super) require: Spanned<String>,
    pub(super) tol: Spanned<f64>,
    pub(super) at_least: Option<Spanned<f64>>,
    pub(super) quantiles: Option<Spanned<bool>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ReportDef {
    pub(super) title: Option<String>,
    #[serde(default)]
    pub(super) axes: Vec<String>,
    #[serde(default)]
    pub(super) results: Vec<String>,
    pub(super) panels: Option<i64>,
    pub(super) require: Option<String>,
    pub(super) at_least: Option<f64>,
    pub(super) pareto: Option<Vec<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct TraceDef {
    pub(super) lanes: Vec<u64>,
    pub(super) dt: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct AxisDef {
    pub(super) param: Spanned<String>,
    pub(super) values: Option<Spanned<Vec<toml::Value>>>,
    pub(super) from: Option<Spanned<f64>>,
    pub(super) to: Option<Spanned<f64>>,
    pub(super) n: Option<Spanned<i64>>,
    pub(super) scale: Option<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SamplingDef {
    pub(super) method: Method,
    pub(super) n: Spanned<i64>,
    pub(super) seed: Spanned<Seed>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SensitivityDef {
    pub(super) method: Spanned<String>,
    pub(super) n: Spanned<i64>,
    pub(super) seed: Spanned<Seed>,
    pub(super) bootstrap: Option<Spanned<i64>>,
    pub(super) confidence: Option<Spanned<f64>>,
    #[serde(default)]
    pub(super) results: Vec<Spanned<String>>,
}

/// Largest seed: `sweep.resolved.toml` writes seeds as TOML integers,
/// which are signed 64-bit, and a seed must come back as it was given.
pub const MAX_SEED: u64 = i64::MAX as u64;

/// A seed as written, checked against [`MAX_SEED`] with its line.
pub(super) struct Seed(pub(super) i128);

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
    /// A Saltelli design on scrambled Sobol' points (`[sensitivity]`, not
    /// a `[sampling]` method).
    #[serde(skip)]
    Sobol,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct TolDef {
    pub(super) param: Spanned<String>,
    pub(super) dist: Dist,
    pub(super) tol: Option<f64>,
    pub(super) tol_rel: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct TableDef {
    pub(super) vs: Vec<f64>,
    pub(super) mu: Vec<f64>,
}

/// A sweep file's text, to turn spans into "line N" in errors.
pub(super) struct At<'a> {
    pub(super) path: &'a Path,
    pub(super) text: &'a str,
}

impl At<'_> {
    pub(super) fn bad(&self, span: std::ops::Range<usize>, param: &str, msg: String) -> Error {
        Error::input(
            self.path,
            Some(line_of(self.text, span.start)),
            Some(param),
            msg,
        )
    }
}

/// "line N" of the byte at `pos` of `text`.
pub(super) fn line_of(text: &str, pos: usize) -> String {
    format!(
        "line {}",
        text[..pos.min(text.len())].matches('\n').count() + 1
    )
}

/// The line of each parameter the file sets: `[base]` keys, grid axes,
/// tolerances (a later entry of the same name does not replace an earlier).
pub(super) fn key_lines(text: &str, file: &SweepFile) -> Vec<(&'static str, usize)> {
    let line = |pos: usize| text[..pos.min(text.len())].matches('\n').count() + 1;
    let mut out: Vec<(&'static str, usize)> = Vec::new();
    let spans = file
        .base
        .iter()
        .map(|(k, v)| (k.as_str(), v.span().start))
        .chain(file.grid.iter().map(|a| {
            let p = &a.get_ref().param;
            (p.get_ref().as_str(), p.span().start)
        }))
        .chain(file.tolerance.iter().map(|t| {
            let p = &t.get_ref().param;
            (p.get_ref().as_str(), p.span().start)
        }));
    for (name, pos) in spans {
        if let Some(p) = Param::from_name(name) {
            if !out.iter().any(|(n, _)| *n == p.name()) {
                out.push((p.name(), line(pos)));
            }
        }
    }
    out
}
