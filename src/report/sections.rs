//! The report's sections after its answers: outcomes, maps, the tolerance
//! study, and traces (results along one axis are in `lines`).

use super::charts::{histogram, line_chart, tornado, x_axis, Curve};
use super::html::Page;
use super::map_plots::{category_map, heat_map, HeatMarks};
use super::outcome::{self, OUTCOMES};
use super::plots::Axis;
use super::scan::{Folder, CONTACT_NAMES};
use super::words::{param_label, share_cells};
use crate::columns::Column;
use crate::columns::{DRIVE, HOLD, LANE, STATUS};
use crate::output::names::{SUMMARY, TRACES};

/// A table of word counts out of `n` lanes: word, lanes, share, and the
/// 95 % Wilson interval where the lanes are sampled.
fn share_table(page: &mut Page, f: &Folder, head: &str, counts: &[(String, u64)], n: u64) {
    let rows: Vec<Vec<String>> = counts
        .iter()
        .map(|(w, k)| {
            let [a, b, c] = share_cells(*k, n, f.sampled);
            let mut r = vec![w.clone(), a, b];
            if f.sampled {
                r.push(c);
            }
            r
        })
        .collect();
    let mut h = vec![head, "lanes", "share"];
    if f.sampled {
        h.push("95 % interval (Wilson)");
    }
    page.table(&h, &rows);
}

