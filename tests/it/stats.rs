//! `summary.csv`: its statistics against independent computations from
//! `lanes.csv` (a sort for quantiles), and the streaming quantile estimate
//! against the exact one.

use std::collections::BTreeMap;
use std::path::Path;

use crate::common::cpu;
use crate::common::{col, read_csv, run_ok};
use tswm::stats::quantile::{Sketch, ALPHA, TINY};

/// Type-7 quantile of a sorted sample, written out here independently.
fn type7(s: &[f64], q: f64) -> f64 {
    let h = (s.len() - 1) as f64 * q;
    let lo = h.floor();
    s[lo as usize] + (h - lo) * (s[h.ceil() as usize] - s[lo as usize])
}

/// lanes.csv columns as f64 (empty cells left out), by name.
/// A lane at rest at its end has no running point (docs/model.md section
/// 10): its `_ss` cells are left out of the statistics.
fn columns(dir: &Path) -> BTreeMap<String, Vec<f64>> {
    let (h, rows) = read_csv(&dir.join("lanes.csv"));
    let mut m: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    for r in &rows {
        let at_rest = col(&h, r, "contact_end") == "stick";
        for (name, cell) in h.iter().zip(r) {
            if at_rest && name.ends_with("_ss") {
                continue;
            }
            if let Ok(x) = cell.parse::<f64>() {
                m.entry(name.clone()).or_default().push(x);
            }
        }
    }
    m
}

const PROBS: [(&str, f64); 5] = [
    ("p1", 0.01),
    ("p5", 0.05),
    ("p50", 0.5),
    ("p95", 0.95),
    ("p99", 0.99),
];

#[test]
fn exact_quantiles_agree_with_a_sort_of_the_column() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = crate::common::root().join("sweeps/tolerance.toml");
    run_ok(
        &cpu(&["run", sweep.to_str().unwrap(), "--out", "o"]),
        dir.path(),
    );
    let o = dir.path().join("o");
    let cols = columns(&o);
    let (h, rows) = read_csv(&o.join("summary.csv"));
    let mut checked = 0;
    for r in rows.iter().filter(|r| col(&h, r, "kind") == "number") {
        let name = col(&h, r, "name");
        let mut v = cols.get(name).cloned().unwrap_or_default();
        assert_eq!(col(&h, r, "count"), v.len().to_string(), "{name}");
        if v.is_empty() {
            continue;
        }
        assert_eq!(col(&h, r, "quantiles"), "exact");
        v.sort_by(f64::total_cmp);
        for (p, q) in PROBS {
            let got: f64 = col(&h, r, p).parse().unwrap();
            let want = type7(&v, q);
            assert!(
                (got - want).abs() <= 1e-12 * want.abs().max(1.0),
                "{name} {p}: {got} vs {want}"
            );
            checked += 1;
        }
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        let got: f64 = col(&h, r, "mean").parse().unwrap();
        assert!(
            (got - mean).abs() <= 1e-9 * mean.abs().max(1.0),
            "{name} mean"
        );
        assert_eq!(col(&h, r, "min").parse::<f64>().unwrap(), v[0]);
        assert_eq!(col(&h, r, "max").parse::<f64>().unwrap(), v[v.len() - 1]);
    }
    assert!(checked >= 50, "{checked}");
    // Status shares add up to one, and the ok share holds every lane.
    let ok = rows
        .iter()
        .find(|r| col(&h, r, "kind") == "status" && col(&h, r, "name") == "ok")
        .unwrap();
    assert_eq!(col(&h, ok, "count"), "5000");
    assert_eq!(col(&h, ok, "share"), "1.0");
}

