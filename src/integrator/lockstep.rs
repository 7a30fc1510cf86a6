//! N lanes in lockstep on one thread ([`Slots`], the batch driver's
//! slots): the part of their states every step reads and writes,
//! component-major (`y[i][j]`: component i of lane j), and the common
//! step attempt on it as vector code.
//!
//! Most attempts are common: an accepted step with no event inside, not
//! landing on a time event, whose mesh powers keep their signs; or a
//! rejected one. For those a lane's plan and its outcome (the state, the
//! energy flow, the error budget, the next size) are computed for all N
//! lanes at once, branch-free, with the same per-lane arithmetic as the
//! automaton's (`step::step_size`, `step::retry_size`, `flow::split_whole`,
//! `accuracy::Budgets::add_steps`, `events::Watch::at_end`: one function
//! each, shared). Every other attempt goes to the automaton
//! (`step::prepare`, `step::finish_step`) on the lane's [`LaneState`], which
//! this part is copied into and back from around it. So a lane's row is
//! the bits of `simulate`'s whichever path each of its steps took.

use super::accuracy::Budgets;
use super::automaton::{init, LaneState};
use super::events::Watch;
use super::flow::{crosses, split_whole};
use super::rhs::{powers, Coefs};
use super::step::{
    finish_step, prepare, retry_size, steep_at_rest, step_size, time_stop, StepPlan,
};
use super::stepper::{try_steps, Mode, Trials};
use super::{Settings, NY};
use crate::model::{FrictionTable, Lane};

/// The lanes a driver is to run, by index, in order.
pub(crate) type Order<'a> = &'a mut dyn Iterator<Item = usize>;
/// What a driver does with a finished lane: its index and end state.
pub(crate) type Done<'a> = &'a mut dyn FnMut(usize, &LaneState);

/// The hot part of N lanes' states, and what the common step reads of
/// their automata.
struct Lanes<const N: usize> {
    t: [f64; N],
    /// The proposed size of each lane's next step.
    h: [f64; N],
    y: [[f64; N]; NY],
    k1: [[f64; N]; NY],
    flow: [[f64; N]; 4],
    budget: Budgets<N>,
    steps: [u32; N],
    /// The lane is done (its automaton says so).
    done: [bool; N],
    /// The common plan applies: sliding, derivative valid, not done.
    ready: [bool; N],
    /// The next time event.
    t_stop: [f64; N],
    steep: [bool; N],
    /// What each lane's steps watch for (its direction among it).
    dir: [f64; N],
    running_on: [bool; N],
    agma: [bool; N],
    upper: [bool; N],
    inv_cos_g: [f64; N],
}

impl<const N: usize> Lanes<N> {
    /// N empty slots.
    const EMPTY: Lanes<N> = Lanes {
        t: [0.0; N],
        h: [0.0; N],
        y: [[0.0; N]; NY],
        k1: [[0.0; N]; NY],
        flow: [[0.0; N]; 4],
        budget: Budgets::ZERO,
        steps: [0; N],
        done: [true; N],
        ready: [false; N],
        t_stop: [0.0; N],
        steep: [false; N],
        dir: [0.0; N],
        running_on: [false; N],
        agma: [false; N],
        upper: [false; N],
        inv_cos_g: [0.0; N],
    };

    /// Slot j from lane `lane`'s state `st`.
    #[inline]
    fn load(&mut self, j: usize, lane: &Lane, st: &LaneState) {
        self.t[j] = st.t;
        self.h[j] = st.h;
        for i in 0..NY {
            self.y[i][j] = st.y[i];
            self.k1[i][j] = st.k1[i];
        }
        for q in 0..4 {
            self.flow[q][j] = st.flow[q];
        }
        self.budget.load(j, &st.budget);
        self.steps[j] = st.steps;
        self.done[j] = st.done;
        self.ready[j] = !st.stuck && st.k1_valid && !st.done;
        self.t_stop[j] = time_stop(lane, st);
        self.steep[j] = steep_at_rest(lane);
        let w = Watch::of(lane, st.mode(), st.running_on);
        self.dir[j] = w.dir;
        self.running_on[j] = w.running_on;
        self.agma[j] = w.agma;
        self.upper[j] = w.upper;
        self.inv_cos_g[j] = w.inv_cos_g;
    }

