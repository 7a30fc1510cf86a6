//! CPU against GPU on the same lanes: a lane *agrees* when the columns the
//! table of result columns compares exactly (status, switches, reversals,
//! sticks, final contact, hold) are identical, its first switch is within
//! 2e-5 s and x1, v1, the works, the mesh energies and the stop time are
//! within 5e-5 of max(1, |value|) (`columns::Compare`). The check passes
//! when at least 98 % of lanes agree; every other lane is listed with the
//! reason. Rows of the f64 GPU path (`--precision f64`) are held to the
//! CPU path's own bound instead: 1e-6 on every compared column, on every
//! lane.
//!
//! The worst deviation of each column (over lanes whose discrete fields
//! agree) and the number of lanes over each bound are reported too, the
//! verdict first; at most 20 disagreeing lanes are listed (all of them go
//! to a CSV file when asked), so memory does not grow with them. Lanes
//! that miss are f32-ill-conditioned cases (a switch near synchronous speed
//! under a near-zero load, a contact force that grazes zero), and the
//! report shows how many there are and how far they are off.

use std::fmt::Write as _;
use std::io::Write as _;

use crate::backend::{Backend, CpuBackend};
use crate::columns::{results, Column, Compare};
use crate::error::Result;
use crate::input::lanes::Source;
use crate::integrator::LaneResult;
use crate::model::FrictionTable;
use crate::params::ParamColumns;
use crate::progress::Show;
use crate::run::{pipeline, Sink};

pub use crate::columns::{SWITCH_BOUND, VALUE_BOUND};
/// Least share of lanes that must agree.
pub(crate) const AGREE_SHARE: f64 = 0.98;

/// The compared continuous columns, in table order.
pub fn compared() -> Vec<&'static Column> {
    results()
        .iter()
        .filter(|c| matches!(c.compare, Compare::Seconds(_) | Compare::Relative(_)))
        .collect()
}

/// The bound of a compared column on the f32 path's rows.
fn bound(c: &Column) -> f64 {
    match c.compare {
        Compare::Seconds(b) | Compare::Relative(b) => b,
        _ => f64::INFINITY,
    }
}

/// The bound on every compared column of the f64 GPU path's rows: the
/// CPU path's (1e-6 s in time, 1e-6 of max(1, |value|)).
pub const F64_BOUND: f64 = crate::integrator::accuracy::BOUND;

/// The discrete fields of a row, joined by `/`.
fn discrete(r: &LaneResult) -> String {
    results()
        .iter()
        .filter(|c| c.compare == Compare::Exact)
        .map(|c| match c.cell(0, r) {
            crate::columns::Cell::S(w) => w.into_owned(),
            x => format!("{}", x.number()),
        })
        .collect::<Vec<_>>()
        .join("/")
}

/// Disagreeing lanes listed in the printed report; all of them go to the
/// `--disagreements` file when one is asked for.
pub const LISTED: usize = 20;

/// Accumulated comparison. Its memory does not grow with the number of
/// lanes or of disagreeing lanes.
pub struct Report {
    /// Lanes compared.
    pub lanes: u64,
    /// Worst deviation of each of [`compared`] and its lane (lanes whose
    /// discrete fields agree).
    pub worst: Vec<(f64, u64)>,
    /// Lanes over the bound, per column.
    pub over: Vec<u64>,
    /// Lanes whose discrete fields differ.
    pub discrete_differ: u64,
    /// Lanes that do not agree.
    pub disagree: u64,
    /// GPU rows the GPU path's self-check recomputed in f64.
    pub recomputed: u64,
    /// The first [`LISTED`] lanes that do not agree: (lane, reason).
    pub listed: Vec<(u64, String)>,
    /// Every lane that does not agree, as CSV rows (lane,reason).
    pub all: Option<Box<dyn std::io::Write + Send>>,
    /// Rows of the f64 GPU path: every column held to [`F64_BOUND`], on
    /// every lane.
    pub f64_rows: bool,
}

impl Default for Report {
    fn default() -> Report {
        let n = compared().len();
        Report {
            lanes: 0,
            worst: vec![(0.0, 0); n],
            over: vec![0; n],
            discrete_differ: 0,
            disagree: 0,
            recomputed: 0,
            listed: Vec::new(),
            all: None,
            f64_rows: false,
        }
    }
}

impl Report {
    /// A report that also writes every disagreeing lane to `all`.
    pub(crate) fn writing_to(mut all: Box<dyn std::io::Write + Send>) -> std::io::Result<Report> {
        writeln!(all, "lane,reason")?;
        Ok(Report {
            all: Some(all),
            ..Report::default()
        })
    }