pub(super) fn outcomes(page: &mut Page, f: &Folder) {
    page.section("Outcomes");
    page.note(&super::words::lanes_text(f.lanes));
    if !f.independent {
        page.note(
            "No intervals: the lanes of a sensitivity design are not independent draws (a row \
             group shares every input but one), so a Wilson interval would overstate what they \
             show. The shares are those of the design's lanes; for a share with an interval, run \
             a [sampling] study.",
        );
    } else if !f.sampled {
        page.note(
            "No intervals: the run samples nothing (every lane is a grid point or a row of a lane \
             table), so each share is exact for these lanes.",
        );
    }
    let status: Vec<(String, u64)> = f
        .by_status
        .iter()
        .filter(|(s, k)| *k > 0 || *s == "ok")
        .map(|&(s, k)| (s.to_string(), k))
        .collect();
    share_table(page, f, STATUS, &status, f.lanes);
    let ok = f.by_status.iter().find(|s| s.0 == "ok").map_or(0, |s| s.1);
    let contact: Vec<(String, u64)> = CONTACT_NAMES
        .iter()
        .enumerate()
        .map(|(i, (c, meaning))| (format!("{} ({meaning})", c.name()), f.by_contact[i]))
        .collect();
    share_table(page, f, "final contact (finished lanes)", &contact, ok);
    let words = |v: &[(&str, u64)]| -> Vec<(String, u64)> {
        v.iter().map(|(w, k)| (w.to_string(), *k)).collect()
    };
    if f.drive_lanes > 0 {
        page.heading("Does the motor drive it? (lanes whose motor runs to the end)");
        share_table(page, f, DRIVE, &words(&f.by_drive), f.drive_lanes);
        page.note(
            "runs: sliding in the motor's direction, the motor driving the load; overhauled: \
             sliding in the motor's direction with the mesh driving the worm side, the load \
             overhauls and the motor brakes it; stalled: at rest and stuck with the motor on, the \
             motor cannot start (or keep moving) the load, and the lane has no running point; \
             back_driven: sliding against the motor, the load drives the worm backwards.",
        );
    }
    if f.hold_lanes > 0 {
        page.heading("Does it hold? (lanes whose motor is cut)");
        share_table(page, f, HOLD, &words(&f.by_hold), f.hold_lanes);
        page.note(
            "held: at rest and stuck with the motor off; runs_away: sliding and not slowing down, \
             the load back-drives the gear; coasting: still sliding and slowing down when the run \
             ended, not decided (set t_max).",
        );
    }
    if f.unfinished_total > 0 {
        page.heading("Lanes that could not be finished");
        let mut head = vec![LANE, STATUS];
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
pub(super) fn efficiency_note(page: &mut Page, results: &[&Column]) {
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

pub(super) fn maps(page: &mut Page, f: &Folder) {
    let m = f.map.as_ref().expect("checked");
    page.section("Maps");
    page.note(&format!(
        "Each cell is one grid point{} over {} and {}. The red line is the static self-locking \
         limit (lock_margin_deg = 0, i.e. gamma = atan(mu_s / cos alpha_n)): where the map \
         crosses it the drive starts to hold its load with the motor off.{}",
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
    map_notes(page, f);
    let (x, y) = (
        Axis::grid(&param_label(m.x), &m.xs),
        Axis::grid(&param_label(m.y), &m.ys),
    );
    for p in &m.panels {
        map_panel(page, f, p, &x, &y);
    }
}

/// What the marks of the maps mean: struck-through stalled cells, and
/// inverse efficiencies <= 0.
fn map_notes(page: &mut Page, f: &Folder) {
    let at_rest: u64 = outcome::AT_REST.iter().map(|&k| f.by_outcome[k]).sum();
    let running = f.results.iter().any(|c| c.running);
    if at_rest > 0 && running {
        page.note(&format!(
            "Struck-through cells (a diagonal) of a running efficiency (_ss) hold lanes at rest at \
             their end ({at_rest} in all: stalled, held or at rest without a motor): they have no \
             running point, so the cell shows the mean of its sliding lanes, or none."
        ));
    }
    if f.results
        .iter()
        .any(|c| crate::columns::is_inverse_efficiency(c.name))
    {
        page.note(
            "Dark grey cells of an inverse efficiency are <= 0: the drive is self-locking there \
             (the wheel cannot drive the worm); the colour scale spans the other cells.",
        );
    }
}

/// One panel of the maps: a heat map per result, and the outcome map.
fn map_panel(page: &mut Page, f: &Folder, p: &super::aggregates::Panel, x: &Axis, y: &Axis) {
    {
        page.heading(&p.label);
        let mut figs = Vec::new();
        let line = p.lock_line();
        let struck = p.at_rest_cells();
        for (r, c) in f.results.iter().enumerate() {
            let marks = HeatMarks {
                line: Some(&line),
                struck: c.running.then_some((&struck[..], "at rest")),
                at_most_zero: crate::columns::is_inverse_efficiency(c.name)
                    .then_some("self-locking"),
            };
            figs.push(heat_map(
                c.quantity,
                x,
                y,
                &p.means(r),
                &crate::columns::label(c.name, "", c.unit),
                marks,
            ));
        }
        let cells = p.outcome_cells();
        let mut seen = [0u64; outcome::N];
        for &k in &cells {
            if k < outcome::N {
                seen[k] += 1;
            }
        }
        figs.push(category_map(
            "outcome (most lanes)",
            x,
            y,
            &cells,
            &OUTCOMES,
            outcome::NONE_COLOUR,
            &outcome::present(&seen),
        ));
        page.figures(figs);
    }
}

pub(super) fn study(page: &mut Page, f: &Folder) {
    page.section("Tolerance study");
    page.note(&format!(
        "Per grid point (or the whole study): the quantiles of each result from summary.csv, the \
         probability of each final contact, drive and hold{}, histograms with the empirical CDF, and the \
         Spearman rank correlation of each sampled input with the result (a tornado: the longer \
         the bar, the more that tolerance moves the result).",
        if f.independent {
            " with its 95 % Wilson interval"
        } else {
            " (no interval: the lanes of a sensitivity design are not independent draws)"
        }
    ));
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

pub(super) fn traces(page: &mut Page, f: &Folder) {
    page.section("Traces");
    page.note(&format!(
        "Traced lanes through time ({TRACES}): the contact reactions S1 and S2, the force transfer \
         function psi, and the speed. Grey vertical lines mark events (a switch of the contact \
         side, a stop, the motor's cut-off); at each, the trace has the state just before and just \
         after. A lane with more rows than the plot resolves is drawn from the first, lowest, \
         highest and last value of each of {} time slices, which draws what all of them would.",
        super::trace::TRACE_BUCKETS
    ));
    for t in &f.traces {
        let label = f
            .trace_labels
            .iter()
            .find(|(l, _)| *l == t.lane)
            .map_or(String::new(), |(_, s)| format!(": {s}"));
        page.heading(&format!(
            "lane {}{label} ({} rows, {} event{}{})",
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
            let x = x_axis("time, t (s)", curves, &marks, false);
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
