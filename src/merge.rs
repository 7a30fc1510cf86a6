//! `tswm merge`: the shard folders of one sweep joined into what one run
//! would have written: the table (byte-identical to an unsharded run's on
//! the same backend), `traces.csv`, `summary.csv` and
//! `sweep.resolved.toml`; `main` then writes the report from them.
//!
//! Every shard is checked before anything is written: each has its
//! manifest (written last by its run, so its presence means complete),
//! files of the recorded sizes, the same sweep hash, shard count, tool
//! version and backend kind as the others, and the lane range its index
//! gives; each index 0..N appears exactly once. The rows are then
//! streamed, one shard after the other, and checked lane by lane on the
//! way; any failure drops the partial files, so nothing is written.

use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::integrator::{Contact, Status};
use crate::lanes::Source;
use crate::lanes_file::{columns, Cell, Format, LanesWriter, RowReader};
use crate::outdir::{commit_together, AtomicFile, OutDir};
use crate::output::{time_line, CsvLines, SHARD_LINE, TIME_LINE, TRACE_COLUMNS};
use crate::params::Num;
use crate::shard::{Manifest, Shard, MANIFEST};
use crate::stats::{Grouping, Stats, NUMBER_COLUMNS};
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
}

impl Merged {
    /// The one-line summary.
    pub fn line(&self) -> String {
        format!(
            "tswm merge: {} lanes from {} shards ({:.2} s of shard runs); wrote {}",
            self.lanes,
            self.shards,
            self.seconds,
            self.table.display()
        )
    }
}

/// A shard folder with its manifest.
struct Part {
    dir: PathBuf,
    m: Manifest,
}

