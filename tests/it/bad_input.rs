//! Bad input: a one-line error naming the file, the line
//! or row, the parameter and what is allowed; exit code 2; nothing written.

use crate::common::tswm;
use std::path::Path;

/// Runs `tswm run` on a sweep file (and optionally a lane table) with the
/// given text and checks the error contract; `want` must all appear.
fn rejects(sweep: Option<&str>, lanes: Option<&str>, want: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let mut args = vec!["run"];
    if let Some(t) = sweep {
        std::fs::write(dir.path().join("s.toml"), t).unwrap();
        args.push("s.toml");
    }
    if let Some(t) = lanes {
        std::fs::write(dir.path().join("l.csv"), t).unwrap();
        args.extend(["--lanes", "l.csv"]);
    }
    args.extend(["--out", "out", "--backend", "cpu"]);
    check(&args, dir.path(), want);
}

fn check(args: &[&str], dir: &Path, want: &[&str]) {
    let out = tswm(args, dir);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "args {args:?}: stderr {err}");
    assert_eq!(
        err.trim_end().lines().count(),
        1,
        "one line expected, got: {err}"
    );
    for w in want {
        assert!(err.contains(w), "`{w}` missing from: {err}");
    }
    assert!(
        !dir.join("out").exists(),
        "nothing may be written on bad input"
    );
}

#[test]
fn unknown_key_in_base() {
    rejects(
        Some("[base]\nm1 = 586\nmass = 3\n"),
        None,
        &[
            "s.toml",
            "line 3",
            "mass",
            "unknown parameter",
            "allowed: m1",
        ],
    );
}

#[test]
fn unknown_section_or_axis_key() {
    rejects(
        Some("[basis]\nm1 = 1\n"),
        None,
        &["s.toml", "line 1", "unknown field"],
    );
    rejects(
        Some("[[grid]]\nparam = \"m1\"\nvalus = [1]\n"),
        None,
        &["s.toml", "line 3", "valus"],
    );
}

#[test]
fn unknown_column_in_lane_table() {
    rejects(
        None,
        Some("m1,mass\n586,3\n"),
        &["l.csv", "line 1", "mass", "unknown column", "allowed:"],
    );
}

#[test]
fn text_where_a_number_belongs() {
    rejects(
        Some("[base]\nm1 = \"heavy\"\n"),
        None,
        &["s.toml", "line 2", "m1", "expected a number"],
    );
    rejects(
        None,
        Some("m1,f2\n586,abc\n"),
        &["l.csv", "row 1 (line 2)", "f2", "not a number"],
    );
}

#[test]
fn nan_and_infinity() {
    rejects(
        Some("[base]\nf2 = nan\n"),
        None,
        &["s.toml", "line 2", "f2", "finite"],
    );
    rejects(
        Some("[base]\nf2 = inf\n"),
        None,
        &["s.toml", "line 2", "f2", "finite"],
    );
    rejects(
        None,
        Some("m1\n586\ninf\n"),
        &["l.csv", "row 2 (line 3)", "m1", "finite"],
    );
    rejects(
        None,
        Some("m1\nNaN\n"),
        &["l.csv", "row 1 (line 2)", "m1", "finite"],
    );
}

#[test]
fn masses_must_be_positive() {
    rejects(
        Some("[base]\nm1 = 0\n"),
        None,
        &["s.toml", "m1", "must be > 0"],
    );
    rejects(
        None,
        Some("m2\n10275\n-5\n"),
        &["l.csv", "row 2 (line 3)", "m2", "must be > 0"],
    );
    // A grid value is checked in its lane.
    rejects(
        Some("[[grid]]\nparam = \"m1\"\nvalues = [586, -1]\n"),
        None,
        &["s.toml", "lane 1", "m1", "must be > 0"],
    );
}

#[test]
fn lead_angle_inside_0_90() {
    for g in ["0", "90", "120", "-3"] {
        rejects(
            Some(&format!("[base]\ngamma_deg = {g}\n")),
            None,
            &["s.toml", "gamma_deg", "(0, 90)"],
        );
    }
}

