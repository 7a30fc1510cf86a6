//! Events inside a step (docs/model.md section 8): the switching function's
//! sign change (a switch), ẋ1 reaching 0 (rest) and, while a lane runs on
//! past t_end with its motor cut, its acceleration turning from braking
//! to driving (speeding up: it runs away), and under a law of several
//! branches the sliding speed leaving its branch (`agma`'s 10 ft/min, a
//! `table`'s speeds), located by the Illinois method on the step's dense
//! output.

use super::stepper::Trial;
use crate::model::kernel::{load_term, sliding_speed};
use crate::model::{branch_edges, motion, phi, switch_value, FrictionTable, Lane, Mode};

/// Root-location tolerance for events, s.
pub const T_ROOT_TOL: f64 = 1e-13;

/// ẋ1 at fraction θ of the step, from the dense output.
#[inline]
pub(crate) fn dense_v(r: &[f64; 5], th: f64) -> f64 {
    let th1 = 1.0 - th;
    r[0] + th * (r[1] + th1 * (r[2] + th * (r[3] + th1 * r[4])))
}

/// Which event function a root is sought for. The codes are the shader's
/// `EV_*` constants.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum EventFn {
    /// c·φ(ẋ1): leaves > 0 when the contact side flips.
    Switch = 0,
    /// s·ẋ1: leaves > 0 when the lane comes to rest.
    Rest = 1,
    /// −s·ẍ1·D (−s·ẍ1 without its pole): leaves > 0 when a lane running
    /// on past t_end stops slowing down (only then is it looked for).
    Speeding = 2,
    /// Under a law of several branches (`agma`, `table`), the sliding
    /// speed's distance from the nearer edge of the mode's branch
    /// (`branch_edges`): leaves > 0 when the speed crosses to the next
    /// branch.
    Branch = 3,
}

impl EventFn {
    /// Every event function, in code order.
    pub const ALL: [EventFn; 4] = [
        EventFn::Switch,
        EventFn::Rest,
        EventFn::Speeding,
        EventFn::Branch,
    ];
}

/// The event function's value at speed `v`; an event is where it turns
/// from >= 0 to < 0.
#[inline]
pub(crate) fn event_value(
    lane: &Lane,
    tables: &[FrictionTable],
    mode: Mode,
    which: EventFn,
    v: f64,
) -> f64 {
    match which {
        EventFn::Switch => switch_value(
            mode.side as f64,
            phi(lane, v, mode.motor_on),
            load_term(lane.f2, lane.m2, lane.tan_g),
        ),
        EventFn::Rest => rest_value(mode.dir as f64, v),
        EventFn::Speeding => {
            let m = motion(lane, tables, mode, v);
            speeding_value(mode.dir as f64, m.acc, m.d)
        }
        EventFn::Branch => {
            let (lo, hi) = branch_edges(lane, tables, mode.branch);
            branch_value(mode.dir as f64, v, lane.inv_cos_g, lo, hi)
        }
    }
}

/// The rest event's function s·ẋ1 at speed `v`, direction `dir`.
#[inline(always)]
fn rest_value(dir: f64, v: f64) -> f64 {
    dir * v
}

/// The speeding-up event's function −s·ẍ1·D at acceleration `acc` and
/// D `d`: the sign of −s·ẍ1 where D > 0, without its pole. Where a wedge
/// jams, D passes 0 inside a step and ẍ1 = (F1 − ψ F2)/D through
/// infinity to the other sign: −s·ẍ1 then had a root there, read as the
/// lane speeding up (`runs_away`), where the lane is inconsistent.
#[inline(always)]
fn speeding_value(dir: f64, acc: f64, d: f64) -> f64 {
    -dir * acc * d
}

/// The branch event's function at speed `v`: the sliding speed's
/// distance from the nearer of its branch's edges `lo` and `hi` (an
/// infinite edge is never near).
#[inline(always)]
fn branch_value(dir: f64, v: f64, inv_cos_g: f64, lo: f64, hi: f64) -> f64 {
    let vs = sliding_speed(dir, v, inv_cos_g);
    (vs - lo).min(hi - vs)
}

