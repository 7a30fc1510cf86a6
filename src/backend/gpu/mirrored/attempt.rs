//! A whole step attempt compared in f64: the f64 shader's `attempt` and
//! the Rust one start from the same states (those of `state`, taken along
//! the CPU path's integration of lanes of every law and motor) and must
//! end in the same state: every value within 1e-9 of max(1, |value|),
//! every decision (side, direction, flags, status, counts) the same, and
//! the error budget's terms as the CPU's to the precision of their own
//! arithmetic (an in or out part's local term unless which parts the
//! step fed is such a decision: `fed_by_rounding`). Through it the
//! functions an attempt calls are compared by what they compute
//! together: the trial step, its verdict, the earliest event and the
//! step to it, the energy flow and its split, and the error budget's
//! sums. The cases are counted by what the attempt did
//! (rejected, accepted, an event, a lane finished), and each kind must
//! occur. Needs an adapter with 64-bit floats (lavapipe); without one the
//! test says it is skipped, unless TSWM_REQUIRE_GPU=1.

use super::super::layout::GpuState64;
use super::state::{run, state_values, states, test_lanes, to_gpu};
use crate::integrator::accuracy::{BOUND, LIMIT};
use crate::integrator::step::lane_caps;
use crate::integrator::stepper::error_scale;
use crate::integrator::{attempt, LaneState, Settings, NY};
use crate::model::Lane;

/// A step attempt (`attempt`, and through it the trial step, its
/// verdict, the event it finds, the step to that event, the energy flow
/// and the error budget) from each input state, in f64. An entry point of
/// its own, the attempt inside a loop whose trip count (the case's fourth
/// word, 1) the compiler cannot see, as the shader's own entry point runs
/// its attempts: called once in straight-line code, lavapipe's LLVM
/// spends tens of minutes in its loop analysis (ScalarEvolution) before
/// the first dispatch.
pub(super) const ATTEMPT: &str = concat!(
    state_bindings!(),
    r#"
@compute @workgroup_size(64)
fn mirrored_attempt(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= arrayLength(&s_cases)) { return; }
    let c = s_cases[id.x];
    var st = s_states[c.z];
    let l = s_lanes[c.x];
    // One attempt (c.w = 1), in a loop of a trip count the compiler
    // cannot see, as the shader's own entry point runs them: called once
    // in straight-line code, lavapipe's LLVM spends tens of minutes in its
    // loop analysis (ScalarEvolution) before the first dispatch.
    var left = c.w;
    loop {
        if (left == 0u) { break; }
        left -= 1u;
        attempt(l, &st);
    }
    s_res[id.x].st = st;
}
"#
);

/// The error budget's terms of a state, by name.
fn budget_values(s: &GpuState64) -> Vec<(String, f64)> {
    let mut v = vec![("lag".to_string(), s.lag)];
    v.extend((0..s.phase.len()).map(|i| (format!("phase[{i}]"), s.phase[i])));
    v.extend((0..s.local.len()).map(|i| (format!("local[{i}]"), s.local[i])));
    v
}

/// How far the shader's `b` is from the Rust `a` for a value named
/// `name`, and which of [`BOUNDS`] holds it. The error estimates are
/// differences of stage derivatives that cancel far below the
/// derivatives, so their relative rounding is large (up to 1e-5 here)
/// where that of the state is not:
/// - 0, a value of the state, to max(1, |a|);
/// - 1, the next step's size, a proposal (h times err^(−1/5)) carrying a
///   fifth of the error norm's relative rounding, to itself;
/// - 2, a phase or local term of the error budget, to what it is
///   compared with ([`LIMIT`] × [`BOUND`] of max(1, |result|));
/// - 3, the budget's lag, to itself or a picosecond: within the bound, a
///   difference under 1e-16 s, which through a change of rate under 1e6
///   (W, or m/s²) moves a phase term by under 1e-10, a thirty-thousandth
///   of the threshold.
fn off(name: &str, a: f64, b: f64) -> (usize, f64) {
    let (kind, scale) = match name {
        "h" => (1, a.abs()),
        "lag" => (3, a.abs().max(1e-12)),
        _ if name.starts_with("phase") || name.starts_with("local") => (2, LIMIT * BOUND),
        _ => (0, a.abs().max(1.0)),
    };
    let d = if a == b { 0.0 } else { (a - b).abs() / scale };
    (kind, if d.is_nan() { f64::INFINITY } else { d })
}