    fn disagrees(&mut self, lane: u64, why: String) -> std::io::Result<()> {
        self.disagree += 1;
        if let Some(w) = self.all.as_mut() {
            writeln!(w, "{lane},\"{why}\"")?;
        }
        if self.listed.len() < LISTED {
            self.listed.push((lane, why));
        }
        Ok(())
    }

    /// Adds lanes `first..` with their CPU (reference) and GPU results.
    pub fn add(
        &mut self,
        first: u64,
        cpu: &[LaneResult],
        gpu: &[LaneResult],
    ) -> std::io::Result<()> {
        for (i, (c, g)) in cpu.iter().zip(gpu).enumerate() {
            let lane = first + i as u64;
            self.lanes += 1;
            if matches!(g.path, crate::integrator::RowPath::Recomputed(_)) {
                self.recomputed += 1;
            }
            let (dc, dg) = (discrete(c), discrete(g));
            if dc != dg {
                self.discrete_differ += 1;
                self.disagrees(lane, format!("discrete fields differ: cpu {dc}, gpu {dg}"))?;
                continue;
            }
            let mut reasons = Vec::new();
            for (k, col) in compared().into_iter().enumerate() {
                let (a, b) = (col.cell(lane, g).number(), col.cell(lane, c).number());
                let d = match col.compare {
                    // Both have none (no switch): nothing to compare.
                    Compare::Seconds(_) if a.is_nan() && b.is_nan() => 0.0,
                    Compare::Seconds(_) => (a - b).abs(),
                    _ if a.is_nan() && b.is_nan() => 0.0,
                    _ => (a - b).abs() / b.abs().max(1.0),
                };
                // NaN (numbers on one side only) counts as infinitely far.
                let d = if d.is_nan() { f64::INFINITY } else { d };
                if d > self.worst[k].0 {
                    self.worst[k] = (d, lane);
                }
                let bound = self.bound(col);
                if d > bound {
                    self.over[k] += 1;
                    reasons.push(format!("{} off by {d:.3e} (bound {bound:.0e})", col.name));
                }
            }
            if !reasons.is_empty() {
                self.disagrees(lane, reasons.join(", "))?;
            }
        }
        Ok(())
    }

    /// The bound of a compared column on these rows.
    fn bound(&self, c: &Column) -> f64 {
        [bound(c), F64_BOUND][self.f64_rows as usize]
    }

    /// Least share of lanes that must agree: [`AGREE_SHARE`], or every
    /// lane for the f64 path's rows.
    fn required(&self) -> f64 {
        [AGREE_SHARE, 1.0][self.f64_rows as usize]
    }

    /// Share of lanes that agree.
    pub(crate) fn agree_share(&self) -> f64 {
        if self.lanes == 0 {
            1.0
        } else {
            1.0 - self.disagree as f64 / self.lanes as f64
        }
    }

    /// Whether at least 98 % of lanes agree (every lane, for the f64
    /// path's rows).
    pub fn passes(&self) -> bool {
        self.agree_share() >= self.required()
    }

    /// The printed report: the verdict first, then the table per column,
    /// then at most [`LISTED`] disagreeing lanes.
    pub fn text(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "{}: {} of {} lanes agree within every bound ({:.3} %, at least {:.0} % required)",
            if self.passes() { "PASS" } else { "FAIL" },
            self.lanes - self.disagree,
            self.lanes,
            100.0 * self.agree_share(),
            100.0 * self.required()
        );
        // The name column as wide as the longest name, so the table lines up.
        let wide = compared()
            .iter()
            .map(|c| c.name.len())
            .max()
            .unwrap_or(6)
            .max("column".len());
        let _ = writeln!(
            s,
            "{:<wide$} {:>10} {:>6} {:>10} {:>10}",
            "column", "worst", "bound", "lanes over", "worst lane"
        );
        for (i, c) in compared().into_iter().enumerate() {
            let bound = self.bound(c);
            let (w, lane) = self.worst[i];
            let _ = writeln!(
                s,
                "{:<wide$} {w:>10.3e} {bound:>6.0e} {:>10} {lane:>10}",
                c.name, self.over[i]
            );
        }
        let exact: Vec<&str> = results()
            .iter()
            .filter(|c| c.compare == Compare::Exact)
            .map(|c| c.name)
            .collect();
        let _ = writeln!(
            s,
            "discrete fields ({}) differ on {} lanes; \
             {} GPU rows were recomputed in f64 by the GPU path's self-check",
            exact.join("/"),
            self.discrete_differ,
            self.recomputed
        );
        if self.disagree > 0 {
            let _ = writeln!(
                s,
                "{} lanes disagree; the first {}{}:",
                self.disagree,
                self.listed.len(),
                if self.all.is_some() {
                    " (all of them are in the --disagreements file)"
                } else {
                    " (all of them: --disagreements FILE.csv)"
                }
            );
        }
        for (lane, why) in &self.listed {
            let _ = writeln!(s, "  lane {lane}: {why}");
        }
        s
    }
}

