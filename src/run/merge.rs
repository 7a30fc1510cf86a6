//! `tswm merge`: the shard folders of one sweep joined into what one run
//! would have written: the table (byte-identical to an unsharded run's on
//! the same backend, in either format), `traces.csv`, `summary.csv`,
//! `sweep.resolved.toml` and the report.
//!
//! Shards are verified, not trusted ([`super::verify`]). Each shard's
//! table, its SHA-256 compared with its manifest's, is then read as Arrow
//! batches, one shard after the other, checked lane by lane, and each
//! batch goes to the table's writer and the statistics as a run's batch
//! does (`merge_batches.rs`): no Parquet value goes through text. Any
//! failure drops the partial files, so nothing is written.

use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};

use super::merge_batches::merge_part;
use super::verify::{check_shards, Part};
use crate::error::{Error, Result};
use crate::input::lanes::Source;
use crate::output::batch::typed;
use crate::output::csv_lines::CsvLines;
use crate::output::names::{RESOLVED, SUMMARY, TRACES};
use crate::output::provenance::{time_line, SHARD_LINE, TIME_LINE};
use crate::output::table::{Format, LanesWriter};
use crate::output::traces::TRACE_COLUMNS;
use crate::output::{AtomicFile, OutDir};
use crate::stats::{Grouping, Stats};

/// What a merge wrote.
#[derive(Debug)]
pub struct Merged {
    /// Lanes in the merged table.
    pub lanes: u64,
    /// Shards joined.
    pub shards: u64,
    /// The shards' run times added up, s.
    pub seconds: f64,
    /// The merged table.
    pub table: PathBuf,
    /// Whether the folder held an earlier run's results, now replaced.
    pub replaced: bool,
    /// Seconds the report took, when one was written.
    pub report_seconds: Option<f64>,
}

impl Merged {
    /// The one-line summary.
    pub fn line(&self) -> String {
        format!(
            "tswm merge: {} lanes from {} shards ({:.2} s of shard runs); wrote {}{}{}",
            self.lanes,
            self.shards,
            self.seconds,
            self.table.display(),
            if self.replaced {
                "; replaced the earlier run's results there"
            } else {
                ""
            },
            self.report_seconds
                .map(|s| format!("; report.html in {s:.2} s"))
                .unwrap_or_default()
        )
    }
}

/// Merges the shard folders `dirs` into `out` as `format`, and writes its
/// report when `with_report`; the folder stays locked until the last file
/// is committed.
pub fn merge(dirs: &[PathBuf], out: &Path, format: Format, with_report: bool) -> Result<Merged> {
    let parts = check_shards(dirs)?;
    for p in &parts {
        if same_folder(&p.dir, out) {
            return Err(Error::input(
                out,
                None,
                Some("--out"),
                "is one of the shard folders; allowed: a folder of its own",
            ));
        }
    }
    let first = &parts[0];
    let resolved_path = first.dir.join(RESOLVED);
    // Verified (read_part): whole and UTF-8.
    let resolved =
        std::fs::read_to_string(&resolved_path).map_err(|e| Error::io(&resolved_path, e))?;
    let (sweep, _) = crate::output::provenance::read_resolved(&resolved_path, &resolved)?;
    let search = sweep.search.is_some();
    let source = Source::Sweep {
        sweep,
        file: resolved_path.clone(),
    };
    let mut out_dir = OutDir::open(out)?;
    let replaced = out_dir.held_results();
    let seconds: f64 = parts.iter().map(|p| p.m.seconds).sum();
    let total = first.m.lanes_total;

    let mut table = LanesWriter::create(out_dir.path(), format, false, search)?;
    let mut stats = Stats::create(&out_dir.join(SUMMARY), Grouping::of(&source))?;
    let next = stream_parts(&parts, search, &mut table, &mut stats)?;

    let mut files = vec![merged_resolved(
        out_dir.path(),
        &resolved,
        parts.len(),
        seconds,
        total,
    )?];
    files.extend(merge_traces(&parts, out_dir.path())?);
    files.extend(stats.finish()?.0);
    files.push(table.into_file()?);
    out_dir.commit_run(files)?;
    let report_seconds = if with_report {
        let start = std::time::Instant::now();
        crate::report::write(&mut out_dir)?;
        Some(start.elapsed().as_secs_f64())
    } else {
        None
    };
    Ok(Merged {
        lanes: next,
        shards: parts.len() as u64,
        seconds,
        table: out_dir.join(format.file_name()),
        replaced,
        report_seconds,
    })
}

