//! Throughput in lanes per second (criterion reports "elem/s").
//!
//! Lanes: `testmodels::paper_like` (the paper's design, load uniform in
//! ±6 kN, start at rest, 2 s), made once outside the timing.
//!
//! - `cpu/1-thread`, `cpu/all-threads`: the f64 path, 4096 lanes.
//! - `cpu-width/{paper-like,heterogeneous}/ISA-xW`: the f64 path on one
//!   thread at each vector width W of this core's widest instruction set
//!   and at the natural width of each narrower one, 4096 paper-like lanes
//!   and the first 4096 of `sweeps/heterogeneous.toml`, in blocks of
//!   `BLOCK_LANES` as `run_cpu_lanes` gives them to a thread.
//! - `kernel/{cpu,gpu}/N`: integration only, N = 10^3..10^6 lanes; for the
//!   GPU this is upload, all dispatches and read-back of the states.
//! - `end_to_end/{cpu,gpu}/N`: `runner::run` on a sweep file of N lanes:
//!   lane generation, integration and `lanes.csv` written to disk.
//! - `heterogeneous/{sweep-order,sorted-by-steps}/N`: the GPU backend on
//!   `sweeps/heterogeneous.toml` (t_end 0.2 to 7.8 s), in sweep order and
//!   sorted by step count.
//! - `table/{lanes.csv,lanes.parquet}/{1-thread,C-threads}/N`:
//!   the results table alone, N rows of integrated lanes formatted,
//!   encoded and committed (the file sizes are printed).
//!
//! GPU benchmarks use the best adapter (`Gpu::new(false)`) and are skipped,
//! with a message, when there is none. Set TSWM_BENCH_MAX=100000 to stop
//! below 10^6 lanes.

use criterion::{criterion_group, BenchmarkId, Criterion, Throughput};
use tswm::backend::cpu::{run_cpu_lanes, BLOCK_LANES};
use tswm::backend::gpu::layout::{GpuGlobals, GpuLane};
use tswm::backend::gpu::{Gpu, GpuBackend};
use tswm::backend::{Backend, CpuBackend};
use tswm::input::lanes::Source;
use tswm::input::testmodels::paper_like;
use tswm::integrator::width::{isas, Width, LANES};
use tswm::integrator::{simulate_batch_at, Settings};
use tswm::model::Lane;
use tswm::output::table::{Format, LanesWriter};
use tswm::params::{ParamColumns, Params};

fn lanes(n: usize) -> Vec<Params> {
    paper_like(n, 1)
        .iter()
        .map(|s| s.resolve(&[]).unwrap())
        .collect()
}

/// Lanes one thread steps together, and its instruction set: the
/// widest set's widths (`LANES`), and each narrower set's own.
fn widths() -> Vec<Width> {
    let all = isas();
    let best = *all.last().unwrap();
    let mut v: Vec<Width> = LANES.map(|lanes| Width { lanes, isa: best }).to_vec();
    v.extend(all[..all.len() - 1].iter().map(|&i| Width::natural(i)));
    v
}

fn cpu_widths(c: &mut Criterion) {
    let n = 4096;
    let paper: Vec<Lane> = lanes(n).iter().map(|p| Lane::new(p, &[])).collect();
    let (het, _) = tswm::backend::gpu::cost::heterogeneous_and_sorted(n);
    let het: Vec<Lane> = het.iter().map(|p| Lane::new(p, &[])).collect();
    let mut g = c.benchmark_group("cpu-width");
    g.throughput(Throughput::Elements(n as u64));
    g.sample_size(10);
    let set = Settings::default();
    let mut out = vec![tswm::integrator::LaneResult::EMPTY; n];
    for (name, lanes) in [("paper-like", &paper), ("heterogeneous", &het)] {
        for w in widths() {
            let id = BenchmarkId::new(name, w.name().replace(' ', "-"));
            g.bench_function(id, |b| {
                b.iter(|| {
                    let b = BLOCK_LANES;
                    for (l, o) in lanes.chunks(b).zip(out.chunks_mut(b)) {
                        simulate_batch_at(w, l, &[], &set, o);
                    }
                })
            });
        }
    }
    g.finish();
}

