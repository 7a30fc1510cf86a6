//! `[search]`: each drive's critical value of one numeric parameter, the
//! value where a requirement's answer changes, found by bisection in
//! rounds; with a tolerance study and `at_least`, also the boundary that
//! share of the drives meets, with a distribution-free 95 % interval.
//!
//! ```toml
//! # fragment
//! [search]
//! param = "gamma_deg"      # the parameter whose critical value is found
//! from = 1.0               # the bracket searched, in its unit
//! to = 20.0
//! require = "hold = held"  # as [report] require
//! tol = 1e-4               # the final bracket's width, in its unit
//! at_least = 0.99          # with [sampling]: the boundary of this share
//! quantiles = true         # with at_least: the P1 ... P99 too (more lanes)
//! ```
//!
//! The search sets the parameter's nominal value (the value a grid would
//! set); a tolerance on the same parameter still moves each drive around
//! it, with the drive's own draws in every round.

use super::file::{At, SearchDef, SweepFile};
use super::require::Requirement;
use super::{Axis, Study};
use crate::error::{did_you_mean, Result};
use crate::input::MAX_RUN_LANES;
use crate::params::{FrictionKind, MotorKind, Num, Param, Spec};

/// Points of the first round of a drive's own search (its bracket's ends
/// and the points between, evenly spaced): more than one change of the
/// answer among them is reported, not searched.
pub const FIRST_ROUND_POINTS: u64 = 9;

/// A search's definition.
#[derive(Clone, Debug, PartialEq)]
pub struct Search {
    /// The searched parameter.
    pub param: Num,
    /// The bracket searched, `from` < `to`.
    pub from: f64,
    /// See [`Search::from`].
    pub to: f64,
    /// The requirement whose answer changes at the critical value.
    pub require: Requirement,
    /// The final bracket's width.
    pub tol: f64,
    /// With a tolerance study: the share of drives whose boundary is found.
    pub at_least: Option<f64>,
    /// With `at_least`: also refine the critical value's quantiles
    /// ([`crate::stats::quantile::PROBS`]) to `tol` (each drive's own
    /// search finds them anyway).
    pub quantiles: bool,
}

impl Search {
    /// The rounds of one drive's own bisection after the first: until
    /// the bracket between two first-round points is no wider than `tol`.
    pub fn bisections(&self) -> u64 {
        let first = (self.to - self.from) / (FIRST_ROUND_POINTS - 1) as f64;
        (first / self.tol).log2().ceil().max(0.0) as u64
    }

    /// The most lanes `drives` drives may integrate: every drive's first
    /// round and bisection (a share boundary refines fewer).
    pub(crate) fn most_lanes(&self, drives: u64) -> u128 {
        drives as u128 * (FIRST_ROUND_POINTS + self.bisections()) as u128
    }
}

impl super::Sweep {
    /// The sweep of a search's first round for every drive, as one-round
    /// lanes: the searched parameter a last grid axis of the first
    /// round's points (`tswm check` compares these; later rounds depend
    /// on results). None without a search.
    pub(crate) fn first_round(&self) -> Option<super::Sweep> {
        let s = self.search.as_ref()?;
        let mut sweep = self.clone();
        sweep.axes.push(Axis {
            param: Param::Num(s.param),
            values: super::AxisValues::Range {
                from: s.from,
                to: s.to,
                n: FIRST_ROUND_POINTS,
                log: false,
            },
        });
        sweep.search = None;
        sweep.trace = None;
        Some(sweep)
    }
}

/// Reads `[search]`, checked against the sweep's base, axes and study.
pub(super) fn parse_search(
    at: &At,
    file: &SweepFile,
    base: &Spec,
    axes: &[Axis],
    study: Option<&Study>,
    drives: Option<u64>,
) -> Result<Option<Search>> {
    let Some(s) = &file.search else {
        return Ok(None);
    };
    let d = s.get_ref();
    if let Some(sn) = &file.sensitivity {
        return Err(at.bad(
            sn.span(),
            "sensitivity",
            "a sweep has [search] or [sensitivity], not both: a search finds critical values of \
             drives, a sensitivity design ranks tolerances"
                .into(),
        ));
    }
    let param = searched_param(at, d, axes)?;
    check_law(at, d.param.span(), param, base, axes)?;
    let (from, to, tol) = bracket(at, d, param)?;
    let at_least = share(at, d, study)?;
    let quantiles = match (&d.quantiles, at_least) {
        (Some(q), None) if *q.get_ref() => {
            return Err(at.bad(
                q.span(),
                "search.quantiles",
                "needs at_least: without it every drive is searched to tol, and the \
                 quantiles are known anyway"
                    .into(),
            ))
        }
        (q, _) => q.as_ref().is_some_and(|q| *q.get_ref()),
    };
    let require = Requirement::parse(d.require.get_ref(), at_least.unwrap_or(1.0))
        .map_err(|m| at.bad(d.require.span(), "search.require", m))?;
    let search = Search {
        param,
        from,
        to,
        require,
        tol,
        at_least,
        quantiles,
    };
    if let Some(drives) = drives {
        search
            .check_size(drives)
            .map_err(|m| at.bad(s.span(), "search", m))?;
    }
    Ok(Some(search))
}

