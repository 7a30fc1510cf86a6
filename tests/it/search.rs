//! `[search]`: each drive's critical value, found by bisection in rounds,
//! against closed forms (MODEL.md sections 4, 5 and 10) over random drives
//! of several laws, flank angles and motors; the share boundary's 95 %
//! interval against the true quantile of a known distribution over 40
//! seeds; its cost; shards; bad inputs.

use std::path::Path;

use crate::common::{col, cpu, file, read_csv, rejected, root, tswm};
use crate::property::Gen;

/// Runs `tswm` on the CPU path, asserting success; its stdout.
fn ok(args: &[&str], cwd: &Path) -> String {
    let out = tswm(&cpu(args), cwd);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn num(s: &str) -> f64 {
    s.parse()
        .unwrap_or_else(|_| panic!("`{s}` is not a number"))
}

/// One drive of a closed-form case: its grid of one point, written as the
/// base, and the true critical value.
struct Case {
    base: String,
    search: String,
    truth: f64,
}

/// The static friction angle ρs (deg) of a coefficient μs on a flank αn.
fn rho_s(mu_s: f64, alpha_n_deg: f64) -> f64 {
    (mu_s / alpha_n_deg.to_radians().cos()).atan().to_degrees()
}

/// Holding with the motor off from rest (section 4: held iff γ ≤ ρs):
/// the critical lead angle is ρs, for coulomb, agma (μs = 0.150) and the
/// paper's law (ρ(0) = 1/c degrees).
fn hold_case(g: &mut Gen) -> Case {
    let alpha = if g.below(2) == 0 {
        0.0
    } else {
        30.0 * g.unit()
    };
    let (law, truth) = match g.below(3) {
        0 => {
            let mu = 0.02 + 0.05 * g.unit();
            let mu_s = mu + 0.15 * g.unit();
            (
                format!(
                    "friction = \"coulomb\"\nmu = {mu}\nmu_static = {mu_s}\nalpha_n_deg = {alpha}\n"
                ),
                rho_s(mu_s, alpha),
            )
        }
        1 => (
            format!("friction = \"agma\"\nalpha_n_deg = {alpha}\n"),
            rho_s(0.150, alpha),
        ),
        _ => {
            let c = 0.08 + 0.2 * g.unit();
            (format!("friction = \"paper\"\nfric_c = {c}\n"), 1.0 / c)
        }
    };
    let f2 = 1000.0 + 9000.0 * g.unit();
    Case {
        base: format!("{law}f2 = {f2}\nmotor_off = 0.0\nt_end = 0.5\n"),
        search: "param = \"gamma_deg\"\nfrom = 1.0\nto = 25.0\nrequire = \"hold = held\"\n".into(),
        truth,
    }
}

/// Starting a lifting load from rest (section 4's stick test with F2 =
/// −L): the motor starts it iff F1 (cos γ − μs sin γ) > L (sin γ + μs
/// cos γ), i.e. L < F1 / tan(γ + ρs); F1 is the constant motor's force or
/// the Kloss motor's at rest, 2 f_crit σk / (1 + σk²). The sliding μ is
/// below μs, so a drive that starts keeps running.
fn start_case(g: &mut Gen) -> Case {
    let gamma = 3.0 + 17.0 * g.unit();
    let alpha = if g.below(2) == 0 {
        0.0
    } else {
        25.0 * g.unit()
    };
    let mu = 0.02 + 0.04 * g.unit();
    let mu_s = mu + 0.02 + 0.1 * g.unit();
    let (motor, f1) = if g.below(2) == 0 {
        let f1 = 1000.0 + 6000.0 * g.unit();
        (format!("motor = \"constant\"\nf1 = {f1}\n"), f1)
    } else {
        let (v_sync, v_crit, f_crit) = (3.35, 2.07, 2000.0 + 4000.0 * g.unit());
        let sk: f64 = (v_sync - v_crit) / v_sync;
        (
            format!("motor = \"kloss\"\nf_crit = {f_crit}\n"),
            2.0 * f_crit * sk / (1.0 + sk * sk),
        )
    };
    let truth = -f1 / (gamma + rho_s(mu_s, alpha)).to_radians().tan();
    Case {
        base: format!(
            "{motor}friction = \"coulomb\"\nmu = {mu}\nmu_static = {mu_s}\n\
             alpha_n_deg = {alpha}\ngamma_deg = {gamma}\nt_end = 1.0\n"
        ),
        search: "param = \"f2\"\nfrom = -200000.0\nto = -1.0\nrequire = \"drive = runs\"\n".into(),
        truth,
    }
}

/// The friction coefficient at which the steady direct efficiency
/// tan γ / tan(γ + ρ) falls to a bound e (section 10): ρ = atan(tan γ /
/// e) − γ and μ = tan ρ · cos αn.
fn efficiency_case(g: &mut Gen) -> Case {
    let gamma: f64 = 4.0 + 20.0 * g.unit();
    let alpha: f64 = 25.0 * g.unit();
    let e = 0.5 + 0.3 * g.unit();
    let t = gamma.to_radians().tan();
    let rho = (t / e).atan() - gamma.to_radians();
    let truth = rho.tan() * alpha.to_radians().cos();
    Case {
        base: format!(
            "friction = \"coulomb\"\nalpha_n_deg = {alpha}\ngamma_deg = {gamma}\nf2 = -1500.0\n"
        ),
        search: format!(
            "param = \"mu\"\nfrom = 0.0005\nto = 0.4\nrequire = \"eta_direct_ss >= {e}\"\n"
        ),
        truth,
    }
}

/// Runs one case with `tol`; its lanes.csv row.
fn found(dir: &Path, c: &Case, tol: f64) -> (Vec<String>, Vec<String>) {
    file(
        dir,
        "s.toml",
        &format!("[base]\n{}\n[search]\n{}tol = {tol:e}\n", c.base, c.search),
    );
    let _ = std::fs::remove_dir_all(dir.join("o"));
    ok(&["run", "s.toml", "--out", "o", "--no-report"], dir);
    let (h, rows) = read_csv(&dir.join("o/lanes.csv"));
    assert_eq!(rows.len(), 1);
    (h, rows.into_iter().next().unwrap())
}

/// Every `found` drive holds the closed form inside its final bracket,
/// which is no wider than `tol`: 60 random drives over three questions,
/// three friction laws, flank angles and both motors.
#[test]
fn each_found_bracket_holds_the_closed_form_critical_value() {
    let t = tempfile::tempdir().unwrap();
    let mut g = Gen(0x5ea7c4);
    for i in 0..60 {
        let (c, tol) = match i % 3 {
            0 => (hold_case(&mut g), 1e-4),
            1 => (start_case(&mut g), 0.5),
            _ => (efficiency_case(&mut g), 1e-6),
        };
        let (h, row) = found(t.path(), &c, tol);
        let status = col(&h, &row, "search_status");
        assert_eq!(status, "found", "case {i}: {}\n{}", c.base, c.search);
        let (lo, hi) = (
            num(col(&h, &row, "search_lo")),
            num(col(&h, &row, "search_hi")),
        );
        assert!(
            hi - lo <= tol * (1.0 + 1e-9),
            "case {i}: bracket ({lo}, {hi}] wider than {tol}"
        );
        // The closed form within the bracket, allowing the integrator's
        // own error at the bracket's ends (rel. 1e-9 of the value).
        let slack = 1e-9 * c.truth.abs().max(1.0);
        assert!(
            lo - slack <= c.truth && c.truth <= hi + slack,
            "case {i}: true {} outside ({lo}, {hi}]: {}\n{}",
            c.truth,
            c.base,
            c.search
        );
        let critical = num(col(&h, &row, "critical"));
        assert!((critical - 0.5 * (lo + hi)).abs() <= 1e-12 * critical.abs().max(1.0));
    }
}

/// A drive whose answer does not change inside the bracket says which
/// end meets the requirement, and gives no critical value.
#[test]
fn a_drive_without_a_change_says_which_end_meets_the_requirement() {
    let t = tempfile::tempdir().unwrap();
    // μs = 0.1 holds up to 5.71°: held at both ends of 1..4, at neither
    // of 8..20.
    let base = "friction = \"coulomb\"\nmu = 0.05\nmu_static = 0.1\nf2 = 5000.0\n\
                motor_off = 0.0\nt_end = 0.5\n";
    for ((from, to), want) in [
        ((1.0, 4.0), "met_at_both_ends"),
        ((8.0, 20.0), "met_at_neither_end"),
    ] {
        let c = Case {
            base: base.into(),
            search: format!(
                "param = \"gamma_deg\"\nfrom = {from:?}\nto = {to:?}\nrequire = \"hold = held\"\n"
            ),
            truth: f64::NAN,
        };
        let (h, row) = found(t.path(), &c, 1e-3);
        assert_eq!(col(&h, &row, "search_status"), want);
        assert_eq!(col(&h, &row, "critical"), "");
    }
}

/// The tolerance study of the coverage test: μs uniform within ±30 % of
/// 0.1, coulomb on a flank `alpha`; held iff γ ≤ atan(μs / cos αn), so
/// the largest lead angle that a share p of drives holds is
/// atan(q / cos αn) with q = 0.1 (0.7 + 0.6 (1 − p)), the (1 − p)
/// quantile of μs.
fn study(seed: u64, n: u64, at_least: f64, alpha: f64, tol: f64) -> (String, f64) {
    let text = format!(
        "[base]\nfriction = \"coulomb\"\nmu = 0.05\nmu_static = 0.1\nalpha_n_deg = {alpha}\n\
         f2 = 5000.0\nmotor_off = 0.0\nt_end = 0.5\n\n\
         [search]\nparam = \"gamma_deg\"\nfrom = 1.0\nto = 15.0\nrequire = \"hold = held\"\n\
         tol = {tol:e}\nat_least = {at_least}\n\n\
         [sampling]\nmethod = \"monte_carlo\"\nn = {n}\nseed = {seed}\n\n\
         [[tolerance]]\nparam = \"mu_static\"\ndist = \"uniform\"\ntol_rel = 0.3\n"
    );
    let q = 0.1 * (0.7 + 0.6 * (1.0 - at_least));
    (text, rho_s(q, alpha))
}

/// summary.csv's boundary row: (value, ci95_low, ci95_high).
fn boundary(dir: &Path) -> (f64, f64, f64) {
    let (h, rows) = read_csv(&dir.join("summary.csv"));
    let r = rows
        .iter()
        .find(|r| col(&h, r, "kind") == "boundary")
        .expect("a boundary row");
    (
        num(col(&h, r, "p50")),
        num(col(&h, r, "ci95_low")),
        num(col(&h, r, "ci95_high")),
    )
}

/// The lanes a search integrated, as its summary line says ("(N lanes
/// integrated").
fn lanes_integrated(out: &str) -> u64 {
    out.split(" lanes integrated")
        .next()
        .and_then(|s| s.rsplit('(').next())
        .and_then(|s| s.trim().parse().ok())
        .unwrap_or_else(|| panic!("no lane count in: {out}"))
}

/// Over 40 seeds the distribution-free 95 % interval of the 90 % share
/// boundary holds the true quantile at least 36 times.
#[test]
fn the_share_boundarys_interval_covers_the_true_quantile_in_36_of_40_seeds() {
    let t = tempfile::tempdir().unwrap();
    let mut covered = 0;
    for seed in 0..40 {
        let (text, truth) = study(1000 + seed, 300, 0.9, 14.5, 1e-4);
        file(t.path(), "s.toml", &text);
        let _ = std::fs::remove_dir_all(t.path().join("o"));
        ok(&["run", "s.toml", "--out", "o", "--no-report"], t.path());
        let (_, lo, hi) = boundary(&t.path().join("o"));
        if lo <= truth && truth <= hi {
            covered += 1;
        }
    }
    assert!(
        covered >= 36,
        "the interval held the truth in {covered} of 40"
    );
}

/// The 1 % boundary of 2000 drives to 1e-4° costs at most 12,000
/// integrated lanes (bisecting every drive would cost some 34,000), and
/// the summary line says how many.
#[test]
fn a_one_percent_boundary_of_2000_drives_costs_at_most_12000_lanes() {
    let t = tempfile::tempdir().unwrap();
    let (text, truth) = study(7, 2000, 0.99, 0.0, 1e-4);
    file(t.path(), "s.toml", &text);
    let out = ok(&["run", "s.toml", "--out", "o", "--no-report"], t.path());
    let lanes = lanes_integrated(&out);
    assert!(lanes <= 12_000, "{lanes} lanes: {out}");
    assert!(out.contains("2000 drives searched"), "{out}");
    let (value, lo, hi) = boundary(&t.path().join("o"));
    assert!(lo <= value && value <= hi);
    // 2000 drives: the sample 1 % quantile is near the true one.
    assert!((value - truth).abs() < 0.1, "{value} against {truth}");
}

/// With `quantiles = true` a share search also gives the critical
/// value's P1 ... P99: each within tol / 2 of the nearest-rank quantile of
/// the drives' closed-form critical values (from each drive's drawn μs
/// in lanes.csv), at well under half the lanes of searching every drive.
#[test]
fn a_share_search_with_quantiles_gives_each_to_tol() {
    let t = tempfile::tempdir().unwrap();
    let (n, tol, alpha) = (500, 1e-4, 10.0);
    let (text, _) = study(11, n, 0.95, alpha, tol);
    let text = text.replace("at_least = 0.95\n", "at_least = 0.95\nquantiles = true\n");
    assert!(text.contains("quantiles = true"));
    file(t.path(), "s.toml", &text);
    let out = ok(&["run", "s.toml", "--out", "o", "--no-report"], t.path());
    let lanes = lanes_integrated(&out);
    // Every drive's own search: 9 first-round points and 17 bisections.
    assert!(lanes * 2 < n * 26, "{lanes} lanes: {out}");
    let (h, rows) = read_csv(&t.path().join("o/lanes.csv"));
    let mut c: Vec<f64> = rows
        .iter()
        .map(|r| rho_s(num(col(&h, r, "mu_static")), alpha))
        .collect();
    c.sort_by(f64::total_cmp);
    let (h, rows) = read_csv(&t.path().join("o/summary.csv"));
    let r = rows
        .iter()
        .find(|r| col(&h, r, "kind") == "critical")
        .expect("a critical row");
    for (p, name) in [
        (0.01, "p1"),
        (0.05, "p5"),
        (0.5, "p50"),
        (0.95, "p95"),
        (0.99, "p99"),
    ] {
        let k = ((p * n as f64).ceil() as usize).clamp(1, n as usize);
        let got = num(col(&h, r, name));
        assert!(
            (got - c[k - 1]).abs() <= 0.5 * tol + 1e-9,
            "{name}: {got} against {}",
            c[k - 1]
        );
    }
}

/// A search split into shards merges into exactly the unsharded files;
/// a tampered shard is refused.
#[test]
fn a_search_in_shards_merges_byte_identically_and_refuses_a_tampered_shard() {
    let t = tempfile::tempdir().unwrap();
    let d = t.path();
    let sweep = root().join("sweeps/start_load.toml");
    let sweep = sweep.to_str().unwrap();
    ok(&["run", sweep, "--out", "full"], d);
    let mut parts = Vec::new();
    for k in 0..3 {
        let o = format!("s{k}");
        ok(
            &["run", sweep, "--shard", &format!("{k}/3"), "--out", &o],
            d,
        );
        parts.push(o);
    }
    let mut args = vec!["merge"];
    args.extend(parts.iter().map(String::as_str));
    args.extend(["--out", "merged"]);
    let out = tswm(&args, d);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for f in ["lanes.csv", "summary.csv"] {
        assert_eq!(
            std::fs::read(d.join("full").join(f)).unwrap(),
            std::fs::read(d.join("merged").join(f)).unwrap(),
            "{f}"
        );
    }
    // One critical value changed in shard 1: the merge refuses it.
    let p = d.join("s1/lanes.csv");
    let text = std::fs::read_to_string(&p).unwrap();
    let (h, rows) = read_csv(&p);
    let old = col(&h, &rows[0], "critical").to_string();
    std::fs::write(&p, text.replacen(&old, "-1234.5", 1)).unwrap();
    args.pop();
    args.push("again");
    let out = tswm(&args, d);
    assert_eq!(
        out.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(!d.join("again").exists());
}

/// Each bad search input is one line naming the file, line, key and what
/// is allowed; exit 2; nothing written.
#[test]
fn bad_searches_are_refused_with_one_line() {
    let t = tempfile::tempdir().unwrap();
    let base = "[base]\nfriction = \"coulomb\"\nmu = 0.05\nmotor_off = 0.0\n\n";
    let search = |body: &str| format!("{base}[search]\n{body}");
    let ok_body = "param = \"gamma_deg\"\nfrom = 1.0\nto = 20.0\nrequire = \"hold = held\"\n\
                   tol = 1e-4\n";
    let cases: Vec<(String, Vec<&str>)> = vec![
        (
            search(&ok_body.replace("\"gamma_deg\"", "\"friction\"")),
            vec!["line 7", "search.param", "word parameter"],
        ),
        (
            search(&ok_body.replace("\"gamma_deg\"", "\"gama_deg\"")),
            vec!["search.param", "not a parameter", "gamma_deg"],
        ),
        (
            search(&ok_body.replace("\"gamma_deg\"", "\"fric_a\"")),
            vec!["search.param", "fric_a", "not used by", "coulomb"],
        ),
        (
            search(&ok_body.replace("from = 1.0", "from = -5.0")),
            vec!["search.from", "allowed range"],
        ),
        (
            search(&ok_body.replace("from = 1.0\nto = 20.0", "from = 20.0\nto = 1.0")),
            vec!["search.to", "from < to"],
        ),
        (
            search(&ok_body.replace("tol = 1e-4", "tol = 0.0")),
            vec!["search.tol", "above 0"],
        ),
        (
            search(&ok_body.replace("tol = 1e-4", "tol = 50.0")),
            vec!["search.tol", "below the bracket's width"],
        ),
        (
            search(&ok_body.replace("hold = held", "hold = helt")),
            vec!["search.require", "helt"],
        ),
        (
            search(&ok_body.replace("hold = held", "holdd = held")),
            vec!["search.require", "holdd"],
        ),
        (
            search(&format!("{ok_body}at_least = 0.99\n")),
            vec!["search.at_least", "[sampling]"],
        ),
        (
            search(&format!("{ok_body}quantiles = true\n")),
            vec!["search.quantiles", "needs at_least"],
        ),
        (
            format!(
                "{}\n[sensitivity]\nmethod = \"sobol\"\nn = 64\nseed = 1\n\n\
                 [[tolerance]]\nparam = \"mu\"\ndist = \"uniform\"\ntol_rel = 0.1\n",
                search(ok_body)
            ),
            vec!["sensitivity", "not both"],
        ),
        (
            format!(
                "{}\n[[grid]]\nparam = \"mu\"\nfrom = 0.01\nto = 0.1\nn = 100000000\n",
                search(ok_body)
            ),
            vec!["search", "integrated lanes", "larger tol", "shards"],
        ),
        (
            search(&ok_body.replace("tol = 1e-4", "tol = 1e-300")),
            vec!["search.tol", "finer than a float can bracket"],
        ),
        (
            format!(
                "{}\n[[grid]]\nparam = \"gamma_deg\"\nvalues = [3.0, 4.0]\n",
                search(ok_body)
            ),
            vec!["search.param", "grid axis"],
        ),
    ];
    for (text, want) in cases {
        file(t.path(), "bad.toml", &text);
        let mut w = vec!["bad.toml: line"];
        w.extend(want);
        rejected(&cpu(&["run", "bad.toml", "--out", "o"]), t.path(), &w);
        assert!(!t.path().join("o").exists(), "{text}");
    }
}

/// On a terminal the bar of a search counts drives, rounds and the lanes
/// they integrated (run under `script`, which gives it a terminal).
#[test]
fn a_searchs_bar_counts_drives_rounds_and_lanes() {
    let Ok(script) = which("script") else {
        crate::common::skipped(
            "a_searchs_bar_counts_drives_rounds_and_lanes",
            "no `script` (util-linux) to give the run a terminal",
        );
        return;
    };
    let t = tempfile::tempdir().unwrap();
    // Ten times the shipped drives: a second or so, many redraws.
    let text = std::fs::read_to_string(root().join("sweeps/lead_angle_holds.toml")).unwrap();
    assert!(text.contains("\nn = 2000\n"));
    file(
        t.path(),
        "s.toml",
        &text.replace("\nn = 2000\n", "\nn = 20000\n"),
    );
    let cmd = format!(
        "{} run s.toml --out o --no-report --backend cpu",
        env!("CARGO_BIN_EXE_tswm")
    );
    let out = std::process::Command::new(script)
        .args(["-qec", &cmd, "/dev/null"])
        .current_dir(t.path())
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let text = String::from_utf8_lossy(&out.stdout);
    let shown: Vec<&str> = text
        .split(['\r', '\n'])
        .filter(|l| l.contains("drives searched,"))
        .collect();
    assert!(!shown.is_empty(), "no bar in: {text}");
    // The rounds and lanes only grow, to more lanes than drives.
    let counts: Vec<(u64, u64)> = shown
        .iter()
        .filter_map(|l| {
            let n = |key: &str| -> Option<u64> {
                l.split(key)
                    .next()?
                    .rsplit([' ', ','])
                    .find(|w| !w.is_empty())?
                    .parse()
                    .ok()
            };
            Some((n(" rounds")?, n(" lanes integrated")?))
        })
        .collect();
    assert!(!counts.is_empty(), "{shown:?}");
    assert!(
        counts
            .windows(2)
            .all(|w| w[0].0 <= w[1].0 && w[0].1 <= w[1].1),
        "{counts:?}"
    );
    assert!(counts.iter().any(|c| c.0 >= 2 && c.1 > 0), "{counts:?}");
}

/// The path of a program on PATH.
fn which(name: &str) -> Result<std::path::PathBuf, ()> {
    std::env::var_os("PATH")
        .and_then(|p| {
            std::env::split_paths(&p)
                .map(|d| d.join(name))
                .find(|f| f.is_file())
        })
        .ok_or(())
}
