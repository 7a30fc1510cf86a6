//! `tswm merge`: the shard folders of one sweep joined into what one run
//! would have written: the table (byte-identical to an unsharded run's on
//! the same backend), `traces.csv`, `summary.csv`,
//! `sweep.resolved.toml` and the report.
//!
//! Shards are verified, not trusted. Before anything is written, each
//! shard must have its manifest (written last by its run, so its presence
//! means complete), the same sweep hash, shard count, tool version,
//! backend kind and lane count as the others, the lane range its index
//! gives, each index 0..N once, and files of the sizes and SHA-256 the
//! manifest records; its `sweep.resolved.toml` must hash to the sweep
//! hash, and `traces.csv` must be there exactly when a traced lane falls
//! in the shard. The rows are then streamed, one shard after the other,
//! parsed cell by cell and checked lane by lane, and each table's SHA-256
//! is compared as it ends (a CSV table is hashed as it is read); any
//! failure drops the partial files, so nothing is written.

use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::lanes::Source;
use crate::lanes_file::{columns, Cell, Format, LanesWriter, RowReader};
use crate::outdir::names::{RESOLVED, SUMMARY, TRACES};
use crate::outdir::{AtomicFile, OutDir};
use crate::output::{time_line, CsvLines, SHARD_LINE, TIME_LINE, TRACE_COLUMNS};
use crate::shard::{file_digest, sweep_hash, Manifest, Shard, MANIFEST};
use crate::stats::{Grouping, Stats};
use crate::sweep::Sweep;

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

/// A shard folder with its manifest.
struct Part {
    dir: PathBuf,
    m: Manifest,
}

/// A shard refused: the shard's folder, and why.
fn refused(dir: &Path, m: &Manifest, why: String) -> Error {
    Error::input(
        dir,
        None,
        None,
        format!(
            "shard {}/{} refused: {why}; run the shard again",
            m.shard, m.shards
        ),
    )
}

/// The body of a `sweep.resolved.toml`: the text after its header
/// comments (what the sweep hash covers).
fn resolved_body(text: &str) -> &str {
    let mut at = 0;
    for line in text.split_inclusive('\n') {
        if !line.starts_with('#') {
            break;
        }
        at += line.len();
    }
    &text[at..]
}

/// Reads one shard's manifest and verifies its files, all but the table
/// (hashed while it is merged): the resolved sweep and traces by SHA-256,
/// the resolved sweep against the sweep hash, and traces.csv there
/// exactly when a traced lane falls in the shard.
fn read_part(dir: &Path) -> Result<Part> {
    if !dir.is_dir() {
        return Err(Error::input(
            dir,
            None,
            None,
            "missing shard folder: it does not exist or is not a folder; allowed: folders of `tswm run --shard K/N`",
        ));
    }
    let m = Manifest::read(dir)?.ok_or_else(|| {
        Error::input(
            dir,
            None,
            None,
            format!(
                "incomplete shard: no {MANIFEST} (its run did not finish, or this is not a shard folder); \
                 run the shard again"
            ),
        )
    })?;
    let table = m.format.file_name();
    for name in [table, RESOLVED] {
        if !m.files.contains_key(name) {
            return Err(refused(
                dir,
                &m,
                format!("{MANIFEST} does not cover {name}"),
            ));
        }
    }
    if let Some(extra) = m
        .files
        .keys()
        .find(|n| ![table, RESOLVED, TRACES].contains(&n.as_str()))
    {
        return Err(refused(
            dir,
            &m,
            format!(
                "{MANIFEST} names {}, which is no file of a shard",
                crate::error::shown(extra, 40)
            ),
        ));
    }
    for name in m.files.keys() {
        // The table's SHA-256 is checked as it is merged.
        if let Some(why) = m.file_differs(dir, name, name != table) {
            return Err(refused(dir, &m, why));
        }
    }
    let path = dir.join(RESOLVED);
    let text = std::fs::read_to_string(&path)
        .map_err(|e| refused(dir, &m, format!("{RESOLVED} cannot be read: {e}")))?;
    let body = resolved_body(&text);
    if sweep_hash(body, m.lane_table_sha256.as_deref()) != m.sweep_hash {
        return Err(refused(
            dir,
            &m,
            format!("its {RESOLVED} does not hash to the sweep hash its manifest records"),
        ));
    }
    let sweep = Sweep::parse(&path, &text)?;
    let traced = sweep.trace.as_ref().is_some_and(|t| {
        t.lanes
            .iter()
            .any(|l| (m.lane_start..m.lane_end).contains(l))
    });
    match (traced, m.files.contains_key(TRACES)) {
        (true, false) => {
            return Err(refused(
                dir,
                &m,
                format!("a traced lane falls in it but {MANIFEST} covers no {TRACES}"),
            ))
        }
        (false, true) => {
            return Err(refused(
                dir,
                &m,
                format!("{MANIFEST} covers {TRACES} but no traced lane falls in it"),
            ))
        }
        _ => {}
    }
    if !m.files.contains_key(TRACES) && dir.join(TRACES).exists() {
        return Err(refused(
            dir,
            &m,
            format!("{TRACES} is there but {MANIFEST} does not cover it"),
        ));
    }
    Ok(Part {
        dir: dir.to_path_buf(),
        m,
    })
}