/// The searched parameter: a number parameter that no grid axis sets.
fn searched_param(at: &At, d: &SearchDef, axes: &[Axis]) -> Result<Num> {
    let name = d.param.get_ref().as_str();
    let bad = |span: std::ops::Range<usize>, key: &str, m: String| at.bad(span, key, m);
    let param = match Param::from_name(name) {
        Some(Param::Num(n)) => n,
        Some(p) => {
            return Err(bad(
                d.param.span(),
                "search.param",
                format!(
                    "`{}` is a word parameter; a search needs a number parameter (its critical \
                     value is a number)",
                    p.name()
                ),
            ))
        }
        None => {
            return Err(bad(
                d.param.span(),
                "search.param",
                format!(
                    "`{}` is not a parameter{}; allowed: a number parameter of the guide's table",
                    crate::error::shown(name, 40),
                    did_you_mean(name, Num::ALL.map(Num::name))
                ),
            ))
        }
    };
    if axes.iter().any(|a| a.param == Param::Num(param)) {
        return Err(bad(
            d.param.span(),
            "search.param",
            format!(
                "{} is also a grid axis; the search sets it (give the other axes a grid, and \
                 the bracket in [search])",
                param.name()
            ),
        ));
    }
    Ok(param)
}

/// The bracket searched and the final bracket's width.
fn bracket(at: &At, d: &SearchDef, param: Num) -> Result<(f64, f64, f64)> {
    let bad = |span: std::ops::Range<usize>, key: &str, m: String| at.bad(span, key, m);
    let (from, to) = (*d.from.get_ref(), *d.to.get_ref());
    let def = param.def();
    for (v, sp, key) in [
        (from, d.from.span(), "search.from"),
        (to, d.to.span(), "search.to"),
    ] {
        if !v.is_finite() || !def.in_range(v) {
            return Err(bad(
                sp,
                key,
                format!(
                    "{v} is outside {}'s allowed range; allowed: {}",
                    param.name(),
                    def.range_text()
                ),
            ));
        }
    }
    if from >= to {
        return Err(bad(
            d.to.span(),
            "search.to",
            format!("must be above from ({from}), got {to}; allowed: from < to"),
        ));
    }
    let tol = *d.tol.get_ref();
    // Below a few ulps of the bracket's ends no bisection can narrow it.
    let finest = 16.0 * f64::EPSILON * from.abs().max(to.abs());
    if tol.is_finite() && tol > 0.0 && tol < finest {
        return Err(bad(
            d.tol.span(),
            "search.tol",
            format!(
                "{tol:e} is finer than a float can bracket near {}; allowed: at least {finest:.1e}",
                from.abs().max(to.abs())
            ),
        ));
    }
    if !(tol > 0.0 && tol < to - from) {
        return Err(bad(
            d.tol.span(),
            "search.tol",
            format!(
                "{tol} is not a bracket width; allowed: above 0 and below the bracket's width \
                 ({})",
                to - from
            ),
        ));
    }
    Ok((from, to, tol))
}

/// `at_least`: a share in (0, 1), with a tolerance study only.
fn share(at: &At, d: &SearchDef, study: Option<&Study>) -> Result<Option<f64>> {
    let bad = |span: std::ops::Range<usize>, key: &str, m: String| at.bad(span, key, m);
    Ok(match &d.at_least {
        None => None,
        Some(a) if study.is_none() => {
            return Err(bad(
                a.span(),
                "search.at_least",
                "needs a [sampling] study: it is the share of the sampled drives whose boundary \
                 is found"
                    .into(),
            ))
        }
        Some(a) if !(*a.get_ref() > 0.0 && *a.get_ref() < 1.0) => {
            return Err(bad(
                a.span(),
                "search.at_least",
                format!("{} is not a share; allowed: in (0, 1)", a.get_ref()),
            ))
        }
        Some(a) => Some(*a.get_ref()),
    })
}

impl Search {
    /// Refuses a search of `drives` drives whose rounds may integrate more
    /// lanes than one run takes, saying how many and what to do.
    pub(crate) fn check_size(&self, drives: u64) -> std::result::Result<(), String> {
        let most = self.most_lanes(drives);
        if most > MAX_RUN_LANES as u128 {
            return Err(format!(
                "{drives} drives may need {most} integrated lanes, more than one run takes (at \
                 most {MAX_RUN_LANES:.0e}); allowed: a larger tol (each doubling saves one lane a \
                 drive), fewer drives, or shards (tswm run --shard K/N)"
            ));
        }
        Ok(())
    }
}

/// The searched parameter must belong to every law a lane may have.
fn check_law(
    at: &At,
    span: std::ops::Range<usize>,
    param: Num,
    base: &Spec,
    axes: &[Axis],
) -> Result<()> {
    let mut laws = vec![(
        base.motor.unwrap_or(MotorKind::Kloss),
        base.friction.unwrap_or(FrictionKind::Paper),
    )];
    for a in axes {
        if let super::AxisValues::Words(w) = &a.values {
            let (m0, f0) = laws[0];
            for word in w {
                match a.param {
                    Param::Motor => laws.extend(
                        MotorKind::ALL
                            .into_iter()
                            .filter(|m| m.name() == word)
                            .map(|m| (m, f0)),
                    ),
                    Param::Friction => laws.extend(
                        FrictionKind::ALL
                            .into_iter()
                            .filter(|f| f.name() == word)
                            .map(|f| (m0, f)),
                    ),
                    _ => {}
                }
            }
        }
    }
    let owner = param.def().owner;
    if let Some((m, f)) = laws.into_iter().find(|&(m, f)| !owner.applies(m, f)) {
        return Err(at.bad(
            span,
            "search.param",
            format!(
                "{} is not used by motor = {}, friction = {}; it belongs to {}",
                param.name(),
                m.name(),
                f.name(),
                owner.law()
            ),
        ));
    }
    Ok(())
}
