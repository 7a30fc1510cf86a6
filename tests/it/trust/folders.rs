//! One folder holds one run: locks, a folder of one's own files,
//! replacing a run, a dangling symlink, and SIGTERM while the report is
//! written.

use super::*;

/// A run into the folder while a merge writes its report is refused: the
/// merge holds the folder's lock until its last file is committed.
#[test]
fn a_run_into_a_folder_during_a_merges_report_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = root().join("sweeps/paper.toml");
    let sweep = sweep.to_str().unwrap();
    for k in 0..2 {
        let (s, o) = (format!("{k}/2"), format!("s{k}"));
        let out = tswm(
            &cpu(&["run", sweep, "--shard", &s, "--out", &o]),
            dir.path(),
        );
        assert!(out.status.success());
    }
    let merge = Command::new(env!("CARGO_BIN_EXE_tswm"))
        .args(["merge", "s0", "s1", "--out", "m"])
        .env("TSWM_TEST_PAUSE", "before-report:3000")
        .current_dir(dir.path())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The merge's table is committed: its report phase has begun.
    let table = dir.path().join("m/lanes.csv");
    let start = Instant::now();
    while !table.exists() {
        assert!(start.elapsed() < Duration::from_secs(60), "no merged table");
        std::thread::sleep(Duration::from_millis(10));
    }
    rejected(
        &cpu(&["run", sweep, "--out", "m"]),
        dir.path(),
        &["m: another tswm command is writing to this folder"],
    );
    let out = merge.wait_with_output().unwrap();
    assert!(out.status.success());
    // The folder holds the merge's run alone, its report included.
    let (_, rows) = read_csv(&table);
    assert_eq!(rows.len(), 2);
    assert!(dir.path().join("m/report.html").exists());
}

#[test]
fn tswm_report_takes_the_folders_lock() {
    let dir = tempfile::tempdir().unwrap();
    report_of(dir.path(), SMALL);
    let lock = std::fs::File::options()
        .write(true)
        .open(dir.path().join("o/.tswm.lock"))
        .unwrap();
    lock.lock().unwrap();
    rejected(
        &["report", "o"],
        dir.path(),
        &["another tswm command is writing to this folder"],
    );
}

#[test]
fn a_folder_of_ones_own_files_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    std::fs::create_dir(&out).unwrap();
    std::fs::write(out.join("report.html"), "my own report").unwrap();
    file(dir.path(), "s.toml", SMALL);
    rejected(
        &cpu(&["run", "s.toml", "--out", "o"]),
        dir.path(),
        &["o: --out: holds files tswm did not write (report.html)"],
    );
    assert_eq!(
        std::fs::read_to_string(out.join("report.html")).unwrap(),
        "my own report"
    );
}

#[test]
fn replacing_an_earlier_run_is_said() {
    let dir = tempfile::tempdir().unwrap();
    file(dir.path(), "s.toml", SMALL);
    let args = cpu(&["run", "s.toml", "--out", "o"]);
    let (first, _, _) = run_ok(&args, dir.path());
    assert!(!String::from_utf8_lossy(&first.stdout).contains("replaced"));
    let (second, _, _) = run_ok(&args, dir.path());
    assert!(String::from_utf8_lossy(&second.stdout).contains("replaced the earlier run's results"));
}

#[test]
fn a_dangling_symlink_out_is_one_error_line() {
    let dir = tempfile::tempdir().unwrap();
    file(dir.path(), "s.toml", SMALL);
    std::os::unix::fs::symlink(dir.path().join("nowhere"), dir.path().join("o")).unwrap();
    rejected(
        &cpu(&["run", "s.toml", "--out", "o"]),
        dir.path(),
        &["o: --out: is a symbolic link to", "does not exist"],
    );
}

#[test]
fn sigterm_in_the_report_phase_says_what_was_committed() {
    let dir = tempfile::tempdir().unwrap();
    file(dir.path(), "s.toml", SMALL);
    let child = Command::new(env!("CARGO_BIN_EXE_tswm"))
        .args(cpu(&["run", "s.toml", "--out", "o"]))
        .env("TSWM_TEST_PAUSE", "before-report:5000")
        .current_dir(dir.path())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let table = dir.path().join("o/lanes.csv");
    let start = Instant::now();
    while !table.exists() {
        assert!(start.elapsed() < Duration::from_secs(60));
        std::thread::sleep(Duration::from_millis(10));
    }
    std::thread::sleep(Duration::from_millis(100));
    assert!(Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap()
        .success());
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(143), "{err}");
    assert!(
        !err.contains("nothing was committed") && err.contains("lanes.csv"),
        "{err}"
    );
}
