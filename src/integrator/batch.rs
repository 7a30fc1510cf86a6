//! The batch driver: runs lanes to their ends, several interleaved on one
//! thread (the CPU path), as the shader's entry point runs one lane per
//! invocation (the GPU path).

use super::accuracy::{needs_refining, ErrorBudget};
use super::automaton::init;
use super::lockstep::{Done, Order, Slots};
use super::result::{LaneResult, RowPath};
use super::settings::Settings;
use super::step::advance;
use super::width::{best_isa, isas, width, Isa, Width};
use crate::model::{FrictionTable, Lane};

/// Runs `lanes` to their ends, `out[i]` for `lanes[i]`, stepping
/// [`width`]`().lanes` of them in lockstep on this thread, lanes as
/// vector elements: each slot takes the next lane when its lane finishes.
/// Lanes whose error estimate asks for it are then run again at
/// [`Settings::tighter`]. Per lane the arithmetic is exactly
/// [`simulate`]'s, so a row does not depend on the width.
pub fn simulate_batch(
    lanes: &[Lane],
    tables: &[FrictionTable],
    set: &Settings,
    out: &mut [LaneResult],
) {
    simulate_batch_at(own_width(), lanes, tables, set, out)
}

/// The width this process runs: the forced one, or the core's own. A
/// width the variable forces wrongly is refused before any command runs
/// (and by the CPU backend); here it falls back to the core's own.
pub fn own_width() -> Width {
    width().unwrap_or_else(|_| Width::natural(best_isa()))
}

/// [`simulate_batch`] at width `w` (tests and benchmarks compare widths
/// in one process). Panics when this core lacks `w.isa`.
pub fn simulate_batch_at(
    w: Width,
    lanes: &[Lane],
    tables: &[FrictionTable],
    set: &Settings,
    out: &mut [LaneResult],
) {
    let redo = first_pass(w, lanes, tables, set, out);
    let picked: Vec<Lane> = redo.iter().map(|&i| lanes[i]).collect();
    let mut rows = vec![LaneResult::EMPTY; redo.len()];
    refine_pass(w, &picked, tables, set, &mut rows);
    for (i, r) in redo.into_iter().zip(rows) {
        out[i] = r;
    }
}

/// The first pass of [`simulate_batch_at`]: every lane's row at `set`
/// into `out`; returns the indices of the lanes whose error estimate
/// asks for a second run (their rows are to be replaced by
/// [`refine_pass`]'s). The CPU backend gathers these from all of a
/// chunk's blocks, so that its threads refine them in full vectors.
pub fn first_pass(
    w: Width,
    lanes: &[Lane],
    tables: &[FrictionTable],
    set: &Settings,
    out: &mut [LaneResult],
) -> Vec<usize> {
    assert_eq!(lanes.len(), out.len());
    let mut redo = Vec::new();
    run_width(
        w,
        lanes,
        &mut (0..lanes.len()),
        tables,
        set,
        &mut |i, st| {
            out[i] = st.end_state().result(&lanes[i], tables);
            if needs_refining(set, &out[i], &st.budget) {
                redo.push(i);
            }
        },
    );
    redo
}

/// The second pass: `lanes` run again at [`Settings::tighter`] than
/// `set`, row k (marked refined) into `rows[k]`.
pub fn refine_pass(
    w: Width,
    lanes: &[Lane],
    tables: &[FrictionTable],
    set: &Settings,
    rows: &mut [LaneResult],
) {
    assert_eq!(lanes.len(), rows.len());
    let tight = set.tighter();
    run_width(
        w,
        lanes,
        &mut (0..lanes.len()),
        tables,
        &tight,
        &mut |k, st| {
            rows[k] = st.end_state().result(&lanes[k], tables);
            rows[k].path = RowPath::Refined;
        },
    );
}

