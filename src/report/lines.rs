//! The report's section of results along one grid axis: a panel per
//! value of the other axes (an axis of laws or tables gets panels, never
//! a line), each with its results and final contacts as points (a few
//! values, or words) or lines.

use plotters::chart::SeriesLabelPosition;

use super::charts::{line_chart, points_chart, x_axis, Curve, Series};
use super::html::Page;
use super::line::{LineData, LinePanel};
use super::plots::{self, Axis};
use super::scan::{Folder, CONTACT_NAMES};
use super::sections::efficiency_note;
use super::{param_label, FEW};

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
        figs.push(contact_along(f, l, p, few));
        page.figures(figs);
        if f.study {
            contact_table(page, l, p);
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

/// A study's final contacts along the axis, with their intervals.
fn contact_table(page: &mut Page, l: &LineData, p: &LinePanel) {
    page.heading(&format!("Final contact against {}", l.x.param.name()));
    page.note(
        "The probability of each final contact over each grid point's sampled lanes, with its \
         95 % Wilson interval. Held (stick) means the drive holds its load at the end of the run.",
    );
    let rows = p.contact_rows(&l.x);
    let unit = match l.x.param {
        crate::params::Param::Num(n) => n.def().unit,
        _ => "",
    };
    let head = [
        crate::columns::label(l.x.param.name(), "", unit),
        "finished lanes".into(),
        "held".into(),
        "held, 95 % interval".into(),
        "a-a".into(),
        "b-b".into(),
    ];
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

/// The share of each final contact along the one grid axis.
fn contact_along(f: &Folder, l: &LineData, p: &LinePanel, few: bool) -> Result<String, String> {
    if few {
        let series: Vec<Series> = CONTACT_NAMES
            .iter()
            .enumerate()
            .map(|(i, c)| Series {
                name: c.1,
                // One lane a point without a study: its share is 0 or 1,
                // and an interval would say nothing.
                values: p
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
        return points_chart(
            "final contact",
            &l.x.categories(),
            &Axis::fixed("share of finished lanes", 0.0, 1.0),
            &series,
            None,
            SeriesLabelPosition::UpperRight,
        );
    }
    let curves: Vec<Curve> = CONTACT_NAMES
        .iter()
        .enumerate()
        .map(|(i, c)| Curve {
            name: c.1,
            points: l
                .xs()
                .iter()
                .zip(p.contact_share(i))
                .filter(|(_, s)| s.0.is_finite())
                .map(|(x, s)| (*x, s.0))
                .collect(),
            band: Vec::new(),
            colour: Some(plots::CONTACT_COLOURS[i]),
        })
        .collect();
    let x = x_axis(&param_label(l.x.param), &curves, &[], l.x.log);
    line_chart(
        "final contact",
        &x,
        l.x.log,
        "share of finished lanes",
        &curves,
        &[],
    )
}
