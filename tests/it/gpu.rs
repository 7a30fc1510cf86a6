//! The GPU path against the f64 CPU path. These tests need a GPU adapter
//! (lavapipe counts); without one they print why they are skipped, unless
//! TSWM_REQUIRE_GPU=1 (as in CI), where a missing adapter fails them.

use std::sync::{Mutex, MutexGuard, OnceLock};

use crate::common::*;
use tswm::backend::gpu::{Gpu, GpuBackend};
use tswm::backend::{Backend, CpuBackend};
use tswm::input::lanes::Source;
use tswm::integrator::{LaneResult, Settings};
use tswm::params::{ParamColumns, Params};
use tswm::run::compare::Report;

static GPU: OnceLock<Result<Mutex<GpuBackend>, String>> = OnceLock::new();

/// The shared GPU backend, or None (after printing why) when there is none.
fn gpu(test: &str) -> Option<MutexGuard<'static, GpuBackend>> {
    let g = GPU.get_or_init(|| {
        quiet_mesa();
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

/// The first `n` lanes of `sweeps/heterogeneous.toml` (lanes of very
/// unlike length).
fn heterogeneous(n: usize) -> Vec<Params> {
    let src = Source::open(Some(&root().join("sweeps/heterogeneous.toml")), None).unwrap();
    let mut cols = tswm::params::ParamColumns::default();
    src.reader().unwrap().fill(n, &mut cols).unwrap();
    cols.rows()
}

fn run_both(gpu: &mut GpuBackend, params: &[Params]) -> (Vec<LaneResult>, Vec<LaneResult>) {
    let mut cpu = CpuBackend::new(0, Settings::default()).unwrap();
    let (mut rc, mut rg) = (Vec::new(), Vec::new());
    let mut first = 0;
    for chunk in params.chunks(gpu.chunk_lanes()) {
        let (mut c, mut g) = (Vec::new(), Vec::new());
        let chunk: ParamColumns = chunk.iter().collect();
        cpu.run_chunk(first, &chunk, &[], &mut c).unwrap();
        gpu.run_chunk(first, &chunk, &[], &mut g).unwrap();
        rc.extend(c);
        rg.extend(g);
        first += chunk.len() as u64;
    }
    (rc, rg)
}

/// the docs/model.md cases on the GPU: first switch within 2e-5 s of
/// the reference; x1, v1 and energies within 5e-5 of max(1, |value|);
/// identical discrete fields.
#[test]
fn model_md_reference_cases_on_gpu() {
    let Some(mut g) = gpu("model_md_reference_cases_on_gpu") else {
        return;
    };
    eprintln!("GPU: {}", g.name());
    let src = Source::open(None, Some(&fixture("paper_lanes.csv"))).unwrap();
    let mut cols = tswm::params::ParamColumns::default();
    src.reader().unwrap().fill(100, &mut cols).unwrap();
    let mut res = Vec::new();
    g.run_chunk(0, &cols, &[], &mut res).unwrap();
    let (worst, worst_t) = check_reference_cases(&res, 2e-5, 5e-5);
    eprintln!("GPU, docs/model.md cases: worst value deviation {worst:.2e}, first switch off by {worst_t:.2e} s");
}

/// The same cases given in gear terms (`paper_gear_lanes.csv`): converted
/// once per lane, they meet the same bounds on the GPU.
#[test]
fn model_md_reference_cases_in_gear_terms_on_gpu() {
    let Some(mut g) = gpu("model_md_reference_cases_in_gear_terms_on_gpu") else {
        return;
    };
    let src = Source::open(None, Some(&fixture("paper_gear_lanes.csv"))).unwrap();
    let mut cols = tswm::params::ParamColumns::default();
    src.reader().unwrap().fill(100, &mut cols).unwrap();
    let mut res = Vec::new();
    g.run_chunk(0, &cols, &[], &mut res).unwrap();
    let (worst, worst_t) = check_reference_cases(&res, 2e-5, 5e-5);
    eprintln!(
        "GPU, gear terms: worst value deviation {worst:.2e}, first switch off by {worst_t:.2e} s"
    );
}

/// On 10,000 random user lanes, the raw f32 kernel (no self-check)
/// against CPU within the bounds of `tswm::run::compare`, discrete fields
/// identical on at least 98 % of lanes.
#[test]
fn random_lanes_gpu_matches_cpu() {
    let Some(mut g) = gpu("random_lanes_gpu_matches_cpu") else {
        return;
    };
    let params: Vec<Params> = tswm::input::testmodels::random_user_lanes(10_000, 31)
        .iter()
        .map(|s| s.resolve(&[]).unwrap())
        .collect();
    g.self_check = false;
    let (rc, rg) = run_both(&mut g, &params);
    g.self_check = true;
    let mut report = Report::default();
    report.add(0, &rc, &rg).unwrap();
    eprintln!("{}", report.text());
    assert!(report.passes(), "{}", report.text());
}

/// Compares GPU-backend rows with the f64 path: returns how many rows
/// were recomputed, and panics on any row that says `ok`, was trusted
/// from the GPU, and is off by more than 100 times the GPU bounds or in
/// status or final contact.
fn no_wrong_ok_row(g: &mut GpuBackend, what: &str, specs: &[tswm::params::Spec]) -> usize {
    use tswm::integrator::{RowPath, Status};
    let params: Vec<Params> = specs.iter().map(|s| s.resolve(&[]).unwrap()).collect();
    let (rc, rg) = run_both(g, &params);
    let mut redone = 0;
    for (i, (c, r)) in rc.iter().zip(&rg).enumerate() {
        if r.path != RowPath::Gpu {
            redone += 1;
            assert_eq!(format!("{:?}", c.status), format!("{:?}", r.status));
            assert_eq!(c.x1_end.to_bits(), r.x1_end.to_bits(), "{what} lane {i}");
            continue;
        }
        assert!(
            r.status == Status::Ok,
            "{what} lane {i}: a trusted GPU row is ok"
        );
        assert_eq!(c.status, r.status, "{what} lane {i}");
        assert_eq!(c.contact_end, r.contact_end, "{what} lane {i}");
        for (name, a, b) in [
            ("x1_end", r.x1_end, c.x1_end),
            ("v1_end", r.v1_end, c.v1_end),
            ("w_motor", r.w_motor, c.w_motor),
            ("w_load", r.w_load, c.w_load),
            ("w_friction", r.w_friction, c.w_friction),
        ] {
            assert!(
                rel1(a, b) <= tswm::backend::gpu::verify::TRUSTED_BOUND,
                "{what} lane {i}: {name} {a} vs f64 {b}"
            );
        }
    }
    eprintln!(
        "{what}: {redone} of {} rows recomputed in f64 ({:.2} %)",
        rg.len(),
        100.0 * redone as f64 / rg.len() as f64
    );
    redone
}

/// No GPU row says `ok` while it is wrong: on 10,000 random user lanes
/// (few recomputed), on long horizons with stiff motors (where 21 % of
/// lanes missed the bounds), and on the lanes of the failures seen.
#[test]
fn gpu_self_check_leaves_no_wrong_ok_row() {
    let Some(mut g) = gpu("gpu_self_check_leaves_no_wrong_ok_row") else {
        return;
    };
    let random = tswm::input::testmodels::random_user_lanes(10_000, 31);
    let redone = no_wrong_ok_row(&mut g, "random user lanes", &random);
    assert!(
        redone < 200,
        "{redone} of 10,000 random user lanes recomputed"
    );
    no_wrong_ok_row(
        &mut g,
        "long horizons, stiff motors",
        &tswm::input::testmodels::long_stiff_lanes(100, 7),
    );
    let stiff = tswm::input::testmodels::stiff_at_sync_lanes(20);
    assert_eq!(
        no_wrong_ok_row(&mut g, "stiff motors at v_sync", &stiff),
        stiff.len()
    );
}

/// The lanes of the failures seen, recreated from their figures: an
/// extremely stiff motor started at synchronous speed, which ran out of
/// dispatch budget and came back `ok` short of t_end (t_end 6 s and 20 s
/// gave the same x1_end), and inputs beyond f32's range, which came back
/// `ok` or `stick` with zeros. All now come from the f64 path.
#[test]
fn unfinished_and_f32_range_lanes_come_from_the_f64_path() {
    let Some(mut g) = gpu("unfinished_and_f32_range_lanes_come_from_the_f64_path") else {
        return;
    };
    use tswm::params::{MotorKind, Num, Spec};
    let mut specs = Vec::new();
    for t_end in [6.0, 20.0] {
        let mut s = Spec::default();
        s.set(Num::VCrit, 3.35 - 1e-4);
        s.set(Num::V10, 3.35);
        s.set(Num::F2, -4774.0);
        s.set(Num::TEnd, t_end);
        specs.push(s);
    }
    for (p, v) in [(Num::FCrit, 1e39), (Num::F2, 1e300)] {
        let mut s = Spec::default();
        s.set(p, v);
        specs.push(s);
    }
    let mut s = Spec {
        motor: Some(MotorKind::Constant),
        ..Default::default()
    };
    s.set(Num::F1, 1e308);
    specs.push(s);
    let params: Vec<Params> = specs.iter().map(|s| s.resolve(&[]).unwrap()).collect();
    let (rc, rg) = run_both(&mut g, &params);
    for (i, (c, r)) in rc.iter().zip(&rg).enumerate() {
        assert!(
            r.path.name().starts_with("cpu:"),
            "lane {i}: {}",
            r.path.name()
        );
        // Every field is the f64 path's, bit for bit (Debug shows NaN too).
        let same_path = tswm::integrator::LaneResult { path: c.path, ..*r };
        assert_eq!(format!("{same_path:?}"), format!("{c:?}"), "lane {i}");
    }
    assert_ne!(
        rg[0].x1_end, rg[1].x1_end,
        "t_end 6 s and 20 s end in different places"
    );
    for r in &rg[2..] {
        assert_eq!(r.path.name(), "cpu:f32_range");
    }
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
        lanes: &ParamColumns,
        table: &[tswm::model::FrictionTable],
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
    let target = tswm::run::Target {
        dir: Some(dir.path()),
        format: tswm::output::table::Format::Csv,
        range: None,
        threads: 1,
        settings: Default::default(),
        keep: false,
    };
    let err = match tswm::run::run(&src, &mut be, target, None, None, &Default::default()) {
        Ok(_) => panic!("the run must fail"),
        Err(e) => e.to_string(),
    };
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
    quiet_mesa();
    if let Some(hw) = tswm::backend::gpu::adapters()
        .iter()
        .find(|a| tswm::backend::gpu::is_hardware(&a.info))
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

/// docs/model.md section 10 on the GPU path: the usual bounds (5e-5).
#[test]
fn engineering_columns_on_gpu() {
    let Some(mut g) = gpu("engineering_columns_on_gpu") else {
        return;
    };
    let src = Source::open(None, Some(&fixture("paper_lanes.csv"))).unwrap();
    let mut cols = tswm::params::ParamColumns::default();
    src.reader().unwrap().fill(100, &mut cols).unwrap();
    let mut res = Vec::new();
    g.run_chunk(0, &cols, &[], &mut res).unwrap();
    let worst = crate::engineering::check_engineering(&res, 5e-5);
    eprintln!("GPU, section 10 fixture: worst deviation {worst:.2e} (bound 5e-5)");
}

/// Lane refill: a lane's end state is the same bit for bit whichever slot
/// ran it and however many lanes that slot worked through before (a slot
/// a lane, 64 slots, 7 slots), on lanes of very unlike length.
#[test]
fn a_lanes_result_does_not_depend_on_the_slot_that_ran_it() {
    use tswm::backend::gpu::layout::{GpuGlobals, GpuLane};
    if gpu("a_lanes_result_does_not_depend_on_the_slot_that_ran_it").is_none() {
        return;
    }
    let lanes: Vec<GpuLane> = heterogeneous(2000)
        .iter()
        .map(|p| GpuLane::from(&tswm::model::Lane::new(p, &[])))
        .collect();
    quiet_mesa();
    let mut dev = Gpu::new(false).unwrap();
    let globals = GpuGlobals::new(&Settings::default(), &[]);
    let mut runs = Vec::new();
    for slots in [u32::MAX, 64, 7] {
        dev.slots = slots;
        let mut states = Vec::new();
        dev.run::<f32>(0, &lanes, globals, &mut states).unwrap();
        assert_eq!(states.len(), lanes.len());
        runs.push(bytemuck::cast_slice::<_, u8>(&states).to_vec());
    }
    assert!(runs[1] == runs[0], "64 slots differ from a slot a lane");
    assert!(runs[2] == runs[0], "7 slots differ from a slot a lane");
}

/// Two parts of a chunk in flight: while the host waits for one part's
/// round or copies out its states, the other part's dispatches are on the
/// device, and a part that ends makes room for the next one's upload. The
/// trace of host-side spans shows it; each part's states are the same bit
/// for bit as when it runs alone.
#[test]
fn parts_of_a_chunk_overlap_upload_compute_and_read_back() {
    use tswm::backend::gpu::layout::{GpuGlobals, GpuLane};
    use tswm::backend::gpu::{Phase, Span};
    if gpu("parts_of_a_chunk_overlap_upload_compute_and_read_back").is_none() {
        return;
    }
    let lanes: Vec<GpuLane> = heterogeneous(3000)
        .iter()
        .map(|p| GpuLane::from(&tswm::model::Lane::new(p, &[])))
        .collect();
    quiet_mesa();
    let mut dev = Gpu::new(false).unwrap();
    // Few slots, so that each part takes several rounds.
    dev.slots = 256;
    let globals = GpuGlobals::new(&Settings::default(), &[]);
    let parts: Vec<&[GpuLane]> = lanes.chunks(1000).collect();
    let mut outs = vec![Vec::new(); parts.len()];
    let mut log: Vec<Span> = Vec::new();
    dev.run_parts::<f32>(0, &parts, globals, &mut outs, 2, Some(&mut log))
        .unwrap();
    for (i, part) in parts.iter().enumerate() {
        let mut alone = Vec::new();
        dev.run::<f32>(0, part, globals, &mut alone).unwrap();
        assert!(
            bytemuck::cast_slice::<_, u8>(&alone) == bytemuck::cast_slice::<_, u8>(&outs[i]),
            "part {i} differs from its run alone"
        );
    }
    let t0 = log.iter().map(|s| s.start).min().unwrap();
    let ms = |t: std::time::Instant| (t - t0).as_secs_f64() * 1e3;
    for s in &log {
        eprintln!(
            "part {} {:?}: {:.2} to {:.2} ms",
            s.part,
            s.phase,
            ms(s.start),
            ms(s.end)
        );
    }
    let overlap = |a: Phase, b: Phase| {
        log.iter().any(|x| {
            x.phase == a
                && log
                    .iter()
                    .any(|y| y.phase == b && y.part != x.part && x.start < y.end && y.start < x.end)
        })
    };
    assert!(
        overlap(Phase::ReadBack, Phase::Compute),
        "no read-back while another part computed"
    );
    assert!(
        overlap(Phase::Upload, Phase::Compute),
        "no upload while another part computed"
    );
    // Never more than two parts in flight: part 2 starts after part 0 or 1 ends.
    let end_of = |p: usize| {
        log.iter()
            .filter(|s| s.part == p && s.phase == Phase::ReadBack)
            .map(|s| s.end)
            .max()
            .unwrap()
    };
    let start_2 = log
        .iter()
        .filter(|s| s.part == 2)
        .map(|s| s.start)
        .min()
        .unwrap();
    assert!(start_2 >= end_of(0).min(end_of(1)));
}

/// The backend with a chunk cut into parts, two in flight (as on a
/// hardware GPU), writes the same rows as with one part a chunk.
#[test]
fn a_chunk_in_parts_gives_the_same_rows() {
    let Some(mut g) = gpu("a_chunk_in_parts_gives_the_same_rows") else {
        return;
    };
    let params = heterogeneous(3000);
    let (part, in_flight) = (g.part, g.in_flight);
    let mut whole = Vec::new();
    g.run_chunk(0, &params.iter().collect(), &[], &mut whole)
        .unwrap();
    g.part = 700;
    g.in_flight = 2;
    let mut parts = Vec::new();
    let run = g.run_chunk(0, &params.iter().collect(), &[], &mut parts);
    (g.part, g.in_flight) = (part, in_flight);
    run.unwrap();
    assert_eq!(format!("{whole:?}"), format!("{parts:?}"));
}

/// Lanes are ordered on the device by their predicted step counts (a
/// model learnt from a pilot wave of the first chunk, then from every
/// chunk): a backend on 64 slots, whose 3,000-lane chunk gets a pilot and
/// a learnt order, writes the same rows as the shared backend.
#[test]
fn ordering_lanes_by_predicted_cost_changes_no_row() {
    let Some(mut shared) = gpu("ordering_lanes_by_predicted_cost_changes_no_row") else {
        return;
    };
    let params = heterogeneous(3000);
    let mut want = Vec::new();
    shared
        .run_chunk(0, &params.iter().collect(), &[], &mut want)
        .unwrap();
    drop(shared);
    quiet_mesa();
    let mut dev = Gpu::new(false).unwrap();
    dev.slots = 64;
    let mut g = GpuBackend::new(dev, Settings::default());
    assert!(!g.cost_model().trained());
    let mut got = Vec::new();
    g.run_chunk(0, &params.iter().collect(), &[], &mut got)
        .unwrap();
    assert!(g.cost_model().trained(), "the pilot wave taught the model");
    assert_eq!(format!("{want:?}"), format!("{got:?}"));
}
