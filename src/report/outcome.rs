//! What became of a finished lane, in one word for the report's outcome
//! maps, lines and tables: the motor's answer (`drive`) for a lane whose
//! motor runs to the end, the load's (`hold`) for one whose motor is cut
//! (docs/model.md section 10). A motor-on lane at rest is "stalled",
//! never "held".

use plotters::style::RGBColor;

use crate::integrator::{Contact, Drive, Hold};

/// The outcomes, in the order of the legends: (word shown, colour).
pub(crate) const OUTCOMES: [(&str, RGBColor); 9] = [
    ("runs", RGBColor(44, 160, 44)),
    ("overhauled", RGBColor(23, 190, 207)),
    ("stalled", RGBColor(214, 39, 40)),
    ("back-driven", RGBColor(255, 127, 14)),
    ("held", RGBColor(31, 119, 180)),
    ("runs away", RGBColor(148, 103, 189)),
    ("coasting", RGBColor(188, 189, 34)),
    ("at rest, no motor", RGBColor(140, 86, 75)),
    ("sliding, no motor", RGBColor(227, 119, 194)),
];

/// How many outcomes there are.
pub const N: usize = OUTCOMES.len();

/// The index of "stalled" in [`OUTCOMES`].
pub(crate) const STALLED: usize = 2;

/// The outcomes of a lane at rest at its end (stalled, held, at rest
/// with no motor): it has no running point.
pub(crate) const AT_REST: [usize; 3] = [STALLED, 4, 7];

/// The colour of a cell with no finished lane.
pub(crate) const NONE_COLOUR: RGBColor = RGBColor(200, 200, 200);

/// The outcome of a finished lane from its `contact_end`, `hold` and
/// `drive` cells (None: empty).
pub fn of(contact: Option<Contact>, hold: Option<Hold>, drive: Option<Drive>) -> usize {
    match (hold, drive) {
        (Some(Hold::Held), _) => 4,
        (Some(Hold::RunsAway), _) => 5,
        (Some(Hold::Coasting), _) => 6,
        (_, Some(Drive::Runs)) => 0,
        (_, Some(Drive::Overhauled)) => 1,
        (_, Some(Drive::Stalled)) => STALLED,
        (_, Some(Drive::BackDriven)) => 3,
        _ if contact == Some(Contact::Stick) => 7,
        _ => 8,
    }
}

/// The words of the outcomes that occur in `counts` (all when none does).
pub fn present(counts: &[u64; N]) -> Vec<usize> {
    let v: Vec<usize> = (0..N).filter(|&i| counts[i] > 0).collect();
    if v.is_empty() {
        (0..N).collect()
    } else {
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_motor_on_lane_at_rest_is_stalled_never_held() {
        let stick = Some(Contact::Stick);
        assert_eq!(OUTCOMES[of(stick, None, Some(Drive::Stalled))].0, "stalled");
        assert_eq!(OUTCOMES[of(stick, Some(Hold::Held), None)].0, "held");
        assert_eq!(
            OUTCOMES[of(Some(Contact::Aa), None, Some(Drive::BackDriven))].0,
            "back-driven"
        );
        assert_eq!(
            OUTCOMES[of(Some(Contact::Bb), None, Some(Drive::Overhauled))].0,
            "overhauled"
        );
        let rest: Vec<&str> = AT_REST.iter().map(|&k| OUTCOMES[k].0).collect();
        assert_eq!(rest, ["stalled", "held", "at rest, no motor"]);
        assert_eq!(OUTCOMES[of(stick, None, None)].0, "at rest, no motor");
    }
}
