//! The one-line summary of a run: lanes by status, final contact and
//! hold, the rows recomputed or refined, and what to do about lanes still
//! coasting.

use std::collections::BTreeMap;

use super::pipeline::Busy;
use std::path::Path;

use crate::integrator::{Contact, Drive, Hold, LaneResult, RowPath, SearchStatus, Side, Status};
use crate::params::{Num, ParamColumns};

/// Counts for the end-of-run summary.
#[derive(Debug, Default, Clone)]
pub struct Summary {
    /// Lanes run.
    pub lanes: u64,
    /// Wall time, s.
    pub seconds: f64,
    /// Lanes by status.
    pub by_status: BTreeMap<Status, u64>,
    /// Lanes by final contact (finished lanes).
    pub by_contact: BTreeMap<Contact, u64>,
    /// Lanes by the path their row came from.
    pub by_path: BTreeMap<RowPath, u64>,
    /// Lanes whose motor is cut, by what became of the load.
    pub by_hold: BTreeMap<Hold, u64>,
    /// Lanes whose motor runs to the end, by what the motor achieved.
    pub by_drive: BTreeMap<Drive, u64>,
    /// The largest t_end of a lane still coasting, and whether one had a
    /// t_max.
    pub coasting_t_end: f64,
    /// See [`Summary::coasting_t_end`].
    pub coasting_with_t_max: bool,
    /// Time spent on the sensitivity indices (a sensitivity design), s.
    pub sensitivity_seconds: Option<f64>,
    /// Time the backend spent integrating and the writer writing, s.
    pub busy: super::pipeline::Busy,
    /// A search's drives by how their search ended.
    pub by_search: BTreeMap<SearchStatus, u64>,
    /// Lanes a search integrated.
    pub search_lanes: u64,
    /// A share search's boundaries (from `summary.csv`'s statistics), and
    /// the searched parameter's name.
    pub boundaries: Vec<crate::stats::summary::Boundary>,
    /// The searched parameter's name (a search run).
    pub search_param: Option<&'static str>,
}

impl Summary {
    /// Counts a chunk's lanes: each run of lanes with the same words
    /// counted at once (a sweep's neighbouring lanes mostly end alike).
    pub(super) fn add_chunk(&mut self, params: &ParamColumns, results: &[LaneResult]) {
        let (t_end, t_max) = (params.num(Num::TEnd), params.num(Num::TMax));
        let key = |r: &LaneResult| {
            (
                r.status,
                r.contact_end,
                r.hold,
                r.drive,
                r.path,
                r.search.map(|s| s.status),
            )
        };
        for r in results {
            if let Some(sr) = r.search {
                self.search_lanes += u64::from(sr.lanes);
            }
        }
        let mut i = 0;
        while i < results.len() {
            let r = &results[i];
            let run = 1 + results[i + 1..]
                .iter()
                .take_while(|q| key(q) == key(r))
                .count();
            self.add(r, run as u64);
            if r.hold == Some(Hold::Coasting) {
                for k in i..i + run {
                    self.coasting_t_end = self.coasting_t_end.max(t_end[k]);
                    self.coasting_with_t_max |= !t_max[k].is_nan();
                }
            }
            i += run;
        }
    }

    /// Counts `n` lanes that ended as `r`.
    fn add(&mut self, r: &LaneResult, n: u64) {
        self.lanes += n;
        *self.by_status.entry(r.status).or_default() += n;
        if r.status == Status::Ok {
            *self.by_contact.entry(r.contact_end).or_default() += n;
        }
        if let Some(h) = r.hold {
            *self.by_hold.entry(h).or_default() += n;
        }
        if let Some(d) = r.drive {
            *self.by_drive.entry(d).or_default() += n;
        }
        *self.by_path.entry(r.path).or_default() += n;
        if let Some(sr) = r.search {
            *self.by_search.entry(sr.status).or_default() += n;
        }
    }

    /// "; search: found N, ...; boundary ..." for a search run: how its
    /// drives' searches ended, and a share boundary's answer (one group's;
    /// more are in summary.csv).
    fn search_note(&self) -> String {
        if self.by_search.is_empty() {
            return String::new();
        }
        let mut s = format!("; search: {}", counts(&self.by_search, |x| x.name()));
        let param = self.search_param.unwrap_or("");
        match self.boundaries.as_slice() {
            [] => {}
            [b] => {
                let tick = |v: f64| format!("{v:.6}");
                let share = 100.0 * b.ranks.q;
                let share = match b.side {
                    Side::Below => 100.0 - share,
                    Side::Above => share,
                };
                let share = format!("{share:.4}");
                let share = share.trim_end_matches('0').trim_end_matches('.');
                s.push_str(&format!(
                    "; boundary of {share} % of drives: {param} = {} (95 %: {} to {}; {} {} \
                     with 95 % confidence)",
                    tick(b.value()),
                    tick(b.interval.0),
                    tick(b.interval.1),
                    match b.side {
                        Side::Below => "at least",
                        Side::Above => "at most",
                    },
                    tick(b.bound)
                ));
            }
            bs => s.push_str(&format!(
                "; {} share boundaries of {param} (a grid point each) in summary.csv",
                bs.len()
            )),
        }
        s
    }

