//! The output folder of a run: locked while a run writes to it, files
//! written under temporary names unique to the run and renamed only when
//! complete, and the files of one run committed together.
//!
//! - A second run into a folder that a run holds is refused (the lock is
//!   an OS file lock on `DIR/.tswm.lock`, released by the OS when the
//!   process ends however it ends, so kill -9 leaves no stale lock).
//! - Temporary files are named `.NAME.PID-N.partial`: recognisable as
//!   partial, never shared by two runs. Whoever holds the lock removes
//!   partial files left by a killed run.
//! - Temporary files are removed on an error (drop), and on SIGINT and
//!   SIGTERM (a signal thread, see [`remove_partials_on_signal`]).
//! - [`OutDir::commit`] syncs every file of a run before it removes the
//!   old results and renames the new ones, so `lanes.csv` never stands
//!   beside another run's `sweep.resolved.toml`.
//! - One folder holds one run: the folder's marker ([`names::MARKER`])
//!   lists the files tswm committed there, and a run refuses a folder
//!   that holds anything else (a user's own `report.html`, say), so it
//!   never replaces a file it did not write.
//! - The lock is held until a command's last file is committed (a merge's
//!   or a run's report included), so no other run slips in between.

use std::fs::{File, TryLockError};
use std::io::{BufWriter, Write as _};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

use crate::error::{Error, Result};
use crate::shard::{FileDigest, Hashing};

/// The names of an output folder's files: each stated here once.
pub mod names {
    /// The results table as CSV.
    pub const LANES_CSV: &str = "lanes.csv";
    /// The results table as Parquet.
    pub const LANES_PARQUET: &str = "lanes.parquet";
    /// Statistics per group.
    pub const SUMMARY: &str = "summary.csv";
    /// Traced lanes through time.
    pub const TRACES: &str = "traces.csv";
    /// The sweep with every lane's source spelled out.
    pub const RESOLVED: &str = "sweep.resolved.toml";
    /// The report.
    pub const REPORT: &str = "report.html";
    /// A shard's manifest, written last.
    pub const MANIFEST: &str = "shard.toml";
    /// The lock file.
    pub const LOCK: &str = ".tswm.lock";
    /// The files tswm committed in the folder, one name a line.
    pub const MARKER: &str = ".tswm.files";
    /// Every file a command of tswm commits in an output folder.
    pub const RESULTS: [&str; 7] = [
        LANES_CSV,
        LANES_PARQUET,
        SUMMARY,
        TRACES,
        RESOLVED,
        REPORT,
        MANIFEST,
    ];
}

/// Name of the lock file inside an output folder.
pub const LOCK_NAME: &str = names::LOCK;

/// Temporary files of this process not yet committed or removed.
static PARTIALS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Files this process has committed, for the message after a signal.
static COMMITTED: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Held while files are renamed into place, so a signal's message (which
/// waits for it) says truthfully what was committed.
static COMMITTING: Mutex<()> = Mutex::new(());

fn register(p: &Path) {
    PARTIALS
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .push(p.to_path_buf());
}

fn unregister(p: &Path) {
    PARTIALS
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .retain(|q| q != p);
}

/// Starts a thread that, on SIGINT or SIGTERM, removes this process's
/// temporary files and exits with 128 + the signal's number.
pub fn remove_partials_on_signal() -> Result<()> {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM])
        .map_err(|e| Error::Internal(format!("cannot install signal handlers: {e}")))?;
    std::thread::spawn(move || {
        if let Some(sig) = signals.forever().next() {
            // Wait for a commit in progress to finish: its files are then
            // all in place, and the message below says so.
            let _commit = COMMITTING.lock().unwrap_or_else(|e| e.into_inner());
            let list = PARTIALS.lock().unwrap_or_else(|e| e.into_inner());
            for p in list.iter() {
                let _ = std::fs::remove_file(p);
            }
            let done = COMMITTED.lock().unwrap_or_else(|e| e.into_inner());
            eprintln!("tswm: stopped by signal {sig}; {}", committed_text(&done));
            std::process::exit(128 + sig);
        }
    });
    Ok(())
}

/// What a signal's message says was committed before it.
fn committed_text(done: &[PathBuf]) -> String {
    if done.is_empty() {
        return "nothing was committed".into();
    }
    let list: Vec<String> = done.iter().map(|p| p.display().to_string()).collect();
    format!(
        "committed before it: {}; nothing else was written",
        list.join(", ")
    )
}

