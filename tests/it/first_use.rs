//! What a new user met first (the first-use review): messages that name
//! the table and what is allowed, a grid that cannot silently drop a
//! value, a law spelled in capitals, the summary line's words, `tswm
//! check`'s table, and the estimate of a run before it.

use crate::common::{cpu, file, quiet_mesa, read_csv, rejected, skipped, tswm};

/// `[sampling]` without `seed`: the line names the table, the key and
/// what it takes (it said "line 5: missing field `seed`").
#[test]
fn a_sampling_table_without_its_seed_names_the_table_and_what_is_allowed() {
    let dir = tempfile::tempdir().unwrap();
    file(
        dir.path(),
        "s.toml",
        "[base]\nf2 = -4774.0\n\n[sampling]\nmethod = \"monte_carlo\"\nn = 10\n\n\
         [[tolerance]]\nparam = \"m1\"\ndist = \"uniform\"\ntol_rel = 0.05\n",
    );
    rejected(
        &cpu(&["run", "s.toml", "--out", "o"]),
        dir.path(),
        &["s.toml: line 4: seed:", "[sampling]", "a whole number"],
    );
    assert!(!dir.path().join("o").exists());
}

/// A grid with `n = 1` between two different ends ran `from` alone.
#[test]
fn a_grid_of_one_value_between_two_ends_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    file(
        dir.path(),
        "g.toml",
        "[[grid]]\nparam = \"gamma_deg\"\nfrom = 3.0\nto = 9.0\nn = 1\n",
    );
    rejected(
        &cpu(&["run", "g.toml", "--out", "o"]),
        dir.path(),
        &[
            "g.toml: line 5: gamma_deg:",
            "n = 1",
            "from (3) and to (9) differ",
        ],
    );
    // One value given as one value runs.
    file(
        dir.path(),
        "g.toml",
        "[[grid]]\nparam = \"gamma_deg\"\nfrom = 3.0\nto = 3.0\nn = 1\n",
    );
    let out = tswm(&cpu(&["run", "g.toml", "--out", "o"]), dir.path());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A law's name in capitals gets a did-you-mean, in a sweep and a table.
#[test]
fn a_law_in_capitals_gets_a_did_you_mean() {
    let dir = tempfile::tempdir().unwrap();
    file(
        dir.path(),
        "s.toml",
        "[base]\nfriction = \"Coulomb\"\nmu = 0.05\n",
    );
    rejected(
        &cpu(&["run", "s.toml", "--out", "o"]),
        dir.path(),
        &["friction", "(did you mean `coulomb`?)"],
    );
    file(dir.path(), "l.csv", "motor,f1\nConstant,100\n");
    rejected(
        &cpu(&["run", "--lanes", "l.csv", "--out", "o"]),
        dir.path(),
        &["l.csv", "motor", "(did you mean `constant`?)"],
    );
}

/// "1 threads" and a pace note of "integration 0.00 s, writing 0.00 s"
/// on a one-lane run.
#[test]
fn one_thread_is_one_thread_and_a_tiny_run_names_no_pace() {
    let dir = tempfile::tempdir().unwrap();
    file(dir.path(), "s.toml", "[base]\nt_end = 0.1\n");
    let out = tswm(
        &cpu(&["run", "s.toml", "--out", "o", "--threads", "1"]),
        dir.path(),
    );
    let line = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success());
    assert!(line.contains("cpu (1 thread, "), "{line}");
    assert!(!line.contains("set the pace"), "{line}");
}

