//! What the report says first: what the run found (its outcomes and the
//! ranges of its main results), lanes whose question is not answered
//! yet, and the answer to the sweep's design requirement.

use plotters::chart::SeriesLabelPosition;

use super::charts::{points_chart, Series, VERDICT_COLOURS};
use super::html::Page;
use super::line::XAxis;
use super::plots::{self, Axis};
use super::require::{RequireData, Verdict};
use super::scan::{Folder, LINE_POINTS};
use super::words::percent;
use crate::input::sweep::Sweep;
use crate::params::Param;

/// The first section: what the run found, in sentences: its size, its
/// outcomes (stalled and coasting lanes named as such), and the range of
/// each plotted result with where its ends lie.
pub(super) fn findings(page: &mut Page, f: &Folder, sweep: &Sweep) {
    page.section("What was found");
    let shape = if sweep.axes.is_empty() {
        String::new()
    } else {
        let axes: Vec<String> = sweep
            .axes
            .iter()
            .map(|a| format!("{} {}", a.len(), a.param.name()))
            .collect();
        format!(
            ": a grid of {}{}",
            axes.join(" x "),
            if f.samples > 1 {
                format!(", {} sampled lanes a grid point", f.samples)
            } else {
                String::new()
            }
        )
    };
    let ok = f.by_status.iter().find(|s| s.0 == "ok").map_or(0, |s| s.1);
    let mut s = format!(
        "{}{shape}. {} finished",
        super::words::lanes_text(f.lanes).trim_end_matches('.'),
        if ok == f.lanes && f.lanes > 1 {
            "All".to_string()
        } else {
            format!("{ok} of them")
        }
    );
    let shown = super::outcome::present(&f.by_outcome);
    if ok > 0 {
        let parts: Vec<String> = shown
            .iter()
            .map(|&k| format!("{} {}", super::outcome::OUTCOMES[k].0, f.by_outcome[k]))
            .collect();
        s.push_str(&format!(": {}.", parts.join(", ")));
    } else {
        s.push('.');
    }
    page.answer(&s);
    if let Some(sheet) = &f.sheet {
        // A small run says in words what each drive does and whether it
        // is self-locking (its data sheet follows).
        page.answer(&sheet.sentences().join(" "));
    }
    let stalled = f.by_outcome[super::outcome::STALLED];
    if stalled > 0 {
        page.warning(&format!(
            "{stalled} of {ok} finished lane{} {} stalled: at rest and stuck with the motor on, the \
             motor cannot start (or keep moving) the load. They have not \"held\" anything, and \
             have no running point: their running (_ss) efficiencies are left out of the ranges \
             and maps (the starting values are eta_direct_start and eta_inverse_start).",
            super::words::plural(ok),
            if stalled == 1 { "is" } else { "are" }
        ));
    }
    if f.unfinished_total > 0 {
        page.warning(&format!(
            "{} could not be finished (their status is not ok; listed under Outcomes): they have \
             no results.",
            super::words::lanes_text(f.unfinished_total).trim_end_matches('.')
        ));
    }
    super::ranges::ranges(page, f, sweep);
}

/// At the top: lanes whose question is not answered yet (still coasting
/// when their run ended), with what to do.
pub(super) fn undecided(page: &mut Page, f: &Folder) {
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
        "{coasting} of {} lane{} whose motor is cut {} still coasting (sliding, slowing down) when \
         their run ended: whether they hold the load is not decided, and their final contact is not \
         an answer to it. To decide them, {what}.",
        f.hold_lanes,
        super::words::plural(f.hold_lanes),
        if coasting == 1 { "was" } else { "were" }
    ));
}

