//! How a step attempt ends, decided once for W lanes at once
//! ([`verdicts`]), and the common endings applied as vector code
//! ([`end_common`]).
//!
//! Most attempts are common: a rejected trial tried again smaller, or an
//! accepted one with no event inside, not landing on a time event, whose
//! mesh powers each go whole to one part (`flow::step_flow`: by the mode,
//! or p1 keeping its sign), with a finite state and steps left. For
//! those the outcome (the state, the energy flow, the error budget, the
//! next size) is branch-free arithmetic per lane. Every other attempt is
//! the lane automaton's (`step::finish_step`). The one-lane path decides
//! and ends its attempts with the same two functions at W = 1, so a
//! lane's row is the same bits whichever path each of its steps took.

use super::automaton::LaneStates;
use super::components::{powers, NY};
use super::control::retry_size;
use super::events::Watches;
use super::flow::{goes_whole, mode_signs, split_whole};
use super::settings::Settings;
use super::stepper::Trials;

/// How the attempts of W lanes end, lane by lane.
pub(crate) struct Verdicts<const W: usize> {
    /// Accepted, and common: the lane moves to the step's end.
    pub(crate) plain: [bool; W],
    /// Rejected, and the smaller size is no step underflow: tried again.
    pub(crate) retry: [bool; W],
    /// Neither (an event, a time event, a sign change of p1 where the mode
    /// does not decide its part, a
    /// state that is not finite, D not > 0 at the step's end, the step
    /// budget, a step underflow): the automaton ends the attempt.
    pub(crate) slow: [bool; W],
    /// The size proposed next: h times the factor the error asks for after
    /// an acceptance, the retry size after a rejection.
    pub(crate) h_next: [f64; W],
    /// The step's increments of (w1_in, w1_out, w2_in, w2_out) when it is
    /// plain (all of each increment goes to one part).
    pub(crate) flow: [[f64; W]; 4],
}

/// The verdicts on the `active` lanes' trial steps `tr` of sizes `h`
/// (`landing` on their time events), taken at times `t` after `steps`
/// accepted steps from derivatives `k1`, watching for `watch`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn verdicts<const W: usize>(
    active: &[bool; W],
    h: &[f64; W],
    landing: &[bool; W],
    t: &[f64; W],
    steps: &[u32; W],
    watch: &Watches<W>,
    k1: &[[f64; W]; NY],
    tr: &Trials<W>,
    set: &Settings,
) -> Verdicts<W> {
    let mut v = Verdicts {
        plain: [false; W],
        retry: [false; W],
        slow: [false; W],
        h_next: [0.0; W],
        flow: [[0.0; W]; 4],
    };
    for j in 0..W {
        let rejected = tr.err[j] > 1.0;
        let (h_retry, underflow) = retry_size(h[j], tr.fac[j], t[j]);
        let w = watch.lane(j);
        let ends = w.at_end(tr.y1[1][j], tr.k7[1][j], tr.d_end[j], tr.g_switch[j]);
        // Folds with `|` and `&`, not `any`, `all` or `&&`: no branch, so
        // the loop over the lanes stays vector code.
        let event = ends.iter().fold(false, |e, g| e | (*g < 0.0));
        // The signs the mode gives the mesh powers; where it gives p1
        // none, p1 at the step's ends.
        let (s1, s2) = mode_signs(w.side, w.dir);
        let by_mode = s1 != 0.0;
        let (p1_0, _) = powers(k1[4][j], k1[5][j]);
        let (p1_end, _) = powers(tr.k7[4][j], tr.k7[5][j]);
        let (p1_0, p1_end) = if by_mode { (s1, 0.0) } else { (p1_0, p1_end) };
        let finite = (0..NY).fold(true, |f, i| f & tr.y1[i][j].is_finite());
        let p1_whole = by_mode | goes_whole(tr.dw[0][j], tr.est[5][j], p1_0, p1_end);
        let common = !event
            & !landing[j]
            & p1_whole
            & finite
            & (tr.d_end[j] > 0.0)
            & (steps[j] < set.max_steps);
        v.plain[j] = active[j] & !rejected & common;
        v.retry[j] = active[j] & rejected & !underflow;
        v.slow[j] = active[j] & !v.plain[j] & !v.retry[j];
        v.h_next[j] = if rejected { h_retry } else { h[j] * tr.fac[j] };
        [v.flow[0][j], v.flow[1][j]] = split_whole(tr.dw[0][j], p1_0, p1_end);
        [v.flow[2][j], v.flow[3][j]] = split_whole(tr.dw[1][j], s2, 0.0);
    }
    v
}

/// Ends the plain and retried attempts of `st`'s lanes (steps of sizes
/// `h` with outcome `tr`, judged `v`); the slow ones are left as they were.
#[inline(always)]
pub(crate) fn end_common<const W: usize>(
    st: &mut LaneStates<W>,
    v: &Verdicts<W>,
    h: &[f64; W],
    tr: &Trials<W>,
) {
    st.budget
        .add_steps(&v.plain, &st.k1, &tr.k7, &tr.est, &v.flow);
    for j in 0..W {
        let a = v.plain[j];
        for (f, d) in st.flow.iter_mut().zip(&v.flow) {
            f[j] = if a { f[j] + d[j] } else { f[j] };
        }
        for i in 0..NY {
            st.y[i][j] = if a { tr.y1[i][j] } else { st.y[i][j] };
            st.k1[i][j] = if a { tr.k7[i][j] } else { st.k1[i][j] };
        }
        st.t[j] = if a { st.t[j] + h[j] } else { st.t[j] };
        st.steps[j] += u32::from(a);
        st.h[j] = if a || v.retry[j] {
            v.h_next[j]
        } else {
            st.h[j]
        };
    }
}