/// `tswm check`'s table lines up (each value under its heading) and
/// compares the section 10 columns too.
#[test]
fn the_checks_table_lines_up_and_holds_the_engineering_columns() {
    quiet_mesa();
    if tswm::backend::gpu::adapters().is_empty() {
        if std::env::var_os("TSWM_REQUIRE_GPU").is_some() {
            panic!("TSWM_REQUIRE_GPU is set but no GPU adapter was found");
        }
        skipped(
            "the check's table",
            "no GPU adapter (apt-get install mesa-vulkan-drivers)",
        );
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let paper = crate::common::root().join("sweeps/paper.toml");
    let out = tswm(&["check", paper.to_str().unwrap()], dir.path());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    let lines: Vec<&str> = text.lines().collect();
    let head = lines
        .iter()
        .position(|l| l.starts_with("column "))
        .expect("a table");
    let ends: Vec<usize> = ["worst", "bound", "lanes over", "worst lane"]
        .iter()
        .map(|w| lines[head].find(w).unwrap() + w.len())
        .collect();
    let mut names = Vec::new();
    for l in lines[head + 1..]
        .iter()
        .take_while(|l| !l.starts_with("discrete"))
    {
        // Each right-aligned value (after the name) ends where its
        // heading ends.
        let mut at = l.find(' ').unwrap();
        for &end in &ends {
            let cell_end = l[at..].find(|c: char| c != ' ').map(|i| at + i).unwrap();
            let stop = l[cell_end..].find(' ').map_or(l.len(), |i| cell_end + i);
            assert_eq!(stop, end, "misaligned: {l:?}\nunder {:?}", lines[head]);
            at = stop;
        }
        names.push(l.split(' ').next().unwrap().to_string());
    }
    for want in [
        "w1_in",
        "eta_direct",
        "eta_inverse",
        "eta_direct_ss",
        "eta_inverse_ss",
        "lock_margin_deg",
        "eta_direct_start",
        "eta_inverse_start",
    ] {
        assert!(
            names.iter().any(|n| n == want),
            "{want} not compared: {names:?}"
        );
    }
}

/// `--dry-run` says what a run would cost and writes nothing; its table
/// size comes from rows formatted as the writer formats them, so it is
/// close to the table a run then writes (within the trial's sampling).
#[test]
fn a_dry_run_estimates_the_table_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    // Cheap lanes, more than a trial holds: the estimate extrapolates.
    file(
        dir.path(),
        "s.toml",
        "[base]\nt_end = 1e-4\n[[grid]]\nparam = \"f2\"\nfrom = -6000.0\nto = 6000.0\nn = 300\n\
         [[grid]]\nparam = \"gamma_deg\"\nfrom = 2.0\nto = 30.0\nn = 1000\n",
    );
    for format in ["csv", "parquet"] {
        let out = tswm(
            &cpu(&[
                "run",
                "s.toml",
                "--out",
                "o",
                "--dry-run",
                "--format",
                format,
            ]),
            dir.path(),
        );
        let line = String::from_utf8_lossy(&out.stdout).into_owned();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(!dir.path().join("o").exists(), "a dry run wrote o/");
        assert!(line.contains("estimate for 300000 lanes"), "{line}");
        assert!(line.contains("nothing run or written"), "{line}");
        let mb: f64 = line
            .split(" MB of lanes.")
            .next()
            .and_then(|s| s.rsplit(' ').next())
            .and_then(|s| s.parse().ok())
            .unwrap_or_else(|| panic!("no size in {line}"));
        let run = tswm(
            &cpu(&[
                "run",
                "s.toml",
                "--out",
                "o",
                "--no-report",
                "--format",
                format,
            ]),
            dir.path(),
        );
        assert!(run.status.success());
        let table = dir.path().join(format!("o/lanes.{format}"));
        let real = std::fs::metadata(&table).unwrap().len() as f64 / 1e6;
        assert!(
            (mb - real).abs() <= 0.1 * real + 1.0,
            "{format}: estimated {mb} MB, wrote {real} MB"
        );
        if format == "csv" {
            assert_eq!(read_csv(&table).1.len(), 300_000);
        }
        std::fs::remove_dir_all(dir.path().join("o")).unwrap();
    }
}

