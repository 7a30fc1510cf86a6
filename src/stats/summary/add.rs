//! Adding a batch's rows to the statistics: each group's rows of the
//! batch column by column, the number columns in parallel, the same
//! values in the same order as one row at a time.

use std::ops::Range;

use super::{Column, Group, Layout, Stats, EXACT_MAX};
use crate::columns::Of;
use crate::error::Result;
use crate::integrator::{Contact, Status};
use crate::output::batch::{word_runs, Col};
use crate::params::Num;
use crate::stats::grouping::grid_values;
use crate::stats::moments::{add_columns, Moments};
use crate::stats::quantile::Sketch;

impl Stats {
    /// Adds the rows of a batch of the results table (every column, in
    /// `table::columns` order: parameters, then results), lanes
    /// `first..`; lanes come in order. Each group's rows of the batch are
    /// added column by column, the columns in parallel on `pool`: the
    /// same values in the same order as one row at a time.
    pub(crate) fn add_batch(
        &mut self,
        first: u64,
        cols: &[Col<'_>],
        pool: &rayon::ThreadPool,
    ) -> Result<()> {
        let n = cols.first().map_or(0, Col::len);
        let mut r = 0;
        while r < n {
            let lane = first + r as u64;
            let id = self.grouping.group_of(lane);
            // This group's rows of the batch.
            let end = match self.grouping.per_group {
                0 => n,
                per => (((id + 1) * per - first) as usize).min(n),
            };
            self.add_rows(id, first, cols, r..end, pool)?;
            r = end;
        }
        Ok(())
    }

    /// Adds rows `rows` of `cols` (lanes `first + row`), all of group `id`.
    fn add_rows(
        &mut self,
        id: u64,
        first: u64,
        cols: &[Col<'_>],
        rows: Range<usize>,
        pool: &rayon::ThreadPool,
    ) -> Result<()> {
        if self.group.as_ref().is_some_and(|g| g.id != id) {
            let g = self.group.take().expect("checked");
            self.write_group(g)?;
        }
        let (axes, inputs, layout) = (&self.grouping.axes, &self.grouping.inputs, &self.layout);
        // A group past the kept values with no sampled input to rank its
        // results against keeps none: its quantiles come from a sketch
        // of every value, added from the first (the same values in the
        // same order as after keeping the first ones).
        let sketch_only = inputs.is_empty() && self.grouping.group_lanes() > EXACT_MAX as u64;
        // Room for the values kept at once: a copy of them as they grow
        // costs more than their adding.
        let room = if sketch_only {
            0
        } else {
            self.grouping.group_lanes().min(EXACT_MAX as u64) as usize
        };
        let g = self.group.get_or_insert_with(|| Group {
            id,
            axis_values: grid_values(axes, id),
            lanes: 0,
            cols: (0..layout.numbers.len())
                .map(|_| Column::default())
                .collect(),
            shares: layout.words.iter().map(|w| w.1.clone()).collect(),
            kept: (0..layout.numbers.len() + inputs.len())
                .map(|_| Vec::with_capacity(room))
                .collect(),
            drives: Vec::new(),
        });
        g.lanes += rows.len() as u64;
        if let Some([lo, hi, meets, status]) = layout.search {
            use crate::integrator::{SearchStatus, Side};
            for r in rows.clone() {
                g.drives.push(super::search::Drive {
                    lo: cols[lo].number(r),
                    hi: cols[hi].number(r),
                    side: cols[meets].code(r).and_then(|c| Side::ALL.get(c).copied()),
                    status: cols[status]
                        .code(r)
                        .and_then(|c| SearchStatus::ALL.get(c).copied()),
                });
            }
        }
        add_shares(g, layout, cols, rows.clone());
        add_numbers(g, layout, inputs, cols, rows.clone(), pool, sketch_only);
        if let Some(sn) = self.sensitivity.as_mut() {
            let words = &self.word_cells;
            for row in rows {
                let lane = first + row as u64;
                for (v, &i) in self.values.iter_mut().zip(&layout.numbers) {
                    *v = cols[i].number(row);
                }
                let word = |name: &str| {
                    words
                        .iter()
                        .find(|(n, _)| *n == name)
                        .map_or("", |&(_, i)| cols[i].word(row))
                };
                sn.add(id, lane - id * self.grouping.per_group, &self.values, word)?;
            }
        }
        Ok(())
    }
}

/// Counts the word columns' words of rows `rows` into group `g`'s shares.
fn add_shares(g: &mut Group, layout: &Layout, cols: &[Col<'_>], rows: Range<usize>) {
    let status = cols[layout.status];
    let words: Vec<Col<'_>> = layout.words.iter().map(|(i, _)| cols[*i]).collect();
    // A run of rows with the same words is counted at once.
    let mut start = rows.start;
    for end in word_runs(&words, rows) {
        let n = (end - start) as u64;
        let ok = status.code(start) == Some(Status::Ok as usize);
        for ((i, _), sh) in layout.words.iter().zip(g.shares.iter_mut()) {
            // The shares' words are the column's vocabulary: a code is
            // the place of its count.
            let code = cols[*i].code(start);
            let counted = match sh.of {
                Of::All => true,
                Of::Ok => ok,
                Of::Given => code.is_some(),
            };
            if counted {
                sh.total += n;
                if let Some(k) = code.filter(|&k| k < sh.counts.len()) {
                    sh.counts[k] += n;
                }
            }
        }
        start = end;
    }
}

/// Columns a task of [`add_numbers`] takes: a vector's worth of
/// moments (`moments::add_columns`), so the number columns make a few
/// tasks of full vectors.
const COLUMNS_A_TASK: usize = 8;

/// Adds `xs`, a column's next values, to its kept values and, past the
/// kept values, to its sketch: the column's quantiles become a sketch's
/// estimates over every finite value. `sketch_only`: straight to the
/// sketch, none kept.
fn keep(c: &mut Column, kept: &mut Vec<f64>, xs: &[f64], sketch_only: bool) {
    if sketch_only {
        c.sketch.get_or_insert_with(Sketch::default).add_all(xs);
        return;
    }
    let room = EXACT_MAX.saturating_sub(kept.len()).min(xs.len());
    kept.extend_from_slice(&xs[..room]);
    let rest = &xs[room..];
    if rest.is_empty() {
        return;
    }
    let s = c.sketch.get_or_insert_with(|| {
        let mut s = Sketch::default();
        s.add_all(kept);
        s
    });
    s.add_all(rest);
}

/// Adds the number columns of rows `rows` to group `g` (a few columns a
/// task, the tasks in parallel on `pool`: each column's moments, kept
/// values and sketch take its values in row order; see [`keep`] for
/// `sketch_only`), and keeps the sampled inputs' values while the
/// group's first lanes are kept.
fn add_numbers(
    g: &mut Group,
    layout: &Layout,
    inputs: &[Num],
    cols: &[Col<'_>],
    rows: Range<usize>,
    pool: &rayon::ThreadPool,
    sketch_only: bool,
) {
    use rayon::prelude::*;
    let numbers = layout.numbers.len();
    let (kept_numbers, kept_inputs) = g.kept.split_at_mut(numbers);
    let xs: Vec<(&Col<'_>, bool)> = layout
        .numbers
        .iter()
        .zip(&layout.running)
        .map(|(&i, &running)| (&cols[i], running))
        .collect();
    // Lanes at rest, whose running values are no running point: left out
    // (as empty cells, so the kept values stay aligned lane by lane).
    let contact = &cols[layout.contact];
    let at_rest: Vec<bool> = rows
        .clone()
        .map(|r| contact.code(r) == Some(Contact::Stick as usize))
        .collect();
    let jobs: Vec<_> = g
        .cols
        .chunks_mut(COLUMNS_A_TASK)
        .zip(kept_numbers.chunks_mut(COLUMNS_A_TASK))
        .zip(xs.chunks(COLUMNS_A_TASK))
        .collect();
    pool.install(|| {
        jobs.into_par_iter().for_each(|((cs, kept), xs)| {
            let xs: Vec<_> = xs
                .iter()
                .map(|&(c, running)| {
                    let mut v = c.numbers(rows.clone());
                    if running && at_rest.contains(&true) {
                        for (x, &rest) in v.to_mut().iter_mut().zip(&at_rest) {
                            if rest {
                                *x = f64::NAN;
                            }
                        }
                    }
                    v
                })
                .collect();
            let slices: Vec<&[f64]> = xs.iter().map(|x| &x[..]).collect();
            let mut ms: Vec<Moments> = cs.iter().map(|c| c.m).collect();
            add_columns(&mut ms, &slices);
            for ((c, m), (k, x)) in cs.iter_mut().zip(ms).zip(kept.iter_mut().zip(&slices)) {
                c.m = m;
                keep(c, k, x, sketch_only);
            }
        })
    });
    for (kept, &n) in kept_inputs.iter_mut().zip(inputs) {
        let i = layout.params[n as usize];
        let room = EXACT_MAX.saturating_sub(kept.len()).min(rows.len());
        kept.extend_from_slice(&cols[i].numbers(rows.start..rows.start + room));
    }
}
