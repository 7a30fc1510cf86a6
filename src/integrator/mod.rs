//! The hybrid integrator: Dormand–Prince 5(4) with its 4th-order dense
//! output, events located by root finding inside the step, and the lane
//! automaton (contact side, direction, rest and sticking, motor cut-off,
//! running on past t_end).
//!
//! One file per part, in the order the shader (`shaders/tswm.wgsl`) keeps
//! them, each of its sections headed by the file it mirrors:
//! [`result`] (status and results, and the one conversion from a lane's
//! end state to its row), [`stepper`] (tableau, right-hand side, trial
//! step), [`events`] (event functions and root location), [`flow`] (the
//! in and out parts of the mesh energies), [`automaton`] (a lane's state
//! and its transitions), [`step`] (one step attempt), [`batch`] (running
//! many lanes, and again tighter when [`accuracy`]'s estimate asks).
//! [`trace`] takes a lane's rows through time from the same steps;
//! [`path`] says where a row came from.

pub mod accuracy;
pub mod automaton;
pub mod batch;
pub mod control;
pub mod events;
pub mod flow;
mod lockstep;
pub mod outcome;
pub mod path;
pub mod result;
pub mod rhs;
pub mod step;
pub mod stepper;
pub mod trace;
pub mod width;

pub use automaton::{init, LaneState, H_INITIAL};
pub use batch::{first_pass, own_width, refine_pass, simulate, simulate_batch, simulate_batch_at};
pub use result::{Contact, Drive, EndState, Hold, LaneResult, Recheck, RowPath, Status};
pub use step::{advance, attempt};

/// Components of the integrated state: x1, ẋ1, w_motor, w_load,
/// w_friction and w_p1 = ∫p1 dt (docs/model.md sections 6 and 10; ∫p2 dt is
/// w_friction − w_p1). The in and out parts of section 10 are not
/// components: see [`flow`].
pub const NY: usize = 6;

/// Default per-step tolerance of the f64 path.
pub const DEFAULT_TOL: f64 = 1e-8;

/// Integration settings shared by every lane of a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// Error tolerance per step, relative to max(1, |y|) of each component.
    pub tol: f64,
    /// Factor on `tol` for x1 and ẋ1 (1: as the works). A lane's timing
    /// follows from ẋ1, and results that a late switch starts are as
    /// sensitive to it as to their own quadrature (see [`accuracy`]).
    pub traj_weight: f64,
    /// Whether a lane whose error estimate is over the bound is run again
    /// at [`Settings::tighter`] (see [`accuracy`]).
    pub refine: bool,
    /// Most accepted steps a lane may take.
    pub max_steps: u32,
    /// Most events (switches, stops, cut-offs) a lane may have.
    pub max_events: u32,
}

impl Default for Settings {
    fn default() -> Self {
        // tol chosen by measurement: 1e-8 keeps 3000 random user lanes
        // within 4e-7 of a 1e-13 integration (bound 1e-6); 2e-8 does not
        // keep that margin (see docs/numerics.md).
        Settings {
            tol: DEFAULT_TOL,
            traj_weight: 1.0,
            refine: true,
            max_steps: 1_000_000,
            max_events: 10_000,
        }
    }
}

impl Settings {
    /// The settings a lane is run again at when its error estimate is over
    /// the bound: a tenth of the tolerance, and a tenth of that again on x1
    /// and ẋ1 (measured on 15,096 lanes: every refined lane within 0.4 of
    /// the bound). Not refined again.
    pub fn tighter(&self) -> Settings {
        Settings {
            tol: 0.1 * self.tol,
            traj_weight: 0.1 * self.traj_weight,
            refine: true,
            ..*self
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{motion, Lane};
    use crate::params::{FrictionKind, MotorKind, Num, Spec};

    fn paper() -> Lane {
        Lane::new(&Spec::default().resolve(&[]).unwrap(), &[])
    }

    #[test]
    fn switch_time_is_located_inside_the_step() {
        // Paper case 1: the switch is at 0.486653423342 s (docs/model.md 7).
        let r = simulate(&paper(), &[], &Settings::default());
        assert_eq!(r.switches, 1);
        assert!(
            (r.t_first_switch - 0.48665342334234873).abs() < 1e-8,
            "{}",
            r.t_first_switch
        );
    }

    #[test]
    fn constant_force_deceleration_stops_at_the_analytic_time() {
        // Coulomb friction, constant forces: the rest time is v0 / |a|.
        let mut s = Spec {
            friction: Some(FrictionKind::Coulomb),
            motor: Some(MotorKind::Constant),
            ..Default::default()
        };
        s.set(Num::F1, 0.0);
        s.set(Num::F2, -4774.0);
        s.set(Num::Mu, 0.2);
        s.set(Num::V10, 2.0);
        s.set(Num::TEnd, 3.0);
        let l = Lane::new(&s.resolve(&[]).unwrap(), &[]);
        let mode = crate::model::Mode {
            side: 1,
            dir: 1,
            motor_on: true,
            upper: false,
        };
        let m = motion(&l, &[], mode, 1.0);
        let t_rest = 2.0 / -m.acc;
        let mut st = init(&l, &[]);
        // Advance until the stop, then check its time.
        while !st.stuck && !st.done {
            advance(&l, &[], &Settings::default(), &mut st, 1);
        }
        assert!(st.stuck);
        assert!((st.t - t_rest).abs() < 1e-12, "{} vs {}", st.t, t_rest);
        let x_rest = 2.0 * t_rest / 2.0;
        assert!((st.y[0] - x_rest).abs() < 1e-10);
    }
}