/// Checks every quantile of a sample against the stated bound: within
/// ALPHA of the order statistic of rank ⌊q(n−1)⌋ (or TINY of it).
fn check_sketch(name: &str, xs: &[f64]) -> f64 {
    let mut s = Sketch::default();
    for &x in xs {
        s.add(x);
    }
    let mut sorted = xs.to_vec();
    sorted.sort_by(f64::total_cmp);
    let mut worst: f64 = 0.0;
    for q in [
        0.0, 0.001, 0.01, 0.05, 0.25, 0.5, 0.75, 0.95, 0.99, 0.999, 1.0,
    ] {
        let want = sorted[(q * (xs.len() - 1) as f64).floor() as usize];
        let got = s.quantile(q);
        let err = (got - want).abs();
        assert!(
            err <= ALPHA * want.abs() + TINY,
            "{name} q={q}: {got} vs {want}"
        );
        if want.abs() > TINY {
            worst = worst.max(err / want.abs());
        }
    }
    worst
}

#[test]
fn streaming_quantiles_stay_within_the_stated_error() {
    use rand_chacha::rand_core::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let mut u = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    let n = 200_000;
    // Efficiencies (bounded, one sign), energies over decades (log-normal),
    // signed loads with zeros, and a heavy tail.
    let eta: Vec<f64> = (0..n).map(|_| 0.2 + 0.6 * u()).collect();
    let lognormal: Vec<f64> = (0..n)
        .map(|_| {
            let (a, b) = (u().max(1e-300), u());
            (3.0 * (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()).exp()
        })
        .collect();
    let signed: Vec<f64> = (0..n)
        .map(|i| {
            if i % 10 == 0 {
                0.0
            } else {
                8000.0 * (2.0 * u() - 1.0)
            }
        })
        .collect();
    let tail: Vec<f64> = (0..n).map(|_| 1.0 / u().max(1e-12) - 1.0).collect();
    for (name, xs) in [
        ("eta", &eta),
        ("lognormal", &lognormal),
        ("signed", &signed),
        ("tail", &tail),
    ] {
        let worst = check_sketch(name, xs);
        eprintln!("sketch, {name}: worst relative error {worst:.2e} (bound {ALPHA:e})");
    }
}

#[test]
fn a_group_past_the_exact_limit_gets_estimates_within_the_bound() {
    let n = tswm::stats::summary::EXACT_MAX + 20_000;
    let dir = tempfile::tempdir().unwrap();
    let sweep = format!(
        "[base]\nfriction = \"coulomb\"\nmu = 0.05\nt_end = 0.2\n\
         [sampling]\nmethod = \"monte_carlo\"\nn = {n}\nseed = 5\n\
         [[tolerance]]\nparam = \"f2\"\ndist = \"uniform\"\ntol_rel = 0.5\n\
         [[tolerance]]\nparam = \"gamma_deg\"\ndist = \"normal\"\ntol = 1.0\n"
    );
    std::fs::write(dir.path().join("big.toml"), sweep).unwrap();
    run_ok(&cpu(&["run", "big.toml", "--out", "o"]), dir.path());
    let o = dir.path().join("o");
    let cols = columns(&o);
    let (h, rows) = read_csv(&o.join("summary.csv"));
    let mut checked = 0;
    for r in rows.iter().filter(|r| col(&h, r, "kind") == "number") {
        let name = col(&h, r, "name");
        if col(&h, r, "count") == "0" {
            // A column no lane has (n1_end without gear terms): no cell in
            // lanes.csv, nothing estimated.
            assert!(!cols.contains_key(name), "{name}");
            assert_eq!(col(&h, r, "quantiles"), "", "{name}");
            continue;
        }
        let mut v = cols[name].clone();
        assert_eq!(col(&h, r, "quantiles"), "estimate", "{name}");
        v.sort_by(f64::total_cmp);
        for (p, q) in PROBS {
            let got: f64 = col(&h, r, p).parse().unwrap();
            let want = v[(q * (v.len() - 1) as f64).floor() as usize];
            assert!(
                (got - want).abs() <= ALPHA * want.abs() + TINY,
                "{name} {p}: {got} vs {want}"
            );
            checked += 1;
        }
    }
    assert!(checked >= 50, "{checked}");
}