/// Why shard `m` of `dir` does not belong with the first shard `f` (of
/// `first`), if it does not.
fn foreign(dir: &Path, m: &Manifest, first: &Path, f: &Manifest) -> Option<Error> {
    let differ = |what: &str, ours: String, theirs: String| {
        Some(Error::input(
            dir,
            None,
            None,
            format!(
                "foreign shard: {what} {theirs}, but {} has {ours}; allowed: shards of one sweep, \
                 one split and one tool version",
                first.display()
            ),
        ))
    };
    if m.sweep_hash != f.sweep_hash {
        return differ(
            "another sweep: hash",
            f.sweep_hash.clone(),
            m.sweep_hash.clone(),
        );
    }
    if m.shards != f.shards {
        return differ(
            "split into",
            format!("{} shards", f.shards),
            format!("{} shards", m.shards),
        );
    }
    if m.version != f.version || m.tool != f.tool {
        return differ(
            "written by",
            format!("{} {}", f.tool, f.version),
            format!("{} {}", m.tool, m.version),
        );
    }
    if m.backend != f.backend {
        return differ(
            "rows from the backend",
            f.backend.clone(),
            m.backend.clone(),
        );
    }
    if m.lanes_total != f.lanes_total {
        return differ(
            "lanes in all",
            f.lanes_total.to_string(),
            m.lanes_total.to_string(),
        );
    }
    None
}

