//! The command line end to end: the shipped sweeps, lane tables, the
//! results table's columns, reproducibility and the summary.

use crate::common::*;

const HEADER: &str = "m1,m2,gamma_deg,f2,motor,v_sync,v_crit,f_crit,f1,motor_off,friction,friction_table,\
fric_a,fric_b,fric_c,mu,mu_static,v_stribeck,stribeck_exp,mu_viscous,alpha_n_deg,x1_0,v1_0,t_end,t_max,d1,z1,z2,m_x,r1,r2,j1,j2,t1,t2,n_sync,n_crit,\
t_crit,n1_0,lane,status,switches,t_first_switch,reversals,sticks,contact_end,x1_end,v1_end,w_motor,w_load,w_friction,\
eta_end,steps,w1_in,w1_out,w2_in,w2_out,eta_direct,eta_inverse,eta_direct_ss,eta_inverse_ss,lock_margin_deg,eta_direct_start,eta_inverse_start,hold,drive,\
t_stop,n1_end,n2_end,path";

#[test]
fn paper_sweep_writes_lanes_csv_and_provenance() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = root().join("sweeps/paper.toml");
    let (out, h, rows) = run_ok(
        &cpu(&["run", sweep.to_str().unwrap(), "--out", "o"]),
        dir.path(),
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(stdout.lines().count(), 1, "{stdout}");
    assert!(
        stdout.contains("2 lanes") && stdout.contains("ok 2") && stdout.contains("aa 1, bb 1"),
        "{stdout}"
    );
    let csv = dir.path().join("o/lanes.csv");
    assert_eq!(
        std::fs::read_to_string(&csv)
            .unwrap()
            .lines()
            .next()
            .unwrap(),
        HEADER
    );
    let (eh, expected) = read_csv(&fixture("paper_expected.csv"));
    for (row, e) in rows.iter().zip(&expected[..2]) {
        assert_eq!(col(&h, row, "contact_end"), col(&eh, e, "contact_end"));
        assert_eq!(col(&h, row, "motor"), "kloss");
        assert_eq!(
            col(&h, row, "mu"),
            "",
            "a parameter the law does not use is empty"
        );
        let x: f64 = col(&h, row, "x1_end").parse().unwrap();
        assert!(rel1(x, col(&eh, e, "x1_end").parse().unwrap()) <= 1e-6);
    }
    let resolved = std::fs::read_to_string(dir.path().join("o/sweep.resolved.toml")).unwrap();
    assert!(
        resolved.contains("values = [4774.0, -4774.0]"),
        "{resolved}"
    );
    assert!(resolved.contains("fric_c = 0.14"));
    let mut names: Vec<_> = std::fs::read_dir(dir.path().join("o"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names, RUN_FILES,
        "only the run's files (its sweep traces both lanes) and the folder's lock"
    );
}

#[test]
fn fixture_lane_table_end_to_end() {
    let dir = tempfile::tempdir().unwrap();
    let (h, rows) = run_fixture_lanes(dir.path());
    let (eh, expected) = read_csv(&fixture("paper_expected.csv"));
    assert_eq!(rows.len(), 5);
    for (row, e) in rows.iter().zip(&expected) {
        for c in [
            "lane",
            "status",
            "switches",
            "reversals",
            "sticks",
            "contact_end",
        ] {
            assert_eq!(col(&h, row, c), col(&eh, e, c), "{c}");
        }
        for c in ["x1_end", "v1_end", "w_motor", "w_load", "w_friction"] {
            let (a, b): (f64, f64) = (
                col(&h, row, c).parse().unwrap(),
                col(&eh, e, c).parse().unwrap(),
            );
            assert!(rel1(a, b) <= 1e-6, "{c}: {a} vs {b}");
        }
    }
}

#[test]
fn lane_table_over_a_sweep_base_with_a_friction_table() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("s.toml"),
        "[base]\nfriction = \"table\"\nf2 = -3000\n[friction_table]\nvs = [0, 1, 4]\nmu = [0.12, 0.06, 0.04]\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("l.csv"), "gamma_deg,t_end\n10,1\n20,\n").unwrap();
    let (_, h, rows) = run_ok(
        &cpu(&["run", "s.toml", "--lanes", "l.csv", "--out", "o"]),
        dir.path(),
    );
    assert_eq!(col(&h, &rows[0], "friction"), "table");
    assert_eq!(col(&h, &rows[0], "f2"), "-3000.0");
    assert_eq!(col(&h, &rows[0], "t_end"), "1.0");
    assert_eq!(
        col(&h, &rows[1], "t_end"),
        "2.0",
        "an empty cell takes the default"
    );
    assert_eq!(col(&h, &rows[1], "status"), "ok");
}

#[test]
fn tolerance_study_is_reproducible_across_thread_counts() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(root().join("sweeps/tolerance.toml"))
        .unwrap()
        .replace("n = 5000", "n = 300");
    std::fs::write(dir.path().join("t.toml"), text).unwrap();
    for (threads, o) in [("1", "a"), ("2", "b"), ("2", "c")] {
        let out = tswm(
            &cpu(&["run", "t.toml", "--threads", threads, "--out", o]),
            dir.path(),
        );
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let a = std::fs::read(dir.path().join("a/lanes.csv")).unwrap();
    assert_eq!(a, std::fs::read(dir.path().join("b/lanes.csv")).unwrap());
    assert_eq!(a, std::fs::read(dir.path().join("c/lanes.csv")).unwrap());
    let (h, rows) = read_csv(&dir.path().join("a/lanes.csv"));
    assert_eq!(rows.len(), 300);
    let m1: Vec<f64> = rows
        .iter()
        .map(|r| col(&h, r, "m1").parse().unwrap())
        .collect();
    assert!(m1.iter().all(|&m| (m - 586.0).abs() <= 0.05 * 586.0 + 1e-9));
    assert!(m1.windows(2).any(|w| w[0] != w[1]), "samples must differ");
}

#[test]
fn shipped_sweeps_parse_and_have_the_documented_size() {
    for (f, n) in [
        ("paper.toml", 2u64),
        ("efficiency_map.toml", 3480),
        ("tolerance.toml", 5000),
        ("self_locking.toml", 25000),
        ("million.toml", 1_000_000),
        ("heterogeneous.toml", 200_000),
    ] {
        let src =
            tswm::input::lanes::Source::open(Some(&root().join("sweeps").join(f)), None).unwrap();
        assert_eq!(src.lane_count(), n, "{f}");
    }
}

#[test]
fn nothing_to_run_is_a_usage_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = tswm(&["run"], dir.path());
    assert_eq!(out.status.code(), Some(2));
}

/// A reader that stops early (`tswm devices | head -1`) is no failure:
/// the output it did not want is dropped, with exit code 0 and no panic.
#[test]
fn a_closed_standard_output_is_no_panic() {
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_tswm"))
        .arg("devices")
        .env("XDG_RUNTIME_DIR", std::env::temp_dir())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Close the reading end before the first line is written.
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{:?}: {stderr}", out.status);
    assert!(!stderr.contains("panicked"), "{stderr}");
}
