//! The GPU path against the f64 CPU path. These tests need a GPU adapter
//! (lavapipe counts); without one they print why they are skipped, unless
//! TSWM_REQUIRE_GPU=1 (as in CI), where a missing adapter fails them.

use std::sync::{Mutex, MutexGuard, OnceLock};

use crate::common::*;
use tswm::backend::{Backend, CpuBackend};
use tswm::check::Report;
use tswm::gpu::{Gpu, GpuBackend};
use tswm::integrator::{LaneResult, Settings};
use tswm::lanes::Source;
use tswm::params::Params;

static GPU: OnceLock<Result<Mutex<GpuBackend>, String>> = OnceLock::new();

/// The shared GPU backend, or None (after printing why) when there is none.
fn gpu(test: &str) -> Option<MutexGuard<'static, GpuBackend>> {
    let g = GPU.get_or_init(|| {
        Gpu::new(false)
            .map(|g| Mutex::new(GpuBackend::new(g, Settings::default())))
            .map_err(|e| e.to_string())
    });
    match g {
        Ok(m) => Some(m.lock().unwrap_or_else(|e| e.into_inner())),
        Err(e) => {
            if std::env::var("TSWM_REQUIRE_GPU").as_deref() == Ok("1") {
                panic!("{test}: TSWM_REQUIRE_GPU=1 but there is no GPU adapter: {e}");
            }
            // Straight to stderr: libtest captures eprintln! of passing tests.
            use std::io::Write;
            let _ = writeln!(std::io::stderr(), "skipped GPU test {test}: {e}");
            None
        }
    }
}

fn run_both(gpu: &mut GpuBackend, params: &[Params]) -> (Vec<LaneResult>, Vec<LaneResult>) {
    let mut cpu = CpuBackend::new(0, Settings::default()).unwrap();
    let (mut rc, mut rg) = (Vec::new(), Vec::new());
    let mut first = 0;
    for chunk in params.chunks(gpu.chunk_lanes()) {
        let (mut c, mut g) = (Vec::new(), Vec::new());
        cpu.run_chunk(first, chunk, None, &mut c).unwrap();
        gpu.run_chunk(first, chunk, None, &mut g).unwrap();
        rc.extend(c);
        rg.extend(g);
        first += chunk.len() as u64;
    }
    (rc, rg)
}

/// the MODEL.md cases on the GPU: first switch within 2e-5 s of
/// the reference; x1, v1 and energies within 5e-5 of max(1, |value|);
/// identical discrete fields.
#[test]
fn model_md_reference_cases_on_gpu() {
    let Some(mut g) = gpu("model_md_reference_cases_on_gpu") else {
        return;
    };
    eprintln!("GPU: {}", g.name());
    let src = Source::open(None, Some(&fixture("paper_lanes.csv"))).unwrap();
    let mut params = Vec::new();
    src.reader().unwrap().fill(100, &mut params).unwrap();
    let mut res = Vec::new();
    g.run_chunk(0, &params, None, &mut res).unwrap();
    let (worst, worst_t) = check_reference_cases(&res, 2e-5, 5e-5);
    eprintln!("GPU, MODEL.md cases: worst value deviation {worst:.2e}, first switch off by {worst_t:.2e} s");
}

/// on 10,000 random user lanes, GPU against CPU within the bounds
/// of `tswm::check`, discrete fields identical on at least 98 % of lanes.
#[test]
fn random_lanes_gpu_matches_cpu() {
    let Some(mut g) = gpu("random_lanes_gpu_matches_cpu") else {
        return;
    };
    let params: Vec<Params> = tswm::testmodels::random_user_lanes(10_000, 31)
        .iter()
        .map(|s| s.resolve(false).unwrap())
        .collect();
    let (rc, rg) = run_both(&mut g, &params);
    let mut report = Report::default();
    report.add(0, &rc, &rg);
    eprintln!("{}", report.text());
    assert!(report.passes(), "{}", report.text());
}

#[test]
fn check_command_passes_on_the_paper_sweep() {
    let Some(_g) = gpu("check_command_passes_on_the_paper_sweep") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let out = tswm(
        &["check", root().join("sweeps/paper.toml").to_str().unwrap()],
        dir.path(),
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains("t_first_switch") && stdout.contains("PASS"),
        "{stdout}"
    );
}

#[test]
fn gpu_backend_writes_the_same_table() {
    let Some(_g) = gpu("gpu_backend_writes_the_same_table") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let lanes = fixture("paper_lanes.csv");
    let (out, h, rows) = run_ok(
        &[
            "run",
            "--lanes",
            lanes.to_str().unwrap(),
            "--backend",
            "gpu",
            "--out",
            "o",
        ],
        dir.path(),
    );
    let (eh, expected) = read_csv(&fixture("paper_expected.csv"));
    for (row, e) in rows.iter().zip(&expected) {
        assert_eq!(col(&h, row, "contact_end"), col(&eh, e, "contact_end"));
    }
    assert!(String::from_utf8_lossy(&out.stdout).contains("gpu: "));
}

/// A backend that fails on its second chunk, like a lost device.
struct Failing(CpuBackend);

impl Backend for Failing {
    fn name(&self) -> String {
        "failing".into()
    }
    fn tolerance(&self) -> f64 {
        self.0.tolerance()
    }
    fn chunk_lanes(&self) -> usize {
        2
    }
    fn run_chunk(
        &mut self,
        first: u64,
        lanes: &[Params],
        table: Option<&tswm::model::FrictionTable>,
        out: &mut Vec<LaneResult>,
    ) -> tswm::error::Result<()> {
        if first >= 2 {
            return Err(tswm::error::Error::Gpu(format!(
                "chunk {}: device lost (simulated)",
                first / 2
            )));
        }
        self.0.run_chunk(first, lanes, table, out)
    }
}

/// device loss, a timeout or running out of memory leaves no
/// lanes.csv under its final name (and no partial file behind).
#[test]
fn a_failing_chunk_leaves_no_lanes_csv() {
    let dir = tempfile::tempdir().unwrap();
    let src = Source::open(None, Some(&fixture("paper_lanes.csv"))).unwrap();
    let mut be = Failing(CpuBackend::new(1, Settings::default()).unwrap());
    let csv = dir.path().join("lanes.csv");
    let err = tswm::runner::run(&src, &mut be, &csv, false)
        .unwrap_err()
        .to_string();
    assert!(err.contains("chunk 1"), "{err}");
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        0,
        "nothing may be left behind"
    );
}

/// `auto` without a hardware GPU: sweeps under the trial threshold run on
/// the CPU path, without opening a software device.
#[test]
fn auto_runs_small_sweeps_on_the_cpu_without_a_hardware_gpu() {
    if let Some(hw) = tswm::gpu::adapters()
        .iter()
        .find(|a| tswm::gpu::is_hardware(&a.info))
    {
        use std::io::Write;
        let _ = writeln!(
            std::io::stderr(),
            "skipped auto test: hardware GPU {} present",
            hw.info.name
        );
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let sweep = root().join("sweeps/paper.toml");
    let (out, _, rows) = run_ok(&["run", sweep.to_str().unwrap(), "--out", "o"], dir.path());
    assert_eq!(rows.len(), 2);
    assert!(String::from_utf8_lossy(&out.stdout).contains("cpu ("));
}
