//! Sensitivity designs (`[sensitivity]`): SALib fed the same sample and
//! outputs gives the same indices; the physics of holding from rest
//! decides which inputs matter; the page is rebuilt the same; bad
//! designs are refused with one line.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

use crate::common::{col, cpu, read_csv, rejected, root, run_ok, tswm};
use crate::reference::{python_for, Needs};

/// SALib (and pandas) from the package index, in a venv of its own
/// (`.ci/run`).
const SALIB: Needs = Needs {
    modules: "SALib, pandas",
    vars: &["TSWM_SALIB_PYTHON", "TSWM_PYTHON"],
    install: "pip install SALib pandas, or set TSWM_SALIB_PYTHON",
};

/// The sensitivity rows of `dir`: (group, result, input) → cells.
fn indices(dir: &Path) -> BTreeMap<(String, String, String), Vec<String>> {
    let (h, rows) = read_csv(&dir.join("sensitivity.csv"));
    rows.iter()
        .map(|r| {
            let key = |n: &str| col(&h, r, n).to_string();
            ((key("group"), key("result"), key("input")), r.clone())
        })
        .collect()
}

/// Holding from rest with the motor off: |F2 sin γ| ≤ μs' |F2 cos γ| does
/// not depend on the load, so the load's total index is 0 exactly (every
/// A and AB row group with the load changed gives the same outcome), and
/// the lead angle and static friction have the two largest. Every lane's
/// outcome is the static lock condition (lock_margin_deg > 0).
const FROM_REST: &str = r#"
[base]
friction = "coulomb"
gamma_deg = 5.0
mu = 0.06
mu_static = 0.085
alpha_n_deg = 20.0
f2 = -4774.0
motor_off = 0.0
t_end = 0.5

[[grid]]
param = "m1"
values = [586.0, 1200.0]

[sensitivity]
method = "sobol"
n = 512
seed = 11
bootstrap = 200

[[tolerance]]
param = "gamma_deg"
dist = "uniform"
tol = 0.6
[[tolerance]]
param = "mu_static"
dist = "uniform"
tol = 0.015
[[tolerance]]
param = "mu"
dist = "uniform"
tol = 0.01
[[tolerance]]
param = "f2"
dist = "uniform"
tol_rel = 0.5
[[tolerance]]
param = "alpha_n_deg"
dist = "normal"
tol = 2.0
"#;

const FROM_REST_INPUTS: [&str; 5] = ["gamma_deg", "mu_static", "mu", "f2", "alpha_n_deg"];

#[test]
fn holding_from_rest_does_not_depend_on_the_load() {
    let t = tempfile::tempdir().unwrap();
    let dir = t.path();
    std::fs::write(dir.join("rest.toml"), FROM_REST).unwrap();
    let (_, h, rows) = run_ok(&cpu(&["run", "rest.toml", "--out", "o"]), dir);
    assert_eq!(rows.len(), 2 * 512 * 7);
    let mut held = 0;
    for r in &rows {
        let stick = col(&h, r, "contact_end") == "stick";
        let margin: f64 = col(&h, r, "lock_margin_deg").parse().unwrap();
        assert_eq!(stick, margin > 0.0, "lane {}", col(&h, r, "lane"));
        held += usize::from(stick);
    }
    // Neither all nor none: the indicator varies.
    assert!(
        held > rows.len() / 10 && held < rows.len() * 9 / 10,
        "{held}"
    );
    let ix = indices(&dir.join("o"));
    for g in ["0", "1"] {
        let get = |input: &str| {
            &ix[&(
                g.to_string(),
                "contact_end=stick".to_string(),
                input.to_string(),
            )]
        };
        let st = |input: &str| get(input)[6].parse::<f64>().unwrap();
        assert_eq!(st("f2"), 0.0, "the load's total index");
        assert_eq!(
            get("f2")[3].parse::<f64>().unwrap(),
            0.0,
            "the load's first-order index"
        );
        let mut by: Vec<(&str, f64)> = FROM_REST_INPUTS.iter().map(|&i| (i, st(i))).collect();
        by.sort_by(|a, b| b.1.total_cmp(&a.1));
        let top: Vec<&str> = by[..2].iter().map(|x| x.0).collect();
        assert!(
            top.contains(&"gamma_deg") && top.contains(&"mu_static"),
            "{by:?}"
        );
        assert_eq!(get("gamma_deg")[9], "512");
    }
}

