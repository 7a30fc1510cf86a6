//! The batch driver: runs lanes to their ends, several interleaved on one
//! thread (the CPU path), as the shader's entry point runs one lane per
//! invocation (the GPU path).

use super::accuracy::{needs_refining, ErrorBudget};
use super::automaton::{advance, finish_step, init, prepare, LaneState, StepPlan};
use super::result::{LaneResult, RowPath};
use super::stepper::try_steps;
use super::{Settings, NY};
use crate::model::{FrictionTable, Lane};

/// Lanes one thread interleaves in [`simulate_batch`]. Measured on one
/// thread (paper-like lanes): 1 lane 23.7k lanes/s, 2: 38.8k, 4: 45.1k,
/// 8: 46.5k; 4 takes nearly all of it with half the state of 8.
pub const INTERLEAVE: usize = 4;

/// Runs `lanes` to their ends, `out[i]` for `lanes[i]`, interleaving
/// [`INTERLEAVE`] lanes on this thread: each slot takes the next lane when
/// its lane finishes. Lanes whose error estimate asks for it are then run
/// again, interleaved too, at [`Settings::tighter`]. Per lane the
/// arithmetic is exactly [`simulate`]'s.
pub fn simulate_batch(
    lanes: &[Lane],
    table: Option<&FrictionTable>,
    set: &Settings,
    out: &mut [LaneResult],
) {
    assert_eq!(lanes.len(), out.len());
    let mut redo = Vec::new();
    interleaved(lanes, 0..lanes.len(), table, set, |i, st| {
        out[i] = st.end_state().result(&lanes[i], table);
        if needs_refining(set, &out[i], &st.budget) {
            redo.push(i);
        }
    });
    if !redo.is_empty() {
        let tight = set.tighter();
        interleaved(lanes, redo.into_iter(), table, &tight, |i, st| {
            out[i] = st.end_state().result(&lanes[i], table);
            out[i].path = RowPath::Refined;
        });
    }
}

/// Runs the lanes `order` names to their ends, [`INTERLEAVE`] at a time,
/// handing each finished lane's index and end state to `done`.
fn interleaved(
    lanes: &[Lane],
    mut order: impl Iterator<Item = usize>,
    table: Option<&FrictionTable>,
    set: &Settings,
    mut done: impl FnMut(usize, &LaneState),
) {
    const N: usize = INTERLEAVE;
    if lanes.is_empty() {
        return;
    }
    let mut slot: [Option<usize>; N] = [None; N];
    let mut st = [init(&lanes[0], table); N];
    loop {
        // Refill finished slots.
        for j in 0..N {
            if let Some(i) = slot[j] {
                if !st[j].done {
                    continue;
                }
                done(i, &st[j]);
                slot[j] = None;
            }
            if let Some(next) = order.next() {
                st[j] = init(&lanes[next], table);
                slot[j] = Some(next);
            }
        }
        if slot.iter().all(Option::is_none) {
            break;
        }
        let mut plan = [StepPlan::IDLE; N];
        let mut active = [false; N];
        for j in 0..N {
            if let Some(i) = slot[j] {
                if !st[j].done {
                    if let Some(p) = prepare(&lanes[i], table, &mut st[j]) {
                        plan[j] = p;
                        active[j] = true;
                    }
                }
            }
        }
        if !active.iter().any(|&a| a) {
            continue;
        }
        let lane: [&Lane; N] = std::array::from_fn(|j| &lanes[slot[j].unwrap_or(0)]);
        let y: [[f64; NY]; N] = std::array::from_fn(|j| st[j].y);
        let k1: [[f64; NY]; N] = std::array::from_fn(|j| st[j].k1);
        let trial = try_steps::<N>(
            lane,
            table,
            std::array::from_fn(|j| plan[j].mode),
            &y,
            &k1,
            std::array::from_fn(|j| plan[j].h),
            active,
            set,
        );
        for j in (0..N).filter(|&j| active[j]) {
            finish_step(lane[j], table, set, &mut st[j], &plan[j], &trial[j]);
        }
    }
}

/// Runs one lane from t = 0 to its end, and again at the tighter
/// settings when its error estimate asks for it (see `accuracy`).
pub fn simulate(lane: &Lane, table: Option<&FrictionTable>, set: &Settings) -> LaneResult {
    let (r, budget) = run_lane(lane, table, set);
    if needs_refining(set, &r, &budget) {
        return refined(lane, table, set);
    }
    r
}

/// One run of a lane under `set`: its result and its error estimate.
pub(crate) fn run_lane(
    lane: &Lane,
    table: Option<&FrictionTable>,
    set: &Settings,
) -> (LaneResult, ErrorBudget) {
    let mut st = init(lane, table);
    advance(lane, table, set, &mut st, u32::MAX);
    (st.end_state().result(lane, table), st.budget)
}

/// The lane run again at [`Settings::tighter`]; its row says so.
fn refined(lane: &Lane, table: Option<&FrictionTable>, set: &Settings) -> LaneResult {
    let (mut r, _) = run_lane(lane, table, &set.tighter());
    r.path = RowPath::Refined;
    r
}
