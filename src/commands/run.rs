//! `tswm run`: a sweep's lanes into an output folder, or one shard of
//! them, committed together, then the report.

use std::io::Write;
use std::path::Path;

use crate::backend;
use crate::cli::{trace_plan, LanesArgs, Plan, RunFlags};
use crate::error::{Error, Result};
use crate::input::sweep::TraceSpec;
use crate::output::names::{MANIFEST, RESOLVED};
use crate::output::provenance;
use crate::output::table::Format;
use crate::output::{AtomicFile, OutDir};
use crate::progress::Show;
use crate::run;
use crate::run::estimate::{estimate, ESTIMATE_FROM};
use crate::run::shard::{Shard, ShardRun, ShardStart};

/// Runs `tswm run`; prints its summary line.
pub fn run(lanes: &LanesArgs, flags: &RunFlags, show: &Show) -> Result<()> {
    let shard = flags.shard.as_deref().map(Shard::parse).transpose()?;
    // Only the lanes that run are checked: a shard's.
    let part = |n: u64, unit: u64| shard.map_or((0, n), |s| s.range_in(n, unit));
    let plan = match (&lanes.sweep, &lanes.lanes, flags.dry_run) {
        // A dry run of a sweep checks only its trial's lanes: the whole
        // check of a large sweep takes minutes, and the estimate is what
        // was asked for (a lane table is read whole to count its rows).
        (Some(file), None, true) => {
            let (threads, settings) = lanes.settings()?;
            Plan {
                source: crate::input::lanes::Source::sweep(file)?,
                threads,
                settings,
                precision: lanes.asked_precision(),
            }
        }
        _ => lanes.plan_part(&part, show)?,
    };
    let done = execute(plan, shard, flags, show, false)?;
    sayln!("{}", done.line);
    Ok(())
}

/// What a run did: its summary line, and its batches when kept.
pub struct Done {
    /// The summary line `tswm run` prints.
    pub line: String,
    /// The results table's batches, in lane order (when asked to keep them).
    pub batches: Vec<arrow_array::RecordBatch>,
}

/// Runs the lanes of `plan` (of shard `shard`, if any) into the folder
/// `flags.out` as `tswm run` does, shown by `show`; keeps the results
/// table's batches when `keep` (Python's `tswm.run` with `out=`). A
/// folder this call created is removed again when it fails.
pub fn execute(
    plan: Plan,
    shard: Option<Shard>,
    flags: &RunFlags,
    show: &Show,
    keep: bool,
) -> Result<Done> {
    let report = !flags.no_report;
    let trace = trace_plan(&flags.trace, flags.trace_dt, &plan.source)?;
    let total = plan.source.lane_count();
    if flags.dry_run {
        return dry_run(&plan, shard, flags);
    }
    let mut dir = OutDir::open(&flags.out)?;
    let shard = match shard {
        None => None,
        Some(s) => match ShardRun::start(s, &plan.source, trace.as_ref(), &dir, flags.format)? {
            ShardStart::Run(run) => Some(run),
            ShardStart::Complete(said) => {
                return Ok(Done {
                    line: said,
                    batches: Vec::new(),
                })
            }
        },
    };
    let mut be = plan.backend(flags.backend, total)?;
    let range = shard.as_ref().map_or((0, total), |s| s.range);
    if range.1 - range.0 > ESTIMATE_FROM {
        // A long run says what it will cost before it starts (on the
        // backend itself: a search's drives are read once, by its rounds).
        let e = estimate(&plan.source, be.as_mut(), plan.threads, flags.format, range)?;
        sayln!("{}", e.line());
    }
    // A search runs its drives in rounds on the backend.
    let mut be = run::search::around(be, &plan.source, range)?;
    let target = run::Target {
        dir: Some(dir.path()),
        format: flags.format,
        range: shard.as_ref().map(|s| s.range),
        threads: plan.threads,
        settings: plan.settings,
        keep,
    };
    let scan = (report && shard.is_none())
        .then(|| report_scan(&plan, trace.as_ref(), be.as_ref(), &dir, flags.format))
        .flatten();
    let mut written = run::run(
        &plan.source,
        be.as_mut(),
        target,
        trace.as_ref(),
        scan,
        show,
    )?;
    let files = files_of(
        &plan,
        &mut written,
        trace.as_ref(),
        be.as_ref(),
        &dir,
        shard.as_ref(),
        flags.format,
    )?;
    let table = dir.join(flags.format.file_name());
    let replaced = dir.held_results();
    dir.commit_run(files)?;
    let mut line = written.summary.line(&be.name(), &table);
    line.push_str(&paper_note(&plan.source));
    line.push_str(if replaced { REPLACED } else { "" });
    match &shard {
        Some(s) => line.push_str(&s.said()),
        None if report => line.push_str(&write_report(&mut dir, written.scan.take())?),
        None => {}
    }
    Ok(Done {
        line,
        batches: std::mem::take(&mut written.batches),
    })
}

