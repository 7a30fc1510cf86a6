//! A share search's targets: the order statistics whose brackets still
//! decide a group's answer, and the queries of the drives around them.

use super::SearchBackend;
use crate::stats::order::{order_bracket, Ranks};

/// A drive of a share search.
#[derive(Clone, Copy)]
pub(super) struct Drive {
    pub(super) lo: f64,
    pub(super) hi: f64,
    /// Whether `lo` (`hi`) is the bracket's end, not yet integrated.
    pub(super) lo_open: bool,
    pub(super) hi_open: bool,
}

impl Drive {
    pub(super) fn width(&self) -> f64 {
        self.hi - self.lo
    }
}

/// The brackets of a group's order statistics that still decide its
/// answer, those wider than `tol`: the boundary's and its interval's, and
/// with `quantiles` the critical value's quantiles' (those cost more
/// lanes: docs/model.md, section 13).
pub(super) struct Targets {
    open: Vec<(f64, f64)>,
}

impl Targets {
    /// The unfinished targets of the group's drives `d` (`los`, `his`:
    /// two buffers reused across rounds).
    pub(super) fn new(
        d: &[Drive],
        ranks: Ranks,
        quantiles: &[usize],
        tol: f64,
        (los, his): (&mut Vec<f64>, &mut Vec<f64>),
    ) -> Targets {
        let mut ts = vec![ranks.k, ranks.lo, ranks.hi, ranks.bound];
        ts.extend_from_slice(quantiles);
        ts.sort_unstable();
        los.clear();
        his.clear();
        los.extend(d.iter().map(|x| x.lo));
        his.extend(d.iter().map(|x| x.hi));
        let mut t = Targets { open: Vec::new() };
        for (i, &r) in ts.iter().enumerate() {
            if r == 0 || (i > 0 && ts[i - 1] == r) {
                continue;
            }
            let (l, u) = order_bracket(los, his, r);
            if u - l > tol {
                t.open.push((l, u));
            }
        }
        t
    }

    fn open(&self) -> &[(f64, f64)] {
        &self.open
    }
}

/// The queries of one group's drives `d` (the chunk's drives `base..`)
/// this round, appended to `q`: those overlapping an unfinished target,
/// and the found ones against an end not yet integrated.
pub(super) fn group_queries(
    s: &SearchBackend<'_>,
    d: &[Drive],
    targets: &Targets,
    base: usize,
    q: &mut Vec<(usize, f64)>,
) {
    let (tol, from, to) = (s.search.tol, s.search.from, s.search.to);
    let open = targets.open();
    for (i, x) in d.iter().enumerate() {
        let w = x.width();
        if !w.is_finite() {
            continue;
        }
        if w > tol {
            let mut overlapping = open.iter().filter(|(l, u)| x.lo < *u && x.hi > *l);
            let Some(&(l0, u0)) = overlapping.next() else {
                continue;
            };
            // The target's middle where it is well inside the drive's
            // bracket: the target's drives are split at one point.
            let inside = std::iter::once((l0, u0))
                .chain(overlapping.copied())
                .map(|(l, u)| 0.5 * (l + u))
                .find(|&m| m > x.lo + 0.05 * w && m < x.hi - 0.05 * w);
            q.push((base + i, inside.unwrap_or(0.5 * (x.lo + x.hi))));
        } else if x.hi_open && x.hi == to {
            q.push((base + i, to));
        } else if x.lo_open && x.lo == from {
            q.push((base + i, from));
        }
    }
}