/// Reads and checks every shard of `dirs`; returns them in shard order.
fn check_shards(dirs: &[PathBuf]) -> Result<Vec<Part>> {
    let mut parts: Vec<Part> = Vec::with_capacity(dirs.len());
    for dir in dirs {
        let p = read_part(dir)?;
        let m = &p.m;
        if let Some(first) = parts.first() {
            if let Some(e) = foreign(dir, m, &first.dir, &first.m) {
                return Err(e);
            }
        }
        let want = Shard {
            k: m.shard,
            n: m.shards,
        };
        if m.shard >= m.shards
            || want.range(m.lanes_total) != (m.lane_start, m.lane_end)
            || m.rows != m.lane_end - m.lane_start
        {
            return Err(Error::input(
                &dir.join(MANIFEST),
                None,
                None,
                format!(
                    "shard {}/{} records lanes {}..{} and {} rows, which its index does not give; \
                     run the shard again",
                    m.shard, m.shards, m.lane_start, m.lane_end, m.rows
                ),
            ));
        }
        if let Some(twin) = parts.iter().find(|q| q.m.shard == m.shard) {
            return Err(Error::input(
                dir,
                None,
                None,
                format!(
                    "doubled shard: shard {}/{} is also {}; give each shard once",
                    m.shard,
                    m.shards,
                    twin.dir.display()
                ),
            ));
        }
        parts.push(p);
    }
    let n = parts.first().map_or(0, |p| p.m.shards);
    let mut missing: Vec<String> = (0..n)
        .filter(|k| !parts.iter().any(|p| p.m.shard == *k))
        .map(|k| format!("{k}/{n}"))
        .collect();
    if !missing.is_empty() {
        let more = missing.len().saturating_sub(10);
        missing.truncate(10);
        return Err(Error::Usage(format!(
            "merge: missing shard {}{} of the sweep {} (lanes {} in all); give every shard's folder once",
            missing.join(", "),
            if more > 0 { format!(" and {more} more") } else { String::new() },
            parts[0].m.sweep_hash,
            parts[0].m.lanes_total
        )));
    }
    parts.sort_by_key(|p| p.m.shard);
    Ok(parts)
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
    let sweep = Sweep::parse(&resolved_path, &resolved)?;
    let source = Source::Sweep {
        sweep,
        file: resolved_path.clone(),
    };
    let mut out_dir = OutDir::open(out)?;
    let replaced = out_dir.held_results();
    let seconds: f64 = parts.iter().map(|p| p.m.seconds).sum();
    let total = first.m.lanes_total;

    let mut table = LanesWriter::create(out_dir.path(), format, false)?;
    let mut stats = Stats::create(&out_dir.join(SUMMARY), Grouping::of(&source))?;
    let kinds = columns();
    let mut rec = csv::ByteRecord::new();
    let mut cells: Vec<Cell> = Vec::with_capacity(kinds.len());
    let mut next = 0u64;
    for p in &parts {
        next = merge_part(p, &kinds, next, &mut rec, &mut cells, |row, rec, cells| {
            table.write_row(rec, cells)?;
            stats.add_row(row, cells)
        })?;
    }

    let mut files = vec![merged_resolved(
        out_dir.path(),
        &resolved,
        parts.len(),
        seconds,
        total,
    )?];
    files.extend(merge_traces(&parts, out_dir.path())?);
    files.push(stats.finish()?);
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

/// Streams shard `p`'s rows (lanes from `next`) into `row`, checking
/// each; the table's SHA-256 against the manifest. Returns the next lane.
fn merge_part(
    p: &Part,
    kinds: &[(&'static str, crate::lanes_file::Kind)],
    mut next: u64,
    rec: &mut csv::ByteRecord,
    cells: &mut Vec<Cell>,
    mut row: impl FnMut(u64, &csv::ByteRecord, &[Cell]) -> Result<()>,
) -> Result<u64> {
    let name = p.m.format.file_name();
    let path = p.dir.join(name);
    let want = &p.m.files[name];
    if p.m.format == Format::Parquet {
        // Read by pages, not as a stream: hashed whole first.
        if file_digest(&path)?.sha256 != want.sha256 {
            return Err(refused(
                &p.dir,
                &p.m,
                format!("{name} is changed: its SHA-256 is not the one the manifest records"),
            ));
        }
    }
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
    let lane_col = kinds.iter().position(|k| k.0 == "lane").unwrap_or(0);
    while rd.read_cells(rec, kinds, cells)? {
        if cells[lane_col] != Cell::I(next) || next >= p.m.lane_end {
            return Err(Error::input(
                &path,
                Some(format!("row {}", next - p.m.lane_start + 1)),
                Some("lane"),
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
    if next != p.m.lane_end {
        return Err(refused(
            &p.dir,
            &p.m,
            format!(
                "{name} has {} rows, the manifest says {}",
                next - p.m.lane_start,
                p.m.rows
            ),
        ));
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
