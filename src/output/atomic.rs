//! Files written under temporary names and committed together.
//!
//! - Temporary files are named `.NAME.PID-N.partial`: recognisable as
//!   partial, never shared by two runs.
//! - Temporary files are removed on an error (drop), and on SIGINT and
//!   SIGTERM (a signal thread, see [`remove_partials_on_signal`]), whose
//!   message says truthfully what was committed before the signal.
//! - [`commit_together`] syncs every file of a run before it removes the
//!   old results and renames the new ones, so `lanes.csv` never stands
//!   beside another run's `sweep.resolved.toml`.

use std::fs::File;
use std::io::{BufWriter, Write as _};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

use super::digest::{FileDigest, Hashing};
use crate::error::{Error, Result};

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

/// Whether a file name is one of our temporary names,
/// `.NAME.PID-N.partial` for a file `ours` accepts: a user's file that
/// merely looks like one (`.notes.partial`) is not ours to remove.
pub(crate) fn is_partial_name(name: &str, ours: impl Fn(&str) -> bool) -> bool {
    let Some(mid) = name
        .strip_prefix('.')
        .and_then(|n| n.strip_suffix(".partial"))
    else {
        return false;
    };
    let Some((file, tag)) = mid.rsplit_once('.') else {
        return false;
    };
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    let tagged = tag
        .split_once('-')
        .is_some_and(|(p, n)| digits(p) && digits(n));
    tagged && ours(file)
}

/// The writer of an [`AtomicFile`]: its file, hashed on the way when
/// asked (a shard's files, whose manifest records their SHA-256).
pub(crate) type FileWriter = BufWriter<Hashing<WriteBehind>>;

/// Bytes a [`WriteBehind`] lets pile up before it starts them on their
/// way to the disk.
const WRITE_BEHIND: u64 = 8 << 20;

/// A file whose bytes start on their way to the disk as they are written,
/// every `WRITE_BEHIND` bytes, without waiting for them: the commit's
/// sync then waits only for the last few, not for the whole file (the
/// sync of a 470 MB `lanes.csv` written all at once took 0.15 s after the
/// run on this project's 2-core VM).
pub struct WriteBehind {
    file: File,
    written: u64,
    started: u64,
}

impl WriteBehind {
    fn new(file: File) -> WriteBehind {
        WriteBehind {
            file,
            written: 0,
            started: 0,
        }
    }

    /// The file.
    pub fn file(&self) -> &File {
        &self.file
    }

    /// Starts the bytes written since the last start on their way to the
    /// disk (Linux: `sync_file_range`, which does not wait for them;
    /// elsewhere the commit's sync writes them all).
    fn start_writeback(&mut self) {
        #[cfg(target_os = "linux")]
        {
            use std::os::fd::AsRawFd;
            // SAFETY: a valid descriptor and a range of the file; the call
            // only starts writeback (an error leaves it to the sync).
            unsafe {
                libc::sync_file_range(
                    self.file.as_raw_fd(),
                    self.started as libc::off64_t,
                    (self.written - self.started) as libc::off64_t,
                    libc::SYNC_FILE_RANGE_WRITE,
                );
            }
        }
        self.started = self.written;
    }
}

impl std::io::Write for WriteBehind {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.file.write(buf)?;
        self.written += n as u64;
        if self.written - self.started >= WRITE_BEHIND {
            self.start_writeback();
        }
        Ok(n)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.file.flush()
    }
}

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
                    Hashing::new(WriteBehind::new(f))
                } else {
                    Hashing::unhashed(WriteBehind::new(f))
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
    pub(crate) fn dest(&self) -> &Path {
        &self.dest
    }

    /// Takes the writer, for a writer that must own it (Parquet's); give
    /// it back with [`AtomicFile::restore_writer`] before the commit.
    pub(crate) fn take_writer(&mut self) -> FileWriter {
        self.w.take().expect("writer taken twice")
    }

    /// Gives back the writer taken by [`AtomicFile::take_writer`].
    pub(crate) fn restore_writer(&mut self, w: FileWriter) {
        self.w = Some(w);
    }

    /// Flushes and syncs the temporary file (everything but the rename).
    fn sync(&mut self) -> Result<()> {
        let w = self.w.take().expect("synced twice");
        let f = w
            .into_inner()
            .map_err(|e| Error::io(&self.tmp, e.into_error()))?;
        f.get_ref()
            .file()
            .sync_all()
            .map_err(|e| Error::io(&self.tmp, e))
    }
}

impl AtomicFile {
    /// Syncs and renames the file into place on its own (the folder's
    /// marker: not one of a run's results).
    pub(super) fn place(mut self) -> Result<()> {
        self.sync()?;
        std::fs::rename(&self.tmp, &self.dest).map_err(|e| Error::io(&self.dest, e))
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

/// Waits where a test asks it to: `TSWM_TEST_PAUSE=POINT:MS` makes the
/// command sleep MS milliseconds at POINT (`before-report`: results
/// committed, report not yet written, the folder still locked). Tests
/// use it to act inside that window (a second run, a signal); nothing
/// else sets it.
pub(crate) fn pause_for_tests(point: &str) {
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

#[cfg(test)]
mod tests {
    use super::is_partial_name;

    #[test]
    fn only_our_temporary_names_are_partial() {
        let ours = |f: &str| ["lanes.csv", ".tswm.files"].contains(&f);
        assert!(is_partial_name(".lanes.csv.123-0.partial", ours));
        assert!(is_partial_name("..tswm.files.9-17.partial", ours));
        for theirs in [
            ".mine.partial",
            ".notes.partial",
            ".lanes.csv.partial",
            ".lanes.csv.x-1.partial",
            ".other.csv.1-2.partial",
            "lanes.csv.1-2.partial",
        ] {
            assert!(!is_partial_name(theirs, ours), "{theirs}");
        }
    }
}
