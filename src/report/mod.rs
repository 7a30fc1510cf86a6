//! `report.html`: what a run answers, as one self-contained page built
//! from an output folder's files (`sweep.resolved.toml`, the results
//! table, `summary.csv`, `traces.csv`). Every file is read as a stream and
//! only bounded aggregates are kept (a few hundred cells a map, bins of a
//! histogram, a fixed number of time buckets a trace), so a run of any
//! size gets its report in bounded memory and in time linear in its rows.

mod aggregates;
pub mod axis;
pub mod html;
pub mod plots;
mod scan;

use std::path::Path;

use crate::columns::Column;
use crate::error::{Error, Result};
use crate::outdir::names::{REPORT, RESOLVED, SUMMARY, TRACES};
use crate::outdir::{AtomicFile, OutDir};
use crate::params::Num;
use crate::stats::wilson;
use crate::sweep::Sweep;
use aggregates::Verdict;
use html::Page;
use plots::{
    category_map, heat_map, histogram, line_chart, points_chart, tornado, Axis, Curve, Series,
};
use plotters::chart::SeriesLabelPosition;
use scan::{Folder, CONTACT_NAMES, LINE_POINTS};

/// A grid axis with at most this many values is drawn as points at its
/// values (a category each), not as a line that would suggest values in
/// between.
const FEW: usize = 8;

/// Writes `DIR/report.html` from the run in the folder `dir` holds
/// (locked), committed beside its other files.
pub fn write(dir: &mut OutDir) -> Result<()> {
    crate::outdir::pause_for_tests("before-report");
    let page = build(dir.path())?;
    let path = dir.join(REPORT);
    let mut f = AtomicFile::create(&path)?;
    std::io::Write::write_all(f.writer(), page.as_bytes()).map_err(|e| Error::io(&path, e))?;
    dir.commit_more(vec![f])
}

/// "meaning, name (unit)": a parameter's axis label.
pub(crate) fn param_label(n: Num) -> String {
    crate::columns::label(n.name(), n.def().meaning, n.def().unit)
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
    [
        k.to_string(),
        percent(k as f64 / n as f64),
        format!("{} to {}", percent(lo), percent(hi)),
    ]
}

/// The report of the run in `dir`, as HTML.
pub fn build(dir: &Path) -> Result<String> {
    let resolved_path = dir.join(RESOLVED);
    let text = std::fs::read_to_string(&resolved_path).map_err(|e| {
        Error::input(
            &resolved_path,
            None,
            None,
            format!(
                "cannot read it ({e}); allowed: a folder written by `tswm run` or `tswm merge`"
            ),
        )
    })?;
    let sweep = Sweep::parse(&resolved_path, &text)?;
    let stated = crate::output::stated_lanes(&text).ok_or_else(|| {
        Error::input(
            &resolved_path,
            None,
            None,
            "its header states no lane count (`# lanes: N`); not written by this tswm version",
        )
    })?;
    let folder = Folder::read(dir, &sweep, stated)?;
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
    undecided(&mut page, &folder);
    if let Some(r) = &folder.require {
        requirement(&mut page, r);
    }

    page.section("What was run");
    let header: Vec<&str> = text.lines().take_while(|l| l.starts_with('#')).collect();
    for l in &header {
        page.note(l.trim_start_matches('#').trim());
    }
    page.note(&format!("Folder: {}", dir.display()));
    page.heading(&format!("The resolved sweep ({RESOLVED})"));
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
        "Written by tswm from the files of its output folder: {} (one row per lane), {SUMMARY} \
         (statistics), {TRACES} (traced lanes) and {RESOLVED}. Efficiencies are energy-averaged \
         over each lane's run: eta_direct = w2_out / w1_in (worm drives wheel), eta_inverse = \
         w1_out / w2_in (wheel drives worm); the _ss values are the steady efficiencies at the \
         final sliding speed; lock_margin_deg = atan(mu_s) - gamma > 0 means the drive holds its \
         load at rest with the motor off; hold says what became of the load of a lane whose motor \
         is cut. Grey cells have no value (the lane did not finish, or the efficiency is \
         undefined).",
        folder.table
    ));
    Ok(page.finish(&title))
}

