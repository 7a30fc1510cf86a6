//! Bad input: a one-line error naming the file, the line
//! or row, the parameter and what is allowed; exit code 2; nothing written.

use crate::common::cpu;
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
    args.extend(cpu(&["--out", "out"]));
    check(&args, dir.path(), want);
}

fn check(args: &[&str], dir: &Path, want: &[&str]) {
    crate::common::rejected(args, dir, want);
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
fn masses_must_be_positive_and_physical() {
    rejects(
        Some("[base]\nm1 = 0\n"),
        None,
        &["s.toml", "m1", "must be in [1e-3, 1e9] kg"],
    );
    rejects(
        None,
        Some("m2\n10275\n-5\n"),
        &["l.csv", "row 2 (line 3)", "m2", "must be in [1e-3, 1e9] kg"],
    );
    // A grid value is checked in its lane.
    rejects(
        Some("[[grid]]\nparam = \"m1\"\nvalues = [586, -1]\n"),
        None,
        &["s.toml", "lane 1", "m1", "must be in [1e-3, 1e9] kg"],
    );
}

/// The lead angle stays in a worm drive's physical range: inside (0, 90)
/// and away from where the efficiencies lose meaning (1e-9 deg gave
/// eta_end = -2e9).
#[test]
fn lead_angle_inside_its_physical_range() {
    for g in ["0", "90", "120", "-3", "1e-9", "89.9"] {
        rejects(
            Some(&format!("[base]\ngamma_deg = {g}\n")),
            None,
            &["s.toml", "gamma_deg", "must be in [0.5, 85] deg"],
        );
    }
}

/// Initial speeds beyond any drive's (1e39 m/s gave `ok` with no heat).
#[test]
fn initial_speed_inside_its_physical_range() {
    rejects(
        None,
        Some("v1_0\n1e39\n"),
        &[
            "l.csv",
            "row 1 (line 2)",
            "v1_0",
            "must be in [-100, 100] m/s",
        ],
    );
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
        &["s.toml", "t_end", "must be in (0, 1e5] s"],
    );
    rejects(
        None,
        Some("t_end\n-1\n"),
        &["l.csv", "row 1 (line 2)", "t_end", "must be in (0, 1e5] s"],
    );
}

#[test]
fn friction_parameters() {
    rejects(
        Some("[base]\nfriction = \"coulomb\"\nmu = -0.1\n"),
        None,
        &["s.toml", "mu", "must be in [0, 10]"],
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
        &["s.toml", "lane ", "m1", "must be in [1e-3, 1e9] kg"],
    );
}

#[test]
fn duplicate_key_is_named() {
    rejects(
        Some("[base]\nm1 = 586\nm1 = 600\n"),
        None,
        &["s.toml", "line 3", "m1: duplicate key"],
    );
}

#[test]
fn ragged_row_says_what_is_wrong() {
    rejects(
        None,
        Some("m1,m2\n586,10275\n586\n"),
        &[
            "l.csv",
            "row 2 (line 3)",
            "has 1 cells but the header has 2",
        ],
    );
}

#[test]
fn a_quoted_line_break_is_one_line() {
    rejects(
        None,
        Some("m1,m2\n586,\"10\n275\"\n"),
        &["l.csv", "row 1 (line 2)", "m2", "holds a line break"],
    );
}

/// `"100` used to be read as 100.
#[test]
fn an_unterminated_quote_is_refused() {
    rejects(
        None,
        Some("m1\n\"100\n"),
        &["l.csv", "line 2", "never closed"],
    );
}

fn study(seed: &str) -> String {
    format!(
        "[sampling]\nmethod = \"monte_carlo\"\nn = 3\nseed = {seed}\n\
         [[tolerance]]\nparam = \"m1\"\ndist = \"uniform\"\ntol = 1\n"
    )
}

/// Seeds are exactly those that sweep.resolved.toml can give back.
#[test]
fn seeds_outside_what_round_trips_are_named() {
    for seed in ["-1", "9223372036854775808", "18446744073709551615"] {
        rejects(
            Some(&study(seed)),
            None,
            &[
                "s.toml",
                "line 4",
                "seed: must be an integer from 0 to 9223372036854775807",
            ],
        );
    }
    rejects(
        Some(&study("1.5")),
        None,
        &[
            "s.toml",
            "line 4",
            "seed: an integer from 0 to 9223372036854775807",
        ],
    );
}

#[test]
fn the_largest_seed_round_trips_through_the_resolved_sweep() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.toml"), study("9223372036854775807")).unwrap();
    let (_, _, a) = crate::common::run_ok(&cpu(&["run", "s.toml", "--out", "o"]), dir.path());
    std::fs::copy(
        dir.path().join("o/sweep.resolved.toml"),
        dir.path().join("r.toml"),
    )
    .unwrap();
    let (_, _, b) = crate::common::run_ok(&cpu(&["run", "r.toml", "--out", "o"]), dir.path());
    assert_eq!(a, b, "the resolved sweep gives the same lanes");
    let text = std::fs::read_to_string(dir.path().join("o/sweep.resolved.toml")).unwrap();
    assert!(text.contains("seed = 9223372036854775807"), "{text}");
}

/// Grid errors point at the key, not at the [[grid]] header.
#[test]
fn grid_errors_name_the_line_of_the_key() {
    rejects(
        Some("[[grid]]\nparam = \"m1\"\nfrom = 1\nto = 2\nn = -3\n"),
        None,
        &["s.toml", "line 5", "m1", "n must be >= 1"],
    );
    rejects(
        Some("[[grid]]\nparam = \"mu\"\nfrom = 1\nto = 2\nn = 3\nscale = \"cubic\"\n[base]\nfriction = \"coulomb\"\n"),
        None,
        &["s.toml", "line 6", "scale `cubic` is unknown"],
    );
    rejects(
        Some("[[grid]]\nparam = \"m1\"\nvalues = []\n"),
        None,
        &["s.toml", "line 3", "values is empty"],
    );
}

/// With --lanes beside a sweep file, the provenance records the file's
/// [base] and [friction_table].
#[test]
fn lane_table_provenance_records_base_and_friction_table() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("s.toml"),
        "[base]\nfriction = \"table\"\nf2 = -3000\n[friction_table]\nvs = [0, 1, 4]\nmu = [0.12, 0.06, 0.04]\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("l.csv"), "gamma_deg\n10\n").unwrap();
    crate::common::run_ok(
        &cpu(&["run", "s.toml", "--lanes", "l.csv", "--out", "o"]),
        dir.path(),
    );
    let text = std::fs::read_to_string(dir.path().join("o/sweep.resolved.toml")).unwrap();
    for want in [
        "\"l.csv\" (1 rows)",
        "f2 = -3000.0",
        "friction = \"table\"",
        "mu = [0.12, 0.06, 0.04]",
    ] {
        assert!(text.contains(want), "`{want}` missing from {text}");
    }
}

#[test]
fn a_tolerance_out_of_range_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = crate::common::root().join("sweeps/paper.toml");
    for tol in ["0", "-1e-8", "1e-15", "0.01", "NaN"] {
        check(
            &cpu(&["run", sweep.to_str().unwrap(), "--out", "out", "--tol", tol]),
            dir.path(),
            &["--tol", "allowed: 1e-13 to 1e-4"],
        );
    }
}
