//! The hybrid integrator: Dormand–Prince 5(4) with its 4th-order dense
//! output, events located by root finding inside the step, and the lane
//! automaton (contact side, direction, rest and sticking, motor cut-off,
//! running on past t_end).
//!
//! One file per part; the shader (`shaders/`) has a file for each part it
//! mirrors, of the same name: [`settings`] and [`components`] (what every
//! lane shares, the state's components), [`result`] (status and results,
//! and the one conversion from a lane's end state to its row),
//! [`control`] (step sizes), [`rhs`] and [`stepper`] (right-hand side,
//! tableau, trial step), [`events`] (event functions and root location),
//! [`flow`] (the in and out parts of the mesh energies), [`automaton`] (a
//! lane's state and its transitions), `verdict` (how an attempt ends,
//! for W lanes at once), [`step`] (one step attempt), [`batch`] (running
//! many lanes in lockstep, and again tighter when [`accuracy`]'s
//! estimate asks). [`trace`] takes a lane's rows through time from the
//! same steps; [`path`] says where a row came from.

pub mod accuracy;
pub mod automaton;
pub mod batch;
pub mod components;
pub mod control;
mod end_words;
pub mod events;
pub mod flow;
mod lockstep;
pub mod outcome;
pub mod path;
pub mod result;
pub mod rhs;
pub mod settings;
pub mod step;
pub mod stepper;
pub mod trace;
mod verdict;
pub mod width;

pub use automaton::{init, LaneState};
pub use batch::{first_pass, own_width, refine_pass, simulate, simulate_batch, simulate_batch_at};
pub use components::NY;
pub use control::H_INITIAL;
pub use result::{
    Contact, Drive, EndState, Hold, LaneResult, Recheck, RowPath, SearchOutcome, SearchStatus,
    Side, Status,
};
pub use settings::{Settings, DEFAULT_TOL};
pub use step::{advance, attempt};

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
            branch: 0,
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
