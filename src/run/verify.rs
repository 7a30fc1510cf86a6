//! Shards are verified, not trusted: before a merge writes anything, each
//! shard must have its manifest (written last by its run, so its presence
//! means complete), the same sweep hash, shard count, tool version,
//! backend kind and lane count as the others, the lane range its index
//! gives, each index 0..N once, and files of the sizes and SHA-256 the
//! manifest records; its `sweep.resolved.toml` must hash to the sweep
//! hash, and `traces.csv` must be there exactly when a traced lane falls
//! in the shard. (A table's SHA-256 is checked as the merge reads it.)

use std::path::{Path, PathBuf};

use super::shard::{sweep_hash, Manifest, Shard, MANIFEST};
use crate::error::{Error, Result};
use crate::output::names::{RESOLVED, TRACES};

/// A shard folder with its manifest.
pub(super) struct Part {
    pub(super) dir: PathBuf,
    pub(super) m: Manifest,
    /// The lanes its range is a whole number of (a share search's groups).
    pub(super) unit: u64,
}

/// A shard refused: the shard's folder, and why.
pub(super) fn refused(dir: &Path, m: &Manifest, why: String) -> Error {
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

/// Shard `p`'s `name` read to its end at lane `next`: `next`, or the
/// refusal when that is not the manifest's end.
pub(super) fn all_rows_read(p: &Part, name: &str, next: u64) -> Result<u64> {
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
    let unit = check_resolved_and_traces(dir, &m)?;
    Ok(Part {
        dir: dir.to_path_buf(),
        m,
        unit,
    })
}

/// A shard's `sweep.resolved.toml` hashes to its sweep hash, and its
/// `traces.csv` is there exactly when a traced lane falls in it; the
/// lanes its range is a whole number of.
fn check_resolved_and_traces(dir: &Path, m: &Manifest) -> Result<u64> {
    let path = dir.join(RESOLVED);
    let text = std::fs::read_to_string(&path)
        .map_err(|e| refused(dir, m, format!("{RESOLVED} cannot be read: {e}")))?;
    let body = resolved_body(&text);
    if sweep_hash(body, m.lane_table_sha256.as_deref()) != m.sweep_hash {
        return Err(refused(
            dir,
            m,
            format!("its {RESOLVED} does not hash to the sweep hash its manifest records"),
        ));
    }
    let (sweep, _) = crate::output::provenance::read_resolved(&path, &text)?;
    let traced = sweep.trace.as_ref().is_some_and(|t| {
        t.lanes
            .iter()
            .any(|l| (m.lane_start..m.lane_end).contains(l))
    });
    match (traced, m.files.contains_key(TRACES)) {
        (true, false) => {
            return Err(refused(
                dir,
                m,
                format!("a traced lane falls in it but {MANIFEST} covers no {TRACES}"),
            ))
        }
        (false, true) => {
            return Err(refused(
                dir,
                m,
                format!("{MANIFEST} covers {TRACES} but no traced lane falls in it"),
            ))
        }
        _ => {}
    }
    if !m.files.contains_key(TRACES) && dir.join(TRACES).exists() {
        return Err(refused(
            dir,
            m,
            format!("{TRACES} is there but {MANIFEST} does not cover it"),
        ));
    }
    let unit = match (&sweep.search, &sweep.study) {
        (Some(s), Some(st)) if s.at_least.is_some() => st.n.max(1),
        _ => 1,
    };
    Ok(unit)
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
pub(super) fn check_shards(dirs: &[PathBuf]) -> Result<Vec<Part>> {
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
            || want.range_in(m.lanes_total, p.unit) != (m.lane_start, m.lane_end)
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