/// At the top: lanes whose question is not answered yet (still coasting
/// when their run ended), with what to do.
fn undecided(page: &mut Page, f: &Folder) {
    let coasting = f
        .by_hold
        .iter()
        .find(|h| h.0 == "coasting")
        .map_or(0, |h| h.1);
    if coasting == 0 {
        return;
    }
    page.section("Not decided: lanes still coasting");
    let what = if f.coasting_t_max.is_finite() {
        format!(
            "they ran on to t_max = {} s and were still sliding; set a larger t_max",
            plots::tick(f.coasting_t_max)
        )
    } else {
        format!(
            "set t_max in [base] (s, > t_end) so that they run on until they are held or run away, \
             e.g. t_max = {}",
            plots::tick(10.0 * f.coasting_t_end)
        )
    };
    page.warning(&format!(
        "{coasting} of {} lanes whose motor is cut were still coasting (sliding, slowing down) when \
         their run ended: whether they hold the load is not decided, and their final contact is not \
         an answer to it. To decide them, {what}.",
        f.hold_lanes
    ));
}

/// "2 to 5.25 (12 values)" or "2, 3 and 5": the runs of consecutive
/// points of `idx` (ascending) among `xs`.
fn runs(xs: &[f64], idx: &[usize]) -> String {
    let mut parts: Vec<String> = Vec::new();
    let mut i = 0;
    while i < idx.len() {
        let mut j = i;
        while j + 1 < idx.len() && idx[j + 1] == idx[j] + 1 {
            j += 1;
        }
        let (a, b) = (plots::tick(xs[idx[i]]), plots::tick(xs[idx[j]]));
        parts.push(match j - i {
            0 => a,
            1 => format!("{a}, {b}"),
            n => format!("{a} to {b} ({} values)", n + 1),
        });
        i = j + 1;
    }
    match parts.len() {
        0 => "none".into(),
        1 => parts.remove(0),
        _ => {
            let last = parts.pop().unwrap_or_default();
            format!("{} and {last}", parts.join(", "))
        }
    }
}

