//! The report's sensitivity section: per shown grid point and chosen
//! result, a bar chart of the first-order and total indices of each input
//! with their intervals, and a sentence that reads it. `sensitivity.csv`
//! is read strictly, keeping only the rows shown (bounded).

use std::collections::BTreeMap;
use std::path::Path;

use plotters::prelude::*;

use super::cells::{bad_row, column, num, open_csv, text};
use super::charts::PALETTE;
use super::html::Page;
use super::plots::{chart, err, inline, Axis, SIZE};
use crate::columns::{Indicator, CONTACT_END, ETA_DIRECT};
use crate::error::{Error, Result};
use crate::input::sweep::{Sensitivity, Sweep};
use crate::integrator::Contact;
use crate::output::names::SENSITIVITY;
use crate::stats::sensitivity::{result_names, SENSITIVITY_COLUMNS};

/// The results charted when `[sensitivity] results` names none: whether
/// the drive holds (the first indicator that is a final contact of
/// `stick`), and its efficiency with the worm driving.
fn default_results() -> Vec<String> {
    let holds = Indicator {
        column: CONTACT_END,
        word: Contact::Stick.name(),
    };
    vec![holds.name(), ETA_DIRECT.to_string()]
}

/// One row of `sensitivity.csv`: s1, s1_low, s1_high, st, st_low,
/// st_high (NaN for empty) and the row groups used.
#[derive(Clone, Copy, Debug)]
struct Row {
    v: [f64; 6],
    samples: u64,
}

/// The rows kept: (group, result) → rows by input, in design order.
type Kept = BTreeMap<(u64, String), Vec<Row>>;

/// Reads the rows of groups below `shown` for `results`, checking every
/// row of the file (as a stream: the file grows with the grid).
fn read(path: &Path, sweep: &Sweep, results: &[String], shown: u64) -> Result<Kept> {
    let mut rd = open_csv(path)?;
    let head = rd.byte_headers().map_err(|e| bad_row(path, e))?.clone();
    let want: Vec<&str> = SENSITIVITY_COLUMNS.split(',').collect();
    if head.len() != want.len() {
        return Err(Error::input(
            path,
            Some("line 1".into()),
            Some("header"),
            format!("allowed: {SENSITIVITY_COLUMNS}"),
        ));
    }
    let cols: Vec<usize> = want
        .iter()
        .map(|n| column(path, &head, n))
        .collect::<Result<_>>()?;
    let names = result_names();
    let inputs: Vec<&str> = sweep.study.as_ref().map_or(Vec::new(), |s| {
        s.params.iter().map(|t| t.param.name()).collect()
    });
    let mut kept = Kept::new();
    let mut rec = csv::ByteRecord::new();
    while rd
        .read_byte_record(&mut rec)
        .map_err(|e| bad_row(path, e))?
    {
        let bad = |what: &str, msg: String| {
            let line = rec.position().map(|p| format!("line {}", p.line()));
            Error::input(path, line, Some(what), msg)
        };
        let count = |i: usize, what: &str| -> Result<u64> {
            let v = num(path, &rec, cols[i], what)?;
            if v >= 0.0 && v.fract() == 0.0 {
                Ok(v as u64)
            } else {
                Err(bad(what, "is not a count".into()))
            }
        };
        let group = count(0, "group")?;
        let result = text(&rec, cols[1]);
        if !names.contains(&result) {
            return Err(bad("result", format!("{result:?} is not a result")));
        }
        let input = text(&rec, cols[2]);
        let Some(k) = inputs.iter().position(|x| *x == input) else {
            return Err(bad(
                "input",
                format!("{input:?} is not an input of the sweep"),
            ));
        };
        let mut v = [f64::NAN; 6];
        for (x, (i, name)) in v.iter_mut().zip(want.iter().enumerate().skip(3)) {
            *x = num(path, &rec, cols[i], name)?;
        }
        let samples = count(9, "samples")?;
        if group < shown && results.contains(&result) {
            let rows = kept.entry((group, result)).or_default();
            if rows.len() != k {
                return Err(bad("input", "inputs out of design order".into()));
            }
            rows.push(Row { v, samples });
        }
    }
    Ok(kept)
}

