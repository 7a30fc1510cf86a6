//! `tswm`: parse, plan, run; one error line and exit code 2 for bad input.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Parser;
use tswm::backend::{self, Choice, CpuBackend};
use tswm::cli::{Cli, Command, LanesArgs};
use tswm::error::{Error, Result};
use tswm::gpu::{Gpu, GpuBackend};
use tswm::lanes_file::Format;
use tswm::outdir::{commit_together, remove_partials_on_signal, AtomicFile, OutDir};
use tswm::shard::{backend_kind, sweep_hash, Manifest, Shard, MANIFEST};
use tswm::{check, output, runner};

fn main() -> ExitCode {
    quiet_mesa();
    let cli = Cli::parse();
    if let Err(e) = remove_partials_on_signal() {
        eprintln!("tswm: error: {e}");
        return ExitCode::from(e.exit_code());
    }
    let result = match cli.command {
        Command::Run {
            lanes,
            out,
            backend,
            trace,
            trace_dt,
            no_report,
            shard,
            format,
        } => run(
            &lanes,
            &out,
            backend,
            &trace,
            trace_dt,
            !no_report,
            shard.as_deref(),
            format,
        ),
        Command::Merge {
            dirs,
            out,
            format,
            no_report,
        } => merge(&dirs, &out, format, !no_report),
        Command::Report { dir } => report(&dir),
        Command::Check {
            lanes,
            disagreements,
        } => check(&lanes, disagreements.as_deref()),
        Command::Devices => devices(),
        Command::Bench { lanes, backend } => bench(&lanes, backend),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("tswm: error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}

/// Without XDG_RUNTIME_DIR, Mesa's Vulkan drivers print an error line while
/// probing for a Wayland display that compute never needs. Set here, before
/// any thread starts, since the environment is not safe to change later.
fn quiet_mesa() {
    if std::env::var_os("XDG_RUNTIME_DIR").is_none() {
        std::env::set_var("XDG_RUNTIME_DIR", std::env::temp_dir());
    }
}

#[allow(clippy::too_many_arguments)]
fn run(
    lanes: &LanesArgs,
    out: &Path,
    choice: Choice,
    trace: &[u64],
    trace_dt: Option<f64>,
    with_report: bool,
    shard: Option<&str>,
    format: Format,
) -> Result<()> {
    let shard = shard.map(Shard::parse).transpose()?;
    let plan = lanes.plan()?;
    let trace = tswm::cli::trace_plan(trace, trace_dt, &plan.source)?;
    let dir = OutDir::open(out)?;
    let total = plan.source.lane_count();
    let shard = match shard {
        None => None,
        Some(s) => {
            let hash = sweep_hash(&plan.source, trace.as_ref())?;
            // A scheduler retries a task with the same index: a complete
            // result of this very shard is kept, not computed again.
            if let Some(m) = Manifest::read(dir.path()).ok().flatten() {
                if m.sweep_hash == hash
                    && (m.shard, m.shards) == (s.k, s.n)
                    && m.format == format
                    && m.version == env!("CARGO_PKG_VERSION")
                    && m.incomplete(dir.path()).is_none()
                {
                    println!(
                        "tswm: shard {}/{} is already complete in {} ({} lanes, {} to {}, {}); nothing to do",
                        s.k,
                        s.n,
                        dir.path().display(),
                        m.rows,
                        m.lane_start,
                        m.lane_end.max(1) - 1,
                        m.backend_name
                    );
                    return Ok(());
                }
            }
            // Anything else here is redone from scratch; the old manifest
            // goes first, so it can never stand beside new files.
            remove_if_there(&dir.join(MANIFEST))?;
            Some((s, s.range(total), hash))
        }
    };
    let mut be = backend::open(choice, total, plan.threads, plan.settings)?;
    let progress = std::io::stderr().is_terminal();
    let target = runner::Target {
        dir: dir.path(),
        format,
        range: shard.as_ref().map(|s| s.1),
        threads: plan.threads,
    };
    let written = runner::run(&plan.source, be.as_mut(), target, trace.as_ref(), progress)?;
    let text = output::provenance(
        &plan.source,
        &be.name(),
        be.tolerance(),
        written.summary.seconds,
        shard.as_ref().map(|s| (s.0, s.1)),
    );
    let resolved = small_file(&dir.join("sweep.resolved.toml"), &text)?;
    // The table last, or for a shard its manifest: its appearance means
    // the run is complete. Files of an earlier run that this one does not
    // write would not belong to it and are removed: its traces, the other
    // format's table, a shard's manifest or an unsharded run's summary and
    // report (the report is built from the committed files).
    let table = dir.join(format.file_name());
    let mut stale = vec![
        dir.join(format.other().file_name()),
        dir.join("report.html"),
        dir.join(MANIFEST),
        dir.join("traces.csv"),
        dir.join("summary.csv"),
    ];
    let mut files = vec![resolved];
    files.extend(written.stats);
    let mut traces = written.traces.map(|t| t.into_file());
    let traces_bytes = traces.as_mut().map(|t| t.flushed_len()).transpose()?;
    files.extend(traces);
    let mut lanes_file = written.lanes;
    let lanes_bytes = lanes_file.flushed_len()?;
    files.push(lanes_file);
    if let Some((s, (a, b), hash)) = &shard {
        let m = Manifest {
            tool: "tswm".into(),
            version: env!("CARGO_PKG_VERSION").into(),
            sweep_hash: hash.clone(),
            shard: s.k,
            shards: s.n,
            lane_start: *a,
            lane_end: *b,
            lanes_total: total,
            rows: written.summary.lanes,
            backend: backend_kind(&be.name()).into(),
            backend_name: be.name(),
            format,
            lanes_bytes,
            traces_bytes,
            seconds: written.summary.seconds,
        };
        files.push(small_file(&dir.join(MANIFEST), &m.text())?);
    }
    let kept: Vec<PathBuf> = files.iter().map(|f| f.dest().to_path_buf()).collect();
    stale.retain(|p| !kept.contains(p));
    let stale: Vec<&Path> = stale.iter().map(|p| p.as_path()).collect();
    commit_together(files, &stale)?;
    let mut line = written.summary.line(&be.name(), &table);
    if let Some((s, (a, b), _)) = &shard {
        line.push_str(&format!(
            "; shard {}/{} (lanes {a} to {}) with {MANIFEST}",
            s.k,
            s.n,
            b.max(&1) - 1
        ));
    } else if with_report {
        let start = std::time::Instant::now();
        tswm::report::write(dir.path())?;
        line.push_str(&format!(
            "; report.html in {:.2} s",
            start.elapsed().as_secs_f64()
        ));
    }
    println!("{line}");
    Ok(())
}

/// A small file, whole, not yet committed.
fn small_file(path: &Path, text: &str) -> Result<AtomicFile> {
    let mut f = AtomicFile::create(path)?;
    f.writer()
        .write_all(text.as_bytes())
        .map_err(|e| Error::io(path, e))?;
    Ok(f)
}

fn remove_if_there(path: &Path) -> Result<()> {
    match std::fs::remove_file(path) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(Error::io(path, e)),
    }
}

fn merge(dirs: &[PathBuf], out: &Path, format: Format, with_report: bool) -> Result<()> {
    let merged = tswm::merge::merge(dirs, out, format)?;
    let mut line = merged.line();
    if with_report {
        let start = std::time::Instant::now();
        tswm::report::write(out)?;
        line.push_str(&format!(
            "; report.html in {:.2} s",
            start.elapsed().as_secs_f64()
        ));
    }
    println!("{line}");
    Ok(())
}

fn report(dir: &Path) -> Result<()> {
    tswm::report::write(dir)?;
    println!("tswm: wrote {}", dir.join("report.html").display());
    Ok(())
}

fn check(lanes: &LanesArgs, disagreements: Option<&Path>) -> Result<()> {
    let plan = lanes.plan()?;
    let cpu = CpuBackend::new(plan.threads, plan.settings)?;
    let cpu_name = backend::Backend::name(&cpu);
    let recompute = CpuBackend::new(plan.threads, plan.settings)?;
    let mut gpu = GpuBackend::with_cpu(Gpu::new(false)?, plan.settings, recompute);
    let report = match disagreements {
        None => check::Report::default(),
        Some(p) => {
            let f = std::fs::File::create(p).map_err(|e| Error::io(p, e))?;
            check::Report::writing_to(Box::new(std::io::BufWriter::new(f)))
                .map_err(|e| Error::io(p, e))?
        }
    };
    let progress = std::io::stderr().is_terminal();
    let report = check::compare(&plan.source, &mut gpu, cpu, progress, report)?;
    println!(
        "tswm check: {} lanes, {} against {cpu_name}",
        report.lanes,
        backend::Backend::name(&gpu),
    );
    print!("{}", report.text());
    if report.passes() {
        Ok(())
    } else {
        Err(Error::CheckFailed(
            "a bound was missed (see the table above)".into(),
        ))
    }
}

/// Counts the lanes of each chunk and drops them.
struct Discard(u64);

impl runner::Sink for Discard {
    type Output = u64;
    fn chunk(
        &mut self,
        _first: u64,
        params: &[tswm::params::Params],
        _results: &[tswm::integrator::LaneResult],
    ) -> Result<()> {
        self.0 += params.len() as u64;
        Ok(())
    }
    fn finish(self) -> Result<u64> {
        Ok(self.0)
    }
}

fn bench(lanes: &LanesArgs, choice: Choice) -> Result<()> {
    let plan = lanes.plan()?;
    let mut be = backend::open(
        choice,
        plan.source.lane_count(),
        plan.threads,
        plan.settings,
    )?;
    let start = std::time::Instant::now();
    let n = runner::pipeline(&plan.source, be.as_mut(), false, Discard(0))?;
    let s = start.elapsed().as_secs_f64();
    println!(
        "tswm bench: {n} lanes in {s:.3} s ({:.0} lanes/s, {}); nothing written",
        n as f64 / s.max(1e-9),
        be.name()
    );
    Ok(())
}

fn devices() -> Result<()> {
    let list = tswm::gpu::adapters();
    if list.is_empty() {
        println!("no GPU adapters found (install a Vulkan driver, e.g. mesa-vulkan-drivers)");
    }
    for a in list {
        let l = &a.limits;
        let w = tswm::gpu::WorkSize::of(&a.info, l);
        println!(
            "{} ({:?}, {:?}, driver {} {})\n  max_storage_buffer_binding_size {} B, max_buffer_size {} B, \
             max_compute_workgroups_per_dimension {}, max_compute_invocations_per_workgroup {}\n  \
             chunks: {} lanes, cut into parts of {} lanes, {} in flight at once, each on {} slots \
             ({}; at most {} lanes a part by the limits)",
            a.info.name,
            a.info.device_type,
            a.info.backend,
            a.info.driver,
            a.info.driver_info,
            l.max_storage_buffer_binding_size,
            l.max_buffer_size,
            l.max_compute_workgroups_per_dimension,
            l.max_compute_invocations_per_workgroup,
            w.in_flight * w.chunk_lanes,
            w.chunk_lanes,
            w.in_flight,
            w.slots,
            if tswm::gpu::is_hardware(&a.info) {
                format!(
                    "hardware: a slot for each invocation an H100 keeps resident, {} lanes a slot",
                    tswm::gpu::HW_LANES_PER_SLOT
                )
            } else {
                format!(
                    "software: {} slots a core, {} lanes a slot",
                    tswm::gpu::SW_SLOTS_PER_CORE,
                    tswm::gpu::SW_LANES_PER_SLOT
                )
            },
            tswm::gpu::max_chunk_lanes(l),
        );
    }
    Ok(())
}