    /// Slot j's hot part back into its lane's state `st`.
    #[inline]
    fn store(&self, j: usize, st: &mut LaneState) {
        st.t = self.t[j];
        st.h = self.h[j];
        for i in 0..NY {
            st.y[i] = self.y[i][j];
            st.k1[i] = self.k1[i][j];
        }
        for q in 0..4 {
            st.flow[q] = self.flow[q][j];
        }
        self.budget.store(j, &mut st.budget);
        st.steps = self.steps[j];
    }

    /// The common plan of every slot (`step::prepare` of a ready lane):
    /// the size of the step to try and whether it lands on the time
    /// event. Meaningless for slots that are not ready.
    #[inline(always)]
    fn plan(&self) -> ([f64; N], [bool; N]) {
        let mut h = [0.0; N];
        let mut landing = [false; N];
        for j in 0..N {
            (h[j], landing[j]) = step_size(
                self.h[j],
                self.steep[j],
                self.dir[j],
                self.y[1][j],
                self.k1[1][j],
                self.t_stop[j] - self.t[j],
            );
        }
        (h, landing)
    }

    /// Ends the attempts of the `active` slots, which tried steps of size
    /// `h` (`landing` on their time events) with outcome `tr`, where the
    /// attempt is common (`step::finish_step`'s arithmetic); returns the
    /// slots whose attempt is not, left as they were for the automaton.
    #[inline(always)]
    fn finish(
        &mut self,
        active: &[bool; N],
        h: &[f64; N],
        landing: &[bool; N],
        tr: &Trials<N>,
        set: &Settings,
    ) -> [bool; N] {
        let mut accept = [false; N];
        let mut retry = [false; N];
        let mut slow = [false; N];
        let mut h_next = [0.0; N];
        let mut d = [[0.0; N]; 4];
        for j in 0..N {
            let rejected = tr.err[j] > 1.0;
            let (h_retry, underflow) = retry_size(h[j], tr.fac[j], self.t[j]);
            let watch = Watch {
                dir: self.dir[j],
                running_on: self.running_on[j],
                agma: self.agma[j],
                upper: self.upper[j],
                inv_cos_g: self.inv_cos_g[j],
            };
            let ends = watch.at_end(tr.y1[1][j], tr.k7[1][j], tr.g_switch[j]);
            let event = ends.iter().any(|g| *g < 0.0);
            // The mesh powers p1 and p2 at the step's ends.
            let (p1_0, p2_0) = powers(self.k1[4][j], self.k1[5][j]);
            let (p1_end, p2_end) = powers(tr.k7[4][j], tr.k7[5][j]);
            let finite = (0..NY).all(|i| tr.y1[i][j].is_finite());
            let plain = !event
                && !landing[j]
                && !crosses(p1_0, p1_end)
                && !crosses(p2_0, p2_end)
                && finite
                && self.steps[j] < set.max_steps;
            accept[j] = active[j] && !rejected && plain;
            retry[j] = active[j] && rejected && !underflow;
            slow[j] = active[j] && !accept[j] && !retry[j];
            h_next[j] = if rejected { h_retry } else { h[j] * tr.fac[j] };
            [d[0][j], d[1][j]] = split_whole(tr.dw[0][j], p1_0, p1_end);
            [d[2][j], d[3][j]] = split_whole(tr.dw[1][j], p2_0, p2_end);
        }
        self.budget
            .add_steps(&accept, &self.k1, &tr.k7, &tr.est, &d);
        for j in 0..N {
            let a = accept[j];
            for (f, d) in self.flow.iter_mut().zip(&d) {
                f[j] = if a { f[j] + d[j] } else { f[j] };
            }
            for i in 0..NY {
                self.y[i][j] = if a { tr.y1[i][j] } else { self.y[i][j] };
                self.k1[i][j] = if a { tr.k7[i][j] } else { self.k1[i][j] };
            }
            self.t[j] = if a { self.t[j] + h[j] } else { self.t[j] };
            self.steps[j] += u32::from(a);
            self.h[j] = if a || retry[j] { h_next[j] } else { self.h[j] };
        }
        slow
    }
}