/// The answer to the sweep's design requirement, in sentences and a
/// marked plot per panel.
fn requirement(page: &mut Page, r: &aggregates::RequireData) {
    let req = &r.req;
    page.section("Requirement");
    let want = format!(
        "`{}` in at least {} of lanes, with 95 % confidence (one-sided Wilson bound; a lane that \
         is not ok or has no value does not meet it)",
        req.text(),
        percent(req.at_least)
    );
    let Some(axis) = r.axis else {
        let (share, lo, _, v) = r.judge(r.counts[0][0]);
        let (k, n) = r.counts[0][0];
        let verdict = match v {
            Some(Verdict::Met) => "met",
            Some(Verdict::NotMet) => "not met",
            Some(Verdict::Undecided) => "not decided: more lanes are needed",
            None => "not decided: no lanes",
        };
        page.answer(&format!(
            "Requirement {want}: {verdict} ({k} of {n} lanes, {}; lower bound {}).",
            percent(share),
            percent(lo)
        ));
        return;
    };
    let name = axis.name();
    let unit = axis.def().unit;
    let mut figs = Vec::new();
    for (p, label) in r.panel_labels.iter().enumerate() {
        let judged: Vec<_> = r.counts[p].iter().map(|&c| r.judge(c)).collect();
        let of = |v: Verdict| -> Vec<usize> {
            (0..judged.len())
                .filter(|&i| judged[i].3 == Some(v))
                .collect()
        };
        let (met, open, not) = (
            of(Verdict::Met),
            of(Verdict::Undecided),
            of(Verdict::NotMet),
        );
        let at = if label == "all lanes" {
            String::new()
        } else {
            format!(" at {label}")
        };
        let mut s = format!(
            "Requirement {want}{at}: met for {name} = {}",
            runs(&r.xs, &met)
        );
        if let (Some(&a), Some(&b)) = (met.first(), met.last()) {
            s.push_str(&format!(
                " (smallest {}, largest {}{})",
                plots::tick(r.xs[a]),
                plots::tick(r.xs[b]),
                if unit.is_empty() {
                    String::new()
                } else {
                    format!(" {unit}")
                }
            ));
        }
        if !open.is_empty() {
            s.push_str(&format!(
                "; not decided for {} (more lanes are needed there)",
                runs(&r.xs, &open)
            ));
        }
        s.push_str(&format!("; not met for {}.", runs(&r.xs, &not)));
        let most = r.counts[p].iter().map(|c| c.1).max().unwrap_or(0);
        if met.is_empty() && most < r.lanes_needed() {
            s.push_str(&format!(
                " With {most} lanes a value, no share can be confirmed at {}: that takes at least {} \
                 lanes a value, all of them meeting it (more samples in [sampling]).",
                percent(req.at_least),
                r.lanes_needed()
            ));
        }
        page.answer(&s);
        let x = Axis::grid(&param_label(axis), &r.xs);
        let y = Axis::fixed(&format!("share of lanes with {}", req.text()), 0.0, 1.0);
        let series_of = |v: Verdict, name, colour| Series {
            name,
            colour: Some(colour),
            values: judged
                .iter()
                .map(|j| {
                    if j.3 == Some(v) {
                        (j.0, j.1, j.2)
                    } else {
                        (f64::NAN, f64::NAN, f64::NAN)
                    }
                })
                .collect(),
        };
        figs.push(points_chart(
            &format!("{}{at}", req.text()),
            &x,
            &y,
            &[
                series_of(Verdict::Met, "met", plots::VERDICT_COLOURS[0]),
                series_of(Verdict::Undecided, "not decided", plots::VERDICT_COLOURS[1]),
                series_of(Verdict::NotMet, "not met", plots::VERDICT_COLOURS[2]),
            ],
            Some((req.at_least, "required share")),
            SeriesLabelPosition::LowerLeft,
        ));
    }
    if r.binned {
        page.note(&format!(
            "{name} has more values than the answer lists: they are binned into {LINE_POINTS} \
             (each named by its first value)."
        ));
    }
    page.note(
        "Points are the share of each value's lanes that meet the requirement; whiskers span its \
         one-sided 95 % bounds (a 90 % interval). Met: the lower bound is at least the required \
         share; not met: the upper bound is below it; otherwise the lanes cannot decide it.",
    );
    if (r.panel_labels.len() as u64) < r.panel_total {
        page.note(&format!(
            "Showing {} of {} combinations of the other axes ([report] panels sets the limit).",
            r.panel_labels.len(),
            r.panel_total
        ));
    }
    page.figures(figs);
}

