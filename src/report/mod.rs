//! `report.html`: what a run answers, as one self-contained page built
//! from an output folder's files (`sweep.resolved.toml`, `lanes.csv`,
//! `summary.csv`, `traces.csv`). Every file is read as a stream and only
//! bounded aggregates are kept (a few hundred cells a map, bins of a
//! histogram, a capped number of trace rows), so a run of any size gets
//! its report in bounded memory.

mod aggregates;
pub mod html;
pub mod plots;
mod scan;

use std::path::Path;

use crate::error::{Error, Result};
use crate::outdir::write_atomic;
use crate::params::Num;
use crate::stats::wilson;
use crate::sweep::Sweep;
use html::Page;
use plots::{category_map, heat_map, histogram, line_chart, tornado, Curve};
use scan::{Folder, CONTACT_NAMES};

/// Writes `DIR/report.html` from the run in `dir`.
pub fn write(dir: &Path) -> Result<()> {
    let page = build(dir)?;
    write_atomic(&dir.join("report.html"), page.as_bytes())
}

/// The unit of a result column, for axis labels.
fn result_unit(name: &str) -> &'static str {
    match name {
        "t_first_switch" => "s",
        "x1_end" => "m",
        "v1_end" => "m/s",
        "lock_margin_deg" => "deg",
        n if n.starts_with("w") => "J",
        _ => "",
    }
}

/// "name (unit)", or the name alone when it has no unit.
fn labelled(name: &str, unit: &str) -> String {
    if unit.is_empty() {
        name.to_string()
    } else {
        format!("{name} ({unit})")
    }
}

fn param_label(n: Num) -> String {
    labelled(n.name(), n.def().unit)
}

/// A share as a percentage: two decimals, or two significant digits
/// below 0.01 % (the upper end of a Wilson interval for no lane of a
/// million is 3.8e-4 %, not 0.00 %); "-" for none.
pub(crate) fn percent(x: f64) -> String {
    if !x.is_finite() {
        "-".into()
    } else if x > 0.0 && x < 1e-4 {
        format!("{:.1e} %", 100.0 * x)
    } else if x < 1.0 && x > 1.0 - 1e-4 {
        // Likewise just below 100 %: enough decimals to tell it from 100.
        let decimals = (-(1.0 - x).log10()).ceil() as usize - 1;
        format!("{:.*} %", decimals, 100.0 * x)
    } else {
        format!("{:.2} %", 100.0 * x)
    }
}

/// A share with its 95 % Wilson interval, as table cells.
fn share_cells(k: u64, n: u64) -> [String; 3] {
    let (lo, hi) = wilson(k, n);
    let pct = percent;
    [
        k.to_string(),
        pct(k as f64 / n as f64),
        format!("{} to {}", pct(lo), pct(hi)),
    ]
}

/// The report of the run in `dir`, as HTML.
pub fn build(dir: &Path) -> Result<String> {
    let resolved_path = dir.join("sweep.resolved.toml");
    let text = std::fs::read_to_string(&resolved_path).map_err(|e| {
        Error::input(
            &resolved_path,
            None,
            None,
            format!("cannot read it ({e}); allowed: a folder written by `tswm run`"),
        )
    })?;
    let sweep = Sweep::parse(&resolved_path, &text)?;
    let folder = Folder::read(dir, &sweep)?;
    let spec = &sweep.report;
    let title = spec.title.clone().unwrap_or_else(|| {
        format!(
            "tswm report: {}",
            dir.canonicalize()
                .unwrap_or(dir.to_path_buf())
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default()
        )
    });
    let mut page = Page::new(&title);

    page.section("What was run");
    let header: Vec<&str> = text.lines().take_while(|l| l.starts_with('#')).collect();
    for l in &header {
        page.note(l.trim_start_matches('#').trim());
    }
    page.note(&format!("Folder: {}", dir.display()));
    page.heading("The resolved sweep (sweep.resolved.toml)");
    page.pre(&text);

    outcomes(&mut page, &folder);
    if folder.map.is_some() {
        maps(&mut page, &folder);
    }
    if folder.line.is_some() {
        lines(&mut page, &folder);
    }
    if folder.study {
        study(&mut page, &folder);
    }
    if !folder.traces.is_empty() {
        traces(&mut page, &folder);
    }
    page.section("About this page");
    page.note(&format!(
        "Written by tswm from the files of its output folder: {} (one row per lane), \
         summary.csv (statistics), traces.csv (traced lanes) and sweep.resolved.toml. \
         Efficiencies are energy-averaged over each lane's run (MODEL.md section 10): eta_direct = \
         w2_out / w1_in (worm drives wheel), eta_inverse = w1_out / w2_in (wheel drives worm); the \
         _ss values are the steady efficiencies at the final sliding speed; lock_margin_deg = \
         atan(mu_s) - gamma > 0 means the drive holds its load with the motor off. Grey cells have \
         no value (the lane did not finish, or the efficiency is undefined).",
        folder.table
    ));
    Ok(page.finish(&title))
}

