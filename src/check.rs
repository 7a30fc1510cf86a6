//! CPU against GPU on the same lanes: a lane *agrees* when its
//! status, switches, reversals, sticks and final contact are identical, its
//! first switch is within 2e-5 s and x1, v1 and the three works are within
//! 5e-5 of max(1, |value|). The check passes when at least 98 % of lanes
//! agree; every other lane is listed with the reason.
//!
//! The worst deviation of each column (over lanes whose discrete fields
//! agree) and the number of lanes over each bound are reported too: lanes
//! that miss are f32-ill-conditioned cases (a switch near synchronous speed
//! under a near-zero load, a contact force that grazes zero), and the
//! report shows how many there are and how far they are off.

use std::fmt::Write as _;

use crate::backend::{Backend, CpuBackend};
use crate::error::Result;
use crate::integrator::LaneResult;
use crate::lanes::Source;
use crate::model::FrictionTable;
use crate::params::Params;
use crate::runner::{pipeline, Sink};

/// Bound on first-switch times, s.
pub const SWITCH_BOUND: f64 = 2e-5;
/// Bound on x1, v1 and the works, relative to max(1, |value|).
pub const VALUE_BOUND: f64 = 5e-5;
/// Least share of lanes that must agree.
pub const AGREE_SHARE: f64 = 0.98;

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
    /// Worst deviation of each of [`COLUMNS`] and its lane (lanes whose
    /// discrete fields agree).
    pub worst: [(f64, u64); 6],
    /// Lanes over the bound, per column.
    pub over: [u64; 6],
    /// Lanes whose discrete fields differ.
    pub discrete_differ: u64,
    /// Every lane that does not agree: (lane, reason).
    pub others: Vec<(u64, String)>,
}

impl Report {
    /// Adds lanes `first..` with their CPU (reference) and GPU results.
    pub fn add(&mut self, first: u64, cpu: &[LaneResult], gpu: &[LaneResult]) {
        for (i, (c, g)) in cpu.iter().zip(gpu).enumerate() {
            let lane = first + i as u64;
            self.lanes += 1;
            let (dc, dg) = (discrete(c), discrete(g));
            if dc != dg {
                self.discrete_differ += 1;
                self.others
                    .push((lane, format!("discrete fields differ: cpu {dc}, gpu {dg}")));
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
            let mut reasons = Vec::new();
            for (k, d) in dev.into_iter().enumerate() {
                // NaN (numbers on one side only) counts as infinitely far.
                let d = if d.is_nan() { f64::INFINITY } else { d };
                if d > self.worst[k].0 {
                    self.worst[k] = (d, lane);
                }
                let bound = if k == 0 { SWITCH_BOUND } else { VALUE_BOUND };
                if d > bound {
                    self.over[k] += 1;
                    reasons.push(format!("{} off by {d:.3e} (bound {bound:.0e})", COLUMNS[k]));
                }
            }
            if !reasons.is_empty() {
                self.others.push((lane, reasons.join(", ")));
            }
        }
    }

    /// Share of lanes that agree.
    pub fn agree_share(&self) -> f64 {
        if self.lanes == 0 {
            1.0
        } else {
            1.0 - self.others.len() as f64 / self.lanes as f64
        }
    }

    /// Whether at least 98 % of lanes agree.
    pub fn passes(&self) -> bool {
        self.agree_share() >= AGREE_SHARE
    }

    /// The printed report.
    pub fn text(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "{:<16} {:>12} {:>8} {:>10}  worst lane",
            "column", "worst", "bound", "lanes over"
        );
        for (i, c) in COLUMNS.iter().enumerate() {
            let bound = if i == 0 { SWITCH_BOUND } else { VALUE_BOUND };
            let (w, lane) = self.worst[i];
            let _ = writeln!(
                s,
                "{c:<16} {w:>12.3e} {bound:>8.0e} {:>10}  {lane}",
                self.over[i]
            );
        }
        let _ = writeln!(
            s,
            "discrete fields (status/switches/reversals/sticks/contact) differ on {} lanes",
            self.discrete_differ
        );
        let _ = writeln!(
            s,
            "{} of {} lanes agree within every bound ({:.3} %, at least {:.0} % required); the others:",
            self.lanes - self.others.len() as u64,
            self.lanes,
            100.0 * self.agree_share(),
            100.0 * AGREE_SHARE
        );
        for (lane, why) in &self.others {
            let _ = writeln!(s, "  lane {lane}: {why}");
        }
        s
    }
}

/// The comparison as a sink of the runner's pipeline: each chunk the GPU
/// returns is run again on the CPU path and compared.
struct Compare {
    cpu: CpuBackend,
    table: Option<FrictionTable>,
    cpu_results: Vec<LaneResult>,
    report: Report,
}

impl Sink for Compare {
    type Output = Report;
    fn chunk(&mut self, first: u64, params: &[Params], results: &[LaneResult]) -> Result<()> {
        self.cpu
            .run_chunk(first, params, self.table.as_ref(), &mut self.cpu_results)?;
        self.report.add(first, &self.cpu_results, results);
        Ok(())
    }
    fn finish(self) -> Result<Report> {
        Ok(self.report)
    }
}

/// Runs every lane of `source` on `gpu` and on `cpu` and compares them.
pub fn compare(
    source: &Source,
    gpu: &mut dyn Backend,
    cpu: CpuBackend,
    progress: bool,
) -> Result<Report> {
    let sink = Compare {
        cpu,
        table: source.friction_table().copied(),
        cpu_results: Vec::new(),
        report: Report::default(),
    };
    pipeline(source, gpu, progress, sink)
}
