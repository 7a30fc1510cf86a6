//! `[report] pareto`: the front the report lists is exactly the set of
//! designs no other design beats, found here by comparing every pair of
//! designs from lanes.csv (each grid point's mean over its drives in a
//! tolerance study), over random grids, objectives and directions; bad
//! objectives are refused.

use std::collections::BTreeSet;
use std::path::Path;

use crate::common::{col, cpu, file, read_csv, rejected, tswm};
use crate::property::Gen;

/// Result number columns that move with the grid below.
const COLUMNS: [&str; 6] = [
    "eta_direct_ss",
    "lock_margin_deg",
    "eta_direct_start",
    "w_friction",
    "x1_end",
    "eta_inverse_start",
];

/// The designs the report lists on the front, and its "N of M" counts.
fn listed(dir: &Path) -> (BTreeSet<u64>, usize, usize) {
    let html = std::fs::read_to_string(dir.join("report.html")).unwrap();
    let at = html.find("<h2>Trade-offs").expect("a trade-offs section");
    let sec = &html[at..];
    let sec = &sec[..sec[4..].find("<h2>").map_or(sec.len(), |e| e + 4)];
    let ids = sec
        .split("<td class=\"l\">")
        .skip(1)
        .filter_map(|c| c.split('<').next()?.rsplit(' ').next()?.parse().ok())
        .collect();
    let counts = sec.split("; ").nth(1).expect("the counts");
    let nums: Vec<usize> = counts
        .split(' ')
        .filter_map(|w| w.parse().ok())
        .take(2)
        .collect();
    (ids, nums[0], nums[1])
}

/// The non-dominated designs by every pair: `v[d]` the objectives' gains.
fn brute_front(v: &[(u64, Vec<f64>)]) -> BTreeSet<u64> {
    let dominates = |a: &[f64], b: &[f64]| {
        a.iter().zip(b).all(|(x, y)| x >= y) && a.iter().zip(b).any(|(x, y)| x > y)
    };
    v.iter()
        .filter(|(_, b)| !v.iter().any(|(_, a)| dominates(a, b)))
        .map(|(id, _)| *id)
        .collect()
}