fn outcomes(page: &mut Page, f: &Folder) {
    page.section("Outcomes");
    page.note(&format!("{} lanes.", f.lanes));
    let rows: Vec<Vec<String>> = f
        .by_status
        .iter()
        .map(|(s, &k)| {
            let [a, b, c] = share_cells(k, f.lanes);
            vec![s.clone(), a, b, c]
        })
        .collect();
    page.table(
        &["status", "lanes", "share", "95 % interval (Wilson)"],
        &rows,
    );
    let ok = f.by_status.get("ok").copied().unwrap_or(0);
    let rows: Vec<Vec<String>> = CONTACT_NAMES
        .iter()
        .enumerate()
        .map(|(i, (name, meaning))| {
            let [a, b, c] = share_cells(f.by_contact[i], ok);
            vec![format!("{name} ({meaning})"), a, b, c]
        })
        .collect();
    page.table(
        &[
            "final contact (finished lanes)",
            "lanes",
            "share",
            "95 % interval (Wilson)",
        ],
        &rows,
    );
    if f.unfinished_total > 0 {
        page.heading("Lanes that could not be finished");
        let mut head = vec!["lane", "status"];
        head.extend(f.shown_params.iter().map(|n| n.name()));
        page.table(&head, &f.unfinished);
        if f.unfinished_total > f.unfinished.len() as u64 {
            page.note(&format!(
                "{} more in {} (status other than ok).",
                f.unfinished_total - f.unfinished.len() as u64,
                f.table
            ));
        }
    }
}

fn maps(page: &mut Page, f: &Folder) {
    let m = f.map.as_ref().expect("checked");
    page.section("Maps");
    page.note(&format!(
        "Each cell is one grid point{} over {} and {}. The red line is the static self-locking \
         limit (lock_margin_deg = 0, i.e. gamma = atan(mu_s)): where the map crosses it the drive \
         starts to hold its load with the motor off.{}",
        if f.study {
            " (the mean over its sampled lanes)"
        } else {
            ""
        },
        m.x.name(),
        m.y.name(),
        if m.binned {
            " Axes with more points than a map shows are binned (cell = mean of its bin)."
        } else {
            ""
        }
    ));
    if m.panels.len() < m.panel_total {
        page.note(&format!(
            "Showing {} of {} panels (one per value of the other axes; [report] panels sets the limit).",
            m.panels.len(),
            m.panel_total
        ));
    }
    for p in &m.panels {
        page.heading(&p.label);
        let mut figs = Vec::new();
        let line = p.lock_line();
        for (r, name) in f.results.iter().enumerate() {
            figs.push(heat_map(
                name,
                &param_label(m.x),
                &m.xs,
                &param_label(m.y),
                &m.ys,
                &p.means(r),
                &labelled(name, result_unit(name)),
                Some(&line),
            ));
        }
        let names: Vec<&str> = CONTACT_NAMES.iter().map(|c| c.1).collect();
        figs.push(category_map(
            "final contact (most lanes)",
            &param_label(m.x),
            &m.xs,
            &param_label(m.y),
            &m.ys,
            &p.contact_cells(),
            &names,
        ));
        page.figures(figs);
    }
}

