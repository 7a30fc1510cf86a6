//! Throughput in lanes per second (criterion reports "elem/s").
//!
//! `cpu/1-thread` and `cpu/all-threads`: the f64 path on paper-like lanes
//! (`testmodels::paper_like`: the paper's design, load uniform in ±6 kN,
//! start at rest, 2 s), lanes made once outside the timing.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use tswm::integrator::Settings;
use tswm::params::Params;
use tswm::runner::run_cpu_lanes;
use tswm::testmodels::paper_like;

fn lanes(n: usize) -> Vec<Params> {
    paper_like(n, 1)
        .iter()
        .map(|s| s.resolve(false).unwrap())
        .collect()
}

fn cpu(c: &mut Criterion) {
    let n = 4096;
    let lanes = lanes(n);
    let mut g = c.benchmark_group("cpu");
    g.throughput(Throughput::Elements(n as u64));
    g.sample_size(20);
    let all = std::thread::available_parallelism().map_or(1, |n| n.get());
    for (name, threads) in [("1-thread", 1), ("all-threads", all)] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut out = Vec::with_capacity(n);
        g.bench_function(name, |b| {
            b.iter(|| run_cpu_lanes(&pool, &Settings::default(), &lanes, None, &mut out))
        });
    }
    g.finish();
}

criterion_group!(benches, cpu);
criterion_main!(benches);