/// Whether `name` is the local term of an in or out part (w1_in, w1_out,
/// w2_in, w2_out) that the attempt from `before` fed in one of the Rust
/// (`want`) and shader (`got`) states and not in the other, by an amount
/// within the bound of a state's value ([`BOUNDS`]`[0]` of max(1,
/// |part|)). Which parts a step feeds is a decision (the sign of p at an
/// end of the step, where a switch leaves p at zero up to rounding), and
/// a part the step feeds takes the step's error estimate of its integral
/// into its local term (`add_step`): a decision within the bound of its
/// threshold may differ, as the module's text says of every decision.
fn fed_by_rounding(name: &str, before: &LaneState, want: &GpuState64, got: &GpuState64) -> bool {
    let Some(q) = name
        .strip_prefix("local[")
        .and_then(|r| r.strip_suffix(']'))
        .and_then(|i| i.parse::<usize>().ok())
        .and_then(|i| i.checked_sub(5))
    else {
        return false;
    };
    let fed = |s: &GpuState64| s.flow[q] - s.flow_c[q] - before.flow[q];
    let (a, b) = (fed(want), fed(got));
    let size = before.flow[q].abs().max(1.0);
    (a == 0.0) != (b == 0.0) && a.abs().max(b.abs()) <= BOUNDS[0] * size
}

/// The bounds of [`off`]'s kinds.
const BOUNDS: [f64; 4] = [1e-9, 1e-4, 1e-6, 1e-4];

/// At the default tolerance, and at a looser one where the error budget
/// steers the steps (`caps`): there the test also counts the states
/// whose caps are below their tolerance's error scale, and some must be.
#[test]
fn the_shaders_step_attempt_computes_what_the_rust_one_does_in_f64() {
    let loose = Settings {
        tol: 1e-6,
        ..Settings::default()
    };
    for set in [Settings::default(), loose] {
        compare_attempts(&super::super::layout::f64_settings(&set));
    }
}

/// How many of `inputs` have a component whose cap for the next step is
/// below its tolerance's error scale (where steering changes the step).
fn capped_states(lanes: &[Lane], inputs: &[(usize, LaneState)], set: &Settings) -> usize {
    let binds = |(li, st): &(usize, LaneState)| {
        let cap = lane_caps(&lanes[*li], st, st.h, set);
        (0..NY).any(|i| cap[i] < error_scale(set.tol_of(i), st.y[i], st.y[i]))
    };
    inputs.iter().filter(|s| !s.1.done && binds(s)).count()
}

fn compare_attempts(set: &Settings) {
    let (lanes, tables) = test_lanes();
    let inputs = states(&lanes, &tables, set);
    let cases: Vec<[u32; 4]> = (0u32..)
        .zip(&inputs)
        .map(|(k, (li, _))| [*li as u32, 0, k, 1])
        .collect();
    let Some((after, _)) = run(
        ("mirrored_attempt", ATTEMPT),
        set,
        &lanes,
        &tables,
        &inputs,
        &cases,
    ) else {
        return;
    };
    let mut worst = [0.0f64; 4];
    let mut bad = Vec::new();
    // Rejected, accepted without an event, an event, finished.
    let mut kinds = [0usize; 4];
    for (n, c) in cases.iter().enumerate() {
        let (li, k) = (c[0] as usize, c[2] as usize);
        let before = inputs[k].1;
        let mut st = before;
        attempt(&lanes[li], &tables, set, &mut st);
        let kind = if st.done && !before.done {
            3
        } else if st.events > before.events {
            2
        } else if st.steps > before.steps {
            1
        } else {
            0
        };
        kinds[kind] += 1;
        let want = to_gpu(&st);
        let (wv, ww) = state_values(&want);
        let (gv, gw) = state_values(&after[n]);
        let what = format!("attempt on lane {li}, state {k}");
        if ww != gw || wv.len() != gv.len() {
            bad.push(format!("{what}: rust {ww}, shader {gw}"));
            continue;
        }
        let budget = budget_values(&want)
            .into_iter()
            .zip(budget_values(&after[n]));
        for ((name, a), (_, b)) in wv.into_iter().zip(gv).chain(budget) {
            let (kind, d) = off(&name, a, b);
            worst[kind] = worst[kind].max(d);
            if d > BOUNDS[kind] && !fed_by_rounding(&name, &before, &want, &after[n]) {
                bad.push(format!("{what}: {name} rust {a:e}, shader {b:e}"));
            }
        }
    }
    let capped = if set.steers() {
        capped_states(&lanes, &inputs, set)
    } else {
        0
    };
    eprintln!(
        "attempt at tol {:e}: {} cases (rejected, accepted, an event, finished: {kinds:?}; \
         capped: {capped}); worst (values, h, budget terms, lag): {worst:?}",
        set.tol,
        cases.len()
    );
    bad.truncate(20);
    assert!(bad.is_empty(), "{bad:#?}");
    assert!(kinds.iter().all(|&k| k > 0), "{kinds:?}");
    assert_eq!(
        capped > 0,
        set.steers(),
        "{capped} capped states at {set:?}"
    );
}
