//! The shown groups' rows of `summary.csv`, for the study's tables,
//! histogram ranges and rank correlations.

use std::path::Path;

use super::aggregates::GroupData;
use super::scan::{bad_row, column, num, open_csv, text, Folder, BINS, CONTACT_NAMES};
use crate::columns::{CONTACT_END, DRIVE, HOLD};
use crate::error::{Error, Result};
use crate::input::sweep::Sweep;
use crate::output::names::SUMMARY;

impl Folder {
    /// The shown groups' rows of summary.csv: tables, histogram ranges
    /// and rank correlations.
    pub(super) fn read_summary(&mut self, dir: &Path, sweep: &Sweep, shown: usize) -> Result<()> {
        let path = dir.join(SUMMARY);
        let mut rd = open_csv(&path)?;
        let head = rd.byte_headers().map_err(|e| bad_row(&path, e))?.clone();
        let cols = SummaryCols::of(&path, &head, sweep)?;
        let mut rec = csv::ByteRecord::new();
        while rd
            .read_byte_record(&mut rec)
            .map_err(|e| bad_row(&path, e))?
        {
            let g = num(&path, &rec, cols.group, "group")?;
            if !(g >= 0.0) || g.fract() != 0.0 {
                return Err(Error::input(
                    &path,
                    rec.position().map(|p| format!("line {}", p.line())),
                    Some("group"),
                    "is not a group number; not a tswm summary",
                ));
            }
            if g < shown as f64 {
                self.add_summary_row(&path, &rec, &cols, sweep, g as usize)?;
            }
        }
        Ok(())
    }

    /// One row of summary.csv, of shown group `g`.
    fn add_summary_row(
        &mut self,
        path: &Path,
        rec: &csv::ByteRecord,
        cols: &SummaryCols,
        sweep: &Sweep,
        g: usize,
    ) -> Result<()> {
        while self.groups.len() <= g {
            self.groups.push(GroupData {
                label: String::new(),
                quantile_rows: Vec::new(),
                contact_rows: Vec::new(),
                hists: vec![None; self.results.len()],
                spearman: Vec::new(),
            });
        }
        if self.groups[g].label.is_empty() {
            let mut parts = Vec::new();
            for (a, &i) in sweep.axes.iter().zip(&cols.axes) {
                let v = if a.is_words() {
                    text(rec, i)
                } else {
                    super::plots::tick(num(path, rec, i, a.param.name())?)
                };
                parts.push(format!("{} = {v}", super::words::param_label(a.param)));
            }
            self.groups[g].label = if parts.is_empty() {
                "all lanes".into()
            } else {
                format!("grid point {g}: {}", parts.join(", "))
            };
        }
        let nm = text(rec, cols.name);
        match rec.get(cols.kind).unwrap_or(b"") {
            b"number" => {
                if let Some(r) = self.results.iter().position(|x| x.name == nm) {
                    let (a, b) = (
                        num(path, rec, cols.min, "min")?,
                        num(path, rec, cols.max, "max")?,
                    );
                    if a.is_finite() && b.is_finite() {
                        self.groups[g].hists[r] = Some((a, b, vec![0; BINS]));
                    }
                }
                let mut row = vec![nm, text(rec, cols.count)];
                row.extend(cols.stats.iter().map(|&i| short(&text(rec, i))));
                self.groups[g].quantile_rows.push(row);
            }
            k if k == CONTACT_END.as_bytes() || k == HOLD.as_bytes() || k == DRIVE.as_bytes() => {
                self.share_row(path, rec, cols, g, nm)?;
            }
            b"spearman" => {
                let r = num(path, rec, cols.rho, "rho")?;
                self.groups[g].spearman.push((nm, text(rec, cols.input), r));
            }
            _ => {}
        }
        Ok(())
    }

    /// A share of a word column's word (`nm`) in group `g`, for the
    /// outcome table; none for a column no lane of the group has.
    fn share_row(
        &mut self,
        path: &Path,
        rec: &csv::ByteRecord,
        cols: &SummaryCols,
        g: usize,
        nm: String,
    ) -> Result<()> {
        let word = CONTACT_NAMES
            .iter()
            .find(|c| c.0.name() == nm)
            .map_or(nm.clone(), |c| format!("{} ({})", c.0.name(), c.1));
        let kind = text(rec, cols.kind);
        let pct = super::words::percent;
        let (s, l, h) = (
            num(path, rec, cols.share, "share")?,
            num(path, rec, cols.lo, "ci95_low")?,
            num(path, rec, cols.hi, "ci95_high")?,
        );
        // A word column no lane of the group has (no lane's motor
        // runs, say) has no share to show.
        if s.is_finite() {
            self.groups[g].contact_rows.push(vec![
                format!("{kind} = {word}"),
                text(rec, cols.count),
                pct(s),
                if l.is_nan() {
                    "-".into()
                } else {
                    format!("{} to {}", pct(l), pct(h))
                },
            ]);
        }
        Ok(())
    }
}

/// A long number cell shortened for a table (6 significant digits).
fn short(s: &str) -> String {
    match s.parse::<f64>() {
        Ok(v) if v != 0.0 && v.is_finite() => {
            let a = v.abs();
            if (1e-3..1e6).contains(&a) {
                let digits = (5 - a.log10().floor() as i32).max(0) as usize;
                format!("{v:.digits$}")
            } else {
                format!("{v:.5e}")
            }
        }
        _ => s.to_string(),
    }
}

/// Where the report reads a row of summary.csv.
struct SummaryCols {
    group: usize,
    kind: usize,
    name: usize,
    input: usize,
    count: usize,
    /// mean to quantiles, as the study's table shows them.
    stats: Vec<usize>,
    min: usize,
    max: usize,
    share: usize,
    lo: usize,
    hi: usize,
    rho: usize,
    /// The grid parameters' columns.
    axes: Vec<usize>,
}

impl SummaryCols {
    fn of(path: &Path, head: &csv::ByteRecord, sweep: &Sweep) -> Result<SummaryCols> {
        let c = |n: &str| column(path, head, n);
        let stats = [
            "mean",
            "std",
            "min",
            "p1",
            "p5",
            "p50",
            "p95",
            "p99",
            "max",
            "quantiles",
        ];
        Ok(SummaryCols {
            group: c("group")?,
            kind: c("kind")?,
            name: c("name")?,
            input: c("input")?,
            count: c("count")?,
            stats: stats.iter().map(|n| c(n)).collect::<Result<_>>()?,
            min: c("min")?,
            max: c("max")?,
            share: c("share")?,
            lo: c("ci95_low")?,
            hi: c("ci95_high")?,
            rho: c("rho")?,
            axes: sweep
                .axes
                .iter()
                .map(|a| c(a.param.name()))
                .collect::<Result<_>>()?,
        })
    }
}
