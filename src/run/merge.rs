//! `tswm merge`: the shard folders of one sweep joined into what one run
//! would have written: the table (`lanes.csv` byte-identical to an
//! unsharded run's on the same backend; `lanes.parquet` the same values,
//! and for 10^6 lanes not the same bytes: its pages come out longer), `traces.csv`,
//! `summary.csv`,
//! `sweep.resolved.toml` and the report.
//!
//! Shards are verified, not trusted ([`super::verify`]). The rows are
//! then streamed, one shard after the other, parsed cell by cell and
//! checked lane by lane, and each table's SHA-256 is compared (a CSV
//! table is hashed as it is read, a Parquet one before); Parquet shards go
//! batch by batch instead, never through
//! text (`merge_batches.rs`). Any failure drops the partial files,
//! so nothing is written.

use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};

use super::merge_batches::merge_parquet_part;
use super::verify::{all_rows_read, check_shards, refused, Part};
use crate::columns::LANE;
use crate::error::{Error, Result};
use crate::input::lanes::Source;
use crate::output::batch::columns_for;
use crate::output::csv_lines::CsvLines;
use crate::output::names::{RESOLVED, SUMMARY, TRACES};
use crate::output::provenance::{time_line, SHARD_LINE, TIME_LINE};
use crate::output::table::{Cell, Format, LanesWriter, RowReader};

/// Rows the statistics of a merge take at a time.
const MERGE_ROWS: usize = 8192;

/// The statistics of a merge, fed rows a batch at a time as a run's are.
struct Batched {
    stats: Stats,
    pool: rayon::ThreadPool,
    rows: Vec<Cell>,
    first: u64,
    /// A search's rows (its columns after the results).
    search: bool,
}

impl Batched {
    fn new(stats: Stats, search: bool) -> Result<Batched> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .map_err(|e| Error::Internal(format!("merge threads: {e}")))?;
        Ok(Batched {
            stats,
            pool,
            rows: Vec::new(),
            first: 0,
            search,
        })
    }

    /// Adds lane `lane`'s row.
    fn add(&mut self, lane: u64, cells: &[Cell]) -> Result<()> {
        if self.rows.is_empty() {
            self.first = lane;
        }
        self.rows.extend_from_slice(cells);
        if self.rows.len() >= MERGE_ROWS * cells.len() {
            self.flush()?;
        }
        Ok(())
    }

    /// Adds a batch of rows whose first lane is `first`.
    fn add_batch(&mut self, first: u64, b: &arrow_array::RecordBatch) -> Result<()> {
        self.flush()?;
        let cols = crate::output::batch::typed(b)?;
        self.stats.add_batch(first, &cols, &self.pool)
    }

    fn flush(&mut self) -> Result<()> {
        if !self.rows.is_empty() {
            let b = crate::output::batch::from_cells(&self.rows, self.search)?;
            let cols = crate::output::batch::typed(&b)?;
            self.stats.add_batch(self.first, &cols, &self.pool)?;
            self.rows.clear();
        }
        Ok(())
    }

    fn finish(mut self) -> Result<Stats> {
        self.flush()?;
        Ok(self.stats)
    }
}
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
    let stats = Stats::create(&out_dir.join(SUMMARY), Grouping::of(&source))?;
    let mut batched = Batched::new(stats, search)?;
    let next = stream_parts(&parts, search, &mut table, &mut batched)?;
    let stats = batched.finish()?;

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

/// Streams the shards' rows, in order, into `table` and the statistics.
/// Returns the number of lanes.
fn stream_parts(
    parts: &[Part],
    search: bool,
    table: &mut LanesWriter,
    batched: &mut Batched,
) -> Result<u64> {
    let kinds = columns_for(search);
    let mut rec = csv::ByteRecord::new();
    let mut cells: Vec<Cell> = Vec::with_capacity(kinds.len());
    let mut next = 0u64;
    let table_pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .map_err(|e| Error::Internal(format!("merge threads: {e}")))?;
    for p in parts {
        if p.m.format == Format::Parquet {
            // Batch by batch: no value goes through text (a CSV table is
            // formatted from the batches as a run formats it).
            next = merge_parquet_part(p, search, next, |first, b| {
                table.write_batch(&table_pool, b)?;
                batched.add_batch(first, b)
            })?;
            continue;
        }
        next = merge_part(p, &kinds, next, &mut rec, &mut cells, |row, rec, cells| {
            table.write_row(rec, cells)?;
            batched.add(row, cells)
        })?;
    }
    Ok(next)
}

/// Streams shard `p`'s rows (lanes from `next`) into `row`, checking
/// each; the table's SHA-256 against the manifest. Returns the next lane.
fn merge_part(
    p: &Part,
    kinds: &[(&'static str, crate::output::table::Kind)],
    mut next: u64,
    rec: &mut csv::ByteRecord,
    cells: &mut Vec<Cell>,
    mut row: impl FnMut(u64, &csv::ByteRecord, &[Cell]) -> Result<()>,
) -> Result<u64> {
    let name = p.m.format.file_name();
    let path = p.dir.join(name);
    let want = &p.m.files[name];
    let mut rd = RowReader::open(&path, p.m.format)?;
    let header: Vec<&[u8]> = rd.header().iter().collect();
    if header.len() != kinds.len() || header.iter().zip(kinds).any(|(a, b)| *a != b.0.as_bytes()) {
        return Err(Error::input(
            rd.path(),
            Some("line 1".into()),
            None,
            "its columns are not those of this tswm version's table; run the shard again",
        ));
    }
    let lane_col = kinds.iter().position(|k| k.0 == LANE).unwrap_or(0);
    while rd.read_cells(rec, kinds, cells)? {
        if cells[lane_col] != Cell::I(next) || next >= p.m.lane_end {
            return Err(Error::input(
                &path,
                Some(format!("row {}", next - p.m.lane_start + 1)),
                Some(LANE),
                format!(
                    "expected lane {next} (shard {}/{} holds lanes {}..{}); run the shard again",
                    p.m.shard, p.m.shards, p.m.lane_start, p.m.lane_end
                ),
            ));
        }
        row(next, rec, cells)?;
        next += 1;
    }
    if let Some(d) = rd.digest() {
        if d != *want {
            return Err(refused(
                &p.dir,
                &p.m,
                format!("{name} is changed: its SHA-256 is not the one the manifest records"),
            ));
        }
    }
    all_rows_read(p, name, next)
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
