//! The output folder of a run: locked while a command writes to it, and
//! holding one run's files alone.
//!
//! - A second command into a folder that one holds is refused (the lock
//!   on `DIR/.tswm.lock`, `output::lock`); the lock is held until a
//!   command's last file is committed (a merge's or a run's report
//!   included), so no other run slips in between.
//! - One folder holds one run: the folder's marker ([`names::MARKER`])
//!   lists the files tswm committed there, and a run refuses a folder
//!   that holds anything else (a user's own `report.html`, say), so it
//!   never replaces a file it did not write.
//! - Whoever commits files removes partial files left by a killed run.
//! - A command that is refused, fails or is stopped before it commits
//!   anything leaves the folder as it found it: a folder it created goes,
//!   and so does a lock file it created, and the folder's times are set
//!   back; someone else's files are refused before the folder is touched.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use super::atomic::{commit_together, is_partial_name, AtomicFile};
use super::lock::{Lock, Times};
use crate::error::{Error, Result};

/// The names of an output folder's files: each stated here once.
pub mod names {
    /// The results table as CSV.
    pub(crate) const LANES_CSV: &str = "lanes.csv";
    /// The results table as Parquet.
    pub(crate) const LANES_PARQUET: &str = "lanes.parquet";
    /// Statistics per group.
    pub(crate) const SUMMARY: &str = "summary.csv";
    /// Sensitivity indices per grid point (a sensitivity design).
    pub(crate) const SENSITIVITY: &str = "sensitivity.csv";
    /// Traced lanes through time.
    pub(crate) const TRACES: &str = "traces.csv";
    /// The sweep with every lane's source spelled out.
    pub(crate) const RESOLVED: &str = "sweep.resolved.toml";
    /// The report.
    pub(crate) const REPORT: &str = "report.html";
    /// A shard's manifest, written last.
    pub const MANIFEST: &str = "shard.toml";
    /// The lock file.
    pub const LOCK: &str = ".tswm.lock";
    /// The files tswm committed in the folder, one name a line.
    pub const MARKER: &str = ".tswm.files";
    /// Every file a command of tswm commits in an output folder.
    pub const RESULTS: [&str; 8] = [
        LANES_CSV,
        LANES_PARQUET,
        SUMMARY,
        SENSITIVITY,
        TRACES,
        RESOLVED,
        REPORT,
        MANIFEST,
    ];

    /// Whether tswm writes a file of this name in an output folder (under
    /// a temporary name first): a result, or the marker.
    pub fn written(name: &str) -> bool {
        RESULTS.contains(&name) || name == MARKER
    }
}

/// Name of the lock file inside an output folder.
pub(crate) const LOCK_NAME: &str = names::LOCK;

/// An output folder held by this run.
pub struct OutDir {
    path: PathBuf,
    /// The files an earlier command of tswm committed here (its marker).
    earlier: Vec<String>,
    /// Holds the lock for as long as the run lives.
    lock: Lock,
    /// Whether this run created the folder: dropped before it committed
    /// anything (refused, failed or stopped), the folder is removed again.
    fresh: bool,
    /// Whether this run committed a file here.
    committed: bool,
    /// The folder (or, for a folder this run created, the folder around
    /// it) and its access and modification times as they were: a command
    /// dropped before it committed anything puts them back, so a refusal
    /// leaves not even a changed time behind.
    times: Option<Times>,
}

impl Drop for OutDir {
    fn drop(&mut self) {
        if self.committed {
            return;
        }
        // Nothing committed: leave the folder as it was. The lock file is
        // removed while still held; a command that opened it before the
        // removal finds, once it holds it, that the name no longer leads
        // to it, and takes the lock again (`lock`).
        if self.lock.made || self.fresh {
            let _ = std::fs::remove_file(self.path.join(LOCK_NAME));
        }
        if self.fresh {
            // The folder goes if that leaves it empty.
            let _ = std::fs::remove_dir(&self.path);
        }
        if let Some(t) = &self.times {
            t.restore();
        }
    }
}

