//! Charts that mean what they show: bounded traces, no trend drawn
//! between grid points, axes named with their units, ticks on cell
//! centres and round values, sorted categories, series on their ticks.

use super::*;

/// A traced lane with 20,000 events is plotted from a bounded number of
/// points (the decimation keeps four a time slice and series), and its
/// events from one mark a slice.
#[test]
fn a_trace_with_20000_events_is_drawn_from_bounded_points() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = root().join("sweeps/paper.toml");
    run_ok(
        &cpu(&["run", sweep.to_str().unwrap(), "--out", "o"]),
        dir.path(),
    );
    // Lane 0 over its 2 s: 20,000 events (two rows each, one time) between
    // rows every 10 µs.
    let mut t = String::from("lane,t,x1,v1,a1,f1,s1,s2,psi,phi,contact\n");
    for i in 0..200_000u32 {
        let time = i as f64 * 1e-5;
        let v = (i as f64 * 0.37).sin();
        t.push_str(&format!("0,{time},0,{v},0,0,{v},{},-0.1,1,aa\n", -v));
        if i % 10 == 5 {
            t.push_str(&format!("0,{time},0,{},0,0,{v},{v},-0.2,-1,bb\n", -v));
        }
    }
    std::fs::write(dir.path().join("o/traces.csv"), t).unwrap();
    let out = report_within(dir.path(), 60);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let html = std::fs::read_to_string(dir.path().join("o/report.html")).unwrap();
    assert!(
        html.contains("(220000 rows, 20000 events; decimated"),
        "no heading of lane 0"
    );
    // Three figures of at most 4 points a slice and series, 1000 slices.
    let points = html.matches(',').count();
    assert!(
        html.len() < 3_000_000,
        "{} bytes, {points} commas",
        html.len()
    );
}

/// The colour-coded polylines of a report section: (colour, points).
fn coloured_polylines(section: &str) -> Vec<Vec<(i64, i64)>> {
    let mut out = Vec::new();
    for part in section.split("<polyline").skip(1) {
        let tag = &part[..part.find('>').unwrap()];
        if tag.contains("stroke=\"#000000\"") {
            continue; // axes and ticks
        }
        let pts = tag.split("points=\"").nth(1).unwrap();
        let pts = &pts[..pts.find('"').unwrap()];
        out.push(
            pts.split_whitespace()
                .map(|p| {
                    let (x, y) = p.split_once(',').unwrap();
                    (x.parse().unwrap(), y.parse().unwrap())
                })
                .collect(),
        );
    }
    out
}

/// A grid axis of two loads is drawn as points with whiskers, never as a
/// line from one load to the other.
#[test]
fn a_grid_of_two_loads_is_not_drawn_as_a_trend() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = root().join("sweeps/paper.toml");
    run_ok(
        &cpu(&["run", sweep.to_str().unwrap(), "--out", "o"]),
        dir.path(),
    );
    let html = std::fs::read_to_string(dir.path().join("o/report.html")).unwrap();
    let sec = &html[html.find("Results against f2").unwrap()..html.find("<h2>Traces").unwrap()];
    assert!(sec.contains("<circle"));
    for line in coloured_polylines(sec) {
        assert!(
            line.iter().all(|p| p.0 == line[0].0),
            "a line joins points across the axis: {line:?}"
        );
    }
}

/// A single-value axis is named by its value, not a band around it.
#[test]
fn a_single_point_axis_reads_its_value() {
    let dir = tempfile::tempdir().unwrap();
    let html = report_of(
        dir.path(),
        "[base]\nt_end = 0.3\n[[grid]]\nparam = \"f2\"\nvalues = [4774.0]\n",
    );
    let sec = &html[html.find("Results against f2").unwrap()..];
    assert!(sec.contains(">\n4774\n<"), "no tick 4774");
    assert!(!sec.contains(">\n4773.5\n<") && !sec.contains(">\n4774.5\n<"));
}

#[test]
fn axes_name_the_quantity_and_its_unit() {
    let dir = tempfile::tempdir().unwrap();
    let html = report_of(
        dir.path(),
        "[base]\nt_end = 0.3\n[[grid]]\nparam = \"gamma_deg\"\nfrom = 3.0\nto = 20.0\nn = 12\n",
    );
    for want in [
        "running direct efficiency, eta_direct_ss",
        "static lock margin, lock_margin_deg (deg)",
        "lead angle, gamma_deg (deg)",
    ] {
        assert!(html.contains(want), "no `{want}`");
    }
}

