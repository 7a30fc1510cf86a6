//! Each drive's own search: a first round at the bracket's
//! [`FIRST_ROUND_POINTS`] evenly spaced points (its ends among them),
//! then, where the answer changes once, bisection of the bracket between
//! the two points where it changes, every active drive one lane a round,
//! until the bracket is no wider than `tol`.

use super::{Answer, Row, SearchBackend, FIRST_ROUND_POINTS};
use crate::error::Result;
use crate::integrator::LaneResult;
use crate::integrator::{SearchOutcome, SearchStatus, Side};
use crate::model::FrictionTable;

/// A drive being bisected.
struct Bisecting {
    lo: f64,
    hi: f64,
    side: Side,
}

/// Searches drives `first + js[i]` each on its own (js: the chunk's
/// drives `first..`); their rows, in the order of `js`.
pub(super) fn search(
    s: &mut SearchBackend<'_>,
    first: u64,
    js: &[usize],
    tables: &[FrictionTable],
) -> Result<Vec<Row>> {
    let xs = s.points();
    let k = xs.len();
    let queries: Vec<(usize, f64)> = js
        .iter()
        .flat_map(|&j| xs.iter().map(move |&x| (j, x)))
        .collect();
    let answers = s.round(first, &queries, tables)?;
    let mut rows = Vec::with_capacity(js.len());
    // (index into rows, bisection)
    let mut active: Vec<(usize, Bisecting)> = Vec::new();
    for (i, a) in answers.chunks(k).enumerate() {
        let (row, bisect) = first_round(&xs, a, s.search.from, s.search.to);
        rows.push(row);
        if let Some(b) = bisect {
            active.push((i, b));
        }
    }
    s.reuse(answers);
    let tol = s.search.tol;
    keep_unfinished(&mut active, &mut rows, tol);
    while !active.is_empty() {
        let queries: Vec<(usize, f64)> = active
            .iter()
            .map(|(i, b)| (js[*i], 0.5 * (b.lo + b.hi)))
            .collect();
        let answers = s.round(first, &queries, tables)?;
        for ((j, b), (a, &(_, x))) in active.iter_mut().zip(answers.iter().zip(&queries)) {
            let row = &mut rows[*j];
            row.outcome.lanes += 1;
            // Met below the critical value: a met query raises the lower
            // end; met above: lowers the upper end.
            match (b.side, a.meets) {
                (Side::Below, true) | (Side::Above, false) => b.lo = x,
                (Side::Below, false) | (Side::Above, true) => b.hi = x,
            }
            if a.meets {
                row.lane = Some((x, a.result));
            }
            row.outcome.lo = b.lo;
            row.outcome.hi = b.hi;
        }
        s.reuse(answers);
        keep_unfinished(&mut active, &mut rows, tol);
    }
    Ok(rows)
}

/// A drive's first round (answers `a` at the points `xs`): its row, and
/// its bisection where the answer changes exactly once.
fn first_round(xs: &[f64], a: &[Answer], from: f64, to: f64) -> (Row, Option<Bisecting>) {
    let changes: Vec<usize> = (0..a.len() - 1)
        .filter(|&p| a[p].meets != a[p + 1].meets)
        .collect();
    let lane = |p: usize| -> Option<(f64, LaneResult)> { Some((xs[p], a[p].result)) };
    let outcome = |status, lo, hi, side| SearchOutcome {
        lo,
        hi,
        side,
        status,
        lanes: FIRST_ROUND_POINTS as u32,
    };
    match changes.as_slice() {
        [] if a[0].meets => (
            Row {
                outcome: outcome(SearchStatus::MetAtBothEnds, from, to, None),
                lane: lane(a.len() - 1),
            },
            None,
        ),
        [] => (
            Row {
                outcome: outcome(SearchStatus::MetAtNeitherEnd, from, to, None),
                lane: lane(0),
            },
            None,
        ),
        &[p] => {
            let side = if a[p].meets { Side::Below } else { Side::Above };
            let meeting = if a[p].meets { p } else { p + 1 };
            (
                Row {
                    // Not yet found: the bisection says so when it is.
                    outcome: outcome(SearchStatus::StoppedClear, xs[p], xs[p + 1], Some(side)),
                    lane: lane(meeting),
                },
                Some(Bisecting {
                    lo: xs[p],
                    hi: xs[p + 1],
                    side,
                }),
            )
        }
        _ => {
            let meeting = (0..a.len()).find(|&p| a[p].meets).unwrap_or(0);
            (
                Row {
                    outcome: outcome(SearchStatus::SeveralChanges, from, to, None),
                    lane: lane(meeting),
                },
                None,
            )
        }
    }
}

/// Marks the drives whose bracket is no wider than `tol` found, and keeps
/// the others bisecting.
fn keep_unfinished(active: &mut Vec<(usize, Bisecting)>, rows: &mut [Row], tol: f64) {
    active.retain(|(j, b)| {
        let done = b.hi - b.lo <= tol;
        if done {
            rows[*j].outcome.status = SearchStatus::Found;
        }
        !done
    });
}
