//! docs/model.md section 11: traces against `paper_trace.csv`, from the same
//! integration as the lane's row.

use crate::common::*;
use tswm::input::lanes::Source;
use tswm::integrator::trace::{simulate_traced, TraceRow};
use tswm::integrator::{simulate, Settings};
use tswm::model::Lane;

fn traced(lane: usize, dt: f64) -> (Vec<TraceRow>, tswm::integrator::LaneResult, Lane) {
    let src = Source::open(None, Some(&fixture("paper_lanes.csv"))).unwrap();
    let mut cols = tswm::params::ParamColumns::default();
    src.reader().unwrap().fill(100, &mut cols).unwrap();
    let params = cols.rows();
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

/// A trace whose interval does not divide the stop time ends with a row
/// at the stop: the state the lane's row reports.
#[test]
fn a_trace_ends_at_the_lanes_stop() {
    for (lane, dt) in [(0usize, 0.3), (1, 0.7), (2, 0.45), (4, 0.6)] {
        let (rows, r, _) = traced(lane, dt);
        let last = rows.last().unwrap();
        assert_eq!(last.t, r.t_stop, "lane {lane}");
        assert_eq!(last.x1, r.x1_end, "lane {lane}");
        assert_eq!(last.v1, r.v1_end, "lane {lane}");
        assert_eq!(last.contact, r.contact_end, "lane {lane}");
        // Rows in time order, the samples on multiples of dt before it.
        assert!(rows.windows(2).all(|w| w[0].t <= w[1].t), "lane {lane}");
    }
}

/// The traces of a lane table: `--trace` with and without `--trace-dt`,
/// `[trace]` in a sweep file beside the table, the report rebuilt from
/// the folder, and shards of a traced lane table merged.
#[test]
fn lane_tables_are_traced_reported_and_sharded() {
    let dir = tempfile::tempdir().unwrap();
    let table = fixture("paper_lanes.csv");
    let table = table.to_str().unwrap();
    let lanes_of = |d: &str| -> Vec<String> {
        let (h, rows) = read_csv(&dir.path().join(d).join("traces.csv"));
        let mut v: Vec<String> = rows
            .iter()
            .map(|r| col(&h, r, "lane").to_string())
            .collect();
        v.dedup();
        v
    };
    // With an interval, and without one (about a thousand rows a lane:
    // lane 2 runs 5 s, so 5 ms).
    for (out, extra) in [("a", vec!["--trace-dt", "0.01"]), ("b", vec![])] {
        let mut args = vec!["run", "--lanes", table, "--trace", "2,4", "--out", out];
        args.extend(extra);
        let o = tswm(&cpu(&args), dir.path());
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(dir.path().join(out).join("report.html").exists());
        assert_eq!(lanes_of(out), ["2", "4"]);
        let o = tswm(&["report", out], dir.path());
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let (h, rows) = read_csv(&dir.path().join("b/traces.csv"));
    let ts: Vec<f64> = rows
        .iter()
        .filter(|r| col(&h, r, "lane") == "4")
        .map(|r| col(&h, r, "t").parse().unwrap())
        .collect();
    assert_eq!((ts[1], *ts.last().unwrap()), (0.005, 2.0));
    // [trace] in a sweep file beside the table: row indices of the table.
    file(dir.path(), "t.toml", "[trace]\nlanes = [1, 3]\ndt = 0.05\n");
    let o = tswm(
        &cpu(&["run", "--lanes", table, "t.toml", "--out", "c"]),
        dir.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(lanes_of("c"), ["1", "3"]);
    // ... and a row index past the table is refused, naming the file.
    file(dir.path(), "u.toml", "[trace]\nlanes = [5]\ndt = 0.05\n");
    rejected(
        &cpu(&["run", "--lanes", table, "u.toml", "--out", "d"]),
        dir.path(),
        &["u.toml", "trace", "lane 5 is not in the run", "0 to 4"],
    );
    // Shards of the traced table merge into the unsharded run's folder.
    for k in 0..2 {
        let s = format!("{k}/2");
        let o = format!("s{k}");
        let out = tswm(
            &cpu(&[
                "run",
                "--lanes",
                table,
                "--trace",
                "2,4",
                "--trace-dt",
                "0.01",
                "--shard",
                &s,
                "--out",
                &o,
            ]),
            dir.path(),
        );
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let o = tswm(&["merge", "s0", "s1", "--out", "m"], dir.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for f in ["lanes.csv", "traces.csv"] {
        assert_eq!(
            std::fs::read(dir.path().join("m").join(f)).unwrap(),
            std::fs::read(dir.path().join("a").join(f)).unwrap(),
            "{f}"
        );
    }
    assert!(dir.path().join("m/report.html").exists());
}

/// On the GPU a traced lane's row comes from the integration its trace is
/// taken from: the f64 row, marked `cpu:traced`, equal to the CPU run's.
#[test]
fn a_traced_lanes_row_and_trace_are_one_integration_on_the_gpu() {
    if no_gpu("traced rows on the GPU") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let sweep = root().join("sweeps/paper.toml");
    let s = sweep.to_str().unwrap();
    run_ok(&cpu(&["run", s, "--out", "o"]), dir.path());
    let out = tswm(&["run", s, "--out", "g", "--backend", "gpu"], dir.path());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (h, c) = read_csv(&dir.path().join("o/lanes.csv"));
    let (_, g) = read_csv(&dir.path().join("g/lanes.csv"));
    let path = h.iter().position(|x| x == "path").unwrap();
    for (a, b) in c.iter().zip(&g) {
        assert_eq!(b[path], "cpu:traced");
        assert_eq!(a[..path], b[..path], "the row is the CPU's");
    }
    assert_eq!(
        std::fs::read(dir.path().join("o/traces.csv")).unwrap(),
        std::fs::read(dir.path().join("g/traces.csv")).unwrap()
    );
}