fn sizes() -> Vec<usize> {
    let max: usize = std::env::var("TSWM_BENCH_MAX")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1_000_000);
    [1_000, 10_000, 100_000, 1_000_000]
        .into_iter()
        .filter(|&n| n <= max)
        .collect()
}

fn gpu() -> Option<Gpu> {
    match Gpu::new(false) {
        Ok(g) => {
            eprintln!("GPU benchmarks on {}", g.describe());
            Some(g)
        }
        Err(e) => {
            eprintln!("GPU benchmarks skipped: {e}");
            None
        }
    }
}

fn cpu_threads(c: &mut Criterion) {
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
            b.iter(|| {
                run_cpu_lanes(
                    &pool,
                    &Settings::default(),
                    &lanes.iter().collect(),
                    &[],
                    &mut out,
                )
            })
        });
    }
    g.finish();
}

fn kernel(c: &mut Criterion) {
    let mut g = c.benchmark_group("kernel");
    g.sample_size(10);
    let pool = rayon::ThreadPoolBuilder::new().build().unwrap();
    let device = gpu();
    for n in sizes() {
        let params = lanes(n);
        g.throughput(Throughput::Elements(n as u64));
        let mut out = Vec::with_capacity(n);
        let cols: ParamColumns = params.iter().collect();
        g.bench_with_input(BenchmarkId::new("cpu", n), &cols, |b, p| {
            b.iter(|| run_cpu_lanes(&pool, &Settings::default(), p, &[], &mut out))
        });
        if let Some(dev) = &device {
            let l32: Vec<GpuLane> = params
                .iter()
                .map(|p| GpuLane::from(&Lane::new(p, &[])))
                .collect();
            let globals = GpuGlobals::new(&Settings::default(), &[]);
            let chunk = tswm::backend::gpu::WorkSize::of(&dev.info, &dev.limits).chunk_lanes;
            let mut states = Vec::new();
            g.bench_with_input(BenchmarkId::new("gpu", n), &l32, |b, l| {
                b.iter(|| {
                    for (k, part) in l.chunks(chunk).enumerate() {
                        dev.run::<f32>(k as u64, part, globals, &mut states)
                            .unwrap();
                    }
                })
            });
        }
    }
    g.finish();
}

/// One end-to-end run: lanes.csv streamed, synced and renamed into place.
fn write_table(src: &Source, be: &mut dyn Backend, dir: &std::path::Path) {
    let target = tswm::run::Target {
        dir: Some(dir),
        format: Format::Csv,
        range: None,
        threads: 0,
        settings: Default::default(),
        keep: false,
    };
    let written = tswm::run::run(src, be, target, None, None, &Default::default()).unwrap();
    let mut files: Vec<_> = written.lanes.into_iter().collect();
    files.extend(written.stats);
    tswm::output::commit_together(files, &[]).unwrap();
}

/// Writing the results table alone: the rows of N paper-like lanes
/// (integrated once, outside the timing) formatted, encoded, synced and
/// renamed into place, in chunks of the CPU backend's size, as a run
/// writes them, on 1 thread and on all cores (CSV rows are formatted in
/// parallel; Parquet's columns are encoded in parallel). Prints each
/// file's size.
fn table(c: &mut Criterion) {
    let n = *sizes().last().unwrap();
    let params = lanes(n);
    let pool = rayon::ThreadPoolBuilder::new().build().unwrap();
    let mut results = Vec::new();
    run_cpu_lanes(
        &pool,
        &Settings::default(),
        &params.iter().collect(),
        &[],
        &mut results,
    );
    let dir = tempfile::tempdir().unwrap();
    let mut g = c.benchmark_group("table");
    g.sample_size(10);
    g.throughput(Throughput::Elements(n as u64));
    let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
    let runs = [
        (Format::Csv, 1, "lanes.csv/1-thread".to_string()),
        (Format::Csv, cores, format!("lanes.csv/{cores}-threads")),
        (Format::Parquet, 1, "lanes.parquet/1-thread".to_string()),
        (
            Format::Parquet,
            cores,
            format!("lanes.parquet/{cores}-threads"),
        ),
    ];
    for (format, threads, name) in runs {
        let writers = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        const CHUNK: usize = 16384;
        let mut chunks: Vec<ParamColumns> =
            params.chunks(CHUNK).map(|p| p.iter().collect()).collect();
        let mut write = || {
            let mut w = LanesWriter::create(dir.path(), format, false, false).unwrap();
            let mut builder = tswm::output::batch::Builder::default();
            for (k, (p, r)) in chunks.iter_mut().zip(results.chunks(CHUNK)).enumerate() {
                // The run's path: the chunk's batch of columns, then the
                // file, the batch's buffers kept for the next chunk.
                let b = builder.build((k * CHUNK) as u64, p, r, &writers).unwrap();
                w.write_batch(&writers, &b).unwrap();
                builder.recycle(b, p);
            }
            tswm::output::commit_together(vec![w.into_file().unwrap()], &[]).unwrap();
        };
        write();
        let path = dir.path().join(format.file_name());
        let size = std::fs::metadata(&path).unwrap().len();
        eprintln!(
            "table: {} for {n} lanes: {size} bytes ({:.1} bytes a lane)",
            format.file_name(),
            size as f64 / n as f64
        );
        g.bench_function(BenchmarkId::new(name, n), |b| b.iter(&mut write));
    }
    g.finish();
}

