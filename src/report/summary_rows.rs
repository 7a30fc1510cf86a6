//! The shown groups' rows of `summary.csv`, for the study's tables,
//! histogram ranges and rank correlations.

use std::path::Path;

use super::aggregates::GroupData;
use super::scan::{bad_row, column, num, open_csv, text, Folder, BINS, CONTACT_NAMES};
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
        let c = |n: &str| column(&path, &head, n);
        let (group, kind, name, input, count) = (
            c("group")?,
            c("kind")?,
            c("name")?,
            c("input")?,
            c("count")?,
        );
        let stat_names = [
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
        let stat_cols: Vec<usize> = stat_names.iter().map(|n| c(n)).collect::<Result<_>>()?;
        let (share, lo, hi, rho) = (c("share")?, c("ci95_low")?, c("ci95_high")?, c("rho")?);
        let (minc, maxc) = (c("min")?, c("max")?);
        let axis_cols: Vec<usize> = sweep
            .axes
            .iter()
            .map(|a| c(a.param.name()))
            .collect::<Result<_>>()?;
        let mut rec = csv::ByteRecord::new();
        while rd
            .read_byte_record(&mut rec)
            .map_err(|e| bad_row(&path, e))?
        {
            let g = num(&path, &rec, group, "group")?;
            if !(g >= 0.0) || g.fract() != 0.0 {
                return Err(Error::input(
                    &path,
                    rec.position().map(|p| format!("line {}", p.line())),
                    Some("group"),
                    "is not a group number; not a tswm summary",
                ));
            }
            if g >= shown as f64 {
                continue;
            }
            let g = g as usize;
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
                for (a, &i) in sweep.axes.iter().zip(&axis_cols) {
                    let v = num(&path, &rec, i, a.param.name())?;
                    parts.push(format!(
                        "{} = {}",
                        super::param_label(a.param),
                        super::plots::tick(v)
                    ));
                }
                self.groups[g].label = if parts.is_empty() {
                    "all lanes".into()
                } else {
                    format!("grid point {g}: {}", parts.join(", "))
                };
            }
            let nm = text(&rec, name);
            match rec.get(kind).unwrap_or(b"") {
                b"number" => {
                    if let Some(r) = self.results.iter().position(|x| x.name == nm) {
                        let (a, b) = (
                            num(&path, &rec, minc, "min")?,
                            num(&path, &rec, maxc, "max")?,
                        );
                        if a.is_finite() && b.is_finite() {
                            self.groups[g].hists[r] = Some((a, b, vec![0; BINS]));
                        }
                    }
                    let mut row = vec![nm, text(&rec, count)];
                    row.extend(stat_cols.iter().map(|&i| short(&text(&rec, i))));
                    self.groups[g].quantile_rows.push(row);
                }
                b"contact_end" | b"hold" => {
                    let word = CONTACT_NAMES
                        .iter()
                        .find(|c| c.0 == nm)
                        .map_or(nm.clone(), |c| format!("{} ({})", c.0, c.1));
                    let kind = text(&rec, kind);
                    let pct = |x: f64| super::percent(x);
                    let (s, l, h) = (
                        num(&path, &rec, share, "share")?,
                        num(&path, &rec, lo, "ci95_low")?,
                        num(&path, &rec, hi, "ci95_high")?,
                    );
                    self.groups[g].contact_rows.push(vec![
                        format!("{kind} = {word}"),
                        text(&rec, count),
                        pct(s),
                        format!("{} to {}", pct(l), pct(h)),
                    ]);
                }
                b"spearman" => {
                    let r = num(&path, &rec, rho, "rho")?;
                    self.groups[g].spearman.push((nm, text(&rec, input), r));
                }
                _ => {}
            }
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
