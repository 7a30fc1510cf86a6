//! Answers that say what they decide: a study decides its lanes,
//! undecided lanes are said to be undecided, a requirement is stated with
//! the bound that decides it, and exact shares carry no interval.

use super::*;

/// The shipped tolerance study answers its question: every lane decided,
/// and held.
#[test]
fn the_shipped_tolerance_study_decides_every_lane() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = root().join("sweeps/tolerance.toml");
    let (out, h, rows) = run_ok(
        &cpu(&["run", sweep.to_str().unwrap(), "--out", "o"]),
        dir.path(),
    );
    assert_eq!(rows.len(), 5000);
    for r in &rows {
        assert_eq!(col(&h, r, "hold"), "held", "lane {}", col(&h, r, "lane"));
        assert_eq!(col(&h, r, "contact_end"), "stick");
        let t: f64 = col(&h, r, "t_stop").parse().unwrap();
        assert!(t > 3.0 && t < 30.0, "{t}");
    }
    let line = String::from_utf8_lossy(&out.stdout);
    assert!(
        line.contains("hold: held 5000") && !line.contains("coasting"),
        "{line}"
    );
    let html = std::fs::read_to_string(dir.path().join("o/report.html")).unwrap();
    assert!(!html.contains("still coasting"));
}

/// A run whose lanes are still coasting says so in its summary line and
/// at the top of its report.
#[test]
fn coasting_lanes_are_said_to_be_undecided() {
    let dir = tempfile::tempdir().unwrap();
    file(
        dir.path(),
        "s.toml",
        "[base]\nf2 = -4774.0\nmotor_off = 1.0\nt_end = 3.0\n[[grid]]\nparam = \"m1\"\nvalues = [500.0, 600.0]\n",
    );
    let (out, h, rows) = run_ok(&cpu(&["run", "s.toml", "--out", "o"]), dir.path());
    assert!(rows.iter().all(|r| col(&h, r, "hold") == "coasting"));
    let line = String::from_utf8_lossy(&out.stdout);
    assert!(
        line.contains("2 lanes still coasting") && line.contains("t_max = 30"),
        "{line}"
    );
    let html = std::fs::read_to_string(dir.path().join("o/report.html")).unwrap();
    let top = &html[..html.find("What was run").unwrap()];
    assert!(
        top.contains("still coasting") && top.contains("t_max"),
        "{top}"
    );
}

#[test]
fn the_self_locking_report_states_its_answer() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = root().join("sweeps/self_locking.toml");
    let (_, h, rows) = run_ok(
        &cpu(&["run", sweep.to_str().unwrap(), "--out", "o"]),
        dir.path(),
    );
    // The answer, from the rows themselves: per lead angle, the one-sided
    // 95 % Wilson lower bound of the share held, against 99 %.
    let mut largest = f64::NAN;
    for g in 0..25 {
        let lanes = &rows[g * 1000..(g + 1) * 1000];
        let k = lanes
            .iter()
            .filter(|r| col(&h, r, "hold") == "held")
            .count() as f64;
        let (n, z) = (1000.0, 1.6448536269514722);
        let p = k / n;
        let lo = (p + z * z / (2.0 * n) - z * (p * (1.0 - p) / n + z * z / (4.0 * n * n)).sqrt())
            / (1.0 + z * z / n);
        if lo >= 0.99 {
            largest = 2.0 + 0.25 * g as f64;
        }
    }
    assert!(largest > 3.0 && largest < 5.0, "{largest}");
    let html = std::fs::read_to_string(dir.path().join("o/report.html")).unwrap();
    let want = format!("largest {largest} deg");
    assert!(
        html.contains("Requirement `hold = held`") && html.contains(&want),
        "no `{want}`"
    );
}

/// The page opens with what was found and ends with what was run; its
/// lock-limit sentence names the line as drawn (atan(mu_s / cos alpha_n)).
#[test]
fn the_report_opens_with_the_results() {
    let dir = tempfile::tempdir().unwrap();
    let html = report_of(
        dir.path(),
        "[base]\nt_end = 0.3\nfriction = \"coulomb\"\nmu = 0.05\nalpha_n_deg = 20\n\
         [[grid]]\nparam = \"gamma_deg\"\nvalues = [3, 10, 20]\n\
         [[grid]]\nparam = \"mu\"\nvalues = [0.02, 0.1]\n",
    );
    let (found, outcomes, run) = (
        html.find("What was found").unwrap(),
        html.find("<h2>Outcomes").unwrap(),
        html.find("What was run").unwrap(),
    );
    assert!(
        found < outcomes && outcomes < run,
        "{found} {outcomes} {run}"
    );
    // Before the resolved sweep's dump, the first screen states results.
    assert!(html[..outcomes].contains("running direct efficiency"));
    assert!(html.contains("gamma = atan(mu_s / cos alpha_n)"));
    assert!(!html.contains("gamma = atan(mu_s))"));
}

/// Shares of lanes that are not sampled (a grid, a lane table) are exact:
/// no Wilson interval in the report or in summary.csv; a study's have one.
#[test]
fn no_interval_where_nothing_is_sampled() {
    let dir = tempfile::tempdir().unwrap();
    let html = report_of(
        dir.path(),
        "[base]\nt_end = 0.3\n[[grid]]\nparam = \"f2\"\nvalues = [-30000.0, 0.0, 4774.0]\n",
    );
    let out = &html[html.find("<h2>Outcomes").unwrap()..];
    assert!(!out.contains("Wilson"), "an interval for a grid's shares");
    let (h, rows) = read_csv(&dir.path().join("o/summary.csv"));
    for r in rows.iter().filter(|r| col(&h, r, "kind") != "number") {
        assert_eq!(col(&h, r, "ci95_low"), "", "{r:?}");
    }
    let dir = tempfile::tempdir().unwrap();
    let html = report_of(
        dir.path(),
        "[base]\nt_end = 0.3\n[sampling]\nmethod = \"monte_carlo\"\nn = 20\nseed = 1\n\
         [[tolerance]]\nparam = \"f2\"\ndist = \"uniform\"\ntol = 100.0\n",
    );
    assert!(html[html.find("<h2>Outcomes").unwrap()..].contains("95 % interval (Wilson)"));
    let (h, rows) = read_csv(&dir.path().join("o/summary.csv"));
    let drive = rows.iter().find(|r| col(&h, r, "kind") == "drive").unwrap();
    assert_ne!(col(&h, drive, "ci95_low"), "");
}

/// A requirement not met is said with the bound that decides it: the
/// upper one.
#[test]
fn not_met_quotes_the_upper_bound() {
    let dir = tempfile::tempdir().unwrap();
    let html = report_of(
        dir.path(),
        "[base]\nt_end = 0.3\n[sampling]\nmethod = \"monte_carlo\"\nn = 40\nseed = 1\n\
         [[tolerance]]\nparam = \"f2\"\ndist = \"uniform\"\ntol = 100.0\n\
         [report]\nrequire = \"contact_end = stick\"\nat_least = 0.9\n",
    );
    assert!(
        html.contains("not met (0 of 40 lanes, 0.00 %; upper bound"),
        "no upper bound"
    );
}