/// "2 to 5.25 (12 values)" or "2, 3 and 5": the runs of consecutive
/// points of `idx` (ascending) along `x`.
fn runs(x: &XAxis, idx: &[usize]) -> String {
    let mut parts: Vec<String> = Vec::new();
    let mut i = 0;
    while i < idx.len() {
        let mut j = i;
        while j + 1 < idx.len() && idx[j + 1] == idx[j] + 1 {
            j += 1;
        }
        let (a, b) = (x.text(idx[i]), x.text(idx[j]));
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
/// Says why the requirement cannot be answered, when no lane has a value
/// of its column (counting them as "not met" would answer a question the
/// run did not ask); whether it said so.
fn unanswerable(page: &mut Page, r: &RequireData) -> bool {
    if r.valued > 0 {
        return false;
    }
    let req = &r.req;
    let why = crate::columns::result(req.column).map_or("", |c| c.empty);
    page.warning(&format!(
        "Requirement `{}` cannot be answered: no lane has a value of {} (it is empty when {}).",
        req.text(),
        req.column,
        if why.is_empty() {
            "the lane has none"
        } else {
            why
        }
    ));
    true
}

pub(super) fn requirement(page: &mut Page, r: &RequireData) {
    let req = &r.req;
    page.section("Requirement");
    let want = if r.exact {
        format!(
            "`{}` in at least {} of lanes (every lane of the grid counted, none sampled: the share \
             is exact; a lane that is not ok or has no value does not meet it)",
            req.text(),
            percent(req.at_least)
        )
    } else {
        format!(
            "`{}` in at least {} of lanes, with 95 % confidence (one-sided Wilson bound; a lane \
             that is not ok or has no value does not meet it)",
            req.text(),
            percent(req.at_least)
        )
    };
    if unanswerable(page, r) {
        return;
    }
    let Some(axis) = &r.x else {
        page.answer(&format!("Requirement {want}: {}", whole_run(r)));
        return;
    };
    let mut figs = Vec::new();
    // Panels with the same answer are answered together.
    let mut answers: Vec<(String, Vec<&str>)> = Vec::new();
    for (p, label) in r.panel_labels.iter().enumerate() {
        let judged: Vec<Judged> = r.counts[p].iter().map(|&c| r.judge(c)).collect();
        let at = if label == "all lanes" {
            String::new()
        } else {
            format!(" at {label}")
        };
        let answer = along_axis(r, axis, p, &judged);
        match answers.iter_mut().find(|a| a.0 == answer) {
            Some(a) => a.1.push(label),
            None => answers.push((answer, vec![label])),
        }
        figs.push(marked_chart(r, axis, &at, &judged));
    }
    let every = answers.len() == 1
        && r.panel_labels.len() > 1
        && r.panel_labels.len() as u64 == r.panel_total;
    for (answer, labels) in &answers {
        let at = match labels.as_slice() {
            _ if every => format!(" at every value of {}", r.others),
            ["all lanes"] => String::new(),
            ls => format!(" at {}", ls.join("; ")),
        };
        page.answer(&format!("Requirement {want}{at}: {answer}"));
    }
    if axis.binned {
        page.note(&format!(
            "{} has more values than the answer lists: they are binned into {LINE_POINTS} \
             (each named by its first value).",
            axis.param.name()
        ));
    }
    page.note(if r.exact {
        "Points are the share of each value's lanes that meet the requirement. The sweep samples \
         nothing (no tolerance study), so each share is exact: met where it is at least the \
         required share, not met where it is below."
    } else {
        "Points are the share of each value's lanes that meet the requirement; whiskers span its \
         one-sided 95 % bounds (a 90 % interval). Met: the lower bound is at least the required \
         share; not met: the upper bound is below it; otherwise the lanes cannot decide it."
    });
    if (r.panel_labels.len() as u64) < r.panel_total {
        page.note(&format!(
            "Showing {} of {} combinations of the other axes ([report] panels sets the limit).",
            r.panel_labels.len(),
            r.panel_total
        ));
    }
    page.figures(figs);
}

/// A point's share, its one-sided bounds and verdict (see
/// [`RequireData::judge`]).
type Judged = (f64, f64, f64, Option<Verdict>);

/// The answer for a sweep without a grid: all its lanes at once.
fn whole_run(r: &RequireData) -> String {
    let (share, lo, _, v) = r.judge(r.counts[0][0]);
    let (k, n) = r.counts[0][0];
    let (_, _, hi, _) = r.judge(r.counts[0][0]);
    let verdict = match v {
        Some(Verdict::Met) => "met",
        Some(Verdict::NotMet) => "not met",
        Some(Verdict::Undecided) => "not decided: more lanes are needed",
        None => "not decided: no lanes",
    };
    if r.exact {
        format!(
            "{verdict} ({k} of {n} lane{}, {}).",
            super::words::plural(n),
            percent(share)
        )
    } else {
        // The bound that decides: the lower for met, the upper for not met.
        let bounds = match v {
            Some(Verdict::Met) => format!("lower bound {}", percent(lo)),
            Some(Verdict::NotMet) => format!("upper bound {}", percent(hi)),
            _ => format!("bounds {} to {}", percent(lo), percent(hi)),
        };
        format!(
            "{verdict} ({k} of {n} lane{}, {}; {bounds}).",
            super::words::plural(n),
            percent(share)
        )
    }
}

/// The answer along the axis for panel `p`: the values that meet it (with
/// the smallest and largest), those that cannot be decided, those that do
/// not, and how many lanes a value would take when too few ran.
fn along_axis(r: &RequireData, axis: &XAxis, p: usize, judged: &[Judged]) -> String {
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
    let mut s = format!("met for {} = {}", axis.param.name(), runs(axis, &met));
    if let (Some(&a), Some(&b), Param::Num(n)) = (met.first(), met.last(), axis.param) {
        let unit = n.def().unit;
        s.push_str(&format!(
            " (smallest {}, largest {}{})",
            axis.text(a),
            axis.text(b),
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
            runs(axis, &open)
        ));
    }
    s.push_str(&format!("; not met for {}.", runs(axis, &not)));
    let most = r.counts[p].iter().map(|c| c.1).max().unwrap_or(0);
    if !r.exact && met.is_empty() && most < r.lanes_needed() {
        s.push_str(&format!(
            " With {most} lanes a value, no share can be confirmed at {}: that takes at least {} \
             lanes a value, all of them meeting it (more samples in [sampling]).",
            percent(r.req.at_least),
            r.lanes_needed()
        ));
    }
    s
}

/// The share of each value that meets the requirement, marked by its
/// verdict, with the required share as a line.
fn marked_chart(
    r: &RequireData,
    axis: &XAxis,
    at: &str,
    judged: &[Judged],
) -> Result<String, String> {
    let x = axis.categories();
    let y = Axis::fixed(&format!("share of lanes with {}", r.req.text()), 0.0, 1.0);
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
    points_chart(
        &format!("{}{at}", r.req.text()),
        &x,
        &y,
        &[
            series_of(Verdict::Met, "met", VERDICT_COLOURS[0]),
            series_of(Verdict::Undecided, "not decided", VERDICT_COLOURS[1]),
            series_of(Verdict::NotMet, "not met", VERDICT_COLOURS[2]),
        ],
        Some((r.req.at_least, "required share")),
        SeriesLabelPosition::LowerLeft,
    )
}
