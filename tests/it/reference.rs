//! tswm against an independent integration written from docs/model.md alone
//! (`tests/reference/scipy_reference.py`: scipy's DOP853 at rtol = atol =
//! 1e-12 with located events) on 1,000 random user lanes drawn in Python
//! (`tests/reference/random_lanes.py`, seed 808).

use std::path::PathBuf;
use std::process::Command;

use crate::common::cpu;
use crate::common::{col, read_csv, rel1, root, run_ok};

/// An independent reference in Python: the modules it imports, the
/// variables that may name its interpreter, and how CI installs it.
pub(crate) struct Needs {
    pub(crate) modules: &'static str,
    pub(crate) vars: &'static [&'static str],
    pub(crate) install: &'static str,
}

/// scipy: `python3-scipy` from Debian (`.ci/run`).
pub(crate) const SCIPY: Needs = Needs {
    modules: "scipy",
    vars: &["TSWM_PYTHON"],
    install: "apt-get install python3-scipy, or set TSWM_PYTHON",
};

/// A Python that imports `needs.modules`: the variables' first, else
/// Debian's (whatever `python3` on the PATH is), else `python3`. None
/// after saying why the test `test` is skipped; in CI, where `.ci/run`
/// installs it, its absence fails the test.
pub(crate) fn python_for(needs: &Needs, test: &str) -> Option<PathBuf> {
    let found = needs
        .vars
        .iter()
        .filter_map(|v| std::env::var_os(v).map(PathBuf::from))
        .chain(["/usr/bin/python3", "python3"].map(PathBuf::from))
        .find(|py| {
            Command::new(py)
                .args(["-c", &format!("import {}", needs.modules)])
                .output()
                .is_ok_and(|o| o.status.success())
        });
    if found.is_none() {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI: python3 with {} is required (.ci/run installs it)",
            needs.modules
        );
        crate::common::skipped(
            test,
            &format!("no python3 with {} ({})", needs.modules, needs.install),
        );
    }
    found
}

