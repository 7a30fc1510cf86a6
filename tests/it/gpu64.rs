//! The f64 GPU path (`--precision f64`) on an adapter with 64-bit floats
//! (lavapipe has them): every lane within the CPU path's bound of the CPU
//! path at the same settings, with the same discrete outcome; `tswm check
//! --precision f64` on every law; `auto` on a software adapter stays f32.
//! Without such an adapter the tests are skipped, unless
//! TSWM_REQUIRE_GPU=1 (as in CI).

use crate::common::*;
use tswm::backend::gpu::layout::f64_settings;
use tswm::backend::gpu::{Gpu, GpuBackend, ShaderReal};
use tswm::backend::{Backend, CpuBackend};
use tswm::integrator::{LaneResult, RowPath, Settings};
use tswm::params::{FrictionKind, MotorKind, Num, ParamColumns, Params};
use tswm::run::compare::Report;

/// An f64 device, or None (said as a skip) where there is none.
fn gpu64(test: &str) -> Option<Gpu> {
    quiet_mesa();
    match Gpu::open(false, ShaderReal::F64) {
        Ok(g) => Some(g),
        Err(e) => {
            assert!(
                std::env::var("TSWM_REQUIRE_GPU").as_deref() != Ok("1"),
                "{test}: TSWM_REQUIRE_GPU=1 but no adapter runs f64: {e}"
            );
            skipped(test, &e.to_string());
            None
        }
    }
}

/// Random user lanes with every law and motor spread over them: paper,
/// coulomb, agma and stribeck friction, Kloss and constant motors, cut
/// and running; plus long horizons (20 to 300 s) with stiff motors. (A
/// motor within 1e-4 m/s of v_sync started there takes 430,796 steps on
/// either path, the same count: 27 s on lavapipe for one lane, so it is
/// left out here.)
fn every_kind_of_lane() -> Vec<Params> {
    let mut specs = tswm::input::testmodels::random_user_lanes(1500, 64);
    for (i, s) in specs.iter_mut().enumerate() {
        match i % 6 {
            2 => {
                s.friction = Some(FrictionKind::Agma);
                s.num[Num::Mu as usize] = None;
                s.num[Num::MuStatic as usize] = None;
                s.set(Num::AlphaNDeg, 20.0);
            }
            3 => {
                s.friction = Some(FrictionKind::Stribeck);
                s.set(Num::Mu, 0.04);
                s.set(Num::MuStatic, 0.1);
                s.set(Num::VStribeck, 0.05 + 0.01 * (i % 7) as f64);
                s.set(Num::MuViscous, 0.002);
            }
            4 => {
                s.motor = Some(MotorKind::Constant);
                s.set(Num::F1, 2000.0 + 10.0 * (i % 300) as f64);
            }
            _ => {}
        }
    }
    specs.extend(tswm::input::testmodels::long_stiff_lanes(12, 9));
    specs.iter().map(|s| s.resolve(&[]).unwrap()).collect()
}

fn run(b: &mut dyn Backend, params: &[Params]) -> Vec<LaneResult> {
    let cols: ParamColumns = params.iter().collect();
    let mut out = Vec::new();
    b.run_chunk(0, &cols, &[], &mut out).unwrap();
    out
}

/// Every lane of every kind within 1e-6 (time in s; values relative to
/// max(1, |value|)) of the CPU path at the settings the f64 GPU path runs
/// at, with identical status, switches, reversals, sticks, final contact,
/// hold and drive; each row says `gpu64`, or the CPU reason it was
/// recomputed for.
#[test]
fn f64_lanes_hold_the_cpu_bound_on_every_lane() {
    let Some(dev) = gpu64("f64_lanes_hold_the_cpu_bound_on_every_lane") else {
        return;
    };
    let settings = Settings::default();
    let mut g = GpuBackend::new(dev, settings);
    let params = every_kind_of_lane();
    let rg = run(&mut g, &params);
    let rc = run(
        &mut CpuBackend::new(0, f64_settings(&settings)).unwrap(),
        &params,
    );
    let mut report = Report {
        f64_rows: true,
        ..Report::default()
    };
    report.add(0, &rc, &rg).unwrap();
    eprintln!("{}", report.text());
    assert!(report.passes(), "{}", report.text());
    assert_eq!(report.disagree, 0);
    // Ran on the device to their end (a refined row did, then its
    // estimate sent it to the CPU).
    let on_gpu = rg
        .iter()
        .filter(|r| matches!(r.path, RowPath::Gpu64 | RowPath::Refined))
        .count();
    let others: Vec<String> = rg
        .iter()
        .filter(|r| r.path != RowPath::Gpu64)
        .map(|r| r.path.name().to_string())
        .collect();
    assert!(
        others
            .iter()
            .all(|p| p == "cpu:unfinished" || p == "cpu:flow_turn" || p == "cpu:refined"),
        "{others:?}"
    );
    // The f64 lanes keep the CPU path's error estimate: the lanes it
    // sends to be run again at the tighter settings are the CPU's own.
    for (i, (c, g)) in rc.iter().zip(&rg).enumerate() {
        let (cr, gr) = (c.path == RowPath::Refined, g.path == RowPath::Refined);
        assert!(
            cr == gr || (g.path != RowPath::Gpu64 && !gr),
            "lane {i}: cpu {} gpu {}",
            c.path.name(),
            g.path.name()
        );
    }
    assert!(rg.iter().any(|r| r.path == RowPath::Refined));
    assert!(
        on_gpu >= params.len() * 99 / 100,
        "{on_gpu} of {}",
        params.len()
    );
}