impl OutDir {
    /// Creates (if need be) and locks `path` for a run's results; removes
    /// partial files a killed run left there. Errors (exit code 2) when
    /// `path` is a file or a dangling link, another run holds the folder,
    /// or the folder holds files tswm did not write.
    pub fn open(path: &Path) -> Result<OutDir> {
        let bad = |m: String| Error::input(path, None, Some("--out"), m);
        if let Ok(meta) = std::fs::symlink_metadata(path) {
            if meta.file_type().is_symlink() && !path.exists() {
                let to = std::fs::read_link(path)
                    .map(|t| t.display().to_string())
                    .unwrap_or_default();
                return Err(bad(format!(
                    "is a symbolic link to {}, which does not exist; allowed: a folder, or a \
                     new name (the folder is created)",
                    crate::error::shown(&to, 80)
                )));
            }
        }
        if path.exists() && !path.is_dir() {
            return Err(bad(
                "exists and is not a folder; --out needs a folder (it is created if missing)"
                    .into(),
            ));
        }
        let fresh = !path.exists();
        // Someone else's files are refused before the folder is touched
        // (and again once it is held: they may have come in between).
        if !fresh {
            refuse_foreign(path, &foreign_in(path, &read_marker(path)?)?)?;
        }
        let times = Times::before(path);
        std::fs::create_dir_all(path).map_err(|e| Error::io(path, e))?;
        let mut dir = OutDir::lock(path)?;
        dir.fresh = fresh;
        dir.times = times;
        refuse_foreign(path, &dir.foreign()?)?;
        Ok(dir)
    }

    /// Locks the existing output folder `path` of an earlier run, to add
    /// files to it (`tswm report`). Errors (exit code 2) when it is not a
    /// folder or another command holds it.
    pub(crate) fn open_existing(path: &Path) -> Result<OutDir> {
        if !path.is_dir() {
            return Err(Error::input(
                path,
                None,
                None,
                "is not a folder; allowed: a folder written by `tswm run` or `tswm merge`",
            ));
        }
        let times = Times::before(path);
        let mut dir = OutDir::lock(path)?;
        dir.times = times;
        Ok(dir)
    }

    /// Takes the folder's lock ([`Lock::take`]) and reads its marker.
    fn lock(path: &Path) -> Result<OutDir> {
        let lock = Lock::take(path)?;
        let earlier = read_marker(path)?;
        Ok(OutDir {
            path: path.to_path_buf(),
            earlier,
            lock,
            fresh: false,
            committed: false,
            times: None,
        })
    }

    /// Entries of the folder that tswm did not write.
    fn foreign(&self) -> Result<Vec<String>> {
        foreign_in(&self.path, &self.earlier)
    }

    /// Whether the folder held an earlier run's results table (which this
    /// run's commit replaces).
    pub(crate) fn held_results(&self) -> bool {
        [names::LANES_CSV, names::LANES_PARQUET]
            .iter()
            .any(|n| self.earlier.iter().any(|e| e == n) && self.path.join(n).is_file())
    }

    /// Commits a run's files: every other result file of an earlier
    /// command in the folder is removed with the old results (its table
    /// in the other format, its traces, report, summary or manifest), so
    /// the folder holds this run's files alone.
    pub(crate) fn commit_run(&mut self, files: Vec<AtomicFile>) -> Result<()> {
        let new: Vec<&Path> = files.iter().map(|f| f.dest()).collect();
        let stale: Vec<PathBuf> = names::RESULTS
            .iter()
            .map(|n| self.path.join(n))
            .filter(|p| !new.contains(&p.as_path()))
            .collect();
        self.commit(files, &stale)
    }

    /// Commits files beside the folder's others (a report of its run).
    pub(crate) fn commit_more(&mut self, files: Vec<AtomicFile>) -> Result<()> {
        self.commit(files, &[])
    }

