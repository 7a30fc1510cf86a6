//! A group's share boundary (`at_least`): the critical value that the
//! given share of its drives clears, and the order statistics of its
//! distribution-free 95 % interval ([`crate::stats::order`]), each found
//! to `tol`, refining only the drives that decide them.
//!
//! The group's nominal design is searched first at the first round's
//! points: which side meets the requirement, and where its answer
//! changes (every drive's first query is there) (the search assumes every
//! drive's answer changes once, on the nominal design's side; a nominal
//! design whose answer does not change once has its drives searched each
//! on its own). Every drive then starts with the whole bracket. A round
//! computes each target order statistic's bracket (L, U] from the drives'
//! brackets, and queries every drive whose bracket still overlaps an
//! unfinished target's: at the target's middle where that lies inside the
//! drive's bracket (the drives around a target are then split at one
//! point, halving the target's bracket a round), else at the drive's own
//! middle. Drives clear of every target stop early (`stopped_clear`). A
//! drive found against an end of the bracket that no query has confirmed
//! has that end integrated: a critical value beyond the bracket is then
//! known as such (met at both ends, or at neither). With `quantiles`,
//! the order statistics of the critical value's quantiles are targets
//! too.

use super::targets::{group_queries, Drive, Targets};
use super::{own, Answer, Row, SearchBackend};
use crate::error::{Error, Result};
use crate::integrator::{SearchOutcome, SearchStatus, Side};
use crate::model::FrictionTable;
use crate::params::ParamColumns;
use crate::stats::order::boundary_ranks;
use crate::stats::quantile::PROBS;

/// Most rounds of a share boundary (each halves a target's bracket; 200
/// is far beyond any bracket and tol a float can hold).
const MAX_ROUNDS: usize = 200;

/// Searches the chunk's groups of drives `first..first + n`; their rows.
pub(super) fn search(
    s: &mut SearchBackend<'_>,
    first: u64,
    n: usize,
    tables: &[FrictionTable],
) -> Result<Vec<Row>> {
    let per = s.per_group as usize;
    if per == 0 || !n.is_multiple_of(per) || !first.is_multiple_of(per as u64) {
        return Err(Error::Internal(format!(
            "a share search's chunk of {n} drives from {first} is not whole groups of {per}"
        )));
    }
    let groups = n / per;
    let point0 = first / per as u64;
    let xs = s.points();
    let (sides, cells) = nominal_sides(s, point0, groups, tables)?;
    let mut rows: Vec<Option<Row>> = (0..n).map(|_| None).collect();
    // Groups whose nominal design does not change once: each drive alone.
    let alone: Vec<usize> = (0..n).filter(|&j| sides[j / per].is_none()).collect();
    if !alone.is_empty() {
        for (j, row) in alone.iter().zip(own::search(s, first, &alone, tables)?) {
            rows[*j] = Some(row);
        }
    }
    let whole = Drive {
        lo: s.search.from,
        hi: s.search.to,
        lo_open: true,
        hi_open: true,
    };
    let mut state = vec![whole; n];
    let mut found: Vec<Row> = (0..n).map(|_| unfinished(&s.search)).collect();
    // The nominal designs' lanes, counted on each group's first drive.
    for (g, side) in sides.iter().enumerate() {
        found[g * per].outcome.lanes += xs.len() as u32;
        for row in &mut found[g * per..(g + 1) * per] {
            row.outcome.side = *side;
        }
    }
    let active_groups: Vec<usize> = (0..groups).filter(|&g| sides[g].is_some()).collect();
    let mut st = State {
        drives: &mut state,
        rows: &mut found,
        sides: &sides,
        per,
    };
    seed_round(s, first, &mut st, &active_groups, &cells, tables)?;
    refine(s, first, &mut st, &active_groups, tables)?;
    for (j, row) in rows.iter_mut().enumerate() {
        if row.is_none() {
            *row = Some(finish(&mut found[j], state[j], &s.search));
        }
    }
    Ok(rows
        .into_iter()
        .map(|r| r.expect("every drive has a row"))
        .collect())
}

/// The rounds after the seed: each queries the drives that overlap an
/// unfinished target of their group, until no target is unfinished.
fn refine(
    s: &mut SearchBackend<'_>,
    first: u64,
    st: &mut State<'_>,
    active_groups: &[usize],
    tables: &[FrictionTable],
) -> Result<()> {
    let per = st.per;
    // Every group has `per` drives: its ranks depend only on its side.
    let at_least = s.search.at_least.unwrap_or(0.5);
    let ranks = |side| boundary_ranks(per, at_least, side);
    let (below, above) = (ranks(Side::Below), ranks(Side::Above));
    // With `quantiles`: the nearest-rank quantiles' order statistics too.
    let quantiles: Vec<usize> = match s.search.quantiles {
        true => PROBS
            .iter()
            .map(|p| ((p * per as f64).ceil() as usize).clamp(1, per))
            .collect(),
        false => Vec::new(),
    };
    let mut los = Vec::with_capacity(per);
    let mut his = Vec::with_capacity(per);
    for _ in 0..MAX_ROUNDS {
        let mut queries: Vec<(usize, f64)> = Vec::new();
        for &g in active_groups {
            let d = &st.drives[g * per..(g + 1) * per];
            let ranks = match st.sides[g].expect("active") {
                Side::Below => below,
                Side::Above => above,
            };
            let targets = Targets::new(d, ranks, &quantiles, s.search.tol, (&mut los, &mut his));
            group_queries(s, d, &targets, g * per, &mut queries);
        }
        if queries.is_empty() {
            break;
        }
        st.absorb_round(s, first, &queries, tables)?;
    }
    Ok(())
}