/// A sweep over every friction law but the table (whose sweep is
/// `friction_laws::TWO_MATERIALS`), and loads both ways.
const EVERY_LAW: &str = "[base]
mu = 0.04
mu_static = 0.10
v_stribeck = 0.1
mu_viscous = 0.002
alpha_n_deg = 20.0
motor_off = 1.5
t_end = 2.0
t_max = 10.0
[[grid]]
param = \"friction\"
values = [\"paper\", \"coulomb\", \"agma\", \"stribeck\"]
[[grid]]
param = \"gamma_deg\"
from = 3.0
to = 21.0
n = 7
[[grid]]
param = \"f2\"
from = -6000
to = 6000
n = 5
";

/// `tswm check --precision f64` passes on every law with 0 rows beyond
/// 1e-6, and says so.
#[test]
fn check_precision_f64_reports_no_row_beyond_the_cpu_bound() {
    if gpu64("check_precision_f64_reports_no_row_beyond_the_cpu_bound").is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let tables = crate::friction_laws::TWO_MATERIALS;
    for (name, text) in [("laws.toml", EVERY_LAW), ("tables.toml", tables)] {
        file(dir.path(), name, text);
        let out = tswm(&["check", name, "--precision", "f64"], dir.path());
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success(),
            "{name}: {stdout}{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(stdout.contains("gpu f64: "), "{stdout}");
        assert!(stdout.contains("PASS: "), "{stdout}");
        assert!(
            stdout.contains("(100.000 %, at least 100 % required)"),
            "{stdout}"
        );
        for line in stdout.lines().filter(|l| l.contains(" 1e-6 ")) {
            let over: u64 = line.split_whitespace().nth(3).unwrap().parse().unwrap();
            assert_eq!(over, 0, "{line}");
        }
    }
}

/// `--precision f64` rows in `lanes.csv` say `gpu64`; `auto` on a
/// software adapter runs f32 (rows `gpu`), whatever the run's size.
#[test]
fn f64_rows_say_so_and_auto_stays_f32_on_a_software_adapter() {
    let Some(dev) = gpu64("f64_rows_say_so_and_auto_stays_f32_on_a_software_adapter") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    file(dir.path(), "laws.toml", EVERY_LAW);
    let (_, h, rows) = run_ok(
        &[
            "run",
            "laws.toml",
            "--backend",
            "gpu",
            "--precision",
            "f64",
            "--out",
            "o",
        ],
        dir.path(),
    );
    // Rows from the device, or run again at the tighter settings where
    // the lane's error estimate asks for it (as the CPU path does).
    assert!(rows
        .iter()
        .all(|r| ["gpu64", "cpu:refined"].contains(&col(&h, r, "path"))));
    assert!(rows.iter().any(|r| col(&h, r, "path") == "gpu64"));
    if tswm::backend::gpu::is_hardware(&dev.info) {
        skipped("auto on a software adapter", "the adapter is hardware");
        return;
    }
    std::fs::remove_dir_all(dir.path().join("o")).unwrap();
    let (_, h, rows) = run_ok(
        &["run", "laws.toml", "--backend", "gpu", "--out", "o"],
        dir.path(),
    );
    assert!(rows.iter().all(|r| col(&h, r, "path") != "gpu64"));
    assert!(rows.iter().any(|r| col(&h, r, "path") == "gpu"));
}

/// `--precision f32` with `--backend cpu` is refused: the CPU path is f64.
#[test]
fn f32_on_the_cpu_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    file(dir.path(), "laws.toml", EVERY_LAW);
    rejected(
        &[
            "run",
            "laws.toml",
            "--backend",
            "cpu",
            "--precision",
            "f32",
            "--out",
            "o",
        ],
        dir.path(),
        &["--precision f32", "--backend cpu computes in f64"],
    );
    assert!(!dir.path().join("o").exists());
}