/// The rows of the data sheet's tables in `html`: label -> cells, one a
/// lane, in lane order (the sheet splits lanes over tables of six).
fn sheet_rows(html: &str) -> std::collections::BTreeMap<String, Vec<String>> {
    let start = html.find("<h2>Data sheet</h2>").expect("a data sheet");
    let end = html[start + 10..]
        .find("<h2>")
        .map_or(html.len(), |i| start + 10 + i);
    let mut rows: std::collections::BTreeMap<String, Vec<String>> = Default::default();
    for tr in html[start..end].split("<tr>").skip(1) {
        let cells: Vec<String> = tr
            .split("<td")
            .skip(1)
            .map(|c| {
                let c = &c[c.find('>').unwrap() + 1..];
                let c = &c[..c.find("</td>").unwrap()];
                c.replace("&lt;", "<")
                    .replace("&gt;", ">")
                    .replace("&#39;", "'")
            })
            .collect();
        if let Some((label, rest)) = cells.split_first() {
            rows.entry(label.clone())
                .or_default()
                .extend(rest.iter().cloned());
        }
    }
    rows
}

/// A small run's report opens with a data sheet whose every number is
/// its lane's `lanes.csv` cell to four significant digits, whose words
/// are the lane's outcome, and whose self-locking answer is the sign of
/// the lock margin; lanes at rest show no running point.
#[test]
fn a_small_runs_data_sheet_matches_its_lanes_csv_rows() {
    let dir = tempfile::tempdir().unwrap();
    let fixture = crate::common::fixture("paper_lanes.csv");
    let gear = crate::common::root().join("sweeps/paper_gear.toml");
    for args in [
        vec!["run", "--lanes", fixture.to_str().unwrap(), "--out", "o"],
        vec!["run", gear.to_str().unwrap(), "--out", "o"],
    ] {
        let out = tswm(&cpu(&args), dir.path());
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let html = std::fs::read_to_string(dir.path().join("o/report.html")).unwrap();
        let rows = sheet_rows(&html);
        let (h, lanes) = read_csv(&dir.path().join("o/lanes.csv"));
        let col = |r: &[String], n: &str| crate::common::col(&h, r, n).to_string();
        for (i, r) in lanes.iter().enumerate() {
            let at_rest = col(r, "contact_end") == "stick";
            for (label, name) in [
                ("running direct efficiency, eta_direct_ss", "eta_direct_ss"),
                (
                    "running inverse efficiency, eta_inverse_ss",
                    "eta_inverse_ss",
                ),
                (
                    "starting direct efficiency, eta_direct_start",
                    "eta_direct_start",
                ),
                (
                    "starting inverse efficiency, eta_inverse_start",
                    "eta_inverse_start",
                ),
                (
                    "static lock margin, lock_margin_deg (deg)",
                    "lock_margin_deg",
                ),
                ("over the run, direct: eta_direct", "eta_direct"),
            ] {
                let shown = &rows[label][i];
                let cell = col(r, name);
                if name.ends_with("_ss") && at_rest {
                    assert_eq!(shown, "at rest: no running point", "lane {i} {name}");
                } else if cell.is_empty() {
                    assert_eq!(shown, "", "lane {i} {name}");
                } else {
                    let (v, s): (f64, f64) = (cell.parse().unwrap(), shown.parse().unwrap());
                    assert!(
                        (v - s).abs() <= 5e-4 * v.abs(),
                        "lane {i} {name}: sheet {s}, lanes.csv {v}"
                    );
                }
            }
            let margin: f64 = col(r, "lock_margin_deg").parse().unwrap();
            let locking = &rows["self-locking"][i];
            assert!(
                locking.starts_with(if margin > 0.0 { "yes" } else { "no" }),
                "{locking}"
            );
            let word = match (col(r, "drive").as_str(), col(r, "hold").as_str()) {
                ("back_driven", _) => "back-driven".to_string(),
                ("", "runs_away") => "runs away".to_string(),
                ("", h) => h.to_string(),
                (d, _) => d.to_string(),
            };
            assert!(
                rows["outcome"][i].starts_with(&word),
                "lane {i}: {word} vs {}",
                rows["outcome"][i]
            );
        }
        std::fs::remove_dir_all(dir.path().join("o")).unwrap();
    }
}