/// A drive's row before its first query: the whole bracket.
fn unfinished(search: &crate::input::sweep::search::Search) -> Row {
    Row {
        outcome: SearchOutcome {
            lo: search.from,
            hi: search.to,
            side: None,
            status: SearchStatus::StoppedClear,
            lanes: 0,
        },
        lane: None,
    }
}

/// The drives of a chunk as a round changes them.
struct State<'d> {
    drives: &'d mut [Drive],
    rows: &'d mut [Row],
    sides: &'d [Option<Side>],
    per: usize,
}

impl State<'_> {
    /// Integrates the round `queries` and narrows each queried drive.
    fn absorb_round(
        &mut self,
        s: &mut SearchBackend<'_>,
        first: u64,
        queries: &[(usize, f64)],
        tables: &[FrictionTable],
    ) -> Result<()> {
        let answers = s.round(first, queries, tables)?;
        let ends = (s.search.from, s.search.to);
        for (&(j, x), a) in queries.iter().zip(&answers) {
            let side = self.sides[j / self.per].expect("active");
            absorb(&mut self.drives[j], &mut self.rows[j], side, x, a, ends);
        }
        s.reuse(answers);
        Ok(())
    }
}

/// The first query: every drive at its nominal design's critical value
/// (the middle of the first-round cell where the nominal answer
/// changes), which splits the drives at once where they are dense, not
/// at the bracket's middle.
fn seed_round(
    s: &mut SearchBackend<'_>,
    first: u64,
    st: &mut State<'_>,
    active: &[usize],
    cells: &[(f64, f64)],
    tables: &[FrictionTable],
) -> Result<()> {
    let per = st.per;
    let seed: Vec<(usize, f64)> = active
        .iter()
        .flat_map(|&g| {
            let x = 0.5 * (cells[g].0 + cells[g].1);
            (g * per..(g + 1) * per).map(move |j| (j, x))
        })
        .collect();
    if seed.is_empty() {
        return Ok(());
    }
    st.absorb_round(s, first, &seed, tables)
}

/// Each group's side that meets the requirement, and the first-round cell
/// where its nominal design's answer changes.
type Nominal = (Vec<Option<Side>>, Vec<(f64, f64)>);

/// Which side of each group's nominal design meets the requirement,
/// from one round at the first round's points (None: its answer does not
/// change exactly once there).
fn nominal_sides(
    s: &mut SearchBackend<'_>,
    point0: u64,
    groups: usize,
    tables: &[FrictionTable],
) -> Result<Nominal> {
    let first = point0 * s.per_group;
    // The nominal designs, one round for every group.
    let xs = s.points();
    let mut lanes = ParamColumns::with_capacity(groups * xs.len());
    for g in 0..groups {
        for &x in &xs {
            s.push_nominal(point0 + g as u64, x, &mut lanes)?;
        }
    }
    let nominal = s.answer(first, &lanes, tables)?;
    let mut sides = vec![None; groups];
    let mut cells = vec![(f64::NAN, f64::NAN); groups];
    for (g, a) in nominal.chunks(xs.len()).enumerate() {
        let changes: Vec<usize> = (0..a.len() - 1)
            .filter(|&p| a[p].meets != a[p + 1].meets)
            .collect();
        if let [p] = changes.as_slice() {
            cells[g] = (xs[*p], xs[*p + 1]);
            sides[g] = Some(if a[*p].meets {
                Side::Below
            } else {
                Side::Above
            });
        }
    }
    s.reuse(nominal);
    Ok((sides, cells))
}

/// A drive's row from its final bracket `d`.
fn finish(found: &mut Row, d: Drive, search: &crate::input::sweep::search::Search) -> Row {
    let outcome = found.outcome;
    let mut r = std::mem::replace(
        found,
        Row {
            outcome,
            lane: None,
        },
    );
    r.outcome.lo = d.lo;
    r.outcome.hi = d.hi;
    r.outcome.status = if d.lo == f64::NEG_INFINITY || d.hi == f64::INFINITY {
        // Beyond the bracket: met throughout it, or nowhere in it.
        let beyond_to = d.hi == f64::INFINITY;
        match (r.outcome.side, beyond_to) {
            (Some(Side::Below), true) | (Some(Side::Above), false) => SearchStatus::MetAtBothEnds,
            _ => SearchStatus::MetAtNeitherEnd,
        }
    } else if d.width() <= search.tol {
        SearchStatus::Found
    } else {
        SearchStatus::StoppedClear
    };
    if matches!(
        r.outcome.status,
        SearchStatus::MetAtBothEnds | SearchStatus::MetAtNeitherEnd
    ) {
        r.outcome.lo = r.outcome.lo.max(search.from);
        r.outcome.hi = r.outcome.hi.min(search.to);
    }
    r
}

/// A query's answer `a` at `x` into drive `d` and its row.
fn absorb(d: &mut Drive, row: &mut Row, side: Side, x: f64, a: &Answer, (from, to): (f64, f64)) {
    row.outcome.lanes += 1;
    // Met below the critical value: a met query puts c above x.
    let c_above = match side {
        Side::Below => a.meets,
        Side::Above => !a.meets,
    };
    if x == to && d.hi_open && d.hi == to {
        d.hi_open = false;
        if c_above {
            // c is beyond the bracket's upper end.
            d.lo = to;
            d.hi = f64::INFINITY;
        }
    } else if x == from && d.lo_open && d.lo == from {
        d.lo_open = false;
        if !c_above {
            d.lo = f64::NEG_INFINITY;
            d.hi = from;
        }
    } else if c_above {
        d.lo = x;
        d.lo_open = false;
    } else {
        d.hi = x;
        d.hi_open = false;
    }
    // The row reports a meeting lane when it has one, else its last.
    if a.meets || row.lane.is_none() {
        row.lane = Some((x, a.result));
    }
}