#[test]
fn motor_parameters() {
    rejects(
        Some("[base]\nv_crit = 3.4\n"),
        None,
        &["s.toml", "v_crit", "< v_sync"],
    );
    rejects(
        Some("[base]\nv_crit = 3.35\n"),
        None,
        &["s.toml", "v_crit", "< v_sync"],
    );
    rejects(
        Some("[base]\nf_crit = 0\n"),
        None,
        &["s.toml", "f_crit", "must be > 0"],
    );
    rejects(
        Some("[base]\nmotor = \"constant\"\n"),
        None,
        &["s.toml", "f1", "required"],
    );
    rejects(
        Some("[base]\nf1 = 100\n"),
        None,
        &["s.toml", "f1", "belongs to motor = constant"],
    );
}

#[test]
fn t_end_positive() {
    rejects(
        Some("[base]\nt_end = 0\n"),
        None,
        &["s.toml", "t_end", "must be > 0"],
    );
    rejects(
        None,
        Some("t_end\n-1\n"),
        &["l.csv", "row 1 (line 2)", "t_end", "must be > 0"],
    );
}

#[test]
fn friction_parameters() {
    rejects(
        Some("[base]\nfriction = \"coulomb\"\nmu = -0.1\n"),
        None,
        &["s.toml", "mu", ">= 0"],
    );
    rejects(
        Some("[base]\nfriction = \"coulomb\"\n"),
        None,
        &["s.toml", "mu", "required"],
    );
    rejects(
        Some("[base]\nmu = 0.1\n"),
        None,
        &["s.toml", "mu", "belongs to friction = coulomb"],
    );
    rejects(
        Some("[base]\nfriction = \"table\"\n"),
        None,
        &["s.toml", "friction", "[friction_table]"],
    );
    rejects(
        Some("[friction_table]\nvs = [0, 1]\nmu = [0.1]\n"),
        None,
        &["s.toml", "line 1", "friction_table", "must match"],
    );
}

#[test]
fn unknown_law_names() {
    rejects(
        Some("[base]\nmotor = \"diesel\"\n"),
        None,
        &["s.toml", "line 2", "motor", "allowed: kloss, constant"],
    );
    rejects(
        None,
        Some("friction\ngrease\n"),
        &[
            "l.csv",
            "row 1 (line 2)",
            "friction",
            "allowed: paper, coulomb, table",
        ],
    );
}

#[test]
fn lane_table_with_no_rows() {
    rejects(None, Some("m1,m2\n"), &["l.csv", "no rows"]);
}

#[test]
fn missing_files() {
    let dir = tempfile::tempdir().unwrap();
    check(
        &["run", "nope.toml", "--out", "out"],
        dir.path(),
        &["nope.toml", "cannot read"],
    );
    check(
        &["run", "--lanes", "nope.csv", "--out", "out"],
        dir.path(),
        &["nope.csv", "cannot read"],
    );
}

#[test]
fn malformed_toml_names_its_line() {
    rejects(
        Some("[base]\nm1 = 586\nm2 = = 3\n"),
        None,
        &["s.toml", "line 3"],
    );
}

#[test]
fn ragged_lane_table() {
    rejects(None, Some("m1,m2\n586,10275\n586\n"), &["l.csv", "line 3"]);
}

#[test]
fn tolerance_study_errors() {
    rejects(
        Some("[[tolerance]]\nparam = \"m1\"\ndist = \"uniform\"\ntol = 1\n"),
        None,
        &["s.toml", "line 1", "[sampling]"],
    );
    rejects(
        Some("[sampling]\nmethod = \"monte_carlo\"\nn = 10\nseed = 1\n[[tolerance]]\nparam = \"m1\"\ndist = \"gaussian\"\ntol = 1\n"),
        None,
        &["s.toml", "line 7", "gaussian"],
    );
    // A band reaching m1 <= 0 is caught in the lane that draws it.
    rejects(
        Some("[sampling]\nmethod = \"monte_carlo\"\nn = 200\nseed = 1\n[[tolerance]]\nparam = \"m1\"\ndist = \"uniform\"\ntol = 1000\n"),
        None,
        &["s.toml", "lane ", "m1", "must be > 0"],
    );
}
