//! The data sheet of a small run (at most [`SHEET_LANES`] lanes): one
//! column a lane, in the terms the lane was given (gear terms, torques
//! and rpm, for a lane given so), with what a catalogue lists: running
//! and starting efficiency both ways, the static lock margin, whether the
//! drive is self-locking, and what became of it (docs/model.md section
//! 10). Its numbers are the lane's `lanes.csv` cells, rounded to four
//! significant digits.

use super::html::Page;
use crate::columns::{self, CONTACT_END, DRIVE, HOLD, LOCK_MARGIN_DEG, STATUS};
use crate::params::{gear, Num, Param};

/// Runs of at most this many lanes get a data sheet.
pub(crate) const SHEET_LANES: u64 = 12;

/// Lanes a table of the sheet shows side by side.
const COLUMNS: usize = 6;

/// The result columns the sheet reads, in its order.
const RESULTS: [&str; 15] = [
    STATUS,
    DRIVE,
    HOLD,
    CONTACT_END,
    columns::ETA_DIRECT_SS,
    columns::ETA_INVERSE_SS,
    columns::ETA_DIRECT_START,
    columns::ETA_INVERSE_START,
    LOCK_MARGIN_DEG,
    columns::ETA_DIRECT,
    columns::ETA_INVERSE,
    columns::V1_END,
    columns::N1_END,
    columns::N2_END,
    columns::T_STOP,
];

/// The lanes' cells as `lanes.csv` spells them: parameters, then
/// [`RESULTS`].
#[derive(Default)]
pub struct Sheet {
    pub(super) lanes: Vec<Vec<String>>,
}

/// The columns the sheet reads: every parameter, then its results.
pub fn names() -> Vec<&'static str> {
    let mut n: Vec<&'static str> = Param::COLUMNS.iter().map(|p| p.name()).collect();
    n.extend(RESULTS);
    n
}