pub(crate) fn script(py: &PathBuf, args: &[&str]) {
    let out = Command::new(py).args(args).output().expect("run python");
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn an_independent_integration_agrees_on_1000_random_lanes() {
    let Some(py) = python_for(&SCIPY, "the scipy reference") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let refdir = root().join("tests/reference");
    let lanes = d.join("lanes_in.csv");
    script(
        &py,
        &[
            refdir.join("random_lanes.py").to_str().unwrap(),
            "1000",
            "808",
            lanes.to_str().unwrap(),
        ],
    );
    run_ok(
        &cpu(&[
            "run",
            "--lanes",
            lanes.to_str().unwrap(),
            "--out",
            "o",
            "--no-report",
        ]),
        d,
    );
    let ours = d.join("o/lanes.csv");
    let theirs = d.join("ref.csv");
    script(
        &py,
        &[
            refdir.join("scipy_reference.py").to_str().unwrap(),
            ours.to_str().unwrap(),
            theirs.to_str().unwrap(),
        ],
    );
    let (h, rows) = read_csv(&ours);
    let (rh, refs) = read_csv(&theirs);
    assert_eq!(rows.len(), 1000);
    assert_eq!(refs.len(), 1000);
    let values = [
        "x1_end",
        "v1_end",
        "w_motor",
        "w_load",
        "w_friction",
        "w1_in",
        "w1_out",
        "w2_in",
        "w2_out",
    ];
    let (mut over, mut worst) = (Vec::new(), 0.0f64);
    for (r, e) in rows.iter().zip(&refs) {
        let lane = col(&h, r, "lane");
        assert_eq!(lane, col(&rh, e, "lane"));
        for f in ["status", "contact_end"] {
            assert_eq!(col(&h, r, f), col(&rh, e, f), "lane {lane}: {f}");
        }
        if col(&h, r, "status") != "ok" {
            continue;
        }
        let num = |row: &[String], hh: &[String], k: &str| col(hh, row, k).parse::<f64>().unwrap();
        let lane_worst = values
            .iter()
            .map(|k| (rel1(num(r, &h, k), num(e, &rh, k)), *k))
            .fold((0.0, ""), |a, b| if b.0 > a.0 { b } else { a });
        worst = worst.max(lane_worst.0);
        if lane_worst.0 > 1e-6 {
            over.push(format!(
                "lane {lane}: {} {:.2e}",
                lane_worst.1, lane_worst.0
            ));
        }
        // The section 10 identity, on every lane.
        let balance =
            num(r, &h, "w1_in") - num(r, &h, "w1_out") + num(r, &h, "w2_in") - num(r, &h, "w2_out");
        assert!(
            rel1(balance, num(r, &h, "w_friction")) < 1e-9,
            "lane {lane}: identity"
        );
    }
    let refined = rows
        .iter()
        .filter(|r| col(&h, r, "path") == "cpu:refined")
        .count();
    eprintln!(
        "scipy DOP853 reference, 1000 random lanes: discrete fields agree on all; {} within 1e-6 \
         (worst {worst:.2e}); {refined} refined; over: {over:?}",
        1000 - over.len()
    );
    // docs/model.md's bound, on every lane: the lanes whose own error estimate
    // is over it are run again tighter (src/integrator/accuracy.rs).
    assert!(over.is_empty(), "{over:?}");
}

/// "Does it hold?" against the independent integration, which runs a
/// coasting lane on to t_max by its own events: 300 lanes with the motor
/// cut (70 % with a t_max), on the CPU path and the GPU path.
#[test]
fn hold_and_t_stop_agree_with_an_independent_integration() {
    let Some(py) = python_for(&SCIPY, "the scipy reference") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let refdir = root().join("tests/reference");
    let lanes = d.join("lanes_in.csv");
    script(
        &py,
        &[
            refdir.join("random_lanes.py").to_str().unwrap(),
            "300",
            "1811",
            lanes.to_str().unwrap(),
            "hold",
        ],
    );
    let theirs = d.join("ref.csv");
    // The reference reads every parameter from the CPU run's table (the
    // lane table leaves the defaults unwritten).
    let (mut rh, mut refs) = (Vec::new(), Vec::new());
    let mut seen = std::collections::BTreeMap::new();
    for backend in ["cpu", "gpu"] {
        let out = crate::common::tswm(
            &[
                "run",
                "--lanes",
                lanes.to_str().unwrap(),
                "--backend",
                backend,
                "--out",
                backend,
                "--no-report",
            ],
            d,
        );
        crate::common::quiet_mesa();
        if backend == "gpu" && tswm::backend::gpu::adapters().is_empty() {
            assert!(
                std::env::var("TSWM_REQUIRE_GPU").as_deref() != Ok("1"),
                "TSWM_REQUIRE_GPU=1 but there is no GPU adapter"
            );
            crate::common::skipped("the GPU half of hold_and_t_stop", "no GPU adapter");
            continue;
        }
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let ours = d.join(backend).join("lanes.csv");
        if backend == "cpu" {
            script(
                &py,
                &[
                    refdir.join("scipy_reference.py").to_str().unwrap(),
                    ours.to_str().unwrap(),
                    theirs.to_str().unwrap(),
                ],
            );
            (rh, refs) = read_csv(&theirs);
        }
        let (h, rows) = read_csv(&ours);
        // The GPU's f32 rows have their own bound, and the share of
        // lanes that must keep it (`tswm check`: 98 %; a contact that
        // grazes zero may switch twice in f64 and not in f32).
        let bound = if backend == "cpu" { 1e-6 } else { 5e-5 };
        let mut missed = Vec::new();
        for (r, e) in rows.iter().zip(&refs) {
            let lane = col(&h, r, "lane");
            for f in ["status", "contact_end", "hold"] {
                assert_eq!(col(&h, r, f), col(&rh, e, f), "{backend} lane {lane}: {f}");
            }
            if backend == "cpu" {
                *seen.entry(col(&h, r, "hold").to_string()).or_insert(0) += 1;
            }
            let num =
                |row: &[String], hh: &[String], k: &str| col(hh, row, k).parse::<f64>().unwrap();
            for k in [
                "t_stop",
                "x1_end",
                "v1_end",
                "w_friction",
                "w1_in",
                "w2_out",
            ] {
                let dev = rel1(num(r, &h, k), num(e, &rh, k));
                if dev.is_nan() || dev >= bound {
                    missed.push(format!("lane {lane}: {k} off by {dev:.2e}"));
                }
            }
        }
        eprintln!("{backend}: over the bound {bound:e}: {missed:?}");
        let allowed = if backend == "cpu" { 0 } else { refs.len() / 50 };
        assert!(missed.len() <= allowed, "{backend}: {missed:?}");
    }
    eprintln!("hold against scipy, 300 lanes: {seen:?}");
    // Every outcome is among them.
    assert!(["held", "runs_away", "coasting"]
        .iter()
        .all(|w| seen.get(*w) > Some(&10)));
}