fn lines(page: &mut Page, f: &Folder) {
    let l = f.line.as_ref().expect("checked");
    page.section(&format!("Results against {}", l.axis.name()));
    if f.study {
        page.note(
            "Lines are the mean over each grid point's sampled lanes; bands span their min to max.",
        );
    }
    let mut figs = Vec::new();
    for (r, name) in f.results.iter().enumerate() {
        let (points, band) = l.curve(r);
        let band = if f.study { band } else { Vec::new() };
        figs.push(line_chart(
            name,
            &param_label(l.axis),
            &labelled(name, result_unit(name)),
            &[Curve { name, points, band }],
            &[],
            l.log,
        ));
    }
    let curves: Vec<Curve> = CONTACT_NAMES
        .iter()
        .enumerate()
        .map(|(i, c)| Curve {
            name: c.1,
            points: l.contact_share(i),
            band: Vec::new(),
        })
        .collect();
    figs.push(line_chart(
        "final contact",
        &param_label(l.axis),
        "share of finished lanes",
        &curves,
        &[],
        l.log,
    ));
    page.figures(figs);
    if f.study {
        page.heading(&format!("Final contact against {}", l.axis.name()));
        page.note(
            "The probability of each final contact over each grid point's sampled lanes, with its \
             95 % Wilson interval. Held (stick) means the drive holds its load at the end of the run.",
        );
        let rows = l.contact_rows();
        let head = [
            labelled(l.axis.name(), l.axis.def().unit),
            "finished lanes".into(),
            "held".into(),
            "held, 95 % interval".into(),
            "a-a".into(),
            "b-b".into(),
        ];
        let head: Vec<&str> = head.iter().map(|s| s.as_str()).collect();
        page.table(&head, &rows);
    }
}

fn study(page: &mut Page, f: &Folder) {
    page.section("Tolerance study");
    page.note(
        "Per grid point (or the whole study): the quantiles of each result from summary.csv, the \
         probability of each final contact with its 95 % Wilson interval, histograms with the \
         empirical CDF, and the Spearman rank correlation of each sampled input with the result \
         (a tornado: the longer the bar, the more that tolerance moves the result).",
    );
    for g in &f.groups {
        page.heading(&g.label);
        let head = [
            "result",
            "count",
            "mean",
            "std",
            "min",
            "P1",
            "P5",
            "P50",
            "P95",
            "P99",
            "max",
            "quantiles",
        ];
        page.table(&head, &g.quantile_rows);
        page.table(
            &[
                "final contact",
                "lanes",
                "probability",
                "95 % interval (Wilson)",
            ],
            &g.contact_rows,
        );
        let mut figs = Vec::new();
        for (r, name) in f.results.iter().enumerate() {
            if let Some((lo, hi, counts)) = g.hist(r) {
                figs.push(histogram(
                    name,
                    &labelled(name, result_unit(name)),
                    lo,
                    hi,
                    counts,
                ));
            }
            let bars = g.tornado(name);
            if !bars.is_empty() {
                figs.push(tornado(&format!("what moves {name}"), &bars));
            }
        }
        page.figures(figs);
    }
    if f.groups_total > f.groups.len() {
        page.note(&format!(
            "Showing {} of {} grid points ([report] panels sets the limit); summary.csv has them all.",
            f.groups.len(),
            f.groups_total
        ));
    }
}

fn traces(page: &mut Page, f: &Folder) {
    page.section("Traces");
    page.note(
        "Traced lanes through time (traces.csv): the contact reactions S1 and S2, the force \
         transfer function psi, and the speed. Grey vertical lines mark events (a switch of the \
         contact side, a stop, the motor's cut-off); at each, the trace has the state just before \
         and just after.",
    );
    for t in &f.traces {
        page.heading(&format!(
            "lane {}{}",
            t.lane,
            if t.thinned {
                " (thinned for plotting)"
            } else {
                ""
            }
        ));
        let figs = vec![
            line_chart(
                "contact reactions",
                "t (s)",
                "force (N)",
                &[
                    Curve {
                        name: "S1",
                        points: t.series(|r| r.s1),
                        band: Vec::new(),
                    },
                    Curve {
                        name: "S2",
                        points: t.series(|r| r.s2),
                        band: Vec::new(),
                    },
                ],
                &t.events,
                false,
            ),
            line_chart(
                "force transfer function",
                "t (s)",
                "psi",
                &[Curve {
                    name: "psi",
                    points: t.series(|r| r.psi),
                    band: Vec::new(),
                }],
                &t.events,
                false,
            ),
            line_chart(
                "speed",
                "t (s)",
                "v1 (m/s)",
                &[Curve {
                    name: "v1",
                    points: t.series(|r| r.v1),
                    band: Vec::new(),
                }],
                &t.events,
                false,
            ),
        ];
        page.figures(figs);
    }
}
