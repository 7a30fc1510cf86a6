//! Bad input found before anything is written: a trace step too fine,
//! a name that would break TOML, a grid parameter's typo.

use super::*;

#[test]
fn a_trace_dt_of_1e_12_is_refused_before_anything_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = root().join("sweeps/paper.toml");
    let line = rejected(
        &cpu(&[
            "run",
            sweep.to_str().unwrap(),
            "--out",
            "o",
            "--trace-dt",
            "1e-12",
        ]),
        dir.path(),
        &["trace dt", "10000000 rows", "at least"],
    );
    assert!(!dir.path().join("o").exists());
    // The interval it names fits.
    let dt = line
        .split("at least ")
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap();
    run_ok(
        &cpu(&[
            "run",
            sweep.to_str().unwrap(),
            "--out",
            "o",
            "--trace-dt",
            dt,
            "--no-report",
        ]),
        dir.path(),
    );
}

#[test]
fn a_newline_in_a_lane_table_name_cannot_write_toml() {
    let dir = tempfile::tempdir().unwrap();
    let name = "l\n[report]\ntitle = \"pwned\"\n.csv";
    std::fs::write(dir.path().join(name), "gamma_deg\n10\n").unwrap();
    run_ok(&cpu(&["run", "--lanes", name, "--out", "o"]), dir.path());
    let text = std::fs::read_to_string(dir.path().join("o/sweep.resolved.toml")).unwrap();
    assert!(!text.lines().any(|l| l.starts_with("[report]")), "{text}");
    let html = std::fs::read_to_string(dir.path().join("o/report.html")).unwrap();
    assert!(!html.contains("<h1>pwned"));
}

#[test]
fn a_grid_parameter_typo_names_its_own_line_and_a_guess() {
    let dir = tempfile::tempdir().unwrap();
    file(
        dir.path(),
        "s.toml",
        "[base]\nm1 = 600.0\n\n[[grid]]\nparam = \"gama_deg\"\nvalues = [5.0, 6.0]\n",
    );
    rejected(
        &["run", "s.toml", "--out", "o"],
        dir.path(),
        &["s.toml: line 5: gama_deg: unknown parameter (did you mean `gamma_deg`?)"],
    );
    file(dir.path(), "s.toml", "[base]\nt_ned = 3.0\n");
    rejected(
        &["run", "s.toml", "--out", "o"],
        dir.path(),
        &["line 2: t_ned: unknown parameter (did you mean `t_end`?)"],
    );
    file(
        dir.path(),
        "s.toml",
        "[[grid]]\nparm = \"m1\"\nvalues = [1.0]\n",
    );
    rejected(
        &["run", "s.toml", "--out", "o"],
        dir.path(),
        &["line 2", "unknown field `parm` (did you mean `param`?)"],
    );
}
