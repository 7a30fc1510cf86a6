//! A search's rows of `summary.csv`, per group, from every drive's final
//! bracket (`search_lo`, `search_hi`, `search_meets`, `search_status`):
//!
//! - kind `critical`: the critical value's quantiles (P1 ... P99, min and
//!   max), each the middle of its order statistic's bracket where that
//!   bracket is no wider than `tol` (else empty: a share search refines
//!   only the drives around its boundary); mean and std where every drive
//!   was found.
//! - kind `boundary` (with `at_least`): the boundary that share of the
//!   drives meets, as its order statistic's bracket (`min`, `max`) and
//!   middle (`p50`), with its distribution-free 95 % interval
//!   (`ci95_low`, `ci95_high`) and `share` = at_least; `quantiles` names
//!   the order statistics.
//! - kind `bound` (with `at_least`): the one-sided 95 % bound in `p50`:
//!   the boundary is at least it where the requirement is met below the
//!   critical value (at most it, above).
//!
//! A drive met at both ends (or at neither) has its critical value beyond
//! the bracket searched, on the side its group's drives say.

use super::{num, Cells, Group};
use crate::error::Result;
use crate::input::sweep::search::Search;
use crate::integrator::{SearchStatus, Side};
use crate::stats::order::{boundary_ranks, order_bracket, Ranks};
use crate::stats::quantile::PROBS;

/// One drive of a group: its bracket, side and status.
#[derive(Clone, Copy, Debug)]
pub(super) struct Drive {
    pub(super) lo: f64,
    pub(super) hi: f64,
    pub(super) side: Option<Side>,
    pub(super) status: Option<SearchStatus>,
}

/// A group's share boundary, for the summary line and the report.
#[derive(Clone, Debug, PartialEq)]
pub struct Boundary {
    /// The group (grid point).
    pub group: u64,
    /// The side the requirement is met on.
    pub side: Side,
    /// The boundary's bracket (its order statistic's).
    pub bracket: (f64, f64),
    /// The two-sided 95 % interval (NaN ends where the drives are too few).
    pub interval: (f64, f64),
    /// The one-sided 95 % bound (NaN where too few).
    pub bound: f64,
    /// Its ranks among the group's drives.
    pub ranks: Ranks,
    /// Drives of the group.
    pub drives: usize,
}

impl Boundary {
    /// The boundary: its bracket's middle.
    pub fn value(&self) -> f64 {
        0.5 * (self.bracket.0 + self.bracket.1)
    }
}

/// The side of a group: the one its drives that saw a change agree on
/// (the most of them), if any saw one.
fn common_side(drives: &[Drive]) -> Option<Side> {
    let below = drives
        .iter()
        .filter(|d| d.side == Some(Side::Below))
        .count();
    let above = drives
        .iter()
        .filter(|d| d.side == Some(Side::Above))
        .count();
    match (below, above) {
        (0, 0) => None,
        (b, a) if b >= a => Some(Side::Below),
        _ => Some(Side::Above),
    }
}

/// Each drive's bracket (lo, hi] of its critical value, beyond the
/// bracket searched for a drive met at both ends or at neither.
fn brackets(drives: &[Drive], side: Option<Side>, s: &Search) -> (Vec<f64>, Vec<f64>) {
    let (inf, from, to) = (f64::INFINITY, s.from, s.to);
    drives
        .iter()
        .map(|d| match (d.status, side) {
            (Some(SearchStatus::MetAtBothEnds), Some(Side::Below))
            | (Some(SearchStatus::MetAtNeitherEnd), Some(Side::Above)) => (to, inf),
            (Some(SearchStatus::MetAtBothEnds), Some(Side::Above))
            | (Some(SearchStatus::MetAtNeitherEnd), Some(Side::Below)) => (-inf, from),
            (Some(SearchStatus::MetAtBothEnds | SearchStatus::MetAtNeitherEnd), None) => {
                (f64::NAN, f64::NAN)
            }
            _ => (d.lo, d.hi),
        })
        .unzip()
}

/// The middle of an order statistic's bracket, where it is no wider than
/// `tol` (NaN otherwise, or where it lies beyond the bracket searched).
fn resolved((l, u): (f64, f64), tol: f64) -> f64 {
    if l.is_finite() && u.is_finite() && u - l <= tol * (1.0 + 1e-9) {
        0.5 * (l + u)
    } else {
        f64::NAN
    }
}