/// The comparison as a sink of the runner's pipeline: each chunk the GPU
/// returns is run again on the CPU path and compared.
struct Comparison {
    cpu: CpuBackend,
    tables: Vec<FrictionTable>,
    cpu_results: Vec<LaneResult>,
    report: Report,
}

impl Sink for Comparison {
    type Output = Report;
    fn chunk(
        &mut self,
        first: u64,
        params: &mut ParamColumns,
        results: &[LaneResult],
    ) -> Result<()> {
        self.cpu
            .run_chunk(first, params, &self.tables, &mut self.cpu_results)?;
        self.report
            .add(first, &self.cpu_results, results)
            .map_err(|e| crate::error::Error::Internal(format!("writing the disagreements: {e}")))
    }
    fn finish(mut self) -> Result<Report> {
        if let Some(w) = self.report.all.as_mut() {
            w.flush().map_err(|e| {
                crate::error::Error::Internal(format!("writing the disagreements: {e}"))
            })?;
        }
        Ok(self.report)
    }
}

/// Runs every lane of `source` on `gpu` and on `cpu` and compares them
/// into `report`.
pub fn compare(
    source: &Source,
    gpu: &mut dyn Backend,
    cpu: CpuBackend,
    show: &Show,
    report: Report,
) -> Result<Report> {
    let sink = Comparison {
        cpu,
        tables: source.friction_tables().tables.clone(),
        cpu_results: Vec::new(),
        report,
    };
    pipeline(source, gpu, show, sink)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::{Contact, RowPath, Status};

    fn row(x: f64) -> LaneResult {
        LaneResult {
            status: Status::Ok,
            contact_end: Contact::Aa,
            x1_end: x,
            v1_end: 1.0,
            w_motor: 1.0,
            w_load: 1.0,
            w_friction: 1.0,
            eta_end: 0.5,
            steps: 1,
            w1_in: 1.0,
            w1_out: 0.0,
            w2_in: 0.0,
            w2_out: 1.0,
            eta_direct: 1.0,
            eta_direct_ss: 0.7,
            eta_inverse_ss: 0.6,
            lock_margin_deg: 1.0,
            t_stop: 2.0,
            path: RowPath::Gpu,
            ..LaneResult::EMPTY
        }
    }

    /// 1,000 disagreeing lanes: the verdict comes first, 20 are listed,
    /// all 1,000 go to the file, and the report holds only the 20.
    #[test]
    fn disagreeing_lanes_are_bounded_in_print_and_memory() {
        let file = std::sync::Arc::new(std::sync::Mutex::new(Vec::<u8>::new()));
        struct Shared(std::sync::Arc<std::sync::Mutex<Vec<u8>>>);
        impl std::io::Write for Shared {
            fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
                self.0.lock().unwrap().extend_from_slice(b);
                Ok(b.len())
            }
            fn flush(&mut self) -> std::io::Result<()> {
                Ok(())
            }
        }
        let mut r = Report::writing_to(Box::new(Shared(file.clone()))).unwrap();
        let cpu: Vec<_> = (0..2000).map(|_| row(1.0)).collect();
        let gpu: Vec<_> = (0..2000)
            .map(|i| row(if i % 2 == 0 { 1.0 } else { 2.0 }))
            .collect();
        r.add(0, &cpu, &gpu).unwrap();
        let text = r.text();
        assert!(text.starts_with("FAIL: 1000 of 2000 lanes agree"), "{text}");
        assert_eq!(r.listed.len(), LISTED);
        assert_eq!(
            text.lines().filter(|l| l.starts_with("  lane ")).count(),
            LISTED
        );
        let csv = String::from_utf8(file.lock().unwrap().clone()).unwrap();
        assert_eq!(csv.lines().count(), 1 + 1000);
        assert!(csv
            .lines()
            .nth(1)
            .unwrap()
            .starts_with("1,\"x1_end off by 1.000e0"));
    }
}
