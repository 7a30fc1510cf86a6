//! A tolerance study: `[sampling]` (method, samples, seed) and its
//! `[[tolerance]]` entries, checked against the base and the grid.

use toml::Spanned;

use super::axes::numeric_param;
use super::file::At;
use super::file::{SweepFile, TolDef, MAX_SEED};
use super::{Axis, Study, Tolerance};
use crate::error::Result;
use crate::input::sampling::Permutation;
use crate::params::{Param, Spec};

pub(super) fn parse_study(
    at: &At,
    file: &SweepFile,
    base: &Spec,
    axes: &[Axis],
) -> Result<Option<Study>> {
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