/// The `critical` row's numbers: mean, std, min, P1 ... P99, max (NaN
/// where not known to `tol`).
pub(super) fn critical(drives: &[Drive], s: &Search) -> [f64; 9] {
    let n = drives.len();
    let mut out = [f64::NAN; 9];
    if n == 0 {
        return out;
    }
    let side = common_side(drives);
    let (mut los, mut his) = brackets(drives, side, s);
    if los.iter().any(|x| x.is_nan()) {
        return out;
    }
    let at = |t: usize, los: &mut Vec<f64>, his: &mut Vec<f64>| {
        resolved(order_bracket(los, his, t.clamp(1, n)), s.tol)
    };
    out[2] = at(1, &mut los, &mut his);
    for (i, &p) in PROBS.iter().enumerate() {
        // The nearest-rank quantile: the ceil(p n)-th smallest.
        out[3 + i] = at((p * n as f64).ceil() as usize, &mut los, &mut his);
    }
    out[8] = at(n, &mut los, &mut his);
    if drives.iter().all(|d| d.status == Some(SearchStatus::Found)) {
        let c: Vec<f64> = drives.iter().map(|d| 0.5 * (d.lo + d.hi)).collect();
        let mean = c.iter().sum::<f64>() / n as f64;
        out[0] = mean;
        out[1] = if n > 1 {
            (c.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt()
        } else {
            f64::NAN
        };
    }
    out
}

/// The share boundary of a group's drives (None without `at_least`, or
/// where no drive saw the answer change).
pub(super) fn boundary(group: u64, drives: &[Drive], s: &Search) -> Option<Boundary> {
    let at_least = s.at_least?;
    let side = common_side(drives)?;
    let n = drives.len();
    let (mut los, mut his) = brackets(drives, Some(side), s);
    let ranks = boundary_ranks(n, at_least, side);
    let mut bracket_of = |t: usize| {
        if t == 0 {
            (f64::NAN, f64::NAN)
        } else {
            order_bracket(&mut los, &mut his, t)
        }
    };
    let bracket = bracket_of(ranks.k);
    let interval = (bracket_of(ranks.lo).0, bracket_of(ranks.hi).1);
    let b = bracket_of(ranks.bound);
    let bound = match side {
        Side::Below => b.0,
        Side::Above => b.1,
    };
    Some(Boundary {
        group,
        side,
        bracket,
        interval,
        bound,
        ranks,
        drives: n,
    })
}

impl super::Stats {
    /// A search's rows of the group (`search.rs`).
    pub(super) fn search_rows(&mut self, key: &str, g: &Group) -> Result<()> {
        let Some(sr) = self.grouping.search.clone() else {
            return Ok(());
        };
        let param = sr.param.name();
        let n = g.drives.len() as u64;
        let c = critical(&g.drives, &sr);
        let mut cells = Cells::default();
        for (cell, x) in cells.0[..9].iter_mut().zip(c) {
            *cell = num(x);
        }
        cells.0[9] = "bracketed".into();
        self.row(key, "critical", crate::columns::CRITICAL, param, n, cells)?;
        let Some(b) = boundary(g.id, &g.drives, &sr) else {
            return Ok(());
        };
        let mut cells = Cells::default();
        cells.0[2] = num(b.bracket.0);
        cells.0[5] = num(b.value());
        cells.0[8] = num(b.bracket.1);
        cells.0[9] = format!(
            "order statistic {} of {n}; 95 %: {} to {}",
            b.ranks.k, b.ranks.lo, b.ranks.hi
        );
        cells.0[10] = num(sr.at_least.unwrap_or(f64::NAN));
        cells.0[11] = num(b.interval.0);
        cells.0[12] = num(b.interval.1);
        self.row(key, "boundary", crate::columns::CRITICAL, param, n, cells)?;
        let mut cells = Cells::default();
        cells.0[5] = num(b.bound);
        cells.0[9] = format!(
            "one-sided 95 %: the boundary is {} this (order statistic {})",
            match b.side {
                crate::integrator::Side::Below => "at least",
                crate::integrator::Side::Above => "at most",
            },
            b.ranks.bound
        );
        cells.0[10] = num(sr.at_least.unwrap_or(f64::NAN));
        self.row(key, "bound", crate::columns::CRITICAL, param, n, cells)?;
        self.boundaries.push(b);
        Ok(())
    }
}