/// An output folder held by this run.
pub struct OutDir {
    path: PathBuf,
    /// The files an earlier command of tswm committed here (its marker).
    earlier: Vec<String>,
    /// Holds the lock for as long as the run lives.
    _lock: File,
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
        std::fs::create_dir_all(path).map_err(|e| Error::io(path, e))?;
        let dir = OutDir::lock(path)?;
        let foreign = dir.foreign()?;
        if !foreign.is_empty() {
            let more = foreign.len().saturating_sub(5);
            let shown: Vec<String> = foreign
                .iter()
                .take(5)
                .map(|n| crate::error::shown(n, 40))
                .collect();
            return Err(bad(format!(
                "holds files tswm did not write ({}{}); allowed: a new or empty folder, or the \
                 folder of an earlier tswm run (whose results a run replaces)",
                shown.join(", "),
                if more > 0 {
                    format!(" and {more} more")
                } else {
                    String::new()
                }
            )));
        }
        dir.remove_stale_partials()?;
        Ok(dir)
    }

    /// Locks the existing output folder `path` of an earlier run, to add
    /// files to it (`tswm report`). Errors (exit code 2) when it is not a
    /// folder or another command holds it.
    pub fn open_existing(path: &Path) -> Result<OutDir> {
        if !path.is_dir() {
            return Err(Error::input(
                path,
                None,
                None,
                "is not a folder; allowed: a folder written by `tswm run` or `tswm merge`",
            ));
        }
        let dir = OutDir::lock(path)?;
        dir.remove_stale_partials()?;
        Ok(dir)
    }

    fn lock(path: &Path) -> Result<OutDir> {
        let lock_path = path.join(LOCK_NAME);
        let lock = File::options()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&lock_path)
            .map_err(|e| Error::io(&lock_path, e))?;
        match lock.try_lock() {
            Ok(()) => {}
            Err(TryLockError::WouldBlock) => return Err(Error::input(
                path,
                None,
                None,
                "another tswm command is writing to this folder; wait for it or choose another folder",
            )),
            Err(TryLockError::Error(e)) => return Err(Error::io(&lock_path, e)),
        }
        let earlier = read_marker(path)?;
        Ok(OutDir {
            path: path.to_path_buf(),
            earlier,
            _lock: lock,
        })
    }

    /// Entries of the folder that tswm did not write: anything but the
    /// lock, the marker, partial files and the files the marker lists.
    fn foreign(&self) -> Result<Vec<String>> {
        let entries = std::fs::read_dir(&self.path).map_err(|e| Error::io(&self.path, e))?;
        let mut out = Vec::new();
        for e in entries {
            let e = e.map_err(|e| Error::io(&self.path, e))?;
            let name = e.file_name().to_string_lossy().into_owned();
            let ours = name == names::LOCK
                || name == names::MARKER
                || is_partial_name(&name)
                || (self.earlier.contains(&name) && e.path().is_file());
            if !ours {
                out.push(name);
            }
        }
        out.sort();
        Ok(out)
    }

    /// Whether the folder held an earlier run's results table (which this
    /// run's commit replaces).
    pub fn held_results(&self) -> bool {
        [names::LANES_CSV, names::LANES_PARQUET]
            .iter()
            .any(|n| self.earlier.iter().any(|e| e == n) && self.path.join(n).is_file())
    }

    /// Commits a run's files: every other result file of an earlier
    /// command in the folder is removed with the old results (its table
    /// in the other format, its traces, report, summary or manifest), so
    /// the folder holds this run's files alone.
    pub fn commit_run(&mut self, files: Vec<AtomicFile>) -> Result<()> {
        let new: Vec<&Path> = files.iter().map(|f| f.dest()).collect();
        let stale: Vec<PathBuf> = names::RESULTS
            .iter()
            .map(|n| self.path.join(n))
            .filter(|p| !new.contains(&p.as_path()))
            .collect();
        self.commit(files, &stale)
    }

    /// Commits files beside the folder's others (a report of its run).
    pub fn commit_more(&mut self, files: Vec<AtomicFile>) -> Result<()> {
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

    /// Partial files of earlier runs (killed with no chance to clean up):
    /// no run but ours holds the folder, so none of them is being written.
    fn remove_stale_partials(&self) -> Result<()> {
        let entries = std::fs::read_dir(&self.path).map_err(|e| Error::io(&self.path, e))?;
        for e in entries.flatten() {
            if is_partial_name(&e.file_name().to_string_lossy()) {
                let _ = std::fs::remove_file(e.path());
            }
        }
        Ok(())
    }
}

/// Whether a file name is one of our temporary names.
pub fn is_partial_name(name: &str) -> bool {
    name.starts_with('.') && name.ends_with(".partial")
}

/// The writer of an [`AtomicFile`]: its file, hashed on the way when
/// asked (a shard's files, whose manifest records their SHA-256).
pub type FileWriter = BufWriter<Hashing<File>>;

/// A file written under a temporary name unique to this run and renamed to
/// its final name by [`commit_together`]; dropped uncommitted, the
/// temporary file is removed.
pub struct AtomicFile {
    tmp: PathBuf,
    dest: PathBuf,
    w: Option<FileWriter>,
}

impl AtomicFile {
    /// Starts `dest`.
    pub fn create(dest: &Path) -> Result<AtomicFile> {
        AtomicFile::start(dest, false)
    }

    /// Starts `dest`, hashing what is written to it (see
    /// [`AtomicFile::digest`]).
    pub fn create_hashed(dest: &Path) -> Result<AtomicFile> {
        AtomicFile::start(dest, true)
    }

