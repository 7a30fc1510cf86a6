//! The report's sections after its answers: outcomes, maps, the tolerance
//! study, and traces (results along one axis are in `lines`).

use super::charts::{histogram, line_chart, tornado, x_axis, Curve};
use super::html::Page;
use super::plots::{category_map, heat_map, Axis};
use super::scan::{Folder, CONTACT_NAMES};
use super::{param_label, share_cells};
use crate::columns::Column;
use crate::columns::{HOLD, LANE, STATUS};
use crate::output::names::{SUMMARY, TRACES};

pub(super) fn outcomes(page: &mut Page, f: &Folder) {
    page.section("Outcomes");
    page.note(&format!("{} lanes.", f.lanes));
    if !f.independent {
        page.note(
            "No intervals: the lanes of a sensitivity design are not independent draws (a row \
             group shares every input but one), so a Wilson interval would overstate what they \
             show. The shares are those of the design's lanes; for a share with an interval, run \
             a [sampling] study.",
        );
    }
    let rows: Vec<Vec<String>> = f
        .by_status
        .iter()
        .filter(|(s, k)| *k > 0 || *s == "ok")
        .map(|&(s, k)| {
            let [a, b, c] = share_cells(k, f.lanes, f.independent);
            vec![s.to_string(), a, b, c]
        })
        .collect();
    page.table(&[STATUS, "lanes", "share", "95 % interval (Wilson)"], &rows);
    let ok = f.by_status.iter().find(|s| s.0 == "ok").map_or(0, |s| s.1);
    let rows: Vec<Vec<String>> = CONTACT_NAMES
        .iter()
        .enumerate()
        .map(|(i, (name, meaning))| {
            let [a, b, c] = share_cells(f.by_contact[i], ok, f.independent);
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
                let [a, b, c] = share_cells(*k, f.hold_lanes, f.independent);
                vec![w.to_string(), a, b, c]
            })
            .collect();
        page.table(&[HOLD, "lanes", "share", "95 % interval (Wilson)"], &rows);
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

pub(super) fn study(page: &mut Page, f: &Folder) {
    page.section("Tolerance study");
    page.note(&format!(
        "Per grid point (or the whole study): the quantiles of each result from summary.csv, the \
         probability of each final contact and hold{}, histograms with the empirical CDF, and the \
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
