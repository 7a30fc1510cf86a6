//! Faults and odd inputs a prober found, each with the behaviour the
//! project promises: one `tswm: error:` line naming the file, the place,
//! the parameter and what is allowed, exit code 2, nothing written; and
//! a user's own file never taken for one of ours.

use crate::common::*;

/// A file of the user's whose name merely looks like a temporary one of
/// ours stays where it is: the folder holds a file tswm did not write,
/// so the run is refused.
#[test]
fn a_users_partial_looking_file_is_not_deleted() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("o")).unwrap();
    file(&dir.path().join("o"), ".mine.partial", "my notes");
    let sweep = root().join("sweeps/paper.toml");
    rejected(
        &cpu(&["run", sweep.to_str().unwrap(), "--out", "o"]),
        dir.path(),
        &["o", ".mine.partial"],
    );
    assert_eq!(
        std::fs::read_to_string(dir.path().join("o/.mine.partial")).unwrap(),
        "my notes"
    );
}

/// A path with a newline or an escape sequence reaches the terminal
/// escaped, on one line.
#[test]
fn paths_in_errors_are_one_escaped_line() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["a\nb.toml", "c\u{1b}[31md.toml"] {
        let out = tswm(&["run", name, "--out", "o"], dir.path());
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err:?}");
        assert!(!err.contains('\u{1b}'), "{err:?}");
        assert!(err.starts_with("tswm: error: "), "{err:?}");
    }
}

/// A sweep too large for one run is refused at once, with its size and
/// the shards that fit, before anything is checked or written.
#[test]
fn a_sweep_too_large_for_one_run_is_refused_with_the_shards_that_fit() {
    let dir = tempfile::tempdir().unwrap();
    file(
        dir.path(),
        "s.toml",
        "[[grid]]\nparam = \"f2\"\nfrom = -5000.0\nto = 5000.0\nn = 1000000\n\
         [[grid]]\nparam = \"gamma_deg\"\nfrom = 2.0\nto = 30.0\nn = 1000000\n",
    );
    rejected(
        &cpu(&["run", "s.toml", "--out", "o"]),
        dir.path(),
        &[
            "s.toml",
            "1000000000000 lanes",
            "at least 1000 parts",
            "as 1000 shards",
            "--shard K/1000",
        ],
    );
    assert!(!dir.path().join("o").exists());
    // A Sobol' design of 2^30 base samples over 6 inputs, likewise.
    file(
        dir.path(),
        "d.toml",
        "[sensitivity]\nmethod = \"sobol\"\nn = 1073741824\nseed = 1\n\
         [[tolerance]]\nparam = \"gamma_deg\"\ndist = \"uniform\"\ntol = 0.1\n\
         [[tolerance]]\nparam = \"f2\"\ndist = \"uniform\"\ntol = 10.0\n\
         [[tolerance]]\nparam = \"m1\"\ndist = \"uniform\"\ntol = 1.0\n\
         [[tolerance]]\nparam = \"m2\"\ndist = \"uniform\"\ntol = 1.0\n\
         [[tolerance]]\nparam = \"fric_c\"\ndist = \"uniform\"\ntol = 0.01\n\
         [[tolerance]]\nparam = \"fric_a\"\ndist = \"uniform\"\ntol = 0.01\n",
    );
    rejected(
        &cpu(&["run", "d.toml", "--out", "o"]),
        dir.path(),
        &["d.toml", "8589934592 lanes", "shards"],
    );
}

/// A value of the wrong type names its key and what it must be.
#[test]
fn a_value_of_the_wrong_type_names_its_key() {
    let dir = tempfile::tempdir().unwrap();
    file(
        dir.path(),
        "s.toml",
        "[[grid]]\nparam = \"f2\"\nfrom = 1.0\nto = 2.0\nn = 2.5\n",
    );
    rejected(
        &cpu(&["run", "s.toml", "--out", "o"]),
        dir.path(),
        &["s.toml", "line 5", "n: must be a whole number", "2.5"],
    );
}

/// Command-line usage errors are one `tswm: error:` line, exit code 2.
#[test]
fn usage_errors_are_one_line_with_exit_code_2() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = root().join("sweeps/paper.toml");
    let s = sweep.to_str().unwrap();
    for (args, want) in [
        (vec!["run", s, "--threads", "abc"], "--threads"),
        (vec!["run", s, "--shard", "-1/2"], "--shard"),
        (vec!["run", s, "--format", "xlsx"], "csv, parquet"),
        (vec!["run", s, "--out", ""], "--out"),
        (vec!["merge"], "--out"),
        (vec!["run", s, "--trace", "abc"], "--trace"),
        (vec!["frobnicate"], "frobnicate"),
    ] {
        let line = rejected(&args, dir.path(), &[want]);
        assert!(line.starts_with("tswm: error: "), "{args:?}: {line}");
    }
    assert!(!dir.path().join("out").exists());
}

/// Bytes that are not UTF-8 in a sweep file are named by their line.
#[test]
fn a_sweep_file_that_is_not_utf8_names_the_line() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.toml"), b"[base]\nf2 = 1.0\n# caf\xe9\n").unwrap();
    rejected(
        &cpu(&["run", "s.toml", "--out", "o"]),
        dir.path(),
        &["s.toml", "line 3", "not UTF-8"],
    );
}

/// An unknown word on a friction_table axis is reported at its own line.
#[test]
fn an_unknown_table_on_an_axis_is_reported_at_its_line() {
    let dir = tempfile::tempdir().unwrap();
    file(
        dir.path(),
        "s.toml",
        "[base]\nfriction = \"table\"\n[[grid]]\nparam = \"friction_table\"\nvalues = [\"a\",\n  \"zz\"]\n\
         [friction_table.a]\nvs = [0.0, 1.0]\nmu = [0.1, 0.1]\n",
    );
    rejected(
        &cpu(&["run", "s.toml", "--out", "o"]),
        dir.path(),
        &["s.toml", "line 6", "friction_table", "`zz`", "allowed: a"],
    );
}

/// A folder given as a lane table or a sweep file is bad input (exit 2).
#[test]
fn a_folder_as_lane_table_or_sweep_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("f")).unwrap();
    rejected(
        &cpu(&["run", "--lanes", "f", "--out", "o"]),
        dir.path(),
        &["f", "is a folder"],
    );
    rejected(
        &cpu(&["run", "f", "--out", "o"]),
        dir.path(),
        &["f", "is a folder"],
    );
}

/// One lane is "1 lane", in the summary line and the report.
#[test]
fn one_lane_is_one_lane() {
    let dir = tempfile::tempdir().unwrap();
    file(dir.path(), "s.toml", "[base]\nt_end = 0.2\n");
    let (out, _, _) = run_ok(&cpu(&["run", "s.toml", "--out", "o"]), dir.path());
    let line = String::from_utf8_lossy(&out.stdout);
    assert!(line.contains("tswm: 1 lane in"), "{line}");
    let html = std::fs::read_to_string(dir.path().join("o/report.html")).unwrap();
    // "1 lanes", not "21 lanes" or "451 lanes/s".
    let one = html
        .match_indices("1 lanes")
        .any(|(i, _)| !html[..i].ends_with(|c: char| c.is_ascii_digit() || c == '.'));
    assert!(!one, "`1 lanes` in the report");
}
