//! How the GPU's self-check thresholds were chosen (docs/gpu.md):
//! runs lane sets raw on the GPU (no self-check) and on the f64 path, and
//! prints, for every lane whose GPU row is off by more than 100 times the
//! GPU bounds (or whose status or final contact differs), the indicators
//! the self-check could read, and how many lanes each indicator flags.
//!
//!     cargo run --release --example gpu_trust -- [random|long|stiff]

use tswm::backend::cpu::run_cpu_lanes;
use tswm::backend::gpu::layout::{GpuGlobals, GpuLane, GpuState};
use tswm::backend::gpu::Gpu;
use tswm::integrator::Settings;
use tswm::model::Lane;
use tswm::params::Params;

fn main() {
    let which = std::env::args().nth(1).unwrap_or_else(|| "random".into());
    let specs = match which.as_str() {
        "random" => tswm::input::testmodels::random_user_lanes(10_000, 31),
        "long" => tswm::input::testmodels::long_stiff_lanes(300, 7),
        _ => tswm::input::testmodels::stiff_at_sync_lanes(40),
    };
    let params: Vec<Params> = specs.iter().map(|s| s.resolve(&[]).unwrap()).collect();
    let lanes: Vec<Lane> = params.iter().map(|p| Lane::new(p, &[])).collect();
    let pool = rayon::ThreadPoolBuilder::new().build().unwrap();
    let mut cpu = Vec::new();
    run_cpu_lanes(
        &pool,
        &Settings::default(),
        &params.iter().collect(),
        &[],
        &mut cpu,
    );
    let gpu = Gpu::new(false).expect("a GPU adapter");
    let l32: Vec<GpuLane> = lanes.iter().map(GpuLane::from).collect();
    let mut states: Vec<GpuState> = Vec::new();
    let mut all: Vec<GpuState> = Vec::new();
    for (k, part) in l32.chunks(65536).enumerate() {
        gpu.run::<f32>(
            k as u64,
            part,
            GpuGlobals::new(&Settings::default(), &[]),
            &mut states,
        )
        .unwrap();
        all.extend(&states);
    }
    let mut bad = 0;
    let mut missed = 0;
    let mut reasons = std::collections::BTreeMap::new();
    let (mut good_res, mut bad_res) = (Vec::new(), Vec::new());
    let mut flagged = [0usize; 4];
    println!("lane  worst    done  energy_res  sigma_k   steps  cancel  what");
    for (i, (c, st)) in cpu.iter().zip(&all).enumerate() {
        let g = st.end_state(&lanes[i]).result(&lanes[i], &[]);
        let rel = |a: f64, b: f64| (a - b).abs() / b.abs().max(1.0);
        let worst = [
            rel(g.x1_end, c.x1_end),
            rel(g.v1_end, c.v1_end),
            rel(g.w_motor, c.w_motor),
            rel(g.w_load, c.w_load),
            rel(g.w_friction, c.w_friction),
        ]
        .into_iter()
        .fold(0.0, f64::max);
        let discrete = g.status != c.status || g.contact_end != c.contact_end;
        let l = &lanes[i];
        let ke = 0.5 * (l.m1 + l.m2 * l.tan_g * l.tan_g) * (g.v1_end.powi(2) - l.v1_0.powi(2));
        let scale = [
            1.0,
            g.w_motor.abs(),
            g.w_load.abs(),
            g.w_friction.abs(),
            ke.abs(),
        ]
        .into_iter()
        .fold(0.0, f64::max);
        let res = (g.w_motor + g.w_load - g.w_friction - ke).abs() / scale;
        let cancel = [g.w_motor.abs(), g.w_load.abs()]
            .into_iter()
            .fold(f64::MAX, f64::min)
            / scale;
        let done = st.flags & 4 != 0;
        let why = tswm::backend::gpu::verify::recheck(l, &[], &st.end_state(l), &g, done);
        let f = [
            !done,
            res > 1e-4,
            l.sigma_k < 1e-3 && l.motor == tswm::model::MotorKind::Kloss,
            st.steps > 20_000,
        ];
        if let Some(w) = why {
            *reasons.entry(w.name()).or_insert(0usize) += 1;
        }
        for (k, x) in f.iter().enumerate() {
            flagged[k] += *x as usize;
        }
        let is_bad = worst > 5e-3 || discrete || worst.is_nan();
        if g.status.name() == "ok" {
            if is_bad {
                bad_res.push(res)
            } else {
                good_res.push(res)
            }
        }
        if is_bad && why.is_none() {
            missed += 1;
        }
        if is_bad {
            bad += 1;
            println!(
                "{i:5} {worst:8.1e} {done:5} {res:10.2e} {:8.1e} {:7} {cancel:7.1e}  gpu {}/{} cpu {}/{} v1 {:.4} vs {:.4} check: {:?}",
                l.sigma_k, st.steps, g.status.name(), g.contact_end.name(), c.status.name(),
                c.contact_end.name(), g.v1_end, c.v1_end, why.map(|w| w.name())
            );
        }
    }
    good_res.sort_by(f64::total_cmp);
    bad_res.sort_by(f64::total_cmp);
    let q = |v: &[f64], p: f64| {
        v.get(((v.len() as f64 - 1.0) * p) as usize)
            .copied()
            .unwrap_or(f64::NAN)
    };
    println!(
        "energy residual, lanes within 5e-3 (gpu ok): median {:.1e}, p99 {:.1e}, p99.9 {:.1e}, max {:.1e}; lanes off (gpu ok): min {:.1e}",
        q(&good_res, 0.5), q(&good_res, 0.99), q(&good_res, 0.999), q(&good_res, 1.0), q(&bad_res, 0.0)
    );
    // What the check costs: recheck of every row, timed over repeats.
    let rows: Vec<_> = all
        .iter()
        .zip(&lanes)
        .map(|(st, l)| {
            let end = st.end_state(l);
            (end, end.result(l, &[]), st.flags & 4 != 0)
        })
        .collect();
    let t = std::time::Instant::now();
    let mut flagged_again = 0usize;
    for _ in 0..100 {
        for ((end, r, done), l) in rows.iter().zip(&lanes) {
            flagged_again +=
                tswm::backend::gpu::verify::recheck(std::hint::black_box(l), &[], end, r, *done)
                    .is_some() as usize;
        }
    }
    let ns = t.elapsed().as_secs_f64() * 1e9 / (100.0 * rows.len() as f64);
    println!(
        "check cost: {ns:.1} ns per row on one thread ({} flags over the repeats)",
        flagged_again
    );
    let sent: usize = reasons.values().sum();
    println!(
        "self-check: {sent} of {} lanes recomputed ({:.2} %) {reasons:?}; lanes off and not caught: {missed}",
        lanes.len(),
        100.0 * sent as f64 / lanes.len() as f64
    );
    println!(
        "{which}: {} lanes, {bad} off by > 5e-3 or discrete; flagged: unfinished {}, energy>1e-4 {}, sigma_k<1e-3 {}, steps>20000 {}",
        lanes.len(), flagged[0], flagged[1], flagged[2], flagged[3]
    );
}