    fn start(dest: &Path, hashed: bool) -> Result<AtomicFile> {
        static N: AtomicU64 = AtomicU64::new(0);
        let name = dest
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let n = N.fetch_add(1, Ordering::Relaxed);
        let tmp = dest.with_file_name(format!(".{name}.{}-{n}.partial", std::process::id()));
        register(&tmp);
        let f = File::options()
            .write(true)
            .create_new(true)
            .open(&tmp)
            .map_err(|e| {
                unregister(&tmp);
                Error::io(&tmp, e)
            })?;
        Ok(AtomicFile {
            tmp,
            dest: dest.to_path_buf(),
            w: Some(BufWriter::with_capacity(
                1 << 20,
                if hashed {
                    Hashing::new(f)
                } else {
                    Hashing::unhashed(f)
                },
            )),
        })
    }

    /// The size and SHA-256 of what was written (flushes the buffer);
    /// None unless made by [`AtomicFile::create_hashed`].
    pub fn digest(&mut self) -> Result<Option<FileDigest>> {
        let (w, tmp) = (
            self.w.as_mut().expect("writer used after commit"),
            &self.tmp,
        );
        w.flush().map_err(|e| Error::io(tmp, e))?;
        Ok(w.get_ref().digest())
    }

    /// The writer.
    pub fn writer(&mut self) -> &mut FileWriter {
        self.w.as_mut().expect("writer used after commit")
    }

    /// The final name.
    pub fn dest(&self) -> &Path {
        &self.dest
    }

    /// Bytes written so far (flushes the buffer).
    pub fn flushed_len(&mut self) -> Result<u64> {
        let (w, tmp) = (
            self.w.as_mut().expect("writer used after commit"),
            &self.tmp,
        );
        w.flush().map_err(|e| Error::io(tmp, e))?;
        let len = w
            .get_ref()
            .get_ref()
            .metadata()
            .map_err(|e| Error::io(tmp, e))?
            .len();
        Ok(len)
    }

    /// Takes the writer, for a writer that must own it (Parquet's); give
    /// it back with [`AtomicFile::restore_writer`] before the commit.
    pub fn take_writer(&mut self) -> FileWriter {
        self.w.take().expect("writer taken twice")
    }

    /// Gives back the writer taken by [`AtomicFile::take_writer`].
    pub fn restore_writer(&mut self, w: FileWriter) {
        self.w = Some(w);
    }

    /// Flushes and syncs the temporary file (everything but the rename).
    fn sync(&mut self) -> Result<()> {
        let w = self.w.take().expect("synced twice");
        let f = w
            .into_inner()
            .map_err(|e| Error::io(&self.tmp, e.into_error()))?;
        f.get_ref().sync_all().map_err(|e| Error::io(&self.tmp, e))
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        // Committed files have been renamed; anything else is removed.
        let _ = std::fs::remove_file(&self.tmp);
        unregister(&self.tmp);
    }
}

/// Commits the files of one run: all are flushed and synced first (a full
/// disk fails here, leaving the old results as they were); then the old
/// results under these names are removed, and the new ones renamed into
/// place in the order given. A crash between renames can leave the first
/// files without the last, never an old file beside a new one.
///
/// `stale` names files of an earlier run that this run does not write
/// (they are removed with the old results).
pub fn commit_together(mut files: Vec<AtomicFile>, stale: &[&Path]) -> Result<()> {
    for f in &mut files {
        f.sync()?;
    }
    let _commit = COMMITTING.lock().unwrap_or_else(|e| e.into_inner());
    let old = files
        .iter()
        .map(|f| f.dest.as_path())
        .chain(stale.iter().copied());
    for dest in old {
        match std::fs::remove_file(dest) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => return Err(Error::io(dest, e)),
        }
    }
    for f in &files {
        std::fs::rename(&f.tmp, &f.dest).map_err(|e| Error::io(&f.dest, e))?;
        COMMITTED
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push(f.dest.clone());
    }
    if let Some(dir) = files.first().and_then(|f| f.dest.parent()) {
        // The renames themselves reach the disk with the folder's sync.
        if let Ok(d) = File::open(dir) {
            let _ = d.sync_all();
        }
    }
    Ok(())
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
    f.sync()?;
    std::fs::rename(&f.tmp, &f.dest).map_err(|e| Error::io(&f.dest, e))
}

/// Waits where a test asks it to: `TSWM_TEST_PAUSE=POINT:MS` makes the
/// command sleep MS milliseconds at POINT (`before-report`: results
/// committed, report not yet written, the folder still locked). Tests
/// use it to act inside that window (a second run, a signal); nothing
/// else sets it.
pub fn pause_for_tests(point: &str) {
    let Some(v) = std::env::var_os("TSWM_TEST_PAUSE") else {
        return;
    };
    let ms = v
        .to_str()
        .and_then(|v| v.strip_prefix(point))
        .and_then(|r| r.strip_prefix(':'))
        .and_then(|m| m.parse::<u64>().ok());
    if let Some(ms) = ms {
        std::thread::sleep(std::time::Duration::from_millis(ms));
    }
}
