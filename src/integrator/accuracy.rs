//! A lane's own estimate of the error in its results, and the tighter run
//! it calls for when that estimate is over MODEL.md's bound (1e-6 of
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

use super::stepper::Trial;
use super::{LaneResult, Settings, NY};
use crate::model::Lane;

/// Results the budget covers: x1, ẋ1, w_motor, w_load, w_friction, w1_in,
/// w1_out, w2_in, w2_out (lanes.csv's order).
pub const RESULTS: usize = 9;

/// MODEL.md's bound on those results, relative to max(1, |value|).
pub const BOUND: f64 = 1e-6;

/// A lane is run again when a result's estimate is over this many times
/// [`BOUND`] (the estimate overstates the error; see the module's text).
pub const LIMIT: f64 = 3.0;

/// The running error estimate of one lane's results.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ErrorBudget {
    /// Σ (error estimate of ẋ1) / |a| over the steps so far, s.
    lag: f64,
    /// Phase term of each result.
    phase: [f64; RESULTS],
    /// Local term of each result.
    local: [f64; RESULTS],
}

/// Rates of the results at a derivative k of the state (x1, ẋ1, w_motor,
/// w_load, w_friction, ∫p1): ẋ1, a, F1ẋ1, F2ẋ2, p1 + p2, and the in and
/// out parts of p1 and p2.
#[inline]
fn rates(k: &[f64; NY]) -> [f64; RESULTS] {
    let p2 = k[4] - k[5];
    [
        k[0],
        k[1],
        k[2],
        k[3],
        k[4],
        k[5].max(0.0),
        (-k[5]).max(0.0),
        p2.max(0.0),
        (-p2).max(0.0),
    ]
}

impl ErrorBudget {
    /// Adds an accepted step from derivative `k0` to `trial` (whose `k7`
    /// is the derivative at its end); `flow` is the step's share of
    /// (w1_in, w1_out, w2_in, w2_out), which says which parts it fed.
    #[inline]
    pub fn add_step(&mut self, k0: &[f64; NY], trial: &Trial, flow: &[f64; 4]) {
        let (r0, r1) = (rates(k0), rates(&trial.k7));
        for i in 0..RESULTS {
            self.phase[i] += (r1[i] - r0[i]).abs() * self.lag;
        }
        let e = &trial.est;
        for (l, e) in self.local[..5].iter_mut().zip(e) {
            *l += e;
        }
        // ∫p1's estimate goes to the p1 parts the step fed, ∫p2's to p2's.
        for (q, est) in [(0, e[5]), (1, e[5]), (2, e[NY]), (3, e[NY])] {
            if flow[q] != 0.0 {
                self.local[5 + q] += est;
            }
        }
        let a = k0[1].abs().max(trial.k7[1].abs());
        if a > 0.0 {
            self.lag += e[1] / a;
        }
    }

    /// Whether every result of `r` is within [`LIMIT`] × [`BOUND`] by the
    /// estimate. A lane that did not end `ok` has no results to refine.
    pub fn within(&self, r: &LaneResult) -> bool {
        crate::columns::integrated(r).enumerate().all(|(i, v)| {
            let est = self.phase[i] + self.local[i];
            // NaN (a lane that did not finish) compares false: within.
            !(est > LIMIT * BOUND * v.abs().max(1.0))
        })
    }
}

/// Whether a lane that ended with `r` and `budget` under `set` is to be
/// run again at [`Settings::tighter`].
pub fn needs_refining(set: &Settings, r: &LaneResult, budget: &ErrorBudget) -> bool {
    set.refine && r.status == super::Status::Ok && !budget.within(r)
}

/// The settings a lane's row comes from: `set`, or the tighter ones when
/// its run under `set` needs refining (for traces, which must come from
/// the same integration as the row).
pub fn settings_for(
    lane: &Lane,
    table: Option<&crate::model::FrictionTable>,
    set: &Settings,
) -> Settings {
    let (r, budget) = super::batch::run_lane(lane, table, set);
    if needs_refining(set, &r, &budget) {
        set.tighter()
    } else {
        *set
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::{simulate, RowPath};
    use crate::params::{Num, Spec};

    /// A paper-law lane with the given parameters (others at MODEL.md's
    /// defaults).
    fn lane(set: &[(Num, f64)]) -> Lane {
        let mut s = Spec::default();
        for &(n, v) in set {
            s.set(n, v);
        }
        Lane::new(&s.resolve(false).unwrap(), None)
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
        let (first, budget) = super::super::batch::run_lane(&l, None, &set);
        // Unrefined, w1_out is 1.3e-6 off: the estimate must see it.
        assert!(rel(first.w1_out, 1.094897114995884) > 1e-6);
        assert!(!budget.within(&first));
        let r = simulate(&l, None, &set);
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
        let (first, _) = super::super::batch::run_lane(&l, None, &set);
        assert!(rel(first.w_load, -0.2639743164097439) > 1e-6);
        let r = simulate(&l, None, &set);
        assert_eq!(r.path, RowPath::Refined);
        assert!(rel(r.w_load, -0.2639743164097439) < 1e-6, "{}", r.w_load);
        assert!(rel(r.x1_end, 0.0004854995080163585) < 1e-6, "{}", r.x1_end);
    }

    /// The paper's cases (MODEL.md section 7) are within the bound as
    /// they are: no second run.
    #[test]
    fn the_papers_cases_are_not_refined() {
        for f2 in [4774.0, -4774.0] {
            let r = simulate(&lane(&[(Num::F2, f2)]), None, &Settings::default());
            assert_eq!(r.path, RowPath::Cpu, "f2 {f2}");
        }
    }
}