/// `v` to four significant digits ("0.8254", "4774", "-0.2956").
pub(crate) fn sig4(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let digits = (3 - v.abs().log10().floor() as i32).max(0) as usize;
    let s = format!("{v:.digits$}");
    // "4774.0" has no more to say than "4774".
    if s.contains('.') && digits > 0 {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

impl Sheet {
    /// A lane's cell of column `name`.
    fn cell<'a>(&self, lane: &'a [String], name: &str) -> &'a str {
        let i = names().iter().position(|n| *n == name).unwrap_or(0);
        lane.get(i).map_or("", String::as_str)
    }

    fn number(&self, lane: &[String], name: &str) -> f64 {
        self.cell(lane, name).parse().unwrap_or(f64::NAN)
    }

    /// Whether a lane was given in gear terms (a geometry).
    fn geared(&self, lane: &[String]) -> bool {
        [Num::D1, Num::R1]
            .iter()
            .any(|n| !self.cell(lane, n.name()).is_empty())
    }

    /// The parameter rows: each parameter any lane has, in the terms each
    /// was given (a wedge parameter that a lane's gear term gave is left
    /// out of that lane's column).
    fn param_rows(&self, lanes: &[&Vec<String>]) -> Vec<Vec<String>> {
        let mut rows = Vec::new();
        for p in Param::COLUMNS {
            let cells: Vec<String> = lanes
                .iter()
                .map(|l| {
                    let from_gear = match p {
                        Param::Num(n) => {
                            self.geared(l)
                                && gear::GEAR.iter().any(|&g| {
                                    gear::gives(g) == Some(n) && !self.cell(l, g.name()).is_empty()
                                })
                        }
                        _ => false,
                    };
                    let c = self.cell(l, p.name());
                    match c.parse::<f64>() {
                        _ if from_gear || c.is_empty() => String::new(),
                        Ok(v) => sig4(v),
                        Err(_) => c.to_string(),
                    }
                })
                .collect();
            if cells.iter().all(String::is_empty) {
                continue;
            }
            let unit = match p {
                Param::Num(n) if !n.def().unit.is_empty() => format!(" ({})", n.def().unit),
                _ => String::new(),
            };
            let mut row = vec![format!("{}{unit}", p.name())];
            row.extend(cells);
            rows.push(row);
        }
        rows
    }

    /// What became of a lane, in words.
    fn outcome(&self, l: &[String]) -> String {
        let status = self.cell(l, STATUS);
        if status != "ok" {
            return format!("not finished ({status}): no results");
        }
        match (self.cell(l, DRIVE), self.cell(l, HOLD)) {
            ("runs", _) => "runs: the motor drives the load".into(),
            ("overhauled", _) => "overhauled: the load overhauls, the motor brakes it".into(),
            ("stalled", _) => "stalled: the motor cannot start (or keep moving) the load".into(),
            ("back_driven", _) => "back-driven: the load drives the worm backwards".into(),
            (_, "held") => "held: the drive holds its load with the motor off".into(),
            (_, "runs_away") => "runs away: the load back-drives the gear, motor off".into(),
            (_, "coasting") => "coasting: still sliding with the motor off (set t_max)".into(),
            _ if self.cell(l, CONTACT_END) == "stick" => "at rest, no motor".into(),
            _ => "sliding, no motor".into(),
        }
    }

    /// Whether a lane is self-locking, in words: statically by its lock
    /// margin, and while running by its running inverse efficiency.
    fn self_locking(&self, l: &[String]) -> String {
        let m = self.number(l, LOCK_MARGIN_DEG);
        if m.is_nan() {
            return String::new();
        }
        let running = self.number(l, columns::ETA_INVERSE_SS);
        let sliding = self.cell(l, CONTACT_END) != "stick";
        let dynamic = if sliding && running <= 0.0 {
            "; also while running (eta_inverse_ss <= 0)"
        } else {
            ""
        };
        if m > 0.0 {
            format!("yes: holds its load at rest with the motor off{dynamic}")
        } else {
            format!("no: the load can back-drive it from rest{dynamic}")
        }
    }

    /// The result rows of `lanes`.
    fn result_rows(&self, lanes: &[&Vec<String>]) -> Vec<Vec<String>> {
        let num = |l: &[String], name: &str| -> String {
            let at_rest = self.cell(l, CONTACT_END) == "stick";
            match self.cell(l, name).parse::<f64>() {
                _ if at_rest && columns::result(name).is_some_and(|c| c.running) => {
                    "at rest: no running point".into()
                }
                Ok(v) => sig4(v),
                Err(_) => String::new(),
            }
        };
        let row = |label: &str, f: &dyn Fn(&[String]) -> String| -> Vec<String> {
            let mut r = vec![label.to_string()];
            r.extend(lanes.iter().map(|l| f(l)));
            r
        };
        let mut rows = vec![
            row("outcome", &|l| self.outcome(l)),
            row("self-locking", &|l| self.self_locking(l)),
            row("static lock margin, lock_margin_deg (deg)", &|l| {
                num(l, LOCK_MARGIN_DEG)
            }),
            row("running direct efficiency, eta_direct_ss", &|l| {
                num(l, columns::ETA_DIRECT_SS)
            }),
            row("running inverse efficiency, eta_inverse_ss", &|l| {
                num(l, columns::ETA_INVERSE_SS)
            }),
            row("starting direct efficiency, eta_direct_start", &|l| {
                num(l, columns::ETA_DIRECT_START)
            }),
            row("starting inverse efficiency, eta_inverse_start", &|l| {
                num(l, columns::ETA_INVERSE_START)
            }),
            row("over the run, direct: eta_direct", &|l| {
                num(l, columns::ETA_DIRECT)
            }),
            row("over the run, inverse: eta_inverse", &|l| {
                num(l, columns::ETA_INVERSE)
            }),
        ];
        if lanes.iter().any(|l| self.geared(l)) {
            rows.push(row("worm speed at the end, n1_end (rpm)", &|l| {
                num(l, columns::N1_END)
            }));
            rows.push(row("wheel speed at the end, n2_end (rpm)", &|l| {
                num(l, columns::N2_END)
            }));
        } else {
            rows.push(row("speed at the end, v1_end (m/s)", &|l| {
                num(l, columns::V1_END)
            }));
        }
        rows.push(row("stopped at, t_stop (s)", &|l| num(l, columns::T_STOP)));
        rows
    }

    /// The section: a table of at most [`COLUMNS`] lanes at a time.
    pub fn section(&self, page: &mut Page) {
        if self.lanes.is_empty() {
            return;
        }
        page.section("Data sheet");
        page.note(
            "Each lane as a catalogue lists a drive, in the terms it was given (its lanes.csv row, \
             to four significant digits). Running (_ss) efficiencies are at the final sliding \
             speed; starting (_start) ones at breakaway from rest, with static friction. \
             Self-locking: the static lock margin is > 0, so the load is held at rest with the \
             motor off.",
        );
        for (k, chunk) in self.lanes.chunks(COLUMNS).enumerate() {
            let lanes: Vec<&Vec<String>> = chunk.iter().collect();
            let heads: Vec<String> = (0..lanes.len())
                .map(|i| format!("lane {}", k * COLUMNS + i))
                .collect();
            let mut head = vec!["".to_string()];
            head.extend(heads);
            let head: Vec<&str> = head.iter().map(String::as_str).collect();
            let mut rows = self.param_rows(&lanes);
            rows.extend(self.result_rows(&lanes));
            page.table(&head, &rows);
        }
    }

    /// One sentence a lane for what the page says first: its outcome and
    /// whether it is self-locking.
    pub(crate) fn sentences(&self) -> Vec<String> {
        self.lanes
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let locking = self.self_locking(l);
                if locking.is_empty() {
                    format!("Lane {i}: {}.", self.outcome(l))
                } else {
                    format!("Lane {i}: {}; self-locking: {locking}.", self.outcome(l))
                }
            })
            .collect()
    }
}
