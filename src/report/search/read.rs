//! Reading a search's answers back: `summary.csv`'s search rows per
//! grid point, and each drive's bracket from the results table (either
//! format, by column name).

use std::collections::BTreeMap;
use std::path::Path;

use super::super::cells::{bad_row, column, num, open_csv, text};
use super::{val, MAX_POINTS};
use arrow_array::{Array, Float64Array, Int64Array};

use crate::columns::{CRITICAL, LANE, SEARCH_HI, SEARCH_LO, SEARCH_MEETS, SEARCH_STATUS};
use crate::error::Result;
use crate::input::sweep::{AxisValues, Sweep};
use crate::integrator::Side;
use crate::output::table::read_batches;

/// A grid point's search statistics from `summary.csv`.
#[derive(Clone, Debug, Default)]
pub(super) struct Point {
    /// Its value of the first grid axis (NaN without one, or for words).
    pub(super) x: f64,
    /// Its grid values, as `summary.csv` names them.
    pub(super) at: String,
    /// Drives.
    pub(super) n: u64,
    /// P1, P5, P50, P95, P99 of the critical value (NaN: not resolved).
    pub(super) q: [f64; 5],
    /// The share boundary, its 95 % interval and one-sided bound.
    pub(super) boundary: Option<(f64, f64, f64, f64)>,
    /// The side the requirement is met on (from the bound row).
    pub(super) side: Option<Side>,
}

/// A drive's search from `lanes.csv`.
pub(super) struct Lane {
    pub(super) lane: u64,
    pub(super) x: f64,
    /// Its grid values, as a sentence names them.
    pub(super) at: String,
    /// The other grid axes' values (after the first), naming its curve.
    pub(super) rest: String,
    pub(super) critical: f64,
    pub(super) lo: f64,
    pub(super) hi: f64,
    pub(super) status: String,
    pub(super) side: String,
}

/// The search rows of `summary.csv`, a point per group.
pub(super) fn read_summary(path: &Path, sweep: &Sweep) -> Result<Vec<Point>> {
    let mut rd = open_csv(path)?;
    let head = rd.byte_headers().map_err(|e| bad_row(path, e))?.clone();
    let c = |n: &str| column(path, &head, n);
    let (group, kind, quantiles) = (c("group")?, c("kind")?, c("quantiles")?);
    let q: Vec<usize> = ["p1", "p5", "p50", "p95", "p99"]
        .iter()
        .map(|n| c(n))
        .collect::<Result<_>>()?;
    let (lo, hi) = (c("ci95_low")?, c("ci95_high")?);
    let axes: Vec<(usize, String)> = sweep
        .axes
        .iter()
        .map(|a| Ok((c(a.param.name())?, a.param.name().to_string())))
        .collect::<Result<_>>()?;
    let numeric_first = matches!(
        sweep.axes.first().map(|a| &a.values),
        Some(AxisValues::List(_) | AxisValues::Range { .. })
    );
    let mut points: BTreeMap<u64, Point> = BTreeMap::new();
    let mut rec = csv::ByteRecord::new();
    while rd
        .read_byte_record(&mut rec)
        .map_err(|e| bad_row(path, e))?
    {
        let k = text(&rec, kind);
        if !matches!(k.as_str(), "critical" | "boundary" | "bound") {
            continue;
        }
        let g = num(path, &rec, group, "group")? as u64;
        let p = points.entry(g).or_default();
        if p.at.is_empty() && !axes.is_empty() {
            let at: Vec<String> = axes
                .iter()
                .map(|(i, n)| format!("{n} = {}", text(&rec, *i)))
                .collect();
            p.at = at.join(", ");
            p.x = if numeric_first {
                num(path, &rec, axes[0].0, &axes[0].1)?
            } else {
                f64::NAN
            };
        }
        if axes.is_empty() {
            p.x = f64::NAN;
        }
        let n = num(path, &rec, c("count")?, "count")?;
        p.n = n as u64;
        match k.as_str() {
            "critical" => {
                for (j, &i) in q.iter().enumerate() {
                    p.q[j] = num(path, &rec, i, "quantile")?;
                }
            }
            "boundary" => {
                p.boundary = Some((
                    num(path, &rec, q[2], "p50")?,
                    num(path, &rec, lo, "ci95_low")?,
                    num(path, &rec, hi, "ci95_high")?,
                    f64::NAN,
                ));
            }
            _ => {
                let said = text(&rec, quantiles);
                p.side = Some(if said.contains("at most") {
                    Side::Above
                } else {
                    Side::Below
                });
                let b = num(path, &rec, q[2], "p50")?;
                if let Some(bd) = p.boundary.as_mut() {
                    bd.3 = b;
                }
            }
        }
    }
    Ok(points.into_values().collect())
}

/// Row `r` of a number column (NaN where empty or not a number).
fn num_at(a: &dyn Array, r: usize) -> f64 {
    a.as_any()
        .downcast_ref::<Float64Array>()
        .filter(|x| x.is_valid(r))
        .map_or(f64::NAN, |x| x.value(r))
}

/// Row `r` of a column as text: a word, or a number as a sentence shows it.
fn text_at(a: &dyn Array, r: usize) -> String {
    if a.as_any().downcast_ref::<Float64Array>().is_some() {
        let x = num_at(a, r);
        return if x.is_nan() { String::new() } else { val(x) };
    }
    crate::output::batch::Col::of(a).map_or(String::new(), |c| c.word(r).to_string())
}

/// The drives of the results table (the first [`MAX_POINTS`]) and their
/// count, read by column name from `lanes.csv` or `lanes.parquet`.
pub(super) fn read_lanes(dir: &Path, sweep: &Sweep) -> Result<(Vec<Lane>, u64)> {
    let axes: Vec<&str> = sweep.axes.iter().map(|a| a.param.name()).collect();
    let mut names = vec![
        LANE,
        CRITICAL,
        SEARCH_LO,
        SEARCH_HI,
        SEARCH_STATUS,
        SEARCH_MEETS,
    ];
    names.extend(&axes);
    let mut kept = Vec::new();
    let mut total = 0u64;
    read_batches(dir, &names, |b| {
        let col = |n: &str| b.column_by_name(n).expect("asked for").clone();
        let lane = col(LANE);
        let lane = lane.as_any().downcast_ref::<Int64Array>();
        for r in 0..b.num_rows() {
            total += 1;
            if kept.len() >= MAX_POINTS {
                continue;
            }
            let said: Vec<String> = axes
                .iter()
                .map(|n| format!("{n} = {}", text_at(col(n).as_ref(), r)))
                .collect();
            kept.push(Lane {
                lane: lane.map_or(0, |l| l.value(r) as u64),
                x: axes
                    .first()
                    .map_or(f64::NAN, |n| num_at(col(n).as_ref(), r)),
                rest: said[said.len().min(1)..].join(", "),
                at: said.join(", "),
                critical: num_at(col(CRITICAL).as_ref(), r),
                lo: num_at(col(SEARCH_LO).as_ref(), r),
                hi: num_at(col(SEARCH_HI).as_ref(), r),
                status: text_at(col(SEARCH_STATUS).as_ref(), r),
                side: text_at(col(SEARCH_MEETS).as_ref(), r),
            });
        }
        Ok(())
    })?;
    Ok((kept, total))
}