/// The section, for a sweep with a sensitivity design.
pub(super) fn section(page: &mut Page, dir: &Path, sweep: &Sweep, sn: &Sensitivity) -> Result<()> {
    let results: Vec<String> = if sn.results.is_empty() {
        default_results()
    } else {
        sn.results.clone()
    };
    let groups = sweep.axes.iter().map(|a| a.len()).product::<u64>().max(1);
    let shown = groups.min(sweep.report.panels() as u64);
    let kept = read(&dir.join(SENSITIVITY), sweep, &results, shown)?;
    let inputs: Vec<String> = sweep.study.as_ref().map_or(Vec::new(), |s| {
        s.params
            .iter()
            .map(|t| t.param.name().to_string())
            .collect()
    });
    page.section("Which input matters: sensitivity indices");
    page.note(&format!(
        "A Saltelli design of {} base samples over {} inputs ({} lanes a grid point) on scrambled \
         Sobol' points. S1, the first-order index, is the share of a result's variance an input \
         causes alone; ST, the total index, adds its interactions with the others. Whiskers: {} % \
         bootstrap intervals ({} resamples); on Sobol' points they are wider than the error, an \
         upper bound on it. {SENSITIVITY} has every result and grid point.",
        sn.base,
        inputs.len(),
        sn.base * (inputs.len() as u64 + 2),
        100.0 * sn.confidence,
        sn.bootstrap,
    ));
    if shown < groups {
        page.note(&format!(
            "Showing {shown} of {groups} grid points ([report] panels sets the limit)."
        ));
    }
    for g in 0..shown {
        if groups > 1 {
            page.heading(&format!("Grid point {g}"));
        }
        let mut figs = Vec::new();
        for r in &results {
            let rows = kept.get(&(g, r.clone())).map_or(&[][..], |v| &v[..]);
            page.note(&reading(r, &inputs, rows, sn.base));
            if rows.iter().any(|x| x.v[3].is_finite()) {
                figs.push(bars(&format!("{r}: S1 and ST by input"), &inputs, rows));
            }
        }
        page.figures(figs);
    }
    Ok(())
}

/// The sentence that reads one chart.
fn reading(result: &str, inputs: &[String], rows: &[Row], base: u64) -> String {
    let samples = rows.first().map_or(0, |r| r.samples);
    let dropped = if samples < base {
        format!(
            " {} of {base} row groups were dropped (a lane not ok, or no value of {result}).",
            base - samples
        )
    } else {
        String::new()
    };
    if !rows.iter().any(|x| x.v[3].is_finite()) {
        return format!(
            "{result}: no index. It does not vary over the design's A and B samples (or no row group had it), so there is no variance to apportion.{dropped}"
        );
    }
    let (top, row) = rows
        .iter()
        .enumerate()
        .filter(|(_, r)| r.v[3].is_finite())
        .max_by(|a, b| a.1.v[3].total_cmp(&b.1.v[3]))
        .expect("one is finite");
    let sum: f64 = rows.iter().map(|r| r.v[0]).filter(|x| x.is_finite()).sum();
    let interaction = if sum >= 0.95 {
        "the inputs act almost alone (little interaction)".to_string()
    } else {
        format!(
            "about {:.0} % of the variance comes from inputs acting together",
            100.0 * (1.0 - sum.max(0.0))
        )
    };
    format!(
        "{result}: the largest total index is {}'s, ST = {:.3} ({:.3} to {:.3}). The first-order \
         indices sum to {sum:.3}: {interaction}.{dropped}",
        inputs[top], row.v[3], row.v[4], row.v[5]
    )
}

/// Bars of S1 and ST per input with their intervals as whiskers.
fn bars(title: &str, inputs: &[String], rows: &[Row]) -> std::result::Result<String, String> {
    let x = Axis::words("input", inputs.to_vec());
    let vals = rows.iter().flat_map(|r| r.v).filter(|v| v.is_finite());
    let y = Axis::numeric("Sobol' index", vals.chain([0.0, 1.0]));
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let mut c = chart(&root, title, &x, &y, true)?;
        for (k, name) in ["S1 (first order)", "ST (total)"].into_iter().enumerate() {
            let col = PALETTE[k];
            let dx = (k as f64 - 0.5) * 0.35;
            let at = |i: usize| i as f64 + dx;
            let base = 3 * k;
            c.draw_series(
                rows.iter()
                    .enumerate()
                    .filter(|(_, r)| r.v[base].is_finite())
                    .map(|(i, r)| {
                        Rectangle::new(
                            [(at(i) - 0.16, y.map(0.0)), (at(i) + 0.16, y.map(r.v[base]))],
                            col.mix(0.8).filled(),
                        )
                    }),
            )
            .map_err(err)?
            .label(name)
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 12, y + 5)], col.filled()));
            c.draw_series(
                rows.iter()
                    .enumerate()
                    .filter(|(_, r)| r.v[base + 1].is_finite() && r.v[base + 2].is_finite())
                    .map(|(i, r)| {
                        PathElement::new(
                            [(at(i), y.map(r.v[base + 1])), (at(i), y.map(r.v[base + 2]))],
                            BLACK.stroke_width(2),
                        )
                    }),
            )
            .map_err(err)?;
        }
        c.configure_series_labels()
            .position(plotters::chart::SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(err)?;
        root.present().map_err(err)?;
    }
    Ok(inline(svg))
}
