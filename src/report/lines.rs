//! The report's section of results along one grid axis: a panel per
//! value of the other axes (an axis of laws or tables gets panels, never
//! a line), each with its results and outcomes (runs, stalled, held, ...)
//! as points (a few values, or words) or lines.

use plotters::chart::SeriesLabelPosition;

use super::charts::{line_chart, points_chart, x_axis, Curve, Series};
use super::html::Page;
use super::line::{LineData, LinePanel};
use super::outcome::{self, OUTCOMES};
use super::plots::Axis;
use super::scan::Folder;
use super::sections::efficiency_note;
use super::words::{param_label, FEW};

pub(super) fn lines(page: &mut Page, f: &Folder) {
    let l = f.line.as_ref().expect("checked");
    let name = l.x.param.name();
    page.section(&format!("Results against {name}"));
    // Words are categories: always points, never a line between them.
    let few = l.xs().len() <= FEW || l.x.words.is_some();
    if f.study {
        page.note(if few {
            "Points are the mean over each grid point's sampled lanes; whiskers span their min to max."
        } else {
            "Lines are the mean over each grid point's sampled lanes; bands span their min to max."
        });
    }
    efficiency_note(page, &f.results);
    if (l.panels.len() as u64) < l.panel_total {
        page.note(&format!(
            "Showing {} of {} panels (one per value of the other axes; [report] panels sets the limit).",
            l.panels.len(),
            l.panel_total
        ));
    }
    side_by_side(page, f, l, few);
    for p in &l.panels {
        if l.panel_total > 1 {
            page.heading(&p.label);
        }
        let mut figs: Vec<_> = (0..f.results.len())
            .map(|r| result_along(f, l, p, r, few))
            .collect();
        figs.push(outcome_along(f, l, p, few));
        page.figures(figs);
        if f.study {
            outcome_table(page, l, p);
        }
    }
}

/// Most panels drawn together in one chart (one colour each).
const SIDE_BY_SIDE: usize = 6;

/// The panels' results in one chart each, a colour and a legend entry per
/// panel (per material, law or motor of a word axis): what sets them
/// apart at a glance. Only for 2 to 6 panels.
fn side_by_side(page: &mut Page, f: &Folder, l: &LineData, few: bool) {
    let n = l.panels.len();
    if !(2..=SIDE_BY_SIDE).contains(&n) {
        return;
    }
    page.heading("Side by side");
    let figs = f
        .results
        .iter()
        .enumerate()
        .map(|(r, c)| {
            if few {
                let series: Vec<Series> = l
                    .panels
                    .iter()
                    .map(|p| Series {
                        name: &p.values,
                        values: p
                            .per_point(r)
                            .into_iter()
                            .map(|v| (v.0, f64::NAN, f64::NAN))
                            .collect(),
                        colour: None,
                    })
                    .collect();
                let y = Axis::numeric(
                    &c.label(),
                    series.iter().flat_map(|s| s.values.iter().map(|v| v.0)),
                );
                points_chart(
                    c.quantity,
                    &l.x.categories(),
                    &y,
                    &series,
                    None,
                    SeriesLabelPosition::UpperRight,
                )
            } else {
                let curves: Vec<Curve> = l
                    .panels
                    .iter()
                    .map(|p| Curve {
                        name: &p.values,
                        points: p.curve(l.xs(), r).0,
                        band: Vec::new(),
                        colour: None,
                    })
                    .collect();
                let x = x_axis(&param_label(l.x.param), &curves, &[], l.x.log);
                line_chart(c.quantity, &x, l.x.log, &c.label(), &curves, &[])
            }
        })
        .collect();
    page.figures(figs);
}

