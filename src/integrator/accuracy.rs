//! A lane's own estimate of the error in its results, and the tighter run
//! it calls for when that estimate is over docs/model.md's bound (1e-6 of
//! max(1, |value|) for x1, ẋ1, the works and the section 10 energies).
//!
//! Why a lane needs one: the step tolerance bounds each step's error
//! relative to the running values, which is enough for a result of the
//! size of what flowed through it, but not for one that ends far smaller:
//! a work that cancels (a motor that drives, then brakes; a load that is
//! lifted, then lowered), or the part of ∫p1 dt or ∫p2 dt that a switch
//! shortly before t_end starts. Measured against scipy's DOP853 at 1e-12
//! (`tests/reference`), such results were up to 5.7 times the bound at
//! tol 1e-8, on 5 lanes in 15,000.
//!
//! The estimate has two terms per result, both read off steps the lane
//! takes anyway (no right-hand side is evaluated for it):
//! - **local**: the sum of the steps' error estimates of the result (a
//!   work's own quadrature error, which cancellation leaves as it is);
//! - **phase**: between time events the lane is autonomous, so an error δ
//!   in ẋ1 made where the acceleration is a moves the rest of the lane in
//!   time by δ/|a| (its *lag*). That moves a result r by (ṙ(t_end) − ṙ(t))
//!   δ/|a|, which is at most the variation of ṙ after t times δ/|a|: so
//!   each step adds |Δṙ over the step| × (the lag so far) to the result's
//!   phase term, and its own error estimate of ẋ1 over |a| to the lag.
//!   A switch at φ(ẋ1) = 0 shortly before t_end is where this matters.
//!
//! Both terms use the embedded 4th-order error estimate, which overstates
//! the error of the propagated 5th-order solution: on 15,096 lanes
//! (random user lanes and paper-like lanes), actual errors were below
//! [`LIMIT`] times the estimate wherever they exceeded 5 % of the bound,
//! with four exceptions (up to 4.1 times, on results 7 to 21 % of the
//! bound). A lane whose estimate is over [`LIMIT`] times the bound for any
//! result is run again at [`Settings::tighter`]; its row says
//! `cpu:refined` and the run's summary counts it.
//!
//! At a tolerance looser than the default the estimate is also a limit the
//! step control works to (`Budgets::caps`, `Settings::steers`): a step's
//! error in each component is held within the room its result has left
//! below [`BUDGET_AIM`], shared over the rest of the horizon. Otherwise
//! the sum of a lane's step estimates, some steps × tol, would be over the
//! limit for most lanes at a loose tolerance, and most lanes would be run
//! twice (a looser tolerance was slower than the default).

use super::components::{powers, NY};
use super::result::{LaneResult, Status};
use super::settings::{Settings, REFINE_FACTOR};
use super::stepper::{error_scale, Trial};
use crate::lanewise::Lanewise;
use crate::model::vmath::{larger, smaller};

/// Results the budget covers: x1, ẋ1, w_motor, w_load, w_friction, w1_in,
/// w1_out, w2_in, w2_out (lanes.csv's order).
pub const RESULTS: usize = 9;

/// docs/model.md's bound on those results, relative to max(1, |value|).
pub const BOUND: f64 = 1e-6;

/// A lane is run again when a result's estimate is over this many times
/// [`BOUND`] (the estimate overstates the error; see the module's text).
pub const LIMIT: f64 = 3.0;

/// The share of [`LIMIT`] × [`BOUND`] the step control aims a result's
/// estimate at by the lane's end, where the budget steers the steps
/// (`Budgets::caps`, `Settings::steers`).
pub const AIM: f64 = 0.3;

/// [`AIM`] × [`LIMIT`] × [`BOUND`]: what a result's estimate is aimed at,
/// relative to max(1, |its size|) (the shader's `BUDGET_AIM`).
pub const BUDGET_AIM: f64 = AIM * LIMIT * BOUND;

crate::lanewise_struct! {
    /// The running error estimate of one lane's results; [`Budgets`]
    /// holds W lanes', so that the batch driver adds its lanes' common
    /// steps as vector code ([`Budgets::add_steps`]).
    #[derive(Clone, Copy, Debug, Default, PartialEq)]
    pub struct ErrorBudget, Budgets {
        /// Σ (error estimate of ẋ1) / |a| over the steps so far, s.
        lag: f64,
        /// Phase term of each result.
        phase: [f64; RESULTS],
        /// Local term of each result.
        local: [f64; RESULTS],
    }
}