/// N slots of one thread's driver: which lane each holds, its automaton's
/// state and its hot part ([`Lanes`]), its mode and the right-hand sides'
/// constants, and the scratch of the trial steps.
pub(crate) struct Slots<const N: usize> {
    slot: [Option<usize>; N],
    st: [LaneState; N],
    hot: Lanes<N>,
    trials: Trials<N>,
    mode: [Mode; N],
    /// The constants, kept while a slot's lane and mode stay: `fresh[j]`
    /// until the automaton runs on slot j or it takes a new lane.
    coefs: Coefs<N>,
    fresh: [bool; N],
}

impl<const N: usize> Slots<N> {
    /// N empty slots (`any` is a lane to fill the unused ones with).
    #[inline(always)]
    pub(crate) fn new(any: &Lane, tables: &[FrictionTable]) -> Slots<N> {
        let mode = [StepPlan::IDLE.mode; N];
        Slots {
            slot: [None; N],
            st: [init(any, tables); N],
            hot: Lanes::EMPTY,
            trials: Trials::ZERO,
            mode,
            coefs: Coefs::of(&[any; N], &mode),
            fresh: [false; N],
        }
    }

    /// Runs `f` (the automaton) on slot j, lane `lane`: its state copied
    /// out of the hot part and back.
    #[inline(always)]
    fn on_automaton<R>(&mut self, j: usize, lane: &Lane, f: impl FnOnce(&mut LaneState) -> R) -> R {
        self.hot.store(j, &mut self.st[j]);
        let r = f(&mut self.st[j]);
        self.hot.load(j, lane, &self.st[j]);
        self.mode[j] = self.st[j].mode();
        self.fresh[j] = false;
        r
    }

    /// Hands each finished slot's lane to `done` and gives the slot the
    /// next lane of `order`; false when no slot holds a lane any more.
    #[inline(always)]
    pub(crate) fn refill(
        &mut self,
        lanes: &[Lane],
        order: Order,
        tables: &[FrictionTable],
        done: Done,
    ) -> bool {
        for j in 0..N {
            if let Some(i) = self.slot[j] {
                if !self.hot.done[j] {
                    continue;
                }
                self.hot.store(j, &mut self.st[j]);
                done(i, &self.st[j]);
                self.slot[j] = None;
            }
            if let Some(next) = order.next() {
                self.st[j] = init(&lanes[next], tables);
                self.hot.load(j, &lanes[next], &self.st[j]);
                self.mode[j] = self.st[j].mode();
                self.fresh[j] = false;
                self.slot[j] = Some(next);
            }
        }
        self.slot.iter().any(Option::is_some)
    }

    /// One step attempt of every slot with a lane: planned, tried and,
    /// where common, ended as vector code; the automaton on the others.
    #[inline(always)]
    pub(crate) fn attempt(&mut self, lanes: &[Lane], tables: &[FrictionTable], set: &Settings) {
        let (mut h, mut landing) = self.hot.plan();
        let mut active = [false; N];
        for j in 0..N {
            let Some(i) = self.slot[j] else { continue };
            if self.hot.done[j] {
                continue;
            }
            if self.hot.ready[j] {
                active[j] = true;
            } else if let Some(p) =
                self.on_automaton(j, &lanes[i], |s| prepare(&lanes[i], tables, s))
            {
                (h[j], landing[j], active[j]) = (p.h, p.landing(), true);
            }
        }
        if !active.iter().any(|&a| a) {
            return;
        }
        let mut lane = [&lanes[0]; N];
        for (l, s) in lane.iter_mut().zip(&self.slot) {
            *l = &lanes[s.unwrap_or(0)];
        }
        for j in 0..N {
            if active[j] && !self.fresh[j] {
                self.coefs.set(j, lane[j], self.mode[j]);
                self.fresh[j] = true;
            }
        }
        let hot = &mut self.hot;
        try_steps::<N>(
            &self.coefs,
            lane,
            tables,
            self.mode,
            &hot.y,
            &hot.k1,
            h,
            set,
            &mut self.trials,
        );
        let slow = hot.finish(&active, &h, &landing, &self.trials, set);
        for j in (0..N).filter(|&j| slow[j]) {
            let plan = StepPlan::new(self.mode[j], h[j], self.hot.t_stop[j], landing[j]);
            let trial = self.trials.lane(j);
            self.on_automaton(j, lane[j], |s| {
                finish_step(lane[j], tables, set, s, &plan, &trial)
            });
        }
    }
}
