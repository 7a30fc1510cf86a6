//! CPU against GPU on the same lanes: the worst deviation of each result
//! column and the lanes whose discrete fields differ, judged by the bounds
//! of issue 3 (switch times 2e-5 s; x1, v1 and the works 5e-5 relative to
//! max(1, |value|); identical discrete fields on at least 98 % of lanes).

use std::fmt::Write as _;

use crate::integrator::LaneResult;

/// Bound on first-switch times, s.
pub const SWITCH_BOUND: f64 = 2e-5;
/// Bound on x1, v1 and the works, relative to max(1, |value|).
pub const VALUE_BOUND: f64 = 5e-5;
/// Least share of lanes whose discrete fields must agree.
pub const DISCRETE_SHARE: f64 = 0.98;

/// The compared continuous columns.
pub const COLUMNS: [&str; 6] = [
    "t_first_switch",
    "x1_end",
    "v1_end",
    "w_motor",
    "w_load",
    "w_friction",
];

fn discrete(r: &LaneResult) -> String {
    format!(
        "{}/{}/{}/{}/{}",
        r.status.name(),
        r.switches,
        r.reversals,
        r.sticks,
        r.contact_end.name()
    )
}

/// Accumulated comparison.
#[derive(Clone, Debug, Default)]
pub struct Report {
    /// Lanes compared.
    pub lanes: u64,
    /// Worst deviation of each of [`COLUMNS`] and its lane.
    pub worst: [(f64, u64); 6],
    /// Lanes whose discrete fields differ: (lane, cpu, gpu) as
    /// "status/switches/reversals/sticks/contact".
    pub mismatched: Vec<(u64, String, String)>,
}

impl Report {
    /// Adds lanes `first..` with their CPU (reference) and GPU results.
    pub fn add(&mut self, first: u64, cpu: &[LaneResult], gpu: &[LaneResult]) {
        for (i, (c, g)) in cpu.iter().zip(gpu).enumerate() {
            let lane = first + i as u64;
            self.lanes += 1;
            let (dc, dg) = (discrete(c), discrete(g));
            if dc != dg {
                self.mismatched.push((lane, dc, dg));
                continue;
            }
            let rel = |a: f64, b: f64| (a - b).abs() / b.abs().max(1.0);
            let dev = [
                if c.switches > 0 {
                    (g.t_first_switch - c.t_first_switch).abs()
                } else {
                    0.0
                },
                rel(g.x1_end, c.x1_end),
                rel(g.v1_end, c.v1_end),
                rel(g.w_motor, c.w_motor),
                rel(g.w_load, c.w_load),
                rel(g.w_friction, c.w_friction),
            ];
            for (w, d) in self.worst.iter_mut().zip(dev) {
                // NaN (a lane abandoned on one side only) counts as a miss.
                if d > w.0 || d.is_nan() {
                    *w = (if d.is_nan() { f64::INFINITY } else { d }, lane);
                }
            }
        }
    }

    /// Whether every bound holds.
    pub fn passes(&self) -> bool {
        let values_ok =
            self.worst[0].0 <= SWITCH_BOUND && self.worst[1..].iter().all(|w| w.0 <= VALUE_BOUND);
        values_ok && self.agree_share() >= DISCRETE_SHARE
    }

    /// Share of lanes whose discrete fields agree.
    pub fn agree_share(&self) -> f64 {
        if self.lanes == 0 {
            1.0
        } else {
            1.0 - self.mismatched.len() as f64 / self.lanes as f64
        }
    }

    /// The printed report.
    pub fn text(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "{:<16} {:>12} {:>8}  lane", "column", "worst", "bound");
        for (i, c) in COLUMNS.iter().enumerate() {
            let bound = if i == 0 { SWITCH_BOUND } else { VALUE_BOUND };
            let (w, lane) = self.worst[i];
            let mark = if w <= bound { "" } else { "  OVER" };
            let _ = writeln!(s, "{c:<16} {w:>12.3e} {bound:>8.0e}  {lane}{mark}");
        }
        let _ = writeln!(
            s,
            "discrete fields (status/switches/reversals/sticks/contact) differ on {} of {} lanes ({:.3} %, at most {:.0} % allowed)",
            self.mismatched.len(),
            self.lanes,
            100.0 * (1.0 - self.agree_share()),
            100.0 * (1.0 - DISCRETE_SHARE)
        );
        for (lane, c, g) in &self.mismatched {
            let _ = writeln!(s, "  lane {lane}: cpu {c}, gpu {g}");
        }
        s
    }
}
