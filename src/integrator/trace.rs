//! Traces (docs/model.md section 11): a lane's state and internal forces over
//! time, from the dense output of the same integration that gives its row
//! of results (the same `prepare`, `try_step` and `finish_step`; only rows
//! are taken on the way). Rows come every `dt` from 0 to where the lane
//! stops (t_end, or up to t_max for a lane that runs on), one at the stop
//! itself when `dt` does not divide it (so the trace ends at the state of
//! the lane's row), and, at every event, twice with the same t: the state
//! just before it (old mode) and just after it (new mode).

use super::automaton::{init, LaneState};
use super::events::dense_v;
use super::result::{Contact, LaneResult};
use super::settings::Settings;
use super::step::{finish_step, prepare, trial};
use crate::model::{motion, motor_force, phi, FrictionTable, Lane};

/// One row of a trace (docs/model.md section 11).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraceRow {
    /// Time, s.
    pub t: f64,
    /// Position x1, m.
    pub x1: f64,
    /// Speed ẋ1, m/s.
    pub v1: f64,
    /// Acceleration ẍ1, m/s².
    pub a1: f64,
    /// Motor force F1, N.
    pub f1: f64,
    /// Contact reaction S1, N.
    pub s1: f64,
    /// Contact reaction S2, N.
    pub s2: f64,
    /// The force transfer function ψ; NaN while stuck.
    pub psi: f64,
    /// The switching function φ.
    pub phi: f64,
    /// The contact: a-a, b-b, or stuck.
    pub contact: Contact,
}

/// The row of a lane at time `t` with position `x`, speed `v` and the
/// mode of `st` (side, direction, motor, stuck).
fn row(lane: &Lane, tables: &[FrictionTable], st: &LaneState, t: f64, x: f64, v: f64) -> TraceRow {
    if st.stuck {
        let f1 = motor_force(lane, 0.0, st.motor_on);
        return TraceRow {
            t,
            x1: x,
            v1: 0.0,
            a1: 0.0,
            f1,
            s1: f1,
            s2: lane.f2,
            psi: f64::NAN,
            phi: phi(lane, 0.0, st.motor_on),
            contact: Contact::Stick,
        };
    }
    let m = motion(lane, tables, st.mode(), v);
    TraceRow {
        t,
        x1: x,
        v1: v,
        a1: m.acc,
        f1: m.f1,
        s1: m.s1,
        s2: m.s2,
        psi: m.psi,
        phi: phi(lane, v, st.motor_on),
        contact: if st.side > 0 {
            Contact::Aa
        } else {
            Contact::Bb
        },
    }
}

/// x1 at fraction θ of a step of size h from x0: the exact integral of the
/// dense output of ẋ1, r0 + θ(r1 + (1−θ)(r2 + θ(r3 + (1−θ) r4))).
fn dense_x(x0: f64, h: f64, r: &[f64; 5], th: f64) -> f64 {
    let c1 = r[0];
    let c2 = r[1] + r[2];
    let c3 = -r[2] + r[3] + r[4];
    let c4 = -r[3] - 2.0 * r[4];
    let c5 = r[4];
    x0 + h * th * (c1 + th * (c2 / 2.0 + th * (c3 / 3.0 + th * (c4 / 4.0 + th * c5 / 5.0))))
}

/// Runs one lane to its end exactly as `simulate` does, handing `out` a
/// row at every multiple of `dt` up to where it stops, one at the stop,
/// and two at every event.
pub fn simulate_traced(
    lane: &Lane,
    tables: &[FrictionTable],
    set: &Settings,
    dt: f64,
    sink: &mut dyn FnMut(&TraceRow),
) -> LaneResult {
    // The time of the last row handed on: the trace ends at the stop.
    let last_t = std::cell::Cell::new(f64::NEG_INFINITY);
    let mut out = |r: &TraceRow| {
        last_t.set(r.t);
        sink(r)
    };
    let mut st = init(lane, tables);
    // Rows up to t_end, or up to t_max for a lane that runs on (the run
    // ends where the lane stops, and so do its rows).
    let last = (lane.t_end.max(lane.t_max) / dt * (1.0 + 1e-12)).floor() as u64;
    let mut k = 0u64;
    let sample_t = |k: u64| k as f64 * dt;
    // The samples at t = 0 (only k = 0, unless dt is tiny).
    while k <= last && sample_t(k) <= st.t {
        out(&row(lane, tables, &st, sample_t(k), st.y[0], st.y[1]));
        k += 1;
    }
    while !st.done {
        let before = st;
        match prepare(lane, tables, &mut st) {
            None => {
                // A stick phase up to a time event: the state is constant.
                while k <= last && sample_t(k) <= st.t {
                    out(&row(lane, tables, &before, sample_t(k), before.y[0], 0.0));
                    k += 1;
                }
            }
            Some(plan) => {
                let trial = trial(lane, tables, plan.mode, &st, plan.h, set);
                let from = st;
                finish_step(lane, tables, set, &mut st, &plan, &trial);
                if st.t > from.t {
                    while k <= last && sample_t(k) < st.t {
                        let th = (sample_t(k) - from.t) / plan.h;
                        let v = dense_v(&trial.dense_v, th);
                        let x = dense_x(from.y[0], plan.h, &trial.dense_v, th);
                        out(&row(lane, tables, &from, sample_t(k), x, v));
                        k += 1;
                    }
                    // A sample at the step's end: the integrated state.
                    if k <= last && sample_t(k) <= st.t && st.events == before.events {
                        out(&row(lane, tables, &st, sample_t(k), st.y[0], st.y[1]));
                        k += 1;
                    }
                }
            }
        }
        if st.events > before.events {
            // Just before the event: the old mode at the event's state.
            let v_old = if st.stuck || st.dir != before.dir {
                0.0
            } else {
                st.y[1]
            };
            out(&row(lane, tables, &before, st.t, st.y[0], v_old));
            out(&row(lane, tables, &st, st.t, st.y[0], st.y[1]));
            while k <= last && sample_t(k) <= st.t {
                out(&row(lane, tables, &st, sample_t(k), st.y[0], st.y[1]));
                k += 1;
            }
        }
    }
    if last_t.get() < st.t {
        // dt does not divide the stop time: a row at the stop, the
        // state the lane's row reports.
        out(&row(lane, tables, &st, st.t, st.y[0], st.y[1]));
    }
    st.end_state().result(lane, tables)
}