/// Reads and checks every shard of `dirs`; returns them in shard order.
fn check_shards(dirs: &[PathBuf]) -> Result<Vec<Part>> {
    let mut parts: Vec<Part> = Vec::with_capacity(dirs.len());
    for dir in dirs {
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
        if let Some(why) = m.incomplete(dir) {
            return Err(Error::input(
                dir,
                None,
                None,
                format!(
                    "incomplete shard {}/{}: {why}; run the shard again",
                    m.shard, m.shards
                ),
            ));
        }
        if let Some(first) = parts.first() {
            let f = &first.m;
            let foreign = |what: &str, ours: String, theirs: String| {
                Error::input(
                    dir,
                    None,
                    None,
                    format!(
                        "foreign shard: {what} {theirs}, but {} has {ours}; allowed: shards of one sweep, \
                         one split and one tool version",
                        first.dir.display()
                    ),
                )
            };
            if m.sweep_hash != f.sweep_hash {
                return Err(foreign(
                    "another sweep: hash",
                    f.sweep_hash.clone(),
                    m.sweep_hash.clone(),
                ));
            }
            if m.shards != f.shards {
                return Err(foreign(
                    "split into",
                    format!("{} shards", f.shards),
                    format!("{} shards", m.shards),
                ));
            }
            if m.version != f.version || m.tool != f.tool {
                return Err(foreign(
                    "written by",
                    format!("{} {}", f.tool, f.version),
                    format!("{} {}", m.tool, m.version),
                ));
            }
            if m.backend != f.backend {
                return Err(foreign(
                    "rows from the backend",
                    f.backend.clone(),
                    m.backend.clone(),
                ));
            }
            if m.lanes_total != f.lanes_total {
                return Err(foreign(
                    "lanes in all",
                    f.lanes_total.to_string(),
                    m.lanes_total.to_string(),
                ));
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
        if let Some(twin) = parts.iter().find(|p| p.m.shard == m.shard) {
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
        parts.push(Part {
            dir: dir.clone(),
            m,
        });
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

/// Column positions the statistics read from a row.
struct StatColumns {
    lane: usize,
    status: usize,
    contact: usize,
    numbers: Vec<usize>,
    /// Each parameter's column, by `Num` index.
    params: Vec<Option<usize>>,
}

impl StatColumns {
    fn of(header: &csv::ByteRecord) -> Option<StatColumns> {
        let pos = |n: &str| header.iter().position(|h| h == n.as_bytes());
        Some(StatColumns {
            lane: pos("lane")?,
            status: pos("status")?,
            contact: pos("contact_end")?,
            numbers: NUMBER_COLUMNS
                .iter()
                .map(|n| pos(n))
                .collect::<Option<_>>()?,
            params: Num::ALL.iter().map(|n| pos(n.name())).collect(),
        })
    }
}

fn number(rec: &csv::ByteRecord, i: usize) -> f64 {
    std::str::from_utf8(&rec[i])
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(f64::NAN)
}

/// Merges the shard folders `dirs` into `out` as `format`.
pub fn merge(dirs: &[PathBuf], out: &Path, format: Format) -> Result<Merged> {
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
    let resolved_path = first.dir.join("sweep.resolved.toml");
    let resolved =
        std::fs::read_to_string(&resolved_path).map_err(|e| Error::io(&resolved_path, e))?;
    let sweep = Sweep::parse(&resolved_path, &resolved)?;
    let source = Source::Sweep {
        sweep,
        file: resolved_path.clone(),
    };
    let out_dir = OutDir::open(out)?;
    let seconds: f64 = parts.iter().map(|p| p.m.seconds).sum();
    let total = first.m.lanes_total;

    let mut table = LanesWriter::create(out_dir.path(), format)?;
    let mut stats = Stats::create(&out_dir.join("summary.csv"), Grouping::of(&source))?;
    let want_header: Vec<&str> = columns().iter().map(|c| c.0).collect();
    let mut rec = csv::ByteRecord::new();
    let mut cells: Vec<Cell> = Vec::with_capacity(64);
    let mut next = 0u64;
    let mut values = [0.0f64; 20];
    for p in &parts {
        let mut rd = RowReader::open(&p.dir.join(p.m.format.file_name()), p.m.format)?;
        let header: Vec<&[u8]> = rd.header().iter().collect();
        if header.len() != want_header.len()
            || header
                .iter()
                .zip(&want_header)
                .any(|(a, b)| *a != b.as_bytes())
        {
            return Err(Error::input(
                rd.path(),
                Some("line 1".into()),
                None,
                "its columns are not those of this tswm version's table; run the shard again",
            ));
        }
        let cols = StatColumns::of(rd.header()).ok_or_else(|| Error::Internal("columns".into()))?;
        let path = rd.path().to_path_buf();
        while rd.read(&mut rec)? {
            let lane = std::str::from_utf8(&rec[cols.lane])
                .ok()
                .and_then(|s| s.parse::<u64>().ok());
            if lane != Some(next) || next >= p.m.lane_end {
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
            table.write_record(&rec, &mut cells)?;
            let status = Status::ALL
                .into_iter()
                .find(|s| s.name().as_bytes() == &rec[cols.status])
                .unwrap_or(Status::NonFinite);
            let contact = [Contact::Aa, Contact::Bb, Contact::Stick]
                .into_iter()
                .find(|c| c.name().as_bytes() == &rec[cols.contact])
                .unwrap_or(Contact::Aa);
            for (v, &i) in values.iter_mut().zip(&cols.numbers) {
                *v = number(&rec, i);
            }
            stats.add_values(next, status, contact, &values, |n| {
                cols.params[n as usize].map_or(f64::NAN, |i| number(&rec, i))
            })?;
            next += 1;
        }
        if next != p.m.lane_end {
            return Err(Error::input(
                &path,
                None,
                None,
                format!(
                    "incomplete shard {}/{}: {} rows, the manifest says {}; run the shard again",
                    p.m.shard,
                    p.m.shards,
                    next - p.m.lane_start,
                    p.m.rows
                ),
            ));
        }
    }

    let mut files = vec![merged_resolved(
        out_dir.path(),
        &resolved,
        parts.len(),
        seconds,
        total,
    )?];
    let traces = merge_traces(&parts, out_dir.path())?;
    let has_traces = traces.is_some();
    files.extend(traces);
    files.push(stats.finish()?);
    files.push(table.into_file()?);
    let mut stale = vec![
        out_dir.join(format.other().file_name()),
        out_dir.join("report.html"),
        out_dir.join(MANIFEST),
    ];
    if !has_traces {
        stale.push(out_dir.join("traces.csv"));
    }
    let stale: Vec<&Path> = stale.iter().map(|p| p.as_path()).collect();
    commit_together(files, &stale)?;
    Ok(Merged {
        lanes: next,
        shards: parts.len() as u64,
        seconds,
        table: out_dir.join(format.file_name()),
    })
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
    let path = out.join("sweep.resolved.toml");
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
    if parts.iter().all(|p| p.m.traces_bytes.is_none()) {
        return Ok(None);
    }
    let mut w = CsvLines::create(&out.join("traces.csv"), TRACE_COLUMNS)?;
    let mut line = String::new();
    for p in parts.iter().filter(|p| p.m.traces_bytes.is_some()) {
        let path = p.dir.join("traces.csv");
        let f = std::fs::File::open(&path).map_err(|e| Error::io(&path, e))?;
        let mut r = BufReader::new(f);
        let mut first = true;
        loop {
            line.clear();
            if r.read_line(&mut line).map_err(|e| Error::io(&path, e))? == 0 {
                break;
            }
            if std::mem::take(&mut first) {
                if line.trim_end() != TRACE_COLUMNS {
                    return Err(Error::input(
                        &path,
                        Some("line 1".into()),
                        None,
                        "not a tswm traces.csv; run the shard again",
                    ));
                }
                continue;
            }
            w.line().push_str(line.trim_end_matches('\n'));
            w.end_line()?;
        }
    }
    Ok(Some(w.into_file()))
}
