//! The output folder: never mixed, torn or left half-written. A second run
//! into a held folder is refused; partial files are unique, removed on
//! failure, on SIGINT and SIGTERM, and after kill -9 by the next run; a
//! full disk at commit time leaves the old results as they were.

use std::io::Write;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

use crate::common::*;

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// A sweep of `n` paper-like lanes (a few seconds on the CPU at 200,000).
fn big_sweep(dir: &Path, n: u64) -> std::path::PathBuf {
    let p = dir.join("big.toml");
    std::fs::write(
        &p,
        format!("[[grid]]\nparam = \"f2\"\nfrom = -6000.0\nto = 6000.0\nn = {n}\n"),
    )
    .unwrap();
    p
}

#[test]
fn a_second_run_into_a_held_folder_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    std::fs::create_dir(&out).unwrap();
    // Another run holds the folder: its lock is taken.
    let lock = std::fs::File::create(out.join(".tswm.lock")).unwrap();
    lock.lock().unwrap();
    let sweep = root().join("sweeps/paper.toml");
    rejected(
        &cpu(&["run", sweep.to_str().unwrap(), "--out", "o"]),
        dir.path(),
        &["o: another tswm command is writing to this folder"],
    );
    assert_eq!(names(&out), [".tswm.lock"], "nothing written");
    drop(lock);
    run_ok(
        &cpu(&["run", sweep.to_str().unwrap(), "--out", "o"]),
        dir.path(),
    );
}

#[test]
fn two_runs_into_one_folder_never_mix() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = big_sweep(dir.path(), 100_000);
    let args = cpu(&[
        "run",
        sweep.to_str().unwrap(),
        "--out",
        "o",
        "--threads",
        "1",
    ]);
    let spawn = || {
        Command::new(env!("CARGO_BIN_EXE_tswm"))
            .args(&args)
            .current_dir(dir.path())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
    };
    let (a, b) = (spawn(), spawn());
    let (a, b) = (a.wait_with_output().unwrap(), b.wait_with_output().unwrap());
    let codes = [a.status.code(), b.status.code()];
    assert!(codes.contains(&Some(0)), "{codes:?}");
    if codes.contains(&Some(2)) {
        let refused = if a.status.code() == Some(2) { &a } else { &b };
        assert!(String::from_utf8_lossy(&refused.stderr).contains("another tswm command"));
    }
    // Whole, in lane order, and no partial file left behind.
    let (_, rows) = read_csv(&dir.path().join("o/lanes.csv"));
    assert_eq!(rows.len(), 100_000);
    assert!(names(&dir.path().join("o"))
        .iter()
        .all(|n| !n.ends_with(".partial")));
}

#[test]
fn partial_files_of_a_killed_run_are_removed_by_the_next() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    std::fs::create_dir(&out).unwrap();
    std::fs::write(out.join(".lanes.csv.4242-0.partial"), "m1,m2\n586,").unwrap();
    let sweep = root().join("sweeps/paper.toml");
    run_ok(
        &cpu(&["run", sweep.to_str().unwrap(), "--out", "o"]),
        dir.path(),
    );
    assert_eq!(names(&out), RUN_FILES);
}

/// SIGINT and SIGTERM stop a run with 128 + the signal and leave no
/// partial file; the results of an earlier run stay as they were.
#[test]
fn sigint_and_sigterm_leave_no_partial_file() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = big_sweep(dir.path(), 400_000);
    let paper = root().join("sweeps/paper.toml");
    run_ok(
        &cpu(&["run", paper.to_str().unwrap(), "--out", "o"]),
        dir.path(),
    );
    let before = std::fs::read(dir.path().join("o/lanes.csv")).unwrap();
    for (sig, name) in [(2, "INT"), (15, "TERM")] {
        let child = Command::new(env!("CARGO_BIN_EXE_tswm"))
            .args(cpu(&["run", sweep.to_str().unwrap(), "--out", "o"]))
            .current_dir(dir.path())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // Until its partial file exists: the run is streaming rows.
        let out = dir.path().join("o");
        for _ in 0..200 {
            if names(&out).iter().any(|n| n.ends_with(".partial")) {
                break;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        assert!(Command::new("kill")
            .args([&format!("-{name}"), &child.id().to_string()])
            .status()
            .unwrap()
            .success());
        let r = child.wait_with_output().unwrap();
        assert_eq!(
            r.status.code(),
            Some(128 + sig),
            "SIG{name}: {}",
            String::from_utf8_lossy(&r.stderr)
        );
        assert_eq!(names(&out), RUN_FILES, "SIG{name}");
        assert_eq!(
            std::fs::read(out.join("lanes.csv")).unwrap(),
            before,
            "SIG{name}"
        );
    }
}

/// A disk that fills while the results are committed: the run fails, the
/// earlier run's lanes.csv and sweep.resolved.toml stay together, and no
/// partial file is left. Needs root to mount a small tmpfs.
#[test]
fn a_full_disk_leaves_the_old_results_together() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    std::fs::create_dir(&out).unwrap();
    let mounted = Command::new("mount")
        .args([
            "-t",
            "tmpfs",
            "-o",
            "size=256k",
            "tmpfs",
            out.to_str().unwrap(),
        ])
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !mounted {
        let _ = writeln!(
            std::io::stderr(),
            "skipped full-disk test: cannot mount a tmpfs here (needs root)"
        );
        return;
    }
    let paper = root().join("sweeps/paper.toml");
    let run = |sweep: &Path| {
        tswm(
            &cpu(&["run", sweep.to_str().unwrap(), "--out", "o"]),
            dir.path(),
        )
    };
    let first = run(&paper);
    let old = (
        std::fs::read(out.join("lanes.csv")),
        std::fs::read(out.join("sweep.resolved.toml")),
    );
    // 5,000 lanes make about 1.3 MB: more than the disk holds.
    let r = run(&big_sweep(dir.path(), 5_000));
    let left = names(&out);
    let new = (
        std::fs::read(out.join("lanes.csv")),
        std::fs::read(out.join("sweep.resolved.toml")),
    );
    let _ = Command::new("umount").arg(&out).status();
    assert!(first.status.success());
    assert_eq!(
        r.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&r.stderr)
    );
    assert_eq!(left, RUN_FILES);
    assert_eq!(old.0.unwrap(), new.0.unwrap());
    assert_eq!(old.1.unwrap(), new.1.unwrap());
}

#[test]
fn threads_have_an_upper_bound() {
    let dir = tempfile::tempdir().unwrap();
    let paper = root().join("sweeps/paper.toml");
    let paper = paper.to_str().unwrap();
    rejected(
        &["run", paper, "--threads", "100000", "--out", "o"],
        dir.path(),
        &["--threads", "1 to 1024"],
    );
    assert!(!dir.path().join("o").exists());
    let args = cpu(&["run", paper, "--threads", "1024", "--out", "o"]);
    run_ok(&args, dir.path());
}

#[test]
fn out_naming_a_file_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("o"), "not a folder").unwrap();
    let paper = root().join("sweeps/paper.toml");
    rejected(
        &cpu(&["run", paper.to_str().unwrap(), "--out", "o"]),
        dir.path(),
        &["o: --out: exists and is not a folder"],
    );
    assert_eq!(
        std::fs::read_to_string(dir.path().join("o")).unwrap(),
        "not a folder"
    );
}
