//! docs/model.md section 11: traces against `paper_trace.csv`, from the same
//! integration as the lane's row.

use crate::common::*;
use tswm::input::lanes::Source;
use tswm::integrator::trace::{simulate_traced, TraceRow};
use tswm::integrator::{simulate, Settings};
use tswm::model::Lane;

fn traced(lane: usize, dt: f64) -> (Vec<TraceRow>, tswm::integrator::LaneResult, Lane) {
    let src = Source::open(None, Some(&fixture("paper_lanes.csv"))).unwrap();
    let mut params = Vec::new();
    src.reader().unwrap().fill(100, &mut params).unwrap();
    let l = Lane::new(&params[lane], &[]);
    let mut rows = Vec::new();
    let r = simulate_traced(&l, &[], &Settings::default(), dt, &mut |row| {
        rows.push(*row)
    });
    (rows, r, l)
}

/// Every fixture sample within 1e-6 (values relative to max(1, |value|)).
#[test]
fn traces_reproduce_the_fixture() {
    let (h, expected) = read_csv(&fixture("paper_trace.csv"));
    let mut worst = 0.0f64;
    for lane in [0usize, 2, 3] {
        let (rows, _, _) = traced(lane, 0.01);
        for e in expected
            .iter()
            .filter(|e| col(&h, e, "lane") == lane.to_string())
        {
            let t: f64 = col(&h, e, "t").parse().unwrap();
            let r = rows
                .iter()
                .find(|r| (r.t - t).abs() < 1e-9)
                .unwrap_or_else(|| panic!("lane {lane}: no row at t = {t}"));
            assert_eq!(r.contact.name(), col(&h, e, "contact"), "lane {lane} t {t}");
            for (name, got) in [
                ("x1", r.x1),
                ("v1", r.v1),
                ("a1", r.a1),
                ("f1", r.f1),
                ("s1", r.s1),
                ("s2", r.s2),
                ("psi", r.psi),
                ("phi", r.phi),
            ] {
                match col(&h, e, name) {
                    "" => assert!(got.is_nan(), "lane {lane} t {t} {name}: {got}"),
                    want => {
                        let want: f64 = want.parse().unwrap();
                        worst = worst.max(rel1(got, want));
                        assert!(
                            rel1(got, want) <= 1e-6,
                            "lane {lane} t {t} {name}: {got} vs {want}"
                        );
                    }
                }
            }
        }
    }
    eprintln!("traces against paper_trace.csv: worst deviation {worst:.2e} (bound 1e-6)");
}

/// Case 1 has a before/after pair of rows at its switch, and the traced
/// run is the run that gives the lane's row, bit for bit.
#[test]
fn the_switch_has_a_before_and_after_row() {
    let (rows, r, l) = traced(0, 0.1);
    let pair: Vec<_> = rows
        .windows(2)
        .filter(|w| w[0].t == w[1].t && w[0].contact != w[1].contact)
        .collect();
    assert_eq!(pair.len(), 1, "one switch");
    let (a, b) = (pair[0][0], pair[0][1]);
    assert!(
        (a.t - r.t_first_switch).abs() == 0.0,
        "{} vs {}",
        a.t,
        r.t_first_switch
    );
    assert_eq!((a.contact.name(), b.contact.name()), ("aa", "bb"));
    assert!(a.psi != b.psi, "psi jumps at the switch");
    let plain = simulate(&l, &[], &Settings::default());
    assert_eq!(format!("{r:?}"), format!("{plain:?}"));
    // Rows every 0.1 s from 0 to 2 s, plus the pair.
    assert_eq!(rows.len(), 21 + 2);
    assert!(rows.windows(2).all(|w| w[0].t <= w[1].t));
}

/// `--trace` over a sweep's `[trace]`; traces come from the f64 path on
/// either backend; a run without traces leaves no earlier traces.csv.
#[test]
fn traces_csv_from_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    let paper = root().join("sweeps/paper.toml");
    let p = paper.to_str().unwrap();
    run_ok(&cpu(&["run", p, "--out", "o"]), dir.path());
    let (h, rows) = read_csv(&dir.path().join("o/traces.csv"));
    assert_eq!(h.join(","), tswm::output::traces::TRACE_COLUMNS);
    // Both lanes of the sweep's [trace]: 201 rows each, lane 0's switch twice.
    assert_eq!(rows.len(), 201 + 2 + 201);
    run_ok(
        &cpu(&["run", p, "--out", "o", "--trace", "1", "--trace-dt", "0.5"]),
        dir.path(),
    );
    let (_, rows) = read_csv(&dir.path().join("o/traces.csv"));
    assert_eq!(rows.len(), 5);
    let bad = rejected(
        &["run", p, "--out", "o", "--trace", "2", "--trace-dt", "0.1"],
        dir.path(),
        &["--trace", "lane 2", "0 to 1"],
    );
    assert!(!bad.is_empty());
    let map = root().join("sweeps/efficiency_map.toml");
    run_ok(
        &cpu(&["run", map.to_str().unwrap(), "--out", "o"]),
        dir.path(),
    );
    assert!(
        !dir.path().join("o/traces.csv").exists(),
        "an earlier run's traces do not stay"
    );
}
