//! What became of a finished lane, in one word for the report's outcome
//! maps, lines and tables: the motor's answer (`drive`) for a lane whose
//! motor runs to the end, the load's (`hold`) for one whose motor is cut
//! (docs/model.md section 10). A motor-on lane at rest is "stalled",
//! never "held".

use plotters::style::RGBColor;

/// The outcomes, in the order of the legends: (word shown, colour).
pub const OUTCOMES: [(&str, RGBColor); 9] = [
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
pub const STALLED: usize = 2;

/// The outcomes of a lane at rest at its end (stalled, held, at rest
/// with no motor): it has no running point.
pub const AT_REST: [usize; 3] = [STALLED, 4, 7];

/// The colour of a cell with no finished lane.
pub const NONE_COLOUR: RGBColor = RGBColor(200, 200, 200);

/// The outcome of a finished lane from its `contact_end`, `hold` and
/// `drive` cells (words as the results table spells them).
pub fn of(contact: &str, hold: &str, drive: &str) -> usize {
    match (hold, drive) {
        ("held", _) => 4,
        ("runs_away", _) => 5,
        ("coasting", _) => 6,
        (_, "runs") => 0,
        (_, "overhauled") => 1,
        (_, "stalled") => STALLED,
        (_, "back_driven") => 3,
        _ if contact == "stick" => 7,
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
        assert_eq!(OUTCOMES[of("stick", "", "stalled")].0, "stalled");
        assert_eq!(OUTCOMES[of("stick", "held", "")].0, "held");
        assert_eq!(OUTCOMES[of("aa", "", "back_driven")].0, "back-driven");
        assert_eq!(OUTCOMES[of("bb", "", "overhauled")].0, "overhauled");
        let rest: Vec<&str> = AT_REST.iter().map(|&k| OUTCOMES[k].0).collect();
        assert_eq!(rest, ["stalled", "held", "at rest, no motor"]);
        assert_eq!(OUTCOMES[of("stick", "", "")].0, "at rest, no motor");
    }
}
