//! The report's search section (`[search]`): the answers in words and the
//! critical value drawn against the first grid axis.
//!
//! - With a tolerance study: per grid point (group of `summary.csv`), the
//!   critical value's quantiles as a band (P5 to P95 around P50) and, with
//!   `at_least`, the share boundary with its 95 % interval, stated as "the
//!   largest (smallest) value at which the requirement is met in at least
//!   this share of drives is at least (at most) X with 95 % confidence".
//! - Without: each drive's critical value from `lanes.csv`, a point per
//!   drive (the first [`MAX_POINTS`] drives), and a sentence per drive for
//!   a run of up to [`MAX_SENTENCES`] drives.

use std::collections::BTreeMap;
use std::path::Path;

mod read;

use read::{read_lanes, read_summary, Lane, Point};

use super::charts::{line_chart, x_axis, Curve};
use super::html::Page;
use crate::columns::SEARCH_STATUS;
use crate::error::Result;
use crate::input::sweep::search::Search;
use crate::input::sweep::Sweep;
use crate::integrator::Side;
use crate::output::names::SUMMARY;

/// Drives drawn at most (the first ones; the table holds them all).
pub(crate) const MAX_POINTS: usize = 20_000;

/// Drives (or grid points) stated one by one at most.
pub(crate) const MAX_SENTENCES: usize = 12;

/// A number in a sentence: six significant digits, in plain notation.
fn val(x: f64) -> String {
    if !x.is_finite() {
        return "-".into();
    }
    if x == 0.0 {
        return "0".into();
    }
    let digits = (5 - x.abs().log10().floor() as i64).clamp(0, 15) as usize;
    let t = format!("{x:.digits$}");
    if t.contains('.') {
        t.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        t
    }
}

/// The searched parameter with its unit, as a sentence names it.
fn named(s: &Search, x: f64) -> String {
    let unit = s.param.def().unit;
    if unit.is_empty() || unit == "-" {
        val(x)
    } else {
        format!("{} {unit}", val(x))
    }
}

/// Writes the section.
pub fn section(page: &mut Page, dir: &Path, sweep: &Sweep, s: &Search) -> Result<()> {
    page.section(&format!("Critical values of {}", s.param.name()));
    page.note(&format!(
        "Each drive's {} where `{}` changes its answer, searched between {} and {} and found to \
         a bracket of {} (status found; met_at_both_ends or met_at_neither_end: the answer does \
         not change inside; stopped_clear: a share search stopped refining the drive once its \
         bracket lay clear of the answers). Each row of the results table is a drive, with the \
         results of its lane at the end of its bracket that meets the requirement: the tables \
         and charts after this section describe those lanes, not the drives at one design.",
        s.param.name(),
        s.require.text(),
        named(s, s.from),
        named(s, s.to),
        val(s.tol),
    ));
    let axis = sweep.axes.first().filter(|a| !a.is_words());
    let x_label = axis.map(|a| super::words::param_label(a.param));
    if sweep.study.is_some() {
        let points = read_summary(&dir.join(SUMMARY), sweep)?;
        study_answers(page, s, &points);
        let fig = x_label.map(|l| study_chart(s, &points, &l));
        page.figures(fig.into_iter().collect());
    } else {
        let lanes = read_lanes(dir, sweep)?;
        drive_answers(page, s, &lanes);
        if let Some(l) = x_label {
            page.figures(vec![drive_chart(s, &lanes, &l)]);
        }
    }
    Ok(())
}

/// The searched parameter as a sentence names it: "lead angle, gamma_deg".
fn quantity(s: &Search) -> String {
    format!("{} ({})", s.param.def().meaning, s.param.name())
}

/// The words of the side a requirement is met on.
fn meets(side: Side) -> (&'static str, &'static str, &'static str) {
    match side {
        Side::Below => ("largest", "at least", "below"),
        Side::Above => ("smallest", "at most", "above"),
    }
}

/// A sentence per grid point (the first [`MAX_SENTENCES`]).
fn study_answers(page: &mut Page, s: &Search, points: &[Point]) {
    for p in points.iter().take(MAX_SENTENCES) {
        let at = if p.at.is_empty() {
            String::new()
        } else {
            format!("At {}: ", p.at)
        };
        match (p.boundary, p.side, s.at_least) {
            (Some((value, lo, hi, bound)), Some(side), Some(share)) => {
                let (most, bound_word, _) = meets(side);
                let confident = if bound.is_finite() {
                    format!("is {bound_word} {} with 95 % confidence", named(s, bound))
                } else {
                    "has no one-sided 95 % bound: too few drives".into()
                };
                page.answer(&format!(
                    "{at}the {most} {} at which `{}` for at least {} of drives {confident} \
                     (estimate {}, 95 % interval {} to {}; {} drives).",
                    quantity(s),
                    s.require.text(),
                    super::words::percent(share),
                    named(s, value),
                    named(s, lo),
                    named(s, hi),
                    p.n
                ));
            }
            _ => page.answer(&format!(
                "{at}{} of {} drives: median {}, 5 % to 95 % {} to {}.",
                s.param.name(),
                p.n,
                named(s, p.q[2]),
                named(s, p.q[1]),
                named(s, p.q[3]),
            )),
        }
    }
    if points.len() > MAX_SENTENCES {
        page.note(&format!(
            "{} more grid points: {SUMMARY} (kinds critical, boundary, bound).",
            points.len() - MAX_SENTENCES
        ));
    }
}

