//! `[[grid]]` axes: each a numeric parameter with a list or a range of
//! values, or a law selector or `friction_table` with a list of words,
//! checked with the line of the key concerned.

use toml::Spanned;

use super::file::{At, AxisDef};
use super::{Axis, AxisValues};
use crate::error::{did_you_mean, Result};
use crate::params::{Num, Param, Spec};

pub(super) fn parse_axes(at: &At, grid: &[Spanned<AxisDef>]) -> Result<Vec<Axis>> {
    let mut axes: Vec<Axis> = Vec::new();
    for ax in grid {
        let a = ax.get_ref();
        // Errors point at the key concerned, else at the [[grid]] entry.
        let bad = |(span, m): (Option<std::ops::Range<usize>>, String)| {
            at.bad(span.unwrap_or(a.param.span()), a.param.get_ref(), m)
        };
        let param = grid_param(a.param.get_ref()).map_err(|m| bad((None, m)))?;
        let values = match param {
            Param::Num(_) => axis_values(a).map_err(bad)?,
            p => word_values(p, a).map_err(bad)?,
        };
        if axes.iter().any(|x| x.param == param) {
            return Err(bad((None, "appears on two grid axes".into())));
        }
        axes.push(Axis { param, values });
    }
    Ok(axes)
}

/// A grid axis's parameter: any parameter (numbers or words).
fn grid_param(name: &str) -> std::result::Result<Param, String> {
    Param::from_name(name).ok_or_else(|| {
        format!(
            "unknown parameter{}; allowed: {}",
            did_you_mean(name, Param::COLUMNS.map(|p| p.name())),
            Param::all_names()
        )
    })
}

type Bad = (Option<std::ops::Range<usize>>, String);

/// The words of an axis over a law or a friction table, each checked as
/// a lane-table cell would be.
fn word_values(p: Param, a: &AxisDef) -> std::result::Result<AxisValues, Bad> {
    let Some(v) = &a.values else {
        return Err((
            None,
            format!(
                "give values = [\"...\", ...]: {} takes words, not a range",
                p.name()
            ),
        ));
    };
    let span = Some(v.span());
    if v.get_ref().is_empty() {
        return Err((span, "values is empty; give at least one value".into()));
    }
    let mut words = Vec::new();
    for x in v.get_ref() {
        let Some(w) = x.as_str() else {
            return Err((span, format!("{} takes words (\"...\"), got {x}", p.name())));
        };
        Spec::default()
            .set_text(p, w)
            .map_err(|m| (span.clone(), m))?;
        if words.iter().any(|o: &String| o == w) {
            return Err((span, format!("`{w}` is given twice")));
        }
        words.push(w.to_string());
    }
    Ok(AxisValues::Words(words))
}

pub(super) fn numeric_param(name: &str) -> std::result::Result<Num, String> {
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
    match (&a.values, &a.from, &a.to, &a.n) {
        (Some(v), None, None, None) => {
            if let Some(sc) = &a.scale {
                return Err((
                    Some(sc.span()),
                    "scale applies to from/to/n, not to values".into(),
                ));
            }
            let span = Some(v.span());
            if v.get_ref().is_empty() {
                return Err((span, "values is empty; give at least one value".into()));
            }
            let mut nums = Vec::with_capacity(v.get_ref().len());
            for x in v.get_ref() {
                let n = match x {
                    toml::Value::Float(f) => *f,
                    toml::Value::Integer(i) => *i as f64,
                    other => {
                        return Err((
                            span,
                            format!("{} takes numbers, got {other}", a.param.get_ref()),
                        ))
                    }
                };
                if !n.is_finite() {
                    return Err((span, format!("value {n} is not finite")));
                }
                nums.push(n);
            }
            Ok(AxisValues::List(nums))
        }
        (None, Some(from), Some(to), Some(n)) => range_values(a, from, to, n),
        _ => Err((
            None,
            "give either values = [...] or from, to and n (with optional scale)".into(),
        )),
    }
}

/// A range axis's values (`from`, `to`, `n`, `scale`); an error names the
/// span of the key concerned.
fn range_values(
    a: &AxisDef,
    from: &Spanned<f64>,
    to: &Spanned<f64>,
    n: &Spanned<i64>,
) -> std::result::Result<AxisValues, (Option<std::ops::Range<usize>>, String)> {
    let get = |x: &Option<Spanned<f64>>| x.as_ref().map(|v| *v.get_ref());
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
    if *n.get_ref() == 1 && from.get_ref() != to.get_ref() {
        // One value between two ends would silently be `from`.
        return Err((
            Some(n.span()),
            format!(
                "n = 1 gives one value, but from ({}) and to ({}) differ; allowed: n >= 2 \
                 for the range, from = to, or values = [...] for one value",
                from.get_ref(),
                to.get_ref()
            ),
        ));
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
