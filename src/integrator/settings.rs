//! The integration settings every lane of a run shares.

/// Default per-step tolerance of the f64 path.
pub const DEFAULT_TOL: f64 = 1e-8;

/// The error budget steers a lane's steps (`accuracy::Budgets::caps`)
/// only at a tolerance looser than this, the default: there the budget
/// would send most lanes to a second run. At the default it sends 1 to 6
/// in 100, and a lane's steps are its tolerance's alone (with the caps
/// there, a stop time that the budget does not cover moved past the
/// bound on one lane of the tests' sweeps, and every lane paid for them).
pub const STEER_ABOVE: f64 = DEFAULT_TOL;

/// A lane run again ([`Settings::tighter`]) is run at this fraction of
/// the tolerance; where the budget steers, no step's cap drops below this
/// fraction of the error scale at `Settings::floor_tol_of` either
/// (`accuracy::Budgets::caps`, the shader's `REFINE_FACTOR`).
pub const REFINE_FACTOR: f64 = 0.1;

/// The loosest tolerance the floor of the budget's caps follows
/// (`Settings::floor_tol_of`): at a looser one the floor stays at
/// [`REFINE_FACTOR`] times this one's error scale. With the floor at a
/// tenth of any tolerance, the steps of a loose one spent most lanes'
/// budgets, most lanes were run a second time, and a tolerance looser
/// than 3e-7 was slower (1e-5 by 44 %). 3e-7 is where the peer lane
/// table, random user lanes and the heterogeneous sweep ran the fewest
/// instructions with the floor at a tenth of the tolerance
/// (docs/performance.md).
pub const CAP_FLOOR_TOL: f64 = 3e-7;

/// Integration settings shared by every lane of a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// Error tolerance per step, relative to max(1, |y|) of each component.
    pub tol: f64,
    /// Factor on `tol` for x1 and ẋ1 (1: as the works). A lane's timing
    /// follows from ẋ1, and results that a late switch starts are as
    /// sensitive to it as to their own quadrature (see `accuracy`).
    pub traj_weight: f64,
    /// Whether a lane whose error estimate is over the bound is run again
    /// at [`Settings::tighter`] (see `accuracy`).
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
            tol: REFINE_FACTOR * self.tol,
            traj_weight: REFINE_FACTOR * self.traj_weight,
            refine: true,
            ..*self
        }
    }

    /// Whether the error budget steers the steps ([`STEER_ABOVE`]).
    #[inline(always)]
    pub(crate) fn steers(&self) -> bool {
        self.tol > STEER_ABOVE
    }

    /// The tolerance whose error scale, times [`REFINE_FACTOR`], is the
    /// floor of component `i`'s cap (`accuracy::Budgets::caps`): its own
    /// tolerance, or [`CAP_FLOOR_TOL`] where that is tighter. So a lane's
    /// first run never works to a finer scale than its run again would
    /// (a tenth of its tolerance), and at a loose tolerance its budget is
    /// not spent by steps the loose tolerance alone would take.
    #[inline(always)]
    pub(crate) fn floor_tol_of(&self, i: usize) -> f64 {
        crate::model::vmath::smaller(self.tol_of(i), CAP_FLOOR_TOL)
    }

    /// The tolerance of component `i`: x1 and ẋ1 may be held tighter than
    /// the works ([`Settings::traj_weight`]).
    #[inline(always)]
    pub(crate) fn tol_of(&self, i: usize) -> f64 {
        if i < 2 {
            self.tol * self.traj_weight
        } else {
            self.tol
        }
    }
}