/// What the summary line adds when a run replaced an earlier one's results.
const REPLACED: &str = "; replaced the earlier run's results there";

/// "; from the paper's drive (not given): ..." for a run that takes
/// values of the paper's drive because it leaves them out.
fn paper_note(source: &crate::input::lanes::Source) -> String {
    let defaults = crate::params::paper::paper_defaults(&source.given());
    if defaults.is_empty() {
        String::new()
    } else {
        format!("; {}", crate::params::paper::note(&defaults))
    }
}

/// `--dry-run`: the estimate of the run of `plan` (of shard `shard`),
/// with nothing opened, run or written.
fn dry_run(plan: &Plan, shard: Option<Shard>, flags: &RunFlags) -> Result<Done> {
    let total = plan.source.lane_count();
    let range = shard.map_or((0, total), |s| s.range_in(total, plan.source.shard_unit()));
    let mut be = plan.backend(flags.backend, range.1 - range.0)?;
    let e = estimate(&plan.source, be.as_mut(), plan.threads, flags.format, range)?;
    Ok(Done {
        line: format!(
            "{} (--dry-run: nothing run or written; only the trial's lanes were checked)",
            e.line()
        ),
        batches: Vec::new(),
    })
}

/// A run's files in the order they are committed: `sweep.resolved.toml`,
/// the statistics, the traces, the table last, or for a shard its
/// manifest (whose appearance means the run is complete).
fn files_of(
    plan: &Plan,
    written: &mut run::Written,
    trace: Option<&TraceSpec>,
    be: &dyn backend::Backend,
    dir: &OutDir,
    shard: Option<&ShardRun>,
    format: Format,
) -> Result<Vec<AtomicFile>> {
    let text = provenance::provenance(
        &plan.source,
        trace,
        &be.name(),
        be.tolerance(),
        written.summary.seconds,
        shard.map(|s| ((s.shard.k, s.shard.n), s.range)),
    );
    let mut files = vec![small_file(&dir.join(RESOLVED), &text, shard.is_some())?];
    files.append(&mut written.stats);
    files.extend(written.traces.take().map(|t| t.into_file()));
    files.extend(written.lanes.take());
    if let Some(s) = shard {
        let m = s.manifest(
            &mut files,
            &be.name(),
            plan.settings.tol,
            &written.summary,
            format,
        )?;
        files.push(small_file(&dir.join(MANIFEST), &m.text(), false)?);
    }
    Ok(files)
}

/// Runs the lanes of `plan` on `backend` and gives back the results
/// table's batches, in lane order, writing nothing (Python's `tswm.run`
/// without `out=`): the rows `tswm run` would write (a traced lane's GPU
/// row the f64 row of its trace). Memory holds the whole table.
pub fn collect(
    plan: &Plan,
    backend: crate::backend::Choice,
    show: &Show,
) -> Result<Vec<arrow_array::RecordBatch>> {
    let trace = trace_plan(&[], None, &plan.source)?;
    let total = plan.source.lane_count();
    let be = plan.backend(backend, total)?;
    let mut be = run::search::around(be, &plan.source, (0, total))?;
    let target = run::Target {
        dir: None,
        format: Format::Parquet,
        range: None,
        threads: plan.threads,
        settings: plan.settings,
        keep: true,
    };
    let written = run::run(
        &plan.source,
        be.as_mut(),
        target,
        trace.as_ref(),
        None,
        show,
    )?;
    Ok(written.batches)
}

/// Writes the report; "; report.html in 0.12 s" for the summary line.
fn write_report(dir: &mut OutDir, scan: Option<crate::report::Scan>) -> Result<String> {
    let start = std::time::Instant::now();
    crate::report::write_with(dir, scan)?;
    Ok(format!(
        "; report.html in {:.2} s",
        start.elapsed().as_secs_f64()
    ))
}

/// The report's aggregates, gathered as the rows stream past, from the
/// sweep the report will read back (the resolved sweep, its time still
/// to come); None where the report reads the finished folder instead.
fn report_scan(
    plan: &Plan,
    trace: Option<&TraceSpec>,
    be: &dyn backend::Backend,
    dir: &OutDir,
    format: Format,
) -> Option<crate::report::Scan> {
    let text = provenance::provenance(&plan.source, trace, &be.name(), be.tolerance(), 0.0, None);
    let (sweep, stated) = provenance::read_resolved(&dir.join(RESOLVED), &text).ok()?;
    crate::report::scan_for(&sweep, format, stated)
}

/// A small file, whole, not yet committed (hashed when `hashed`).
fn small_file(path: &Path, text: &str, hashed: bool) -> Result<AtomicFile> {
    let mut f = if hashed {
        AtomicFile::create_hashed(path)?
    } else {
        AtomicFile::create(path)?
    };
    f.writer()
        .write_all(text.as_bytes())
        .map_err(|e| Error::io(path, e))?;
    Ok(f)
}