/// Streams the shards' batches, in order, into `table` and the
/// statistics. Returns the number of lanes.
fn stream_parts(
    parts: &[Part],
    search: bool,
    table: &mut LanesWriter,
    stats: &mut Stats,
) -> Result<u64> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .map_err(|e| Error::Internal(format!("merge threads: {e}")))?;
    let mut next = 0u64;
    for p in parts {
        // Batch by batch: a CSV table is formatted from the batches as a
        // run formats it, a Parquet one encoded as a run encodes it.
        next = merge_part(p, search, next, |first, b| {
            table.write_batch(&pool, b)?;
            stats.add_batch(first, &typed(b)?, &pool)
        })?;
    }
    Ok(next)
}

/// Whether `a` and `b` name the same folder (`b` may not exist yet).
fn same_folder(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}

/// The merged `sweep.resolved.toml`: the first shard's, less its shard
/// line, with the shards' run times added up.
fn merged_resolved(
    out: &Path,
    text: &str,
    shards: usize,
    seconds: f64,
    lanes: u64,
) -> Result<AtomicFile> {
    let mut s = String::with_capacity(text.len() + 100);
    for line in text.lines() {
        if line.starts_with(SHARD_LINE) {
            s.push_str(&format!(
                "# merged by tswm merge from {shards} shards; time: the shards' run times added up\n"
            ));
        } else if line.starts_with(TIME_LINE) {
            s.push_str(&time_line(seconds, lanes));
        } else {
            s.push_str(line);
            s.push('\n');
        }
    }
    let path = out.join(RESOLVED);
    let mut f = AtomicFile::create(&path)?;
    f.writer()
        .write_all(s.as_bytes())
        .map_err(|e| Error::io(&path, e))?;
    Ok(f)
}

/// The shards' `traces.csv` joined in shard order (each lane's rows stay
/// together, lanes ascending, as one run writes them); None when no shard
/// traced a lane.
fn merge_traces(parts: &[Part], out: &Path) -> Result<Option<AtomicFile>> {
    let traced: Vec<&Part> = parts
        .iter()
        .filter(|p| p.m.files.contains_key(TRACES))
        .collect();
    if traced.is_empty() {
        return Ok(None);
    }
    let mut w = CsvLines::create(&out.join(TRACES), TRACE_COLUMNS)?;
    let mut line = Vec::new();
    for p in traced {
        let path = p.dir.join(TRACES);
        let f = std::fs::File::open(&path).map_err(|e| Error::io(&path, e))?;
        let mut r = BufReader::new(f);
        let mut first = true;
        loop {
            line.clear();
            if r.read_until(b'\n', &mut line)
                .map_err(|e| Error::io(&path, e))?
                == 0
            {
                break;
            }
            let text = std::str::from_utf8(&line).map_err(|_| {
                Error::input(
                    &path,
                    None,
                    None,
                    "not UTF-8 text: not a tswm traces.csv; run the shard again",
                )
            })?;
            if std::mem::take(&mut first) {
                if text.trim_end() != TRACE_COLUMNS {
                    return Err(Error::input(
                        &path,
                        Some("line 1".into()),
                        None,
                        "not a tswm traces.csv; run the shard again",
                    ));
                }
                continue;
            }
            w.line().push_str(text.trim_end_matches('\n'));
            w.end_line()?;
        }
    }
    Ok(Some(w.into_file()))
}
