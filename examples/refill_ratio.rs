//! The cost of lanes of unlike length sharing a GPU chunk, measured with
//! less noise than one criterion group: `sweeps/heterogeneous.toml`'s
//! lanes in sweep order and the same lanes sorted by their f64 step
//! counts run through the GPU backend in one process, chunk k of one
//! order timed beside chunk k of the other (on a shared VM a slow spell
//! then falls on both orders alike), pass after pass; it prints each
//! pass's ratio (sweep order's lanes/s over sorted's) and the ratio over
//! all passes.
//!
//! `cargo run --release --example refill_ratio [PASSES] [LANES]`
//! (defaults 9 passes, all 200,000 lanes).

use std::time::Instant;
use tswm::backend::gpu::{Gpu, GpuBackend};
use tswm::backend::Backend;
use tswm::integrator::Settings;
use tswm::params::Params;

fn main() {
    if std::env::var_os("XDG_RUNTIME_DIR").is_none() {
        std::env::set_var("XDG_RUNTIME_DIR", std::env::temp_dir());
    }
    let mut args = std::env::args().skip(1);
    let pairs: usize = args.next().map_or(9, |a| a.parse().expect("PAIRS"));
    let max: usize = args
        .next()
        .map_or(usize::MAX, |a| a.parse().expect("LANES"));
    let (params, sorted) = tswm::backend::gpu::cost::heterogeneous_and_sorted(max);
    let gpu = Gpu::new(false).expect("a GPU adapter");
    println!("{} lanes on {}", params.len(), gpu.describe());
    let mut be = GpuBackend::new(gpu, Settings::default());
    let chunk = be.chunk_lanes();
    let mut out = Vec::new();
    // Each order's chunks are timed alternately, chunk k of one order
    // beside chunk k of the other, so that a slow spell of the machine
    // falls on both.
    let mut time = |lanes: &[Params], k: usize| {
        let t = Instant::now();
        let part = &lanes[(k * chunk).min(lanes.len())..((k + 1) * chunk).min(lanes.len())];
        be.run_chunk((k * chunk) as u64, &part.iter().collect(), &[], &mut out)
            .unwrap();
        t.elapsed().as_secs_f64()
    };
    let chunks = params.len().div_ceil(chunk);
    // One pass unmeasured: the pipeline, buffers and cost model warm up.
    for k in 0..chunks {
        time(&params, k);
        time(&sorted, k);
    }
    let mut ratios = Vec::new();
    let (mut all_a, mut all_b) = (0.0, 0.0);
    for p in 0..pairs {
        let (mut ta, mut tb) = (0.0, 0.0);
        for k in 0..chunks {
            if (p + k) % 2 == 0 {
                ta += time(&params, k);
                tb += time(&sorted, k);
            } else {
                tb += time(&sorted, k);
                ta += time(&params, k);
            }
        }
        let n = params.len() as f64;
        println!(
            "pass {p}: sweep order {:.0} lanes/s, sorted by steps {:.0} lanes/s, ratio {:.3}",
            n / ta,
            n / tb,
            tb / ta
        );
        ratios.push(tb / ta);
        all_a += ta;
        all_b += tb;
    }
    ratios.sort_by(f64::total_cmp);
    println!(
        "all passes: ratio {:.3}; median of passes {:.3} (min {:.3}, max {:.3})",
        all_b / all_a,
        ratios[ratios.len() / 2],
        ratios[0],
        ratios[ratios.len() - 1]
    );
}
