//! The table of what the report says first: the lowest and highest
//! value of each plotted result over the finished lanes, where each lies,
//! and the lanes a running value leaves out (at rest: no running point).

use super::html::Page;
use super::plots;
use super::scan::Folder;
use crate::input::sweep::Sweep;

/// The lowest and highest value of each plotted result, and where.
pub(super) fn ranges(page: &mut Page, f: &Folder, sweep: &Sweep) {
    let at = |lane: u64| {
        if sweep.axes.is_empty() {
            format!("lane {lane}")
        } else {
            super::aggregates::panel_short(sweep, &[], lane / f.samples.max(1))
        }
    };
    let rows: Vec<Vec<String>> = f
        .results
        .iter()
        .zip(&f.extremes)
        .filter(|(_, e)| e.count > 0 || e.at_rest > 0)
        .map(|(c, e)| {
            let mut notes = Vec::new();
            if crate::columns::is_inverse_efficiency(c.name) && e.at_most_zero > 0 {
                notes.push(format!(
                    "<= 0 (self-locking) in {} of {}",
                    e.at_most_zero, e.count
                ));
            }
            if e.at_rest > 0 {
                notes.push(format!(
                    "{} at rest left out (no running point)",
                    super::words::lanes_text(e.at_rest).trim_end_matches('.')
                ));
            }
            let note = notes.join("; ");
            if e.count == 0 {
                let none = "none".to_string();
                return vec![
                    c.label(),
                    none.clone(),
                    String::new(),
                    none,
                    String::new(),
                    note,
                ];
            }
            vec![
                c.label(),
                plots::tick(e.min.0),
                at(e.min.1),
                plots::tick(e.max.0),
                at(e.max.1),
                note,
            ]
        })
        .collect();
    if rows.is_empty() {
        return;
    }
    let mut head = vec!["result (finished lanes)", "lowest", "at", "highest", "at"];
    let mut rows = rows;
    if rows.iter().any(|r| !r[5].is_empty()) {
        head.push("");
    } else {
        rows.iter_mut().for_each(|r| {
            r.pop();
        });
    }
    page.table(&head, &rows);
}
