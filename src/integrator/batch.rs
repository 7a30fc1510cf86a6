//! The batch driver: runs lanes to their ends, several interleaved on one
//! thread (the CPU path), as the shader's entry point runs one lane per
//! invocation (the GPU path).

use super::automaton::{advance, finish_step, init, prepare, StepPlan};
use super::result::LaneResult;
use super::stepper::try_steps;
use super::{Settings, NY};
use crate::model::{FrictionTable, Lane};

/// Lanes one thread interleaves in [`simulate_batch`]. Measured on one
/// thread (paper-like lanes): 1 lane 23.7k lanes/s, 2: 38.8k, 4: 45.1k,
/// 8: 46.5k; 4 takes nearly all of it with half the state of 8.
pub const INTERLEAVE: usize = 4;

/// Runs `lanes` to their ends, `out[i]` for `lanes[i]`, interleaving
/// [`INTERLEAVE`] lanes on this thread: each slot takes the next lane when
/// its lane finishes. Per lane the arithmetic is exactly [`simulate`]'s.
pub fn simulate_batch(
    lanes: &[Lane],
    table: Option<&FrictionTable>,
    set: &Settings,
    out: &mut [LaneResult],
) {
    const N: usize = INTERLEAVE;
    assert_eq!(lanes.len(), out.len());
    if lanes.is_empty() {
        return;
    }
    let mut next = 0;
    let mut slot: [Option<usize>; N] = [None; N];
    let mut st = [init(&lanes[0], table); N];
    loop {
        // Refill finished slots.
        for j in 0..N {
            if let Some(i) = slot[j] {
                if !st[j].done {
                    continue;
                }
                out[i] = st[j].end_state().result(&lanes[i], table);
                slot[j] = None;
            }
            if next < lanes.len() {
                st[j] = init(&lanes[next], table);
                slot[j] = Some(next);
                next += 1;
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
            set.tol,
        );
        for j in (0..N).filter(|&j| active[j]) {
            finish_step(lane[j], table, set, &mut st[j], &plan[j], &trial[j]);
        }
    }
}

/// Runs one lane from t = 0 to its end.
pub fn simulate(lane: &Lane, table: Option<&FrictionTable>, set: &Settings) -> LaneResult {
    let mut st = init(lane, table);
    advance(lane, table, set, &mut st, u32::MAX);
    st.end_state().result(lane, table)
}
