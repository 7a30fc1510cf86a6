//! Answers a user can trust: the report of any folder tswm can write (and
//! of one that was tampered with) is a page or one error line, never a
//! panic or a hang; undecided lanes are said to be undecided; folders do
//! not mix; shards are verified. One test per defect found by probing.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::common::*;

/// Runs the sweep `text` on the CPU into `dir/o` and returns the report.
fn report_of(dir: &Path, text: &str) -> String {
    file(dir, "s.toml", text);
    run_ok(&cpu(&["run", "s.toml", "--out", "o"]), dir);
    std::fs::read_to_string(dir.join("o/report.html")).unwrap()
}

/// `tswm report o` in `dir`, killed after `secs`: its output.
fn report_within(dir: &Path, secs: u64) -> std::process::Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_tswm"))
        .args(["report", "o"])
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(secs) {
            let _ = child.kill();
            panic!("tswm report did not finish in {secs} s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// Replaces the cell of `column` in data row `row` (0-based) of
/// `dir/o/lanes.csv` with `value`.
fn set_cell(dir: &Path, row: usize, column: &str, value: &str) {
    let p = dir.join("o/lanes.csv");
    let text = std::fs::read_to_string(&p).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let i = lines[0].split(',').position(|h| h == column).unwrap();
    let mut cells: Vec<String> = lines[row + 1].split(',').map(str::to_string).collect();
    cells[i] = value.to_string();
    lines[row + 1] = cells.join(",");
    std::fs::write(&p, lines.join("\n") + "\n").unwrap();
}

const SMALL: &str = "[base]\nt_end = 0.3\n[[grid]]\nparam = \"f2\"\nvalues = [-3000.0, 3000.0]\n\
                     [[grid]]\nparam = \"gamma_deg\"\nvalues = [5.0, 10.0]\n";

#[test]
fn a_2x2_coulomb_grid_over_f2_and_m1_gets_its_report() {
    let dir = tempfile::tempdir().unwrap();
    let html = report_of(
        dir.path(),
        "[base]\nfriction = \"coulomb\"\nmu = 0.05\nt_end = 0.5\n\
         [[grid]]\nparam = \"f2\"\nvalues = [-3000.0, 3000.0]\n\
         [[grid]]\nparam = \"m1\"\nvalues = [400.0, 800.0]\n",
    );
    assert!(html.contains("<svg") && !html.contains("figure not drawn"));
}

#[test]
fn a_grid_whose_cells_differ_by_1e_9_gets_its_report() {
    let dir = tempfile::tempdir().unwrap();
    let html = report_of(
        dir.path(),
        "[base]\nt_end = 0.3\n[[grid]]\nparam = \"f2\"\nvalues = [4774.0, 4774.000000001]\n\
         [[grid]]\nparam = \"m1\"\nvalues = [586.0, 586.000000001]\n",
    );
    assert!(html.contains("<svg") && !html.contains("figure not drawn"));
}

#[test]
fn extreme_but_allowed_parameters_get_their_report() {
    let dir = tempfile::tempdir().unwrap();
    let html = report_of(
        dir.path(),
        "[base]\nm1 = 1e9\nm2 = 1e9\nt_end = 1e5\n\
         [[grid]]\nparam = \"f2\"\nvalues = [-1000.0, 1000.0]\n\
         [[grid]]\nparam = \"gamma_deg\"\nvalues = [0.5, 85.0]\n",
    );
    assert!(html.contains("<svg") && !html.contains("figure not drawn"));
}

#[test]
fn a_cell_of_1e40_gets_a_report() {
    let dir = tempfile::tempdir().unwrap();
    report_of(dir.path(), SMALL);
    set_cell(dir.path(), 1, "w_friction", "1e40");
    set_cell(dir.path(), 2, "eta_direct", "-1e40");
    let out = report_within(dir.path(), 60);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn a_cell_of_1_7e308_does_not_hang_the_report() {
    let dir = tempfile::tempdir().unwrap();
    report_of(
        dir.path(),
        "[base]\nt_end = 0.3\n[[grid]]\nparam = \"f2\"\nvalues = [-3000.0, 0.0, 3000.0]\n",
    );
    set_cell(dir.path(), 0, "w_friction", "1.7e308");
    set_cell(dir.path(), 1, "w_friction", "-1.7e308");
    set_cell(dir.path(), 2, "eta_direct", "1.7976931348623157e308");
    let out = report_within(dir.path(), 60);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn a_lane_index_beyond_the_sweep_is_one_error_line() {
    let dir = tempfile::tempdir().unwrap();
    report_of(dir.path(), SMALL);
    set_cell(dir.path(), 3, "lane", "4000000");
    rejected(
        &["report", "o"],
        dir.path(),
        &["lanes.csv", "row 4", "lane"],
    );
}

/// The report reads only the columns it shows (a plotted result here);
/// a cell of one that is not a number is one error line. A column it does
/// not read is not parsed: the page cannot depend on it.
#[test]
fn text_in_a_number_cell_is_one_error_line() {
    let dir = tempfile::tempdir().unwrap();
    report_of(dir.path(), SMALL);
    set_cell(dir.path(), 2, "eta_direct_ss", "abc");
    rejected(
        &["report", "o"],
        dir.path(),
        &["lanes.csv", "row 3", "eta_direct_ss"],
    );
}

#[test]
fn a_table_cut_at_a_row_boundary_is_one_error_line() {
    let dir = tempfile::tempdir().unwrap();
    report_of(dir.path(), SMALL);
    let p = dir.path().join("o/lanes.csv");
    let text = std::fs::read_to_string(&p).unwrap();
    let keep: Vec<&str> = text.lines().take(3).collect();
    std::fs::write(&p, keep.join("\n") + "\n").unwrap();
    rejected(
        &["report", "o"],
        dir.path(),
        &["lanes.csv", "has 2 rows", "states 4 lanes"],
    );
}

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

/// A traced lane with 20,000 events is plotted from a bounded number of
/// points (the decimation keeps four a time slice and series), and its
/// events from one mark a slice.
#[test]
fn a_trace_with_20000_events_is_drawn_from_bounded_points() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = root().join("sweeps/paper.toml");
    run_ok(
        &cpu(&["run", sweep.to_str().unwrap(), "--out", "o"]),
        dir.path(),
    );
    // Lane 0 over its 2 s: 20,000 events (two rows each, one time) between
    // rows every 10 µs.
    let mut t = String::from("lane,t,x1,v1,a1,f1,s1,s2,psi,phi,contact\n");
    for i in 0..200_000u32 {
        let time = i as f64 * 1e-5;
        let v = (i as f64 * 0.37).sin();
        t.push_str(&format!("0,{time},0,{v},0,0,{v},{},-0.1,1,aa\n", -v));
        if i % 10 == 5 {
            t.push_str(&format!("0,{time},0,{},0,0,{v},{v},-0.2,-1,bb\n", -v));
        }
    }
    std::fs::write(dir.path().join("o/traces.csv"), t).unwrap();
    let out = report_within(dir.path(), 60);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let html = std::fs::read_to_string(dir.path().join("o/report.html")).unwrap();
    assert!(html.contains("lane 0 (220000 rows, 20000 events; decimated"));
    // Three figures of at most 4 points a slice and series, 1000 slices.
    let points = html.matches(',').count();
    assert!(
        html.len() < 3_000_000,
        "{} bytes, {points} commas",
        html.len()
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

/// The colour-coded polylines of a report section: (colour, points).
fn coloured_polylines(section: &str) -> Vec<Vec<(i64, i64)>> {
    let mut out = Vec::new();
    for part in section.split("<polyline").skip(1) {
        let tag = &part[..part.find('>').unwrap()];
        if tag.contains("stroke=\"#000000\"") {
            continue; // axes and ticks
        }
        let pts = tag.split("points=\"").nth(1).unwrap();
        let pts = &pts[..pts.find('"').unwrap()];
        out.push(
            pts.split_whitespace()
                .map(|p| {
                    let (x, y) = p.split_once(',').unwrap();
                    (x.parse().unwrap(), y.parse().unwrap())
                })
                .collect(),
        );
    }
    out
}

/// A grid axis of two loads is drawn as points with whiskers, never as a
/// line from one load to the other.
#[test]
fn a_grid_of_two_loads_is_not_drawn_as_a_trend() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = root().join("sweeps/paper.toml");
    run_ok(
        &cpu(&["run", sweep.to_str().unwrap(), "--out", "o"]),
        dir.path(),
    );
    let html = std::fs::read_to_string(dir.path().join("o/report.html")).unwrap();
    let sec = &html[html.find("Results against f2").unwrap()..html.find("<h2>Traces").unwrap()];
    assert!(sec.contains("<circle"));
    for line in coloured_polylines(sec) {
        assert!(
            line.iter().all(|p| p.0 == line[0].0),
            "a line joins points across the axis: {line:?}"
        );
    }
}

/// A single-value axis is named by its value, not a band around it.
#[test]
fn a_single_point_axis_reads_its_value() {
    let dir = tempfile::tempdir().unwrap();
    let html = report_of(
        dir.path(),
        "[base]\nt_end = 0.3\n[[grid]]\nparam = \"f2\"\nvalues = [4774.0]\n",
    );
    let sec = &html[html.find("Results against f2").unwrap()..];
    assert!(sec.contains(">\n4774\n<"), "no tick 4774");
    assert!(!sec.contains(">\n4773.5\n<") && !sec.contains(">\n4774.5\n<"));
}

#[test]
fn axes_name_the_quantity_and_its_unit() {
    let dir = tempfile::tempdir().unwrap();
    let html = report_of(
        dir.path(),
        "[base]\nt_end = 0.3\n[[grid]]\nparam = \"gamma_deg\"\nfrom = 3.0\nto = 20.0\nn = 12\n",
    );
    for want in [
        "running direct efficiency, eta_direct_ss",
        "static lock margin, lock_margin_deg (deg)",
        "lead angle, gamma_deg (deg)",
    ] {
        assert!(html.contains(want), "no `{want}`");
    }
}

#[test]
fn efficiency_maps_say_what_an_empty_or_zero_efficiency_means() {
    let dir = tempfile::tempdir().unwrap();
    let html = report_of(dir.path(), SMALL);
    assert!(html.contains("An eta_inverse of 0 means the wheel side fed friction only"));
    assert!(html.contains("eta_direct has no value where the worm side put no energy"));
}

/// Heat-map ticks sit on cell centres: the tick of grid value i is at
/// position i, where cell i is centred.
#[test]
fn heat_map_ticks_name_cell_centres() {
    use tswm::report::plots::Axis;
    let a = Axis::grid("gamma", &[2.0, 5.710593137499643, 10.0]);
    assert_eq!(
        a.ticks(),
        vec![
            (0.0, "2".to_string()),
            (1.0, "5.711".to_string()),
            (2.0, "10".to_string())
        ]
    );
}

/// Grid values along a range too long to label one by one get ticks at
/// round values, at their fractional positions (the grid's 0.1019 is no
/// tick); lists and short ranges are labelled value by value.
#[test]
fn long_grid_axes_get_round_ticks() {
    use tswm::report::plots::Axis;
    let log: Vec<f64> = (0..15)
        .map(|i| (0.01f64.ln() + (0.15f64.ln() - 0.01f64.ln()) * i as f64 / 14.0).exp())
        .collect();
    let ticks = Axis::grid("mu", &log).ticks();
    let labels: Vec<&str> = ticks.iter().map(|t| t.1.as_str()).collect();
    assert_eq!(labels, ["0.01", "0.02", "0.05", "0.1"]);
    let step = (0.15f64.ln() - 0.01f64.ln()) / 14.0;
    for (p, l) in &ticks {
        let v: f64 = l.parse().unwrap();
        assert!(
            (p - (v.ln() - 0.01f64.ln()) / step).abs() < 1e-9,
            "{l} at {p}"
        );
    }
    let lin: Vec<f64> = (0..29).map(|i| 2.0 + i as f64).collect();
    let ticks = Axis::grid("gamma", &lin).ticks();
    assert_eq!(ticks.first(), Some(&(3.0, "5".to_string())));
    assert!(ticks
        .iter()
        .all(|(p, l)| *p == l.parse::<f64>().unwrap() - 2.0));
    assert!(ticks.len() >= 2 && ticks.len() <= 8);
}

/// Shards of a small traced sweep in `dir/s0`, `dir/s1` (the format
/// given), and the arguments of their merge into `dir/m`.
fn traced_shards(dir: &Path, format: &str) {
    file(
        dir,
        "s.toml",
        "[base]\nt_end = 0.4\n[[grid]]\nparam = \"f2\"\nfrom = -5000.0\nto = 5000.0\nn = 40\n\
         [trace]\nlanes = [3, 30]\ndt = 0.01\n",
    );
    for k in 0..2 {
        let (s, o) = (format!("{k}/2"), format!("s{k}"));
        let out = tswm(
            &cpu(&[
                "run", "s.toml", "--shard", &s, "--out", &o, "--format", format,
            ]),
            dir,
        );
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

const MERGE: [&str; 6] = ["merge", "s0", "s1", "--out", "m", "--no-report"];

/// Merging is refused with one line naming the shard, and nothing is
/// written.
fn merge_refused(dir: &Path, want: &[&str]) -> String {
    let line = rejected(&MERGE, dir, want);
    assert!(!dir.join("m/lanes.csv").exists(), "a merge was written");
    line
}

/// Changes the byte at `at` of `path` to another value.
fn flip(path: &Path, at: usize, by: u8) {
    let mut b = std::fs::read(path).unwrap();
    let i = at % b.len();
    b[i] = b[i].wrapping_add(by.max(1));
    std::fs::write(path, b).unwrap();
}

#[test]
fn a_shard_with_text_in_a_number_cell_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    traced_shards(dir.path(), "csv");
    let p = dir.path().join("s1/lanes.csv");
    let text = std::fs::read_to_string(&p).unwrap();
    // Same size: one digit of a number becomes a letter.
    let at = text.lines().next().unwrap().len() + 3;
    let mut b = text.into_bytes();
    assert!(b[at].is_ascii_digit());
    b[at] = b'x';
    std::fs::write(&p, b).unwrap();
    merge_refused(
        dir.path(),
        &["s1/lanes.csv", "row 1", "not a finite number"],
    );
}

#[test]
fn a_parquet_shard_with_flipped_bytes_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    traced_shards(dir.path(), "parquet");
    let p = dir.path().join("s0/lanes.parquet");
    let n = std::fs::metadata(&p).unwrap().len() as usize;
    for i in 0..100 {
        flip(&p, 4 + (i * 7919) % (n - 8), 1);
    }
    merge_refused(
        dir.path(),
        &["s0", "shard 0/2 refused", "lanes.parquet is changed"],
    );
}

#[test]
fn an_edited_traces_csv_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    traced_shards(dir.path(), "csv");
    flip(&dir.path().join("s0/traces.csv"), 200, 1);
    merge_refused(dir.path(), &["s0", "traces.csv is changed"]);
}

#[test]
fn a_manifest_without_its_traces_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    traced_shards(dir.path(), "csv");
    let m = dir.path().join("s1/shard.toml");
    let text = std::fs::read_to_string(&m).unwrap();
    let cut: String = text
        .split("\n[files.\"traces.csv\"]")
        .next()
        .unwrap()
        .to_string();
    assert_ne!(cut, text);
    std::fs::write(&m, cut + "\n").unwrap();
    merge_refused(dir.path(), &["s1", "traces.csv"]);
}

#[test]
fn an_edited_resolved_sweep_is_refused_even_with_its_digest() {
    let dir = tempfile::tempdir().unwrap();
    traced_shards(dir.path(), "csv");
    let r = dir.path().join("s0/sweep.resolved.toml");
    let text = std::fs::read_to_string(&r).unwrap();
    let edited = text.replace("t_end = 0.4", "t_end = 0.5");
    assert_ne!(edited, text);
    std::fs::write(&r, &edited).unwrap();
    merge_refused(dir.path(), &["s0", "sweep.resolved.toml is changed"]);
    // The manifest mended to the edited file's digest: the sweep hash
    // still tells.
    let digest = tswm::output::digest::file_digest(&r).unwrap();
    let m = dir.path().join("s0/shard.toml");
    let mut man: tswm::run::shard::Manifest =
        toml::from_str(&std::fs::read_to_string(&m).unwrap()).unwrap();
    man.files.insert("sweep.resolved.toml".into(), digest);
    std::fs::write(&m, man.text()).unwrap();
    merge_refused(dir.path(), &["s0", "does not hash to the sweep hash"]);
}

/// 100 random same-size corruptions of a shard's table, traces or
/// resolved sweep: every one is refused.
#[test]
fn a_hundred_random_same_size_corruptions_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    traced_shards(dir.path(), "csv");
    let files = ["lanes.csv", "traces.csv", "sweep.resolved.toml"];
    let originals: Vec<Vec<(PathBuf, Vec<u8>)>> = (0..2)
        .map(|k| {
            files
                .iter()
                .map(|f| {
                    let p = dir.path().join(format!("s{k}/{f}"));
                    let b = std::fs::read(&p).unwrap();
                    (p, b)
                })
                .collect()
        })
        .collect();
    // A fixed generator: the same corruptions on every run.
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        x
    };
    for case in 0..100 {
        let shard = (next() % 2) as usize;
        let (path, orig) = &originals[shard][(next() % 3) as usize];
        let mut b = orig.clone();
        for _ in 0..1 + next() % 4 {
            let i = (next() % b.len() as u64) as usize;
            b[i] = b[i].wrapping_add(1 + (next() % 255) as u8);
        }
        std::fs::write(path, &b).unwrap();
        let out = tswm(&MERGE, dir.path());
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(
            out.status.code(),
            Some(2),
            "case {case}: {} merged: {err}",
            path.display()
        );
        assert!(err.contains(&format!("s{shard}")), "case {case}: {err}");
        assert!(!dir.path().join("m/lanes.csv").exists());
        std::fs::write(path, orig).unwrap();
    }
    // Mended, the shards merge.
    let out = tswm(&MERGE, dir.path());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
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

/// A list of values is drawn in ascending order, whatever the list's.
#[test]
fn a_categorical_numeric_axis_is_sorted() {
    let dir = tempfile::tempdir().unwrap();
    let html = report_of(
        dir.path(),
        "[base]\nt_end = 0.3\n[[grid]]\nparam = \"f2\"\nvalues = [4774.0, -4774.0, 0.0]\n",
    );
    let sec = &html[html.find("Results against f2").unwrap()..];
    let at = |v: &str| sec.find(&format!(">\n{v}\n<")).unwrap();
    assert!(at("-4774") < at("0") && at("0") < at("4774"));
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

/// Exclusive series (met, not met) sit on their category's tick; only
/// series that share a category are set side by side.
#[test]
fn points_of_exclusive_series_sit_on_their_ticks() {
    use tswm::report::charts::{points_chart, Series};
    use tswm::report::plots::Axis;
    let x = Axis::grid("x", &[1.0, 2.0, 3.0]);
    let y = Axis::fixed("share", 0.0, 1.0);
    let nan = (f64::NAN, f64::NAN, f64::NAN);
    let met = Series {
        name: "met",
        values: vec![(1.0, 1.0, 1.0), nan, nan],
        colour: None,
    };
    let not = Series {
        name: "not met",
        values: vec![nan, (0.2, 0.1, 0.3), (0.0, 0.0, 0.1)],
        colour: None,
    };
    let svg = points_chart(
        "t",
        &x,
        &y,
        &[met, not],
        None,
        plotters::chart::SeriesLabelPosition::UpperRight,
    )
    .unwrap();
    // The circles' x are three evenly spaced positions: the ticks.
    let cx: Vec<f64> = svg
        .split("<circle cx=\"")
        .skip(1)
        .map(|s| s.split('"').next().unwrap().parse().unwrap())
        .collect();
    let cx: Vec<f64> = cx[..3].to_vec();
    assert!(
        ((cx[1] - cx[0]) - (cx[2] - cx[1])).abs() <= 1.0,
        "points off their ticks: {cx:?}"
    );
}