/// A sweep that leaves the load out runs the paper's overhauling load:
/// the summary line, `sweep.resolved.toml` and the report say so, and a
/// sweep that gives every value (here in gear terms) says nothing.
#[test]
fn a_sweep_that_leaves_the_drive_out_says_it_runs_the_papers() {
    let dir = tempfile::tempdir().unwrap();
    file(
        dir.path(),
        "s.toml",
        "[base]\ngamma_deg = 5.0\nt_end = 0.2\n",
    );
    let out = tswm(&cpu(&["run", "s.toml", "--out", "o"]), dir.path());
    let line = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(out.status.success());
    let want = "from the paper's drive (not given): m1 = 586 kg, m2 = 10275 kg, f2 = 4774 N, \
                motor = kloss, v_sync = 3.35 m/s, v_crit = 2.07 m/s, f_crit = 4375 N, \
                friction = paper";
    assert!(line.contains(want), "{line}");
    assert!(!line.contains("t_end ="), "t_end was given: {line}");
    let resolved = std::fs::read_to_string(dir.path().join("o/sweep.resolved.toml")).unwrap();
    assert!(resolved.contains(&format!("# {want}\n")), "{resolved}");
    let html = std::fs::read_to_string(dir.path().join("o/report.html")).unwrap();
    assert!(html.contains("takes values of the paper&#39;s drive it was not given: m1 = 586 kg"));
    let gear = crate::common::root().join("sweeps/paper_gear.toml");
    let out = tswm(
        &cpu(&["run", gear.to_str().unwrap(), "--out", "g"]),
        dir.path(),
    );
    let line = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(!line.contains("paper's drive"), "{line}");
}

/// A requirement on a column that is empty for every lane (`hold` with
/// the motor never cut) says why it cannot be answered, never "not met".
#[test]
fn a_requirement_no_lane_can_answer_says_why() {
    let dir = tempfile::tempdir().unwrap();
    file(
        dir.path(),
        "s.toml",
        "[base]\nf2 = -4774.0\nt_end = 0.2\n[report]\nrequire = \"hold = held\"\nat_least = 0.9\n",
    );
    let out = tswm(&cpu(&["run", "s.toml", "--out", "o"]), dir.path());
    assert!(out.status.success());
    let html = std::fs::read_to_string(dir.path().join("o/report.html")).unwrap();
    assert!(html.contains(
        "Requirement `hold = held` cannot be answered: no lane has a value of hold (it is empty \
         when the motor is not cut before t_end"
    ));
    assert!(!html.contains("not met"), "answered as not met");
}

/// Traced lanes are headed by their parameters and outcome; the page's
/// title names the sweep; an axis of unevenly spaced values says so.
#[test]
fn traces_are_headed_by_their_lane_and_uneven_axes_say_so() {
    let dir = tempfile::tempdir().unwrap();
    let paper = crate::common::root().join("sweeps/paper.toml");
    let out = tswm(
        &cpu(&["run", paper.to_str().unwrap(), "--out", "o"]),
        dir.path(),
    );
    assert!(out.status.success());
    let html = std::fs::read_to_string(dir.path().join("o/report.html")).unwrap();
    assert!(html.contains("<h1>tswm report: paper.toml, 2 lanes (folder o)</h1>"));
    assert!(
        html.contains("<h3>lane 0: f2 = 4774 N, overhauled ("),
        "trace heading"
    );
    assert!(
        html.contains("<h3>lane 1: f2 = -4774 N, runs ("),
        "trace heading"
    );
    file(
        dir.path(),
        "u.toml",
        "[base]\nf2 = -4774.0\nt_end = 0.1\nfriction = \"coulomb\"\nmu = 0.05\n\
         [[grid]]\nparam = \"gamma_deg\"\nvalues = [2.0, 3.0, 5.0, 8.0, 13.0]\n\
         [[grid]]\nparam = \"mu\"\nfrom = 0.02\nto = 0.1\nn = 5\n",
    );
    let out = tswm(&cpu(&["run", "u.toml", "--out", "u"]), dir.path());
    assert!(out.status.success());
    let html = std::fs::read_to_string(dir.path().join("u/report.html")).unwrap();
    assert!(html.contains("gamma_deg (deg); uneven values, one cell each"));
    assert!(
        !html.contains("mu; uneven values"),
        "an even axis is a scale"
    );
}
