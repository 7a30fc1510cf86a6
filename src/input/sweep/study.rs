//! A tolerance study: `[sampling]` (method, samples, seed) and its
//! `[[tolerance]]` entries, checked against the base and the grid.

use toml::Spanned;

use super::axes::numeric_param;
use super::file::At;
use super::file::{Method, Seed, SensitivityDef, SweepFile, TolDef, MAX_SEED};
use super::{Axis, Sensitivity, Study, Tolerance};
use crate::columns::{indicators, number_columns};
use crate::error::Result;
use crate::input::sampling::Permutation;
use crate::input::sobol_seq::SobolSeq;
use crate::params::{Param, Spec};

pub(super) fn parse_study(
    at: &At,
    file: &SweepFile,
    base: &Spec,
    axes: &[Axis],
) -> Result<Option<Study>> {
    if let (Some(_), Some(sn)) = (&file.sampling, &file.sensitivity) {
        return Err(at.bad(
            sn.span(),
            "sensitivity",
            "a sweep has [sampling] or [sensitivity], not both: [sensitivity] draws its own design over the [[tolerance]] inputs".into(),
        ));
    }
    if let Some(sn) = &file.sensitivity {
        return parse_sensitivity(at, file, sn, base, axes).map(Some);
    }
    let s =
        match (&file.sampling, file.tolerance.first()) {
            (None, None) => return Ok(None),
            (None, Some(t)) => return Err(at.bad(
                t.span(),
                "tolerance",
                "[[tolerance]] needs a [sampling] section (method, n, seed) or a [sensitivity] one"
                    .into(),
            )),
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
    let seed = parse_seed(at, &sd.seed)?;
    let params = parse_tolerances(at, file, base, axes)?;
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
        sensitivity: None,
    }))
}

fn parse_seed(at: &At, seed: &Spanned<Seed>) -> Result<u64> {
    let v = seed.get_ref().0;
    if !(0..=MAX_SEED as i128).contains(&v) {
        return Err(at.bad(
            seed.span(),
            "seed",
            format!("must be an integer from 0 to {MAX_SEED} (so that sweep.resolved.toml gives it back), got {v}"),
        ));
    }
    Ok(v as u64)
}

fn parse_tolerances(
    at: &At,
    file: &SweepFile,
    base: &Spec,
    axes: &[Axis],
) -> Result<Vec<Tolerance>> {
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
    Ok(params)
}

/// `[sensitivity]`: a Saltelli design of `n` base samples over the
/// `[[tolerance]]` inputs, with its bootstrap and the results the report
/// charts.
fn parse_sensitivity(
    at: &At,
    file: &SweepFile,
    sn: &Spanned<SensitivityDef>,
    base: &Spec,
    axes: &[Axis],
) -> Result<Study> {
    let d = sn.get_ref();
    if d.method.get_ref() != "sobol" {
        return Err(at.bad(
            d.method.span(),
            "method",
            format!("allowed: \"sobol\", got {:?}", d.method.get_ref()),
        ));
    }
    if file.tolerance.is_empty() {
        return Err(at.bad(
            sn.span(),
            "sensitivity",
            "[sensitivity] needs at least one [[tolerance]] entry: its inputs".into(),
        ));
    }
    let n = *d.n.get_ref();
    if !(2..=Sensitivity::MAX_BASE as i64).contains(&n) {
        return Err(at.bad(
            d.n.span(),
            "n",
            format!(
                "base samples: an integer from 2 to {} (a power of 2 balances the design), got {n}",
                Sensitivity::MAX_BASE
            ),
        ));
    }
    let (bootstrap, confidence, results) = parse_analysis(at, d)?;
    let seed = parse_seed(at, &d.seed)?;
    let params = parse_tolerances(at, file, base, axes)?;
    if params.len() > Sensitivity::MAX_INPUTS {
        return Err(at.bad(
            sn.span(),
            "tolerance",
            format!(
                "a sensitivity design takes at most {} inputs, got {}",
                Sensitivity::MAX_INPUTS,
                params.len()
            ),
        ));
    }
    let base_n = n as u64;
    Ok(Study {
        method: Method::Sobol,
        n: base_n * (params.len() as u64 + 2),
        seed,
        perms: Vec::new(),
        sensitivity: Some(Box::new(Sensitivity {
            base: base_n,
            bootstrap,
            confidence,
            results,
            seq: SobolSeq::new(2 * params.len(), Some(seed)),
        })),
        params,
    })
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
        && !axes.iter().any(|a| a.param == Param::Num(param))
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

/// `[sensitivity]`'s bootstrap, confidence and charted results.
fn parse_analysis(at: &At, d: &SensitivityDef) -> Result<(usize, f64, Vec<String>)> {
    let bootstrap = match &d.bootstrap {
        None => Sensitivity::DEFAULT_BOOTSTRAP,
        Some(b) if (0..=Sensitivity::MAX_BOOTSTRAP as i64).contains(b.get_ref()) => {
            *b.get_ref() as usize
        }
        Some(b) => {
            return Err(at.bad(
                b.span(),
                "bootstrap",
                format!(
                    "resamples: an integer from 0 (no intervals) to {}, got {}",
                    Sensitivity::MAX_BOOTSTRAP,
                    b.get_ref()
                ),
            ))
        }
    };
    let confidence = match &d.confidence {
        None => Sensitivity::DEFAULT_CONFIDENCE,
        Some(c) if *c.get_ref() > 0.0 && *c.get_ref() < 1.0 => *c.get_ref(),
        Some(c) => {
            return Err(at.bad(
                c.span(),
                "confidence",
                format!(
                    "a coverage strictly between 0 and 1 (0.95 for 95 %), got {}",
                    c.get_ref()
                ),
            ))
        }
    };
    let allowed: Vec<String> = number_columns()
        .map(|c| c.name.to_string())
        .chain(indicators().iter().map(|i| i.name()))
        .collect();
    let mut results = Vec::new();
    for r in &d.results {
        if !allowed.contains(r.get_ref()) {
            return Err(at.bad(
                r.span(),
                "results",
                format!(
                    "{:?} is not a result; allowed: {}",
                    r.get_ref(),
                    allowed.join(", ")
                ),
            ));
        }
        results.push(r.get_ref().clone());
    }
    Ok((bootstrap, confidence, results))
}
