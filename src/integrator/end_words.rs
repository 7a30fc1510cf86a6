//! The words a lane's end gives it (`hold`, `drive`: docs/model.md
//! section 10) from its end state, and whether those words are decided
//! where the end speed is known only to a bound (the GPU's f32 rows).

use super::outcome::{Drive, Hold};
use super::result::{speeding_up, EndState};
use crate::model::kernel::sliding_speed;
use crate::model::{branch_of, motion, FrictionTable, Lane, Mode, Motion};

impl EndState {
    /// The lane's end mode, at speed `v` (its branch is the one `v` is on).
    pub(crate) fn mode_at(&self, lane: &Lane, tables: &[FrictionTable], v: f64) -> Mode {
        Mode {
            side: self.side,
            dir: self.dir,
            motor_on: self.motor_on,
            branch: branch_of(lane, tables, sliding_speed(1.0, v.abs(), lane.inv_cos_g)),
        }
    }

    /// `hold` and `drive` of a lane that ended `ok` at speed `v`, `m` its
    /// motion there in its end mode.
    pub(crate) fn words(&self, lane: &Lane, m: &Motion, v: f64) -> (Option<Hold>, Option<Drive>) {
        let hold = lane.motor_cut().then(|| {
            if self.stuck {
                Hold::Held
            } else if self.speeding || speeding_up(self.dir, m.acc) {
                Hold::RunsAway
            } else {
                Hold::Coasting
            }
        });
        (hold, self.drive(lane, m.s1 * v, v))
    }

    /// What the motor achieved, for a lane whose motor runs to the end
    /// and drives: stalled at rest, else by the direction of motion
    /// against the motor's, and in the motor's direction by the power
    /// `p1` = S1 ẋ1 the worm side puts into the mesh (negative: the load
    /// overhauls and the motor brakes it).
    fn drive(&self, lane: &Lane, p1: f64, v: f64) -> Option<Drive> {
        let d = lane.motor_direction().filter(|_| !lane.motor_cut())?;
        if self.stuck {
            return Some(Drive::Stalled);
        }
        // The direction of motion; at an exact zero speed the direction
        // the lane was sliding in.
        let s = if v != 0.0 {
            v.signum()
        } else {
            self.dir as f64
        };
        Some(if s != d {
            Drive::BackDriven
        } else if p1 < 0.0 {
            Drive::Overhauled
        } else {
            Drive::Runs
        })
    }

    /// Whether the lane's words `said` (its `hold` and `drive`) are the
    /// same at every end speed within `dv` of its own: they turn on signs
    /// at the end (of p1, of the acceleration, of the speed), and where
    /// one of them changes within the speed's bound, a row whose speed is
    /// known only to that bound cannot vouch for its word. Checked at both
    /// ends of the interval (each sign changes once there: p1 at
    /// synchronous speed or where ρ crosses γ, the acceleration at a
    /// terminal speed). At rest and stuck, or with no word, nothing turns.
    /// A lane whose running on ended where it began to speed up is held
    /// to its acceleration there too: in a mode the speed cannot pass a
    /// terminal speed (where the acceleration is 0), so a speeding event
    /// located at one is rounding (f32 ran a table lane on to it at 6.2 s
    /// where the f64 path coasts on towards it to t_max, 18.3 s).
    pub fn words_decided(
        &self,
        lane: &Lane,
        tables: &[FrictionTable],
        said: (Option<Hold>, Option<Drive>),
        dv: f64,
    ) -> bool {
        if self.stuck || said == (None, None) {
            return true;
        }
        let by_acc = EndState {
            speeding: false,
            ..*self
        };
        let at = |v: f64| {
            let m = motion(lane, tables, self.mode_at(lane, tables, v), v);
            by_acc.words(lane, &m, v)
        };
        let v = self.y[1];
        at(v - dv) == said && at(v + dv) == said
    }
}