#[test]
fn salib_gives_the_same_indices() {
    let Some(py) = python_for(&SALIB, "the SALib cross-check") else {
        return;
    };
    let t = tempfile::tempdir().unwrap();
    let dir = t.path();
    // The shipped sweep (one grid point) and a grid of two points with a
    // normal input.
    let shipped = root().join("sweeps/which_tolerance.toml");
    std::fs::write(dir.join("rest.toml"), FROM_REST).unwrap();
    for (sweep, out) in [(shipped.to_str().unwrap(), "a"), ("rest.toml", "b")] {
        let o = tswm(&cpu(&["run", sweep, "--out", out, "--no-report"]), dir);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let script = root().join("tests/reference/salib_sobol.py");
    for (out, n) in [("a", "4096"), ("b", "512")] {
        let o = dir.join(out);
        let mut args = vec![
            script.display().to_string(),
            o.join("lanes.csv").display().to_string(),
            o.join("sensitivity.csv").display().to_string(),
            n.to_string(),
        ];
        args.extend(FROM_REST_INPUTS.iter().map(|s| s.to_string()));
        let res = Command::new(&py).args(&args).output().unwrap();
        let stdout = String::from_utf8_lossy(&res.stdout);
        assert!(
            res.status.success(),
            "{out}: {stdout}{}",
            String::from_utf8_lossy(&res.stderr)
        );
        eprintln!("{out}: {}", stdout.trim());
    }
}

#[test]
fn tswm_report_rebuilds_the_same_page() {
    let t = tempfile::tempdir().unwrap();
    let dir = t.path();
    std::fs::write(dir.join("rest.toml"), FROM_REST).unwrap();
    run_ok(&cpu(&["run", "rest.toml", "--out", "o"]), dir);
    let page = std::fs::read_to_string(dir.join("o/report.html")).unwrap();
    assert!(
        page.contains("Which input matters")
            && page.contains("contact_end=stick: S1 and ST by input")
    );
    assert!(page.contains("the largest total index is"));
    // No Wilson interval on lanes that are not independent draws.
    assert!(page.contains("No intervals: the lanes of a sensitivity design"));
    let out = tswm(&["report", "o"], dir);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("o/report.html")).unwrap(),
        page
    );
    // A changed sensitivity.csv is read strictly: one line, exit 2.
    let s = std::fs::read_to_string(dir.join("o/sensitivity.csv")).unwrap();
    std::fs::write(
        dir.join("o/sensitivity.csv"),
        s.replacen(",gamma_deg,", ",gamma,", 1),
    )
    .unwrap();
    rejected(
        &["report", "o"],
        dir,
        &["sensitivity.csv", "line 2", "input"],
    );
}

#[test]
fn bad_sensitivity_designs_get_one_line() {
    let t = tempfile::tempdir().unwrap();
    let dir = t.path();
    let base = "[base]\nmu = 0.05\nfriction = \"coulomb\"\n";
    let tol = "[[tolerance]]\nparam = \"gamma_deg\"\ndist = \"uniform\"\ntol = 0.5\n";
    let cases: [(&str, String, &[&str]); 8] = [
        ("both", format!("{base}[sampling]\nmethod = \"monte_carlo\"\nn = 4\nseed = 1\n[sensitivity]\nmethod = \"sobol\"\nn = 4\nseed = 1\n{tol}"), &["sensitivity", "not both"]),
        ("method", format!("{base}[sensitivity]\nmethod = \"morris\"\nn = 4\nseed = 1\n{tol}"), &["line 5", "method", "sobol"]),
        ("n", format!("{base}[sensitivity]\nmethod = \"sobol\"\nn = 1\nseed = 1\n{tol}"), &["line 6", "n", "from 2"]),
        ("bootstrap", format!("{base}[sensitivity]\nmethod = \"sobol\"\nn = 8\nseed = 1\nbootstrap = -3\n{tol}"), &["line 8", "bootstrap", "from 0"]),
        ("confidence", format!("{base}[sensitivity]\nmethod = \"sobol\"\nn = 8\nseed = 1\nconfidence = 1.0\n{tol}"), &["line 8", "confidence", "between 0 and 1"]),
        ("results", format!("{base}[sensitivity]\nmethod = \"sobol\"\nn = 8\nseed = 1\nresults = [\"holds\"]\n{tol}"), &["line 8", "results", "contact_end=stick"]),
        ("inputs", format!("{base}[sensitivity]\nmethod = \"sobol\"\nn = 8\nseed = 1\n"), &["sensitivity", "[[tolerance]]"]),
        ("require", format!("{base}[report]\nrequire = \"hold = held\"\nat_least = 0.9\n[sensitivity]\nmethod = \"sobol\"\nn = 8\nseed = 1\n{tol}"), &["report.require", "[sampling]"]),
    ];
    for (name, text, want) in cases {
        let f = format!("{name}.toml");
        std::fs::write(dir.join(&f), text).unwrap();
        let out = format!("o_{name}");
        let mut w = vec![f.as_str()];
        w.extend(want);
        rejected(&["run", &f, "--out", &out], dir, &w);
        assert!(!dir.join(&out).exists(), "{name}: a folder was written");
    }
}