/// [`interleaved`] at width `w`, compiled for its instruction set.
/// Panics when this core lacks `w.isa`.
fn run_width(
    w: Width,
    lanes: &[Lane],
    order: Order,
    tables: &[FrictionTable],
    set: &Settings,
    done: Done,
) {
    assert!(
        isas().contains(&w.isa),
        "this core has no {:?} instructions",
        w.isa
    );
    macro_rules! at {
        ($f:ident) => {
            match w.lanes {
                1 => $f::<1>(lanes, order, tables, set, done),
                2 => $f::<2>(lanes, order, tables, set, done),
                4 => $f::<4>(lanes, order, tables, set, done),
                8 => $f::<8>(lanes, order, tables, set, done),
                _ => $f::<16>(lanes, order, tables, set, done),
            }
        };
    }
    match w.isa {
        // SAFETY: best_isa() found the features on this core.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 => unsafe { at!(on_avx512) },
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2 => unsafe { at!(on_avx2) },
        _ => at!(interleaved),
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx2,fma")]
unsafe fn on_avx512<const N: usize>(
    lanes: &[Lane],
    order: Order,
    tables: &[FrictionTable],
    set: &Settings,
    done: Done,
) {
    interleaved::<N>(lanes, order, tables, set, done)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn on_avx2<const N: usize>(
    lanes: &[Lane],
    order: Order,
    tables: &[FrictionTable],
    set: &Settings,
    done: Done,
) {
    interleaved::<N>(lanes, order, tables, set, done)
}

/// Runs the lanes `order` names to their ends, N at a time in lockstep,
/// handing each finished lane's index and end state to `done`.
#[inline(always)]
fn interleaved<const N: usize>(
    lanes: &[Lane],
    order: Order,
    tables: &[FrictionTable],
    set: &Settings,
    done: Done,
) {
    let Some(first) = lanes.first() else { return };
    let mut slots = Slots::<N>::new(first);
    while slots.refill(lanes, order, tables, done) {
        slots.attempt(lanes, tables, set);
    }
}

/// Runs one lane from t = 0 to its end, and again at the tighter
/// settings when its error estimate asks for it (see `accuracy`).
pub fn simulate(lane: &Lane, tables: &[FrictionTable], set: &Settings) -> LaneResult {
    let (r, budget) = run_lane(lane, tables, set);
    if needs_refining(set, &r, &budget) {
        return refined(lane, tables, set);
    }
    r
}

/// One run of a lane under `set`: its result and its error estimate.
pub(crate) fn run_lane(
    lane: &Lane,
    tables: &[FrictionTable],
    set: &Settings,
) -> (LaneResult, ErrorBudget) {
    let mut st = init(lane, tables);
    advance(lane, tables, set, &mut st, u32::MAX);
    (st.end_state().result(lane, tables), st.budget)
}

/// The lane run again at [`Settings::tighter`]; its row says so.
fn refined(lane: &Lane, tables: &[FrictionTable], set: &Settings) -> LaneResult {
    let (mut r, _) = run_lane(lane, tables, &set.tighter());
    r.path = RowPath::Refined;
    r
}

/// The settings a lane's row comes from: `set`, or the tighter ones when
/// its run under `set` needs refining (for traces, which must come from
/// the same integration as the row).
pub(crate) fn settings_for(lane: &Lane, tables: &[FrictionTable], set: &Settings) -> Settings {
    let (r, budget) = run_lane(lane, tables, set);
    if needs_refining(set, &r, &budget) {
        set.tighter()
    } else {
        *set
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::RowPath;
    use crate::params::{Num, Spec};

    /// A paper-law lane with the given parameters (others at docs/model.md's
    /// defaults).
    fn lane(set: &[(Num, f64)]) -> Lane {
        let mut s = Spec::default();
        for &(n, v) in set {
            s.set(n, v);
        }
        Lane::new(&s.resolve(&[]).unwrap(), &[])
    }

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs().max(1.0)
    }

    // Reference values: scipy's DOP853 at rtol = atol = 1e-12 with located
    // events (tests/reference/scipy_reference.py), an independent code.

    /// A switch 0.045 s before t_end: the b-b parts w1_out and w2_in (about
    /// 1 J of 10^4 J that flowed) move with the lane's timing.
    #[test]
    fn a_late_switch_is_refined_to_the_bound() {
        let l = lane(&[
            (Num::GammaDeg, 19.8137071019642),
            (Num::F2, 325.2184819644972),
            (Num::M1, 685.1808039516292),
            (Num::M2, 12362.132407547735),
            (Num::TEnd, 3.0489152427536252),
        ]);
        let set = Settings::default();
        let (first, budget) = run_lane(&l, &[], &set);
        // Unrefined, w1_out is 1.3e-6 off: the estimate must see it.
        assert!(rel(first.w1_out, 1.094897114995884) > 1e-6);
        assert!(!budget.within(&first));
        let r = simulate(&l, &[], &set);
        assert_eq!(r.path, RowPath::Refined);
        for (got, want) in [
            (r.w1_out, 1.094897114995884),
            (r.w2_in, 1.2225240031607394),
            (r.w1_in, 9369.45812701097),
            (r.w2_out, 8256.02832923246),
            (r.x1_end, 6.203682240027558),
        ] {
            assert!(rel(got, want) < 1e-7, "{got} vs {want}");
        }
    }

    /// Motor off at 0.27 s, the load runs the drive back to 0.5 mm from
    /// its start: w_load ends at −0.26 J of the 210 J the motor put in.
    #[test]
    fn a_work_that_cancels_is_refined_to_the_bound() {
        let l = lane(&[
            (Num::GammaDeg, 7.517261162674344),
            (Num::F2, -4120.3478216415415),
            (Num::M1, 658.2318329800966),
            (Num::M2, 15379.020814148982),
            (Num::TEnd, 2.63037747275986),
            (Num::MotorOff, 0.2669203756849327),
        ]);
        let set = Settings::default();
        let (first, _) = run_lane(&l, &[], &set);
        assert!(rel(first.w_load, -0.2639743164097439) > 1e-6);
        let r = simulate(&l, &[], &set);
        assert_eq!(r.path, RowPath::Refined);
        assert!(rel(r.w_load, -0.2639743164097439) < 1e-6, "{}", r.w_load);
        assert!(rel(r.x1_end, 0.0004854995080163585) < 1e-6, "{}", r.x1_end);
    }

    /// The paper's cases (docs/model.md section 7) are within the bound as
    /// they are: no second run.
    #[test]
    fn the_papers_cases_are_not_refined() {
        for f2 in [4774.0, -4774.0] {
            let r = simulate(&lane(&[(Num::F2, f2)]), &[], &Settings::default());
            assert_eq!(r.path, RowPath::Cpu, "f2 {f2}");
        }
    }
}