/// A study's outcomes along the axis, with their intervals.
fn outcome_table(page: &mut Page, l: &LineData, p: &LinePanel) {
    page.heading(&format!("Outcome against {}", l.x.param.name()));
    page.note(if p.independent() {
        "The probability of each outcome over each grid point's sampled lanes, with its 95 % \
         Wilson interval. Held: at rest with the motor cut (the drive holds its load); stalled: \
         at rest with the motor on (it cannot start or keep moving the load)."
    } else {
        "The share of each outcome over each grid point's lanes (no interval: the lanes of a \
         sensitivity design are not independent draws). Held: at rest with the motor cut; \
         stalled: at rest with the motor on."
    });
    let shown = outcome::present(&p.outcome_totals());
    let rows = p.outcome_rows(&l.x, &shown);
    let unit = match l.x.param {
        crate::params::Param::Num(n) => n.def().unit,
        _ => "",
    };
    let mut head = vec![
        crate::columns::label(l.x.param.name(), "", unit),
        "finished lanes".into(),
    ];
    head.extend(shown.iter().map(|&k| OUTCOMES[k].0.to_string()));
    let head: Vec<&str> = head.iter().map(|s| s.as_str()).collect();
    page.table(&head, &rows);
}

/// Result `r` along the one grid axis: points with whiskers for a few
/// values or words (a study's min to max), else a line with a band.
fn result_along(
    f: &Folder,
    l: &LineData,
    p: &LinePanel,
    r: usize,
    few: bool,
) -> Result<String, String> {
    let c = f.results[r];
    if few {
        let vals = p.per_point(r);
        let y = Axis::numeric(&c.label(), vals.iter().flat_map(|v| [v.0, v.1, v.2]));
        let vals = if f.study {
            vals
        } else {
            vals.into_iter()
                .map(|v| (v.0, f64::NAN, f64::NAN))
                .collect()
        };
        return points_chart(
            c.quantity,
            &l.x.categories(),
            &y,
            &[Series {
                name: c.name,
                values: vals,
                colour: None,
            }],
            None,
            SeriesLabelPosition::UpperRight,
        );
    }
    let (points, band) = p.curve(l.xs(), r);
    let band = if f.study { band } else { Vec::new() };
    let curves = [Curve {
        name: c.name,
        points,
        band,
        colour: None,
    }];
    let x = x_axis(&param_label(l.x.param), &curves, &[], l.x.log);
    line_chart(c.quantity, &x, l.x.log, &c.label(), &curves, &[])
}

/// The share of each outcome along the one grid axis (those that occur).
fn outcome_along(f: &Folder, l: &LineData, p: &LinePanel, few: bool) -> Result<String, String> {
    let shown = outcome::present(&p.outcome_totals());
    // One outcome draws no legend: the title names it.
    let title = match shown.as_slice() {
        [k] => format!("outcome: {}", OUTCOMES[*k].0),
        _ => "outcome".to_string(),
    };
    if few {
        let series: Vec<Series> = shown
            .iter()
            .map(|&i| Series {
                name: OUTCOMES[i].0,
                // One lane a point without a study: its share is 0 or 1,
                // and an interval would say nothing.
                values: p
                    .outcome_share(i)
                    .into_iter()
                    .map(|v| {
                        if f.study {
                            v
                        } else {
                            (v.0, f64::NAN, f64::NAN)
                        }
                    })
                    .collect(),
                colour: Some(OUTCOMES[i].1),
            })
            .collect();
        return points_chart(
            &title,
            &l.x.categories(),
            &Axis::fixed("share of finished lanes", 0.0, 1.0),
            &series,
            None,
            SeriesLabelPosition::UpperRight,
        );
    }
    let curves: Vec<Curve> = shown
        .iter()
        .map(|&i| Curve {
            name: OUTCOMES[i].0,
            points: l
                .xs()
                .iter()
                .zip(p.outcome_share(i))
                .filter(|(_, s)| s.0.is_finite())
                .map(|(x, s)| (*x, s.0))
                .collect(),
            band: Vec::new(),
            colour: Some(OUTCOMES[i].1),
        })
        .collect();
    let x = x_axis(&param_label(l.x.param), &curves, &[], l.x.log);
    line_chart(&title, &x, l.x.log, "share of finished lanes", &curves, &[])
}
