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