/// Rates of the results at derivatives k of W lanes (the state's
/// components x1, ẋ1, w_motor, w_load, w_friction, ∫p1): ẋ1, a, F1ẋ1,
/// F2ẋ2, p1 + p2, and the in and out parts of p1 and p2; component-major,
/// so each is a loop over the lanes. The shader's `rates` mirrors it;
/// [`Budgets::add_steps`] reads the same rates in place (the first five
/// are k's own components, the rest [`parts`]), so that no step copies
/// them into an array: only the mirrored tests call it.
#[inline(always)]
#[cfg_attr(not(test), allow(dead_code))]
pub(crate) fn rates<const N: usize>(k: &[[f64; N]; NY]) -> [[f64; N]; RESULTS] {
    let mut r = [[0.0; N]; RESULTS];
    r[..5].copy_from_slice(&k[..5]);
    for j in 0..N {
        for (q, part) in parts(k[4][j], k[5][j]).into_iter().enumerate() {
            r[5 + q][j] = part;
        }
    }
    r
}

/// The in and out parts of p1 and p2 (w1_in, w1_out, w2_in, w2_out's
/// rates) from one lane's rates of w_friction (`k4`) and ∫p1 (`k5`).
#[inline(always)]
fn parts(k4: f64, k5: f64) -> [f64; 4] {
    let (p1, p2) = powers(k4, k5);
    [p1.max(0.0), (-p1).max(0.0), p2.max(0.0), (-p2).max(0.0)]
}

impl<const N: usize> Budgets<N> {
    /// The largest error estimate a step of size `h` from time `t` may
    /// make in each component (absolute), into `cap`: the room each
    /// result's estimate has left below [`BUDGET_AIM`] of its size, shared
    /// over the rest of the horizon `t_end` in proportion to the step. A
    /// result's size is max(1, |its value|, |the value it would reach at
    /// `t_end` going on at its present rate|): its final size is not
    /// known yet, and where it ends smaller (a work that cancels) the
    /// lane may still be refined. So a lane's estimate is held within the
    /// limit where its step tolerance alone would not hold it there, and
    /// the lane is not run again. ∫p1's cap is that of the part of p1 the
    /// step starts feeding (its sign in `k1`); w_friction's also that of
    /// p2's part. No cap is below [`REFINE_FACTOR`] times the component's
    /// error scale at [`Settings::floor_tol_of`] (`set`): finer than that,
    /// the budget's limit is left to refinement.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn caps(
        &self,
        y: &[[f64; N]; NY],
        k1: &[[f64; N]; NY],
        flow: &[[f64; N]; 4],
        t: &[f64; N],
        t_end: &[f64; N],
        h: &[f64; N],
        set: &Settings,
        cap: &mut [[f64; N]; NY],
    ) {
        // A tenth of each component's floor tolerance: its floor per unit
        // of (1 + |y|).
        let floor: [f64; NY] = std::array::from_fn(|i| REFINE_FACTOR * set.floor_tol_of(i));
        for j in 0..N {
            let left = larger(t_end[j] - t[j], 0.0);
            let share = h[j] / larger(left, h[j]);
            // The room of a result at value v, rate `rate` and estimate
            // so far `used`.
            let room = |v: f64, rate: f64, used: f64| {
                // The result's size at t_end if it went on at its rate.
                let ahead = (v + rate * left).abs();
                let aim = BUDGET_AIM * larger(larger(v.abs(), ahead), 1.0);
                larger(aim - used, 0.0)
            };
            let used = |r: usize| self.phase[r][j] + self.local[r][j];
            // The floor of component i's cap.
            let lo = |i: usize| error_scale(floor[i], y[i][j], y[i][j]);
            for i in 0..4 {
                cap[i][j] = larger(room(y[i][j], k1[i][j], used(i)) * share, lo(i));
            }
            // The part of p1 (of p2) the step starts feeding, in or out:
            // both rooms computed and one selected, as vector code.
            let (p1, p2) = powers(k1[4][j], k1[5][j]);
            let (in1, out1) = (
                room(flow[0][j], p1, used(5)),
                room(flow[1][j], -p1, used(6)),
            );
            let (in2, out2) = (
                room(flow[2][j], p2, used(7)),
                room(flow[3][j], -p2, used(8)),
            );
            let part1 = if p1 < 0.0 { out1 } else { in1 };
            let part2 = if p2 < 0.0 { out2 } else { in2 };
            let cap4 = smaller(room(y[4][j], k1[4][j], used(4)), part2) * share;
            cap[4][j] = larger(cap4, lo(4));
            cap[5][j] = larger(part1 * share, lo(5));
        }
    }
}

impl ErrorBudget {
    /// Adds an accepted step from derivative `k0` to `trial` (whose `k7`
    /// is the derivative at its end); `flow` is the step's share of
    /// (w1_in, w1_out, w2_in, w2_out), which says which parts it fed.
    /// [`Budgets::add_steps`] of one lane.
    #[inline]
    pub(crate) fn add_step(&mut self, k0: &[f64; NY], trial: &Trial, flow: &[f64; 4]) {
        let mut b = self.one();
        b.add_steps(
            &[true],
            &k0.map(|v| [v]),
            &trial.k7.map(|v| [v]),
            &trial.est.map(|v| [v]),
            &flow.map(|v| [v]),
        );
        *self = b.lane(0);
    }

