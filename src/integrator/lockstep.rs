//! N lanes in lockstep on one thread ([`Slots`], the batch driver's
//! slots): their states as columns ([`LaneStates`], `y[i][j]`: component
//! i of lane j), and the common step attempt on them as vector code.
//!
//! Each attempt is planned (`control::step_size`), tried (`try_steps`)
//! and judged (`verdict::verdicts`) for all N lanes at once; the common
//! endings are applied as vector code (`verdict::end_common`), and every
//! other attempt goes to the automaton (`step::prepare`,
//! `step::finish_uncommon`) on the lane's [`LaneState`], taken out of the
//! columns and put back. The one-lane path plans, judges and ends its
//! attempts with the same functions, so a lane's row is the bits of
//! `simulate`'s whichever path each of its steps took.

use super::automaton::{init, LaneState, LaneStates};
use super::components::NY;
use super::control::step_size;
use super::events::{Watch, Watches};
use super::settings::Settings;
use super::step::{finish_uncommon, prepare, time_stop, StepPlan};
use super::stepper::{try_steps, Trials};
use super::verdict::{end_common, verdicts};
use crate::model::{Coef, Coefs, FrictionTable, Lane, Mode};

/// The lanes a driver is to run, by index, in order.
pub(crate) type Order<'a> = &'a mut dyn Iterator<Item = usize>;
/// What a driver does with a finished lane: its index and end state.
pub(crate) type Done<'a> = &'a mut dyn FnMut(usize, &LaneState);

/// N lanes' states, and what the common step reads of their automata.
struct Lanes<const N: usize> {
    st: LaneStates<N>,
    /// The common plan applies: sliding, derivative valid, not done.
    ready: [bool; N],
    /// The next time event.
    t_stop: [f64; N],
    /// The lane's horizon (`Lane::t_end`).
    t_end: [f64; N],
    /// The friction law is steep at rest.
    steep: [bool; N],
    /// What each lane's steps watch for.
    watch: Watches<N>,
}

impl<const N: usize> Lanes<N> {
    /// N empty slots.
    #[inline(always)]
    fn empty() -> Lanes<N> {
        let mut st = LaneStates::zero();
        st.done = [true; N];
        Lanes {
            st,
            ready: [false; N],
            t_stop: [0.0; N],
            t_end: [0.0; N],
            steep: [false; N],
            watch: Watches::zero(),
        }
    }

    /// Slot j from lane `lane`'s state `st`.
    #[inline(always)]
    fn load(&mut self, j: usize, lane: &Lane, tables: &[FrictionTable], st: &LaneState) {
        self.st.set_lane(j, *st);
        self.ready[j] = !st.stuck && st.k1_valid && !st.done;
        self.t_end[j] = lane.t_end;
        self.t_stop[j] = time_stop(lane, st);
        self.steep[j] = lane.steep;
        self.watch
            .set_lane(j, Watch::of(lane, tables, st.mode(), st.running_on));
    }

    /// The common plan of every slot (`step::prepare` of a ready lane):
    /// the size of the step to try and whether it lands on the time
    /// event. Meaningless for slots that are not ready.
    #[inline(always)]
    fn plan(&self) -> ([f64; N], [bool; N]) {
        let mut h = [0.0; N];
        let mut landing = [false; N];
        let st = &self.st;
        for j in 0..N {
            (h[j], landing[j]) = step_size(
                st.h[j],
                self.steep[j],
                self.watch.dir[j],
                st.y[1][j],
                st.k1[1][j],
                self.t_stop[j] - st.t[j],
            );
        }
        (h, landing)
    }
}

/// N slots of one thread's driver: which lane each holds, its state
/// ([`Lanes`]), its mode and the right-hand sides' constants, and the
/// scratch of the trial steps.
pub(crate) struct Slots<const N: usize> {
    slot: [Option<usize>; N],
    hot: Lanes<N>,
    trials: Trials<N>,
    /// Each component's cap on a trial's error (`Budgets::caps`).
    cap: [[f64; N]; NY],
    mode: [Mode; N],
    /// The constants, kept while a slot's lane and mode stay: `fresh[j]`
    /// until the automaton runs on slot j or it takes a new lane.
    coefs: Coefs<N>,
    fresh: [bool; N],
}

impl<const N: usize> Slots<N> {
    /// N empty slots (`any` is a lane to fill the unused ones with).
    #[inline(always)]
    pub(crate) fn new(any: &Lane) -> Slots<N> {
        let mode = [StepPlan::IDLE.mode; N];
        Slots {
            slot: [None; N],
            hot: Lanes::empty(),
            trials: Trials::zero(),
            cap: [[f64::INFINITY; N]; NY],
            mode,
            coefs: Coefs::of(&[any; N], &mode),
            fresh: [false; N],
        }
    }

    /// Runs `f` (the automaton) on slot j, lane `lane`: its state taken
    /// out of the columns and put back.
    #[inline(always)]
    fn on_automaton<R>(
        &mut self,
        j: usize,
        lane: &Lane,
        tables: &[FrictionTable],
        f: impl FnOnce(&mut LaneState) -> R,
    ) -> R {
        let mut st = self.hot.st.lane(j);
        let r = f(&mut st);
        self.hot.load(j, lane, tables, &st);
        self.mode[j] = st.mode();
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
                if !self.hot.st.done[j] {
                    continue;
                }
                done(i, &self.hot.st.lane(j));
                self.slot[j] = None;
            }
            if let Some(next) = order.next() {
                let st = init(&lanes[next], tables);
                self.hot.load(j, &lanes[next], tables, &st);
                self.mode[j] = st.mode();
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
            if self.hot.st.done[j] {
                continue;
            }
            if self.hot.ready[j] {
                active[j] = true;
            } else if let Some(p) =
                self.on_automaton(j, &lanes[i], tables, |s| prepare(&lanes[i], tables, s))
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
                self.coefs.set_lane(j, Coef::of(lane[j], self.mode[j]));
                self.fresh[j] = true;
            }
        }
        let st = &mut self.hot.st;
        // Without steering the caps stay infinite (`Slots::new`), and
        // `capped` leaves every error scale as it is.
        let cap = &mut self.cap;
        if set.steers() {
            let t_end = &self.hot.t_end;
            st.budget
                .caps(&st.y, &st.k1, &st.flow, &st.t, t_end, &h, set, cap);
        }
        try_steps::<N>(
            &self.coefs,
            lane,
            tables,
            &st.y,
            &st.k1,
            h,
            cap,
            set,
            &mut self.trials,
        );
        let tr = &self.trials;
        let v = verdicts(
            &active,
            &h,
            &landing,
            &st.t,
            &st.steps,
            &self.hot.watch,
            &st.k1,
            tr,
            set,
        );
        end_common(st, &v, &h, tr);
        for j in (0..N).filter(|&j| v.slow[j]) {
            let plan = StepPlan::new(self.mode[j], h[j], self.hot.t_stop[j], landing[j]);
            let trial = self.trials.lane(j);
            self.on_automaton(j, lane[j], tables, |s| {
                finish_uncommon(lane[j], tables, set, s, &plan, &trial, v.h_next[j])
            });
        }
    }
}