/// Whether a lane that left its branch (edges `lo`, `hi`) at speed `v`
/// left it upwards, into the next branch, rather than downwards: the
/// nearer edge is the one crossed.
#[inline]
pub(crate) fn left_upwards(dir: f64, v: f64, inv_cos_g: f64, lo: f64, hi: f64) -> bool {
    let vs = sliding_speed(dir, v, inv_cos_g);
    hi - vs <= vs - lo
}

crate::lanewise_struct! {
    /// What a step checks for events: the lane's direction and, when they
    /// apply, the two events not every lane has.
    #[derive(Clone, Copy, Debug)]
    pub(crate) struct Watch, Watches {
        /// Direction of motion s.
        pub(crate) dir: f64,
        /// Contact side c (the mesh powers' signs follow from c and s:
        /// `flow::mode_signs`).
        pub(crate) side: f64,
        /// Running on past t_end: speeding up is an event.
        pub(crate) running_on: bool,
        /// The sliding speeds bounding the mode's branch, m/s
        /// (`branch_edges`): (−∞, ∞) for a law of one branch, whose
        /// branch event is then +∞, never < 0.
        pub(crate) lo: f64,
        /// See `lo`.
        pub(crate) hi: f64,
        /// 1 / cos γ.
        pub(crate) inv_cos_g: f64,
    }
}

impl Watch {
    /// What a lane in `mode` watches for.
    #[inline]
    pub(crate) fn of(lane: &Lane, tables: &[FrictionTable], mode: Mode, running_on: bool) -> Watch {
        let (lo, hi) = branch_edges(lane, tables, mode.branch);
        Watch {
            dir: mode.dir as f64,
            side: mode.side as f64,
            running_on,
            lo,
            hi,
            inv_cos_g: lane.inv_cos_g,
        }
    }

    /// The event functions at a step's end (speed `v`, acceleration
    /// `acc`, D `d`, switching function `g_switch`) in [`EventFn`] order: Rest,
    /// Switch, Speeding, Branch; +∞ for one the lane does not watch. An
    /// event lies inside the step where one is < 0.
    #[inline(always)]
    pub(crate) fn at_end(&self, v: f64, acc: f64, d: f64, g_switch: f64) -> [f64; 4] {
        let off = f64::INFINITY;
        [
            rest_value(self.dir, v),
            g_switch,
            if self.running_on {
                speeding_value(self.dir, acc, d)
            } else {
                off
            },
            branch_value(self.dir, v, self.inv_cos_g, self.lo, self.hi),
        ]
    }
}

/// Locates θ in [0, 1] where the event function crosses from >= 0 to < 0,
/// by the Illinois method on the dense output. Returns the bracket's left
/// end, so the event lies at most `theta_tol` after it.
pub fn locate_root(
    lane: &Lane,
    tables: &[FrictionTable],
    mode: Mode,
    which: EventFn,
    r: &[f64; 5],
    g_end: f64,
    theta_tol: f64,
) -> f64 {
    // A branch event's edge, found once for the whole search.
    let edge =
        (which == EventFn::Branch).then(|| crossed_edge(lane, tables, mode, dense_v(r, 1.0)));
    let value = |v: f64| match edge {
        Some((lo, hi)) => branch_value(mode.dir as f64, v, lane.inv_cos_g, lo, hi),
        None => event_value(lane, tables, mode, which, v),
    };
    let fa = value(r[0]);
    if fa <= 0.0 {
        return 0.0;
    }
    illinois(|th| value(dense_v(r, th)), fa, g_end, theta_tol).0
}

/// The edge of the mode's branch that a step ending at speed `v_end`
/// crossed, as edges (lo, hi) with the other one infinite: the upper
/// where the speed ended above it, else the lower. A step that starts a
/// branch starts on the edge it came in by, where rounding may put it a
/// hair outside; so the root is sought on the edge the step left by
/// alone, not on the nearer edge, which at the start is the one behind
/// it.
#[inline]
fn crossed_edge(lane: &Lane, tables: &[FrictionTable], mode: Mode, v_end: f64) -> (f64, f64) {
    let (lo, hi) = branch_edges(lane, tables, mode.branch);
    if hi - sliding_speed(mode.dir as f64, v_end, lane.inv_cos_g) < 0.0 {
        (f64::NEG_INFINITY, hi)
    } else {
        (lo, f64::INFINITY)
    }
}