/// Lanes of very different lengths (`sweeps/heterogeneous.toml`, 200,000
/// lanes) through the GPU backend (conversion, chunks, the check), in
/// their sweep order and sorted by their f64 step counts, in one run: the
/// cost of lanes of unlike length sharing a chunk.
fn heterogeneous(c: &mut Criterion) {
    let Some(dev) = gpu() else { return };
    let (params, sorted) =
        tswm::backend::gpu::cost::heterogeneous_and_sorted(*sizes().last().unwrap());
    let mut be = GpuBackend::new(dev, Settings::default());
    let chunk = be.chunk_lanes();
    let mut g = c.benchmark_group("heterogeneous");
    g.sample_size(10);
    g.throughput(Throughput::Elements(params.len() as u64));
    let mut out = Vec::new();
    for (name, lanes) in [("sweep-order", &params), ("sorted-by-steps", &sorted)] {
        g.bench_function(BenchmarkId::new(name, lanes.len()), |b| {
            b.iter(|| {
                for (k, part) in lanes.chunks(chunk).enumerate() {
                    be.run_chunk((k * chunk) as u64, &part.iter().collect(), &[], &mut out)
                        .unwrap();
                }
            })
        });
    }
    g.finish();
}

fn end_to_end(c: &mut Criterion) {
    let mut g = c.benchmark_group("end_to_end");
    g.sample_size(10);
    let dir = tempfile::tempdir().unwrap();
    let mut cpu = CpuBackend::new(0, Settings::default()).unwrap();
    let mut gpu = gpu().map(|d| GpuBackend::new(d, Settings::default()));
    for n in sizes() {
        let sweep = dir.path().join(format!("s{n}.toml"));
        std::fs::write(
            &sweep,
            format!("[[grid]]\nparam = \"f2\"\nfrom = -6000.0\nto = 6000.0\nn = {n}\n"),
        )
        .unwrap();
        let src = Source::open(Some(&sweep), None).unwrap();
        let csv = dir.path();
        g.throughput(Throughput::Elements(n as u64));
        g.bench_function(BenchmarkId::new("cpu", n), |b| {
            b.iter(|| write_table(&src, &mut cpu, csv))
        });
        if let Some(be) = gpu.as_mut() {
            g.bench_function(BenchmarkId::new("gpu", n), |b| {
                b.iter(|| write_table(&src, be, csv))
            });
        }
    }
    g.finish();
}

criterion_group!(
    benches,
    cpu_threads,
    cpu_widths,
    kernel,
    end_to_end,
    table,
    heterogeneous
);

fn main() {
    // Mesa's Vulkan drivers print an error line without XDG_RUNTIME_DIR;
    // set it here, before criterion or rayon start a thread.
    if std::env::var_os("XDG_RUNTIME_DIR").is_none() {
        std::env::set_var("XDG_RUNTIME_DIR", std::env::temp_dir());
    }
    benches();
    Criterion::default().configure_from_args().final_summary();
}
