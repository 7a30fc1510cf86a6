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
//! - [`commit_together`] syncs every file of a run before it removes the
//!   old results and renames the new ones, so `lanes.csv` never stands
//!   beside another run's `sweep.resolved.toml`.

use std::fs::{File, TryLockError};
use std::io::{BufWriter, Write as _};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

use crate::error::{Error, Result};

/// Name of the lock file inside an output folder.
pub const LOCK_NAME: &str = ".tswm.lock";

/// Temporary files of this process not yet committed or removed.
static PARTIALS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

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
            let list = PARTIALS.lock().unwrap_or_else(|e| e.into_inner());
            for p in list.iter() {
                let _ = std::fs::remove_file(p);
            }
            eprintln!("tswm: stopped by signal {sig}; nothing was committed");
            std::process::exit(128 + sig);
        }
    });
    Ok(())
}

/// An output folder held by this run.
pub struct OutDir {
    path: PathBuf,
    /// Holds the lock for as long as the run lives.
    _lock: File,
}

impl OutDir {
    /// Creates (if need be) and locks `path`; removes partial files a
    /// killed run left there. Errors (exit code 2) when `path` is a file
    /// or another run holds the folder.
    pub fn open(path: &Path) -> Result<OutDir> {
        if path.exists() && !path.is_dir() {
            return Err(Error::input(
                path,
                None,
                Some("--out"),
                "exists and is not a folder; --out needs a folder (it is created if missing)",
            ));
        }
        std::fs::create_dir_all(path).map_err(|e| Error::io(path, e))?;
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
                Some("--out"),
                "another tswm run is writing to this folder; wait for it or choose another --out",
            )),
            Err(TryLockError::Error(e)) => return Err(Error::io(&lock_path, e)),
        }
        let dir = OutDir {
            path: path.to_path_buf(),
            _lock: lock,
        };
        dir.remove_stale_partials()?;
        Ok(dir)
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

/// A file written under a temporary name unique to this run and renamed to
/// its final name by [`commit_together`]; dropped uncommitted, the
/// temporary file is removed.
pub struct AtomicFile {
    tmp: PathBuf,
    dest: PathBuf,
    w: Option<BufWriter<File>>,
}

impl AtomicFile {
    /// Starts `dest`.
    pub fn create(dest: &Path) -> Result<AtomicFile> {
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
            w: Some(BufWriter::with_capacity(1 << 20, f)),
        })
    }

    /// The writer.
    pub fn writer(&mut self) -> &mut BufWriter<File> {
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
        let len = w.get_ref().metadata().map_err(|e| Error::io(tmp, e))?.len();
        Ok(len)
    }

    /// Takes the writer, for a writer that must own it (Parquet's); give
    /// it back with [`AtomicFile::restore_writer`] before the commit.
    pub fn take_writer(&mut self) -> BufWriter<File> {
        self.w.take().expect("writer taken twice")
    }

    /// Gives back the writer taken by [`AtomicFile::take_writer`].
    pub fn restore_writer(&mut self, w: BufWriter<File>) {
        self.w = Some(w);
    }

    /// Flushes and syncs the temporary file (everything but the rename).
    fn sync(&mut self) -> Result<()> {
        let w = self.w.take().expect("synced twice");
        let f = w
            .into_inner()
            .map_err(|e| Error::io(&self.tmp, e.into_error()))?;
        f.sync_all().map_err(|e| Error::io(&self.tmp, e))
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
    }
    if let Some(dir) = files.first().and_then(|f| f.dest.parent()) {
        // The renames themselves reach the disk with the folder's sync.
        if let Ok(d) = File::open(dir) {
            let _ = d.sync_all();
        }
    }
    Ok(())
}

/// Writes a whole small file under `dest` (committed on its own).
pub fn write_atomic(dest: &Path, bytes: &[u8]) -> Result<()> {
    let mut f = AtomicFile::create(dest)?;
    f.writer()
        .write_all(bytes)
        .map_err(|e| Error::io(dest, e))?;
    commit_together(vec![f], &[])
}