/// The critical value's band and the boundary against the first axis.
fn study_chart(s: &Search, points: &[Point], x: &str) -> std::result::Result<String, String> {
    let name = s.param.name();
    let at = |f: &dyn Fn(&Point) -> f64| -> Vec<(f64, f64)> {
        points.iter().map(|p| (p.x, f(p))).collect()
    };
    let mut curves = Vec::new();
    // A share search resolves only its boundary, not the median.
    if points.iter().any(|p| p.q[2].is_finite()) {
        curves.push(Curve {
            name: "median (P50), band P5 to P95",
            points: at(&|p| p.q[2]),
            band: points.iter().map(|p| (p.x, p.q[1], p.q[3])).collect(),
            colour: None,
        });
    }
    if s.at_least.is_some() {
        curves.push(Curve {
            name: "share boundary, band its 95 % interval",
            points: at(&|p| p.boundary.map_or(f64::NAN, |b| b.0)),
            band: points
                .iter()
                .map(|p| {
                    p.boundary
                        .map_or((p.x, f64::NAN, f64::NAN), |b| (p.x, b.1, b.2))
                })
                .collect(),
            colour: None,
        });
    }
    let xa = x_axis(x, &curves, &[], false);
    line_chart(
        &format!("critical {name} against {x}"),
        &xa,
        false,
        &format!("critical {name}"),
        &curves,
        &[],
    )
}

/// Sentences per drive (up to [`MAX_SENTENCES`] drives), else counts.
fn drive_answers(page: &mut Page, s: &Search, lanes: &(Vec<Lane>, u64)) {
    let (kept, total) = lanes;
    if *total as usize <= MAX_SENTENCES {
        for l in kept {
            let at = if l.at.is_empty() {
                format!("Lane {}", l.lane)
            } else {
                format!("Lane {} ({})", l.lane, l.at)
            };
            let req = s.require.text();
            let text = match (l.status.as_str(), l.side.as_str()) {
                ("found", side) => format!(
                    "{at}: `{req}` for {} {side} {} (between {} and {}).",
                    s.param.name(),
                    named(s, l.critical),
                    named(s, l.lo),
                    named(s, l.hi)
                ),
                ("met_at_both_ends", _) => format!(
                    "{at}: `{req}` throughout {} to {}: its critical value lies beyond.",
                    named(s, s.from),
                    named(s, s.to)
                ),
                ("met_at_neither_end", _) => format!(
                    "{at}: `{req}` nowhere in {} to {}: its critical value lies beyond.",
                    named(s, s.from),
                    named(s, s.to)
                ),
                (other, _) => format!("{at}: {other} (see {})", SEARCH_STATUS),
            };
            page.answer(&text);
        }
        return;
    }
    let mut counts: BTreeMap<&str, u64> = BTreeMap::new();
    for l in kept {
        *counts.entry(l.status.as_str()).or_default() += 1;
    }
    let found: Vec<f64> = kept
        .iter()
        .map(|l| l.critical)
        .filter(|c| c.is_finite())
        .collect();
    let (lo, hi) = found
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &c| {
            (a.min(c), b.max(c))
        });
    let said: Vec<String> = counts.iter().map(|(w, k)| format!("{w} {k}")).collect();
    page.answer(&format!(
        "{total} drives searched ({} shown here: {}); critical {} from {} to {}.",
        kept.len(),
        said.join(", "),
        s.param.name(),
        named(s, lo),
        named(s, hi)
    ));
}

/// Each drive's critical value against the first axis, a curve per
/// combination of the other axes (the first six).
fn drive_chart(
    s: &Search,
    lanes: &(Vec<Lane>, u64),
    x: &str,
) -> std::result::Result<String, String> {
    let mut by: BTreeMap<String, Vec<(f64, f64)>> = BTreeMap::new();
    for l in &lanes.0 {
        let key = l.rest.clone();
        if by.len() < 6 || by.contains_key(&key) {
            by.entry(key).or_default().push((l.x, l.critical));
        }
    }
    let names: Vec<String> = by
        .keys()
        .map(|k| {
            if k.is_empty() {
                format!("critical {}", s.param.name())
            } else {
                k.clone()
            }
        })
        .collect();
    let curves: Vec<Curve> = by
        .values()
        .zip(&names)
        .map(|(pts, n)| Curve {
            name: n,
            points: pts.clone(),
            band: Vec::new(),
            colour: None,
        })
        .collect();
    let xa = x_axis(x, &curves, &[], false);
    line_chart(
        &format!("critical {} against {x}", s.param.name()),
        &xa,
        false,
        &format!("critical {}", s.param.name()),
        &curves,
        &[],
    )
}
