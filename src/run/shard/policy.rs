//! A shard's run: whether the folder already holds it, what the summary
//! line says of it, and the manifest that marks it complete.

use std::path::PathBuf;

use super::{backend_kind, source_hash, Manifest, Shard};
use crate::error::{Error, Result};
use crate::input::lanes::Source;
use crate::input::sweep::TraceSpec;
use crate::output::names::MANIFEST;
use crate::output::table::Format;
use crate::output::{AtomicFile, OutDir};
use crate::run;

/// What a shard's run starts with.
pub enum ShardStart {
    /// The shard to run.
    Run(ShardRun),
    /// The folder already holds it complete: the line that says so.
    Complete(String),
}

/// A shard this run is: which, its lanes, and its sweep's hashes.
pub struct ShardRun {
    /// Which shard.
    pub shard: Shard,
    /// Its lanes: [start, end).
    pub range: (u64, u64),
    hash: String,
    lane_table: Option<String>,
    total: u64,
}

impl ShardRun {
    /// Shard `s` of `source`'s run with the traces `trace` into `dir`; or,
    /// when the folder already holds this shard's complete result (a
    /// scheduler retries a task with the same index), the line that says
    /// so: it is kept, not computed again.
    pub fn start(
        s: Shard,
        source: &Source,
        trace: Option<&TraceSpec>,
        dir: &OutDir,
        format: Format,
    ) -> Result<ShardStart> {
        let (hash, lane_table) = source_hash(source, trace)?;
        if let Some(m) = Manifest::read(dir.path()).ok().flatten() {
            if m.sweep_hash == hash
                && (m.shard, m.shards) == (s.k, s.n)
                && m.format == format
                && m.version == env!("CARGO_PKG_VERSION")
                && m.incomplete(dir.path()).is_none()
            {
                return Ok(ShardStart::Complete(format!(
                    "tswm: shard {}/{} is already complete in {} ({} lanes, {} to {}, {}); nothing to do",
                    s.k,
                    s.n,
                    dir.path().display(),
                    m.rows,
                    m.lane_start,
                    m.lane_end.max(1) - 1,
                    m.backend_name
                )));
            }
        }
        // Anything else here is redone from scratch; the old manifest goes
        // first, so it can never stand beside new files.
        remove_if_there(&dir.join(MANIFEST))?;
        let total = source.lane_count();
        Ok(ShardStart::Run(ShardRun {
            shard: s,
            range: s.range_in(total, source.shard_unit()),
            hash,
            lane_table,
            total,
        }))
    }

    /// "; shard K/N (lanes A to B) with shard.toml", for the summary line.
    pub fn said(&self) -> String {
        format!(
            "; shard {}/{} (lanes {} to {}) with {MANIFEST}",
            self.shard.k,
            self.shard.n,
            self.range.0,
            self.range.1.max(1) - 1
        )
    }

    /// The shard's manifest over its `files` (hashed as they were
    /// written), for a run on `backend` summed up by `summary`.
    pub fn manifest(
        &self,
        files: &mut [AtomicFile],
        backend: &str,
        tol: f64,
        summary: &run::Summary,
        format: Format,
    ) -> Result<Manifest> {
        let mut digests = std::collections::BTreeMap::new();
        for f in files {
            let name = f
                .dest()
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            let d = f
                .digest()?
                .ok_or_else(|| Error::Internal(format!("{name} of a shard was not hashed")))?;
            digests.insert(name, d);
        }
        Ok(Manifest {
            tool: "tswm".into(),
            version: env!("CARGO_PKG_VERSION").into(),
            sweep_hash: self.hash.clone(),
            lane_table_sha256: self.lane_table.clone(),
            shard: self.shard.k,
            shards: self.shard.n,
            lane_start: self.range.0,
            lane_end: self.range.1,
            lanes_total: self.total,
            rows: summary.lanes,
            // Rows of one run come from one kind of backend at one f64
            // tolerance: a shard run with another --tol is refused.
            backend: if tol == crate::integrator::DEFAULT_TOL {
                backend_kind(backend).into()
            } else {
                format!("{}, f64 tol {tol:e}", backend_kind(backend))
            },
            backend_name: backend.to_string(),
            format,
            seconds: summary.seconds,
            files: digests,
        })
    }
}

/// Removes `path` unless it is not there.
fn remove_if_there(path: &PathBuf) -> Result<()> {
    match std::fs::remove_file(path) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(Error::io(path, e)),
    }
}