/// The bracket [a, b] ⊂ [0, 1] around a crossing of `g` from >= 0 (at a)
/// to < 0 (at b), narrowed by the Illinois method until it is at most
/// `tol` wide (or after 100 iterations); `g0` and `g1` are g(0) > 0 and
/// g(1) < 0. Events and the energy flow's sign change share it.
#[inline]
pub(crate) fn illinois(g: impl Fn(f64) -> f64, g0: f64, g1: f64, tol: f64) -> (f64, f64) {
    let (mut a, mut fa) = (0.0, g0);
    let (mut b, mut fb) = (1.0, g1);
    let mut side = 0;
    for _ in 0..100 {
        if b - a <= tol {
            break;
        }
        let mut c = (a * fb - b * fa) / (fb - fa);
        // Keep the secant point strictly inside, else bisect.
        if !(c > a && c < b) {
            c = 0.5 * (a + b);
        }
        let fc = g(c);
        if fc >= 0.0 {
            a = c;
            fa = fc;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            b = c;
            fb = fc;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
    }
    (a, b)
}

/// The earliest event inside an accepted step of size `h`: its fraction θ
/// of the step and which it is; None when the step holds no event. A rest
/// and a switch at the same θ count as a rest. `running_on`: the lane
/// runs on past t_end, so speeding up is an event too.
#[inline]
pub(crate) fn earliest_event(
    lane: &Lane,
    tables: &[FrictionTable],
    mode: Mode,
    trial: &Trial,
    h: f64,
    running_on: bool,
) -> Option<(f64, EventFn)> {
    let theta_tol = T_ROOT_TOL / h;
    let mut theta = 2.0;
    let mut which = EventFn::Rest;
    let watch = Watch::of(lane, tables, mode, running_on);
    // The switching function at the step's end came with the trial (the
    // same arithmetic as `event_value`, as vector code); the step's end
    // derivative holds the acceleration there.
    let ends = watch.at_end(trial.y1[1], trial.k7[1], trial.d_end, trial.g_switch);
    let order = [
        EventFn::Rest,
        EventFn::Switch,
        EventFn::Speeding,
        EventFn::Branch,
    ];
    // In this order: a rest and a switch at the same θ count as a rest.
    for (f, g_end) in order.into_iter().zip(ends) {
        if g_end < 0.0 {
            let th = locate_root(lane, tables, mode, f, &trial.dense_v, g_end, theta_tol);
            if th < theta {
                theta = th;
                which = f;
            }
        }
    }
    (theta <= 1.0).then_some((theta, which))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Spec;

    #[test]
    fn dense_output_interpolates_ends() {
        let r = [1.0, 0.5, 0.3, -0.2, 0.1];
        assert_eq!(dense_v(&r, 0.0), 1.0);
        assert!((dense_v(&r, 1.0) - 1.5).abs() < 1e-15);
    }

    #[test]
    fn locate_root_finds_a_known_crossing() {
        // A constant-force lane: ẋ1 is linear in time, so the rest event of
        // a decelerating lane is known exactly.
        let mut l = Lane::new(&Spec::default().resolve(&[]).unwrap(), &[]);
        l.motor = crate::model::MotorKind::Constant;
        l.f1 = 0.0;
        let mode = Mode {
            side: 1,
            dir: 1,
            motor_on: true,
            branch: 0,
        };
        // v(θ) = 1 − 4θ as dense coefficients: r2 = −4, r3 = h k1 − r2 = 0, ...
        let r = [1.0, -4.0, 0.0, 0.0, 0.0];
        let th = locate_root(&l, &[], mode, EventFn::Rest, &r, -3.0, 1e-14);
        assert!((th - 0.25).abs() < 1e-13, "{th}");
    }
}