    /// Adds a step's [`split_error`](super::flow::split_error) of ∫p1 and
    /// ∫p2 to the local terms of their in and out parts.
    pub(crate) fn add_split(&mut self, err: [f64; 2]) {
        for (q, e) in [err[0], err[0], err[1], err[1]].into_iter().enumerate() {
            self.local[5 + q] += e;
        }
    }

    /// The phase and local terms of each result, absolute (for studies of
    /// the estimate: `examples/estimate_scan.rs`).
    pub fn terms(&self) -> ([f64; RESULTS], [f64; RESULTS]) {
        (self.phase, self.local)
    }

    /// The lag so far, s (see the module's text).
    #[cfg(test)]
    pub(crate) fn lag(&self) -> f64 {
        self.lag
    }

    /// A budget from its terms, as the f64 shader keeps them (`State`'s
    /// `lag`, `phase` and `local`).
    pub(crate) fn from_terms(lag: f64, phase: [f64; RESULTS], local: [f64; RESULTS]) -> Self {
        ErrorBudget { lag, phase, local }
    }

    /// Whether every result of `r` is within [`LIMIT`] × [`BOUND`] by the
    /// estimate. A lane that did not end `ok` has no results to refine.
    pub fn within(&self, r: &LaneResult) -> bool {
        r.integrated().iter().enumerate().all(|(i, v)| {
            let est = self.phase[i] + self.local[i];
            // NaN (a lane that did not finish) compares false: within.
            !(est > LIMIT * BOUND * v.abs().max(1.0))
        })
    }
}

impl<const N: usize> Budgets<N> {
    /// Adds an accepted step to each lane j with `take[j]`: its derivatives
    /// `k0` at the start and `k7` at the end, its error estimates `est`
    /// (`Trial::est`) and its energy flow `flow` (its share of w1_in,
    /// w1_out, w2_in, w2_out, which says which parts it fed), all
    /// component-major: every line a loop over the lanes, a lane's
    /// arithmetic the same whatever N.
    #[inline(always)]
    pub fn add_steps(
        &mut self,
        take: &[bool; N],
        k0: &[[f64; N]; NY],
        k7: &[[f64; N]; NY],
        est: &[[f64; N]; NY + 1],
        flow: &[[f64; N]; 4],
    ) {
        // |Δṙ| over the step of each result, as [`rates`] gives ṙ; the
        // first five rates are k's own components, read in place (a copy
        // of them into an array of rates was a memcpy every step).
        let mut change = [[0.0; N]; RESULTS];
        for i in 0..5 {
            for j in 0..N {
                change[i][j] = (k7[i][j] - k0[i][j]).abs();
            }
        }
        for j in 0..N {
            let (a, b) = (parts(k0[4][j], k0[5][j]), parts(k7[4][j], k7[5][j]));
            for q in 0..4 {
                change[5 + q][j] = (b[q] - a[q]).abs();
            }
        }
        for (phase, change) in self.phase.iter_mut().zip(&change) {
            for j in 0..N {
                let p = phase[j] + change[j] * self.lag[j];
                phase[j] = if take[j] { p } else { phase[j] };
            }
        }
        for (local, e) in self.local[..5].iter_mut().zip(&est[..5]) {
            for j in 0..N {
                let l = local[j] + e[j];
                local[j] = if take[j] { l } else { local[j] };
            }
        }
        // ∫p1's estimate goes to the p1 parts the step fed, ∫p2's to p2's.
        for q in 0..4 {
            let e = &est[if q < 2 { 5 } else { NY }];
            let (local, flow) = (&mut self.local[5 + q], &flow[q]);
            for j in 0..N {
                let l = local[j] + e[j];
                // `&`, not `&&`: no branch, so the loop stays vector code.
                let fed = take[j] & (flow[j] != 0.0);
                local[j] = if fed { l } else { local[j] };
            }
        }
        for j in 0..N {
            let a = k0[1][j].abs().max(k7[1][j].abs());
            // Divided whatever a is, kept where a > 0: a select, not a
            // branch around the division.
            let lag = self.lag[j] + est[1][j] / a;
            let grow = take[j] & (a > 0.0);
            self.lag[j] = if grow { lag } else { self.lag[j] };
        }
    }
}

/// Whether a lane that ended with `r` and `budget` under `set` is to be
/// run again at [`Settings::tighter`].
pub(crate) fn needs_refining(set: &Settings, r: &LaneResult, budget: &ErrorBudget) -> bool {
    set.refine && r.status == Status::Ok && !budget.within(r)
}