    /// Commits `files` (see [`commit_together`]) and updates the marker:
    /// before the renames it lists the earlier files and the new ones, so
    /// whatever a crash leaves is listed; after them, what is there.
    fn commit(&mut self, files: Vec<AtomicFile>, stale: &[PathBuf]) -> Result<()> {
        let mut listed = self.earlier.clone();
        for f in &files {
            let name = file_name(f.dest());
            if !listed.contains(&name) {
                listed.push(name);
            }
        }
        self.remove_stale_partials()?;
        self.fresh = false;
        self.committed = true;
        write_marker(&self.path, &listed)?;
        let stale: Vec<&Path> = stale.iter().map(|p| p.as_path()).collect();
        commit_together(files, &stale)?;
        listed.retain(|n| self.path.join(n).is_file());
        write_marker(&self.path, &listed)?;
        self.earlier = listed;
        Ok(())
    }

    /// The folder.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// A file of the folder.
    pub fn join(&self, name: &str) -> PathBuf {
        self.path.join(name)
    }

    /// Partial files of earlier runs (killed with no chance to clean up),
    /// removed when this run commits (not before: a refused command
    /// changes nothing): no run but ours holds the folder, so none of
    /// them is being written, and this run's own carry its process id.
    fn remove_stale_partials(&self) -> Result<()> {
        let ours = format!(".{}-", std::process::id());
        let entries = std::fs::read_dir(&self.path).map_err(|e| Error::io(&self.path, e))?;
        for e in entries.flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            if is_partial_name(&name, names::written) && !name.contains(&ours) {
                let _ = std::fs::remove_file(e.path());
            }
        }
        Ok(())
    }
}

/// Entries of the folder `path` that tswm did not write: anything but
/// the lock, the marker, partial files and the files `earlier` (the
/// marker) lists.
fn foreign_in(path: &Path, earlier: &[String]) -> Result<Vec<String>> {
    let entries = std::fs::read_dir(path).map_err(|e| Error::io(path, e))?;
    let mut out = Vec::new();
    for e in entries {
        let e = e.map_err(|e| Error::io(path, e))?;
        let name = e.file_name().to_string_lossy().into_owned();
        let ours = name == names::LOCK
            || name == names::MARKER
            || is_partial_name(&name, names::written)
            || (earlier.contains(&name) && e.path().is_file());
        if !ours {
            out.push(name);
        }
    }
    out.sort();
    Ok(out)
}

/// The refusal of a folder holding `foreign` files (none: accepted).
fn refuse_foreign(path: &Path, foreign: &[String]) -> Result<()> {
    if foreign.is_empty() {
        return Ok(());
    }
    let more = foreign.len().saturating_sub(5);
    let shown: Vec<String> = foreign
        .iter()
        .take(5)
        .map(|n| crate::error::shown(n, 40))
        .collect();
    Err(Error::input(
        path,
        None,
        Some("--out"),
        format!(
            "holds files tswm did not write ({}{}); allowed: a new or empty folder, or the \
             folder of an earlier tswm run (whose results a run replaces)",
            shown.join(", "),
            if more > 0 {
                format!(" and {more} more")
            } else {
                String::new()
            }
        ),
    ))
}

fn file_name(p: &Path) -> String {
    p.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// The names the folder's marker lists (none without a marker).
fn read_marker(dir: &Path) -> Result<Vec<String>> {
    let path = dir.join(names::MARKER);
    match std::fs::read_to_string(&path) {
        Ok(t) => Ok(t
            .lines()
            .filter(|l| !l.starts_with('#') && !l.is_empty())
            .map(str::to_string)
            .collect()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(Vec::new()),
        Err(e) => Err(Error::io(&path, e)),
    }
}

/// Writes the folder's marker (whole, then renamed into place).
fn write_marker(dir: &Path, listed: &[String]) -> Result<()> {
    let path = dir.join(names::MARKER);
    let mut text = String::from("# files tswm committed in this folder\n");
    for n in listed {
        text.push_str(n);
        text.push('\n');
    }
    let mut f = AtomicFile::create(&path)?;
    f.writer()
        .write_all(text.as_bytes())
        .map_err(|e| Error::io(&path, e))?;
    f.place()
}