fn outcomes(page: &mut Page, f: &Folder) {
    page.section("Outcomes");
    page.note(&format!("{} lanes.", f.lanes));
    let rows: Vec<Vec<String>> = f
        .by_status
        .iter()
        .filter(|(s, k)| *k > 0 || *s == "ok")
        .map(|&(s, k)| {
            let [a, b, c] = share_cells(k, f.lanes);
            vec![s.to_string(), a, b, c]
        })
        .collect();
    page.table(
        &["status", "lanes", "share", "95 % interval (Wilson)"],
        &rows,
    );
    let ok = f.by_status.iter().find(|s| s.0 == "ok").map_or(0, |s| s.1);
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
    if f.hold_lanes > 0 {
        page.heading("Does it hold? (lanes whose motor is cut)");
        let rows: Vec<Vec<String>> = f
            .by_hold
            .iter()
            .map(|(w, k)| {
                let [a, b, c] = share_cells(*k, f.hold_lanes);
                vec![w.to_string(), a, b, c]
            })
            .collect();
        page.table(&["hold", "lanes", "share", "95 % interval (Wilson)"], &rows);
        page.note(
            "held: at rest and stuck with the motor off; runs_away: sliding and not slowing down, \
             the load back-drives the gear; coasting: still sliding and slowing down when the run \
             ended, not decided (set t_max).",
        );
    }
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

/// What an empty or zero efficiency means, under figures that show one.
fn efficiency_note(page: &mut Page, results: &[&Column]) {
    if results.iter().any(|c| c.name.starts_with("eta_")) {
        page.note(
            "Reading the efficiencies: eta_direct has no value where the worm side put no energy \
             into the mesh (the load drove throughout, or the drive never moved), eta_inverse none \
             where the wheel side put none in. An eta_inverse of 0 means the wheel side fed \
             friction only and nothing reached the worm: the drive locks itself (dynamic \
             self-locking) and the load cannot drive it. A steady value (_ss) <= 0 means the drive \
             cannot be driven from that side at that speed.",
        );
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
    efficiency_note(page, &f.results);
    if (m.panels.len() as u64) < m.panel_total {
        page.note(&format!(
            "Showing {} of {} panels (one per value of the other axes; [report] panels sets the limit).",
            m.panels.len(),
            m.panel_total
        ));
    }
    let (x, y) = (
        Axis::grid(&param_label(m.x), &m.xs),
        Axis::grid(&param_label(m.y), &m.ys),
    );
    for p in &m.panels {
        page.heading(&p.label);
        let mut figs = Vec::new();
        let line = p.lock_line();
        for (r, c) in f.results.iter().enumerate() {
            figs.push(heat_map(
                c.quantity,
                &x,
                &y,
                &p.means(r),
                &crate::columns::label(c.name, "", c.unit),
                Some(&line),
            ));
        }
        let names: Vec<&str> = CONTACT_NAMES.iter().map(|c| c.1).collect();
        figs.push(category_map(
            "final contact (most lanes)",
            &x,
            &y,
            &p.contact_cells(),
            &names,
        ));
        page.figures(figs);
    }
}

fn lines(page: &mut Page, f: &Folder) {
    let l = f.line.as_ref().expect("checked");
    page.section(&format!("Results against {}", l.axis.name()));
    let few = l.xs().len() <= FEW;
    if f.study {
        page.note(if few {
            "Points are the mean over each grid point's sampled lanes; whiskers span their min to max."
        } else {
            "Lines are the mean over each grid point's sampled lanes; bands span their min to max."
        });
    }
    efficiency_note(page, &f.results);
    let x_label = param_label(l.axis);
    let mut figs = Vec::new();
    for (r, c) in f.results.iter().enumerate() {
        if few {
            let vals = l.per_point(r);
            let y = Axis::numeric(&c.label(), vals.iter().flat_map(|v| [v.0, v.1, v.2]));
            let vals = if f.study {
                vals
            } else {
                vals.into_iter()
                    .map(|v| (v.0, f64::NAN, f64::NAN))
                    .collect()
            };
            figs.push(points_chart(
                c.quantity,
                &Axis::grid(&x_label, l.xs()),
                &y,
                &[Series {
                    name: c.name,
                    values: vals,
                    colour: None,
                }],
                None,
                SeriesLabelPosition::UpperRight,
            ));
        } else {
            let (points, band) = l.curve(r);
            let band = if f.study { band } else { Vec::new() };
            let curves = [Curve {
                name: c.name,
                points,
                band,
                colour: None,
            }];
            let x = plots::x_axis(&x_label, &curves, &[], l.log);
            figs.push(line_chart(c.quantity, &x, l.log, &c.label(), &curves, &[]));
        }
    }
    let share = Axis::fixed("share of finished lanes", 0.0, 1.0);
    if few {
        let series: Vec<Series> = CONTACT_NAMES
            .iter()
            .enumerate()
            .map(|(i, c)| Series {
                name: c.1,
                // One lane a point without a study: its share is 0 or 1,
                // and an interval would say nothing.
                values: l
                    .contact_share(i)
                    .into_iter()
                    .map(|v| {
                        if f.study {
                            v
                        } else {
                            (v.0, f64::NAN, f64::NAN)
                        }
                    })
                    .collect(),
                colour: Some(plots::CONTACT_COLOURS[i]),
            })
            .collect();
        figs.push(points_chart(
            "final contact",
            &Axis::grid(&x_label, l.xs()),
            &share,
            &series,
            None,
            SeriesLabelPosition::UpperRight,
        ));
    } else {
        let curves: Vec<Curve> = CONTACT_NAMES
            .iter()
            .enumerate()
            .map(|(i, c)| Curve {
                name: c.1,
                points: l
                    .xs()
                    .iter()
                    .zip(l.contact_share(i))
                    .filter(|(_, s)| s.0.is_finite())
                    .map(|(x, s)| (*x, s.0))
                    .collect(),
                band: Vec::new(),
                colour: Some(plots::CONTACT_COLOURS[i]),
            })
            .collect();
        let x = plots::x_axis(&x_label, &curves, &[], l.log);
        figs.push(line_chart(
            "final contact",
            &x,
            l.log,
            "share of finished lanes",
            &curves,
            &[],
        ));
    }
    page.figures(figs);
    if f.study {
        page.heading(&format!("Final contact against {}", l.axis.name()));
        page.note(
            "The probability of each final contact over each grid point's sampled lanes, with its \
             95 % Wilson interval. Held (stick) means the drive holds its load at the end of the run.",
        );
        let rows = l.contact_rows();
        let head = [
            crate::columns::label(l.axis.name(), "", l.axis.def().unit),
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
         probability of each final contact and hold with its 95 % Wilson interval, histograms \
         with the empirical CDF, and the Spearman rank correlation of each sampled input with the \
         result (a tornado: the longer the bar, the more that tolerance moves the result).",
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
            &["outcome", "lanes", "probability", "95 % interval (Wilson)"],
            &g.contact_rows,
        );
        let mut figs = Vec::new();
        for (r, c) in f.results.iter().enumerate() {
            if let Some((lo, hi, counts)) = g.hist(r) {
                figs.push(histogram(c.quantity, &c.label(), lo, hi, counts));
            }
            let bars = g.tornado(c.name);
            if !bars.is_empty() {
                figs.push(tornado(&format!("what moves {}", c.name), &bars));
            }
        }
        page.figures(figs);
    }
    if f.groups_total > f.groups.len() {
        page.note(&format!(
            "Showing {} of {} grid points ([report] panels sets the limit); {SUMMARY} has them all.",
            f.groups.len(),
            f.groups_total
        ));
    }
}

fn traces(page: &mut Page, f: &Folder) {
    page.section("Traces");
    page.note(&format!(
        "Traced lanes through time ({TRACES}): the contact reactions S1 and S2, the force transfer \
         function psi, and the speed. Grey vertical lines mark events (a switch of the contact \
         side, a stop, the motor's cut-off); at each, the trace has the state just before and just \
         after. A lane with more rows than the plot resolves is drawn from the first, lowest, \
         highest and last value of each of {} time slices, which draws what all of them would.",
        aggregates::TRACE_BUCKETS
    ));
    for t in &f.traces {
        page.heading(&format!(
            "lane {} ({} rows, {} event{}{})",
            t.lane,
            t.rows,
            t.events,
            if t.events == 1 { "" } else { "s" },
            if t.thinned() {
                "; decimated for plotting"
            } else {
                ""
            }
        ));
        let marks = t.marks();
        let chart = |title: &str, y: &str, curves: &[Curve]| {
            let x = plots::x_axis("time, t (s)", curves, &marks, false);
            line_chart(title, &x, false, y, curves, &marks)
        };
        let curve = |name, s| Curve {
            name,
            points: t.series(s),
            band: Vec::new(),
            colour: None,
        };
        page.figures(vec![
            chart(
                "contact reactions",
                "contact reaction (N)",
                &[curve("S1", 1), curve("S2", 2)],
            ),
            chart("force transfer function", "psi", &[curve("psi", 3)]),
            chart("speed", "speed of body 1, v1 (m/s)", &[curve("v1", 0)]),
        ]);
    }
}