#[test]
fn the_listed_front_is_every_design_no_other_beats() {
    let t = tempfile::tempdir().unwrap();
    let mut g = Gen(0x9a7e70);
    for case in 0..8 {
        let k = 2 + g.below(2) as usize;
        let mut cols: Vec<&str> = Vec::new();
        while cols.len() < k {
            let c = *g.pick(&COLUMNS);
            if !cols.contains(&c) {
                cols.push(c);
            }
        }
        let max: Vec<bool> = (0..k).map(|_| g.below(2) == 0).collect();
        let items: Vec<String> = cols
            .iter()
            .zip(&max)
            .map(|(c, m)| format!("\"{} {c}\"", if *m { "max" } else { "min" }))
            .collect();
        let study = case % 2 == 1;
        let n_g = 4 + g.below(6);
        let text = format!(
            "[base]\nfriction = \"coulomb\"\nmu = 0.05\nmu_static = 0.08\nf2 = -3000.0\n\
             t_end = 0.5\n\n[[grid]]\nparam = \"gamma_deg\"\nfrom = 1.0\nto = {}\nn = {n_g}\n\n\
             [[grid]]\nparam = \"alpha_n_deg\"\nvalues = [10.0, 20.0, 30.0]\n\n{}\
             [report]\npareto = [{}]\n",
            3.0 + 9.0 * g.unit(),
            if study {
                "[sampling]\nmethod = \"monte_carlo\"\nn = 4\nseed = 3\n\n[[tolerance]]\n\
                 param = \"mu\"\ndist = \"uniform\"\ntol_rel = 0.2\n\n"
            } else {
                ""
            },
            items.join(", ")
        );
        file(t.path(), "p.toml", &text);
        let out = t.path().join(format!("o{case}"));
        let o = tswm(
            &cpu(&["run", "p.toml", "--out", out.to_str().unwrap()]),
            t.path(),
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        // Each design's objectives: a lane's, or a grid point's mean.
        let (h, rows) = read_csv(&out.join("lanes.csv"));
        let per = if study { 4 } else { 1 };
        let mut designs: Vec<(u64, Vec<f64>)> = Vec::new();
        for (i, chunk) in rows.chunks(per).enumerate() {
            let v: Vec<f64> = cols
                .iter()
                .zip(&max)
                .map(|(c, m)| {
                    let xs: Vec<f64> = chunk
                        .iter()
                        .filter_map(|r| col(&h, r, c).parse::<f64>().ok())
                        .collect();
                    let mean = xs.iter().sum::<f64>() / xs.len() as f64;
                    if *m {
                        mean
                    } else {
                        -mean
                    }
                })
                .collect();
            if v.iter().all(|x| x.is_finite()) {
                designs.push((i as u64, v));
            }
        }
        let want = brute_front(&designs);
        let (ids, on, of) = listed(&out);
        assert_eq!(of, rows.len() / per, "{text}");
        assert!(!want.is_empty() && !ids.is_empty(), "{text}");
        assert_eq!(on, want.len(), "{text}");
        if want.len() <= 60 {
            assert_eq!(ids, want, "{text}");
        }
    }
}

#[test]
fn bad_objectives_are_refused_with_one_line() {
    let t = tempfile::tempdir().unwrap();
    let base = "[base]\nfriction = \"coulomb\"\n\n[[grid]]\nparam = \"gamma_deg\"\n\
                values = [2.0, 4.0]\n\n[report]\n";
    for (pareto, want) in [
        ("[\"eta_direct_ss\"]", vec!["report.pareto", "2 or 3"]),
        (
            "[\"eta_direct_ss\", \"hold\"]",
            vec!["report.pareto", "not a result number column"],
        ),
        (
            "[\"eta_direct_ss\", \"best lock_margin_deg\"]",
            vec!["report.pareto", "max NAME"],
        ),
        (
            "[\"eta_direct_ss\", \"min eta_direct_ss\"]",
            vec!["report.pareto", "twice"],
        ),
        (
            "[\"eta_direct_ss\", \"lock_margin_dg\"]",
            vec!["report.pareto", "lock_margin_deg"],
        ),
    ] {
        file(t.path(), "bad.toml", &format!("{base}pareto = {pareto}\n"));
        rejected(
            &cpu(&["run", "bad.toml", "--out", "o"]),
            t.path(),
            &[&["bad.toml"][..], &want].concat(),
        );
        assert!(!t.path().join("o").exists());
    }
}

/// A front too large to keep (one lead-angle axis of 6,000 values: every
/// design trades efficiency for locking margin, so all are on it) is said,
/// with neither a chart nor a list.
#[test]
fn a_front_too_large_to_keep_is_said_not_drawn() {
    let t = tempfile::tempdir().unwrap();
    file(
        t.path(),
        "p.toml",
        "[base]\nfriction = \"coulomb\"\nmu = 0.05\nf2 = -3000.0\nt_end = 0.2\n\n\
         [[grid]]\nparam = \"gamma_deg\"\nfrom = 1.0\nto = 20.0\nn = 6000\n\n\
         [report]\npareto = [\"eta_direct_ss\", \"lock_margin_deg\"]\n",
    );
    let o = tswm(&cpu(&["run", "p.toml", "--out", "o"]), t.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let html = std::fs::read_to_string(t.path().join("o/report.html")).unwrap();
    let sec = &html[html.find("<h2>Trade-offs").unwrap()..];
    let sec = &sec[..sec[4..].find("<h2>").map_or(sec.len(), |e| e + 4)];
    assert!(
        sec.contains("more than 5000 of 6000 designs are on it"),
        "{sec}"
    );
    assert!(sec.contains("neither drawn nor listed"), "{sec}");
    assert!(!sec.contains("<svg") && !sec.contains("<table"), "{sec}");
}