    /// "; writing set the pace: ..." when the results took longer to
    /// write than the lanes to integrate (the integrator waited on the
    /// writer), with both times and the integration's own rate.
    fn pace_note(&self) -> String {
        let Busy {
            integrating,
            sinking,
        } = self.busy;
        // Below a twentieth of a second neither time is worth a word:
        // both round to nothing on the line.
        if sinking <= integrating || integrating <= 0.0 || sinking < 0.05 {
            return String::new();
        }
        format!(
            "; writing set the pace: integration {integrating:.2} s ({:.0} lanes/s), \
             writing {sinking:.2} s",
            self.lanes as f64 / integrating
        )
    }

    /// "; drive: runs N, stalled N" for runs whose motors run to the end.
    fn drive_note(&self) -> String {
        if self.by_drive.is_empty() {
            return String::new();
        }
        format!("; drive: {}", counts(&self.by_drive, |d| d.name()))
    }

    /// "; hold: held N, runs_away N" for runs whose motors are cut, and
    /// what to do when lanes are still coasting (not decided).
    fn hold_note(&self) -> String {
        if self.by_hold.is_empty() {
            return String::new();
        }
        let mut s = format!("; hold: {}", counts(&self.by_hold, |h| h.name()));
        if let Some(&n) = self.by_hold.get(&Hold::Coasting) {
            s.push_str(&format!(
                "; {n} lane{} still coasting when their run ended: whether they hold is not decided ({})",
                if n == 1 { "" } else { "s" },
                if self.coasting_with_t_max {
                    "set t_max in [base], or raise it".to_string()
                } else {
                    format!(
                        "set t_max in [base] so they run on until held or running away, e.g. t_max = {}",
                        10.0 * self.coasting_t_end
                    )
                }
            ));
        }
        s
    }

    /// "; gpu rows: N checked, M recomputed in f64 (why n, ...)" for runs
    /// with GPU rows, and "; N lanes refined (...)" when the f64 path ran
    /// lanes again; empty otherwise.
    fn recompute_note(&self) -> String {
        let redone: Vec<String> = self
            .by_path
            .iter()
            .filter_map(|(p, n)| match p {
                RowPath::Recomputed(why) => Some(format!("{} {n}", why.name())),
                _ => None,
            })
            .collect();
        let count = |p: RowPath| self.by_path.get(&p).copied().unwrap_or(0);
        let refined = count(RowPath::Refined);
        let refined_note = if refined > 0 {
            format!("; {refined} lane{} refined (run again at a tenth of the tolerance: their error estimate was over the bound)", if refined == 1 { "" } else { "s" })
        } else {
            String::new()
        };
        let cpu = count(RowPath::Cpu) + refined;
        if cpu == self.lanes {
            return refined_note;
        }
        let why = if redone.is_empty() {
            String::new()
        } else {
            format!(" ({})", redone.join(", "))
        };
        let gpu64 = count(RowPath::Gpu64);
        if gpu64 > 0 {
            let n = self.lanes - cpu - gpu64;
            return format!(
                "; gpu rows in f64: {gpu64}, {n} recomputed on the cpu{why}{refined_note}"
            );
        }
        let n: u64 = self.lanes - cpu - count(RowPath::Gpu);
        format!(
            "; gpu rows: {} trusted, {n} recomputed in f64{why}{refined_note}",
            count(RowPath::Gpu),
        )
    }

    /// "N lanes in T s (R lanes/s, backend)", or for a search "N drives
    /// searched in T s (M lanes integrated, R lanes/s, backend)".
    fn size_note(&self, backend: &str) -> String {
        let plural = |n: u64| if n == 1 { "" } else { "s" };
        if self.by_search.is_empty() {
            format!(
                "{} lane{} in {:.2} s ({:.0} lanes/s, {backend})",
                self.lanes,
                plural(self.lanes),
                self.seconds,
                self.lanes as f64 / self.seconds.max(1e-9)
            )
        } else {
            format!(
                "{} drive{} searched in {:.2} s ({} lanes integrated, {:.0} lanes/s, {backend})",
                self.lanes,
                plural(self.lanes),
                self.seconds,
                self.search_lanes,
                self.search_lanes as f64 / self.seconds.max(1e-9)
            )
        }
    }

    /// The one-line summary.
    pub fn line(&self, backend: &str, out: &Path) -> String {
        format!(
            "tswm: {}{}{}; {}status: {}; contact_end: {}{}{}{}{}; wrote {}",
            self.size_note(backend),
            self.pace_note(),
            self.search_note(),
            // A search's rows are each drive's lane at the end of its
            // bracket that meets the requirement, not the drives at one
            // design: the words after say so.
            if self.by_search.is_empty() {
                ""
            } else {
                "the lanes reported (each drive's at its bracket's end that meets the requirement): "
            },
            counts(&self.by_status, |s| s.name()),
            if self.by_contact.is_empty() {
                "-".into()
            } else {
                counts(&self.by_contact, |c| c.name())
            },
            self.drive_note(),
            self.hold_note(),
            self.recompute_note(),
            self.sensitivity_seconds.map_or(String::new(), |s| format!(
                "; sensitivity indices in {s:.2} s ({:.1} % of the run)",
                100.0 * s / self.seconds.max(1e-9)
            )),
            out.display()
        )
    }
}

/// "word N, word N": the lanes per word of one column, in word order.
fn counts<K: Copy>(by: &BTreeMap<K, u64>, name: impl Fn(K) -> &'static str) -> String {
    by.iter()
        .map(|(&k, n)| format!("{} {n}", name(k)))
        .collect::<Vec<_>>()
        .join(", ")
}