#[test]
fn efficiency_maps_say_what_an_empty_or_zero_efficiency_means() {
    let dir = tempfile::tempdir().unwrap();
    let html = report_of(dir.path(), SMALL);
    assert!(html.contains("An eta_inverse of 0 means the wheel side fed friction only"));
    assert!(html.contains("eta_direct has no value where the worm side put no energy"));
}

/// Heat-map ticks sit on cell centres: the tick of grid value i is at
/// position i, where cell i is centred.
#[test]
fn heat_map_ticks_name_cell_centres() {
    use tswm::report::plots::Axis;
    let a = Axis::grid("gamma", &[2.0, 5.710593137499643, 10.0]);
    assert_eq!(
        a.ticks(),
        vec![
            (0.0, "2".to_string()),
            (1.0, "5.711".to_string()),
            (2.0, "10".to_string())
        ]
    );
}

/// Grid values along a range too long to label one by one get ticks at
/// round values, at their fractional positions (the grid's 0.1019 is no
/// tick); lists and short ranges are labelled value by value.
#[test]
fn long_grid_axes_get_round_ticks() {
    use tswm::report::plots::Axis;
    let log: Vec<f64> = (0..15)
        .map(|i| (0.01f64.ln() + (0.15f64.ln() - 0.01f64.ln()) * i as f64 / 14.0).exp())
        .collect();
    let ticks = Axis::grid("mu", &log).ticks();
    let labels: Vec<&str> = ticks.iter().map(|t| t.1.as_str()).collect();
    assert_eq!(labels, ["0.01", "0.02", "0.05", "0.1"]);
    let step = (0.15f64.ln() - 0.01f64.ln()) / 14.0;
    for (p, l) in &ticks {
        let v: f64 = l.parse().unwrap();
        assert!(
            (p - (v.ln() - 0.01f64.ln()) / step).abs() < 1e-9,
            "{l} at {p}"
        );
    }
    let lin: Vec<f64> = (0..29).map(|i| 2.0 + i as f64).collect();
    let ticks = Axis::grid("gamma", &lin).ticks();
    assert_eq!(ticks.first(), Some(&(3.0, "5".to_string())));
    assert!(ticks
        .iter()
        .all(|(p, l)| *p == l.parse::<f64>().unwrap() - 2.0));
    assert!(ticks.len() >= 2 && ticks.len() <= 8);
}

/// A list of values is drawn in ascending order, whatever the list's.
#[test]
fn a_categorical_numeric_axis_is_sorted() {
    let dir = tempfile::tempdir().unwrap();
    let html = report_of(
        dir.path(),
        "[base]\nt_end = 0.3\n[[grid]]\nparam = \"f2\"\nvalues = [4774.0, -4774.0, 0.0]\n",
    );
    let sec = &html[html.find("Results against f2").unwrap()..];
    let at = |v: &str| sec.find(&format!(">\n{v}\n<")).unwrap();
    assert!(at("-4774") < at("0") && at("0") < at("4774"));
}

/// Exclusive series (met, not met) sit on their category's tick; only
/// series that share a category are set side by side.
#[test]
fn points_of_exclusive_series_sit_on_their_ticks() {
    use tswm::report::charts::{points_chart, Series};
    use tswm::report::plots::Axis;
    let x = Axis::grid("x", &[1.0, 2.0, 3.0]);
    let y = Axis::fixed("share", 0.0, 1.0);
    let nan = (f64::NAN, f64::NAN, f64::NAN);
    let met = Series {
        name: "met",
        values: vec![(1.0, 1.0, 1.0), nan, nan],
        colour: None,
    };
    let not = Series {
        name: "not met",
        values: vec![nan, (0.2, 0.1, 0.3), (0.0, 0.0, 0.1)],
        colour: None,
    };
    let svg = points_chart(
        "t",
        &x,
        &y,
        &[met, not],
        None,
        plotters::chart::SeriesLabelPosition::UpperRight,
    )
    .unwrap();
    // The circles' x are three evenly spaced positions: the ticks.
    let cx: Vec<f64> = svg
        .split("<circle cx=\"")
        .skip(1)
        .map(|s| s.split('"').next().unwrap().parse().unwrap())
        .collect();
    let cx: Vec<f64> = cx[..3].to_vec();
    assert!(
        ((cx[1] - cx[0]) - (cx[2] - cx[1])).abs() <= 1.0,
        "points off their ticks: {cx:?}"
    );
}
