//! An output folder's lock file (`DIR/.tswm.lock`) and the folder's times:
//! what lets a command hold a folder, and leave it exactly as it found it
//! when it commits nothing.
//!
//! The lock is an OS file lock, released by the OS when the process ends
//! however it ends (kill -9 leaves no stale lock). A command that made the
//! lock file and commits nothing removes it again while still holding it;
//! a command that opened the file before that removal finds, once it holds
//! it, that the name no longer leads to it, and takes the lock again on
//! the new file, so two commands never hold one folder.

use std::fs::{File, TryLockError};
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

use super::names::LOCK;

/// A folder's lock, held.
pub(super) struct Lock {
    /// Holds the lock for as long as it lives.
    _file: File,
    /// Whether this command created the lock file.
    pub(super) made: bool,
}

impl Lock {
    /// Takes the lock of the folder `path`: the lock file, created if
    /// missing, locked, and checked to be still the file of that name once
    /// held. Another command holding it is a refusal (exit code 2).
    pub(super) fn take(path: &Path) -> Result<Lock> {
        let lock_path = path.join(LOCK);
        loop {
            let (file, made) = match File::options()
                .create_new(true)
                .write(true)
                .open(&lock_path)
            {
                Ok(f) => (f, true),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => (
                    File::options()
                        .write(true)
                        .open(&lock_path)
                        .map_err(|e| Error::io(&lock_path, e))?,
                    false,
                ),
                Err(e) => return Err(Error::io(&lock_path, e)),
            };
            match file.try_lock() {
                Ok(()) => {}
                Err(TryLockError::WouldBlock) => {
                    return Err(Error::input(
                        path,
                        None,
                        None,
                        "another tswm command is writing to this folder; wait for it or choose \
                         another folder",
                    ))
                }
                Err(TryLockError::Error(e)) => return Err(Error::io(&lock_path, e)),
            }
            if same_file(&file, &lock_path) {
                return Ok(Lock { _file: file, made });
            }
        }
    }
}

/// A folder's access and modification times as they were before a
/// command touched it: the output folder, or for a folder the command
/// creates, the folder it is made in.
pub(super) struct Times {
    dir: PathBuf,
    was: std::fs::Metadata,
}

impl Times {
    /// The times of the folder `path`, or of the folder it would be made
    /// in when it does not exist yet (None when neither can be read).
    pub(super) fn before(path: &Path) -> Option<Times> {
        let dir = if path.exists() {
            path.to_path_buf()
        } else {
            match path.parent() {
                Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
                _ => PathBuf::from("."),
            }
        };
        let was = std::fs::metadata(&dir).ok()?;
        Some(Times { dir, was })
    }

    /// Sets them back (where the file system lets the folder's owner;
    /// else they are left as they are).
    pub(super) fn restore(&self) {
        let (Ok(a), Ok(m)) = (self.was.accessed(), self.was.modified()) else {
            return;
        };
        if let Ok(f) = File::open(&self.dir) {
            let _ = f.set_times(std::fs::FileTimes::new().set_accessed(a).set_modified(m));
        }
    }
}

/// Whether the open file `f` is still the file named `path` (same device
/// and inode): a lock file removed and made again is another file.
#[cfg(unix)]
fn same_file(f: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt as _;
    match (f.metadata(), std::fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

/// Elsewhere an open file cannot be removed, so the name still leads to it.
#[cfg(not(unix))]
fn same_file(_: &File, path: &Path) -> bool {
    path.exists()
}
