//! docs/model.md section 12: the drive in gear terms. The paper's drive
//! given as catalogue data reproduces the wedge's reference cases; every
//! duplicate or contradictory gear input is refused with one line; a
//! tolerance on a gear term moves the wedge parameters that follow from it.

use crate::common::*;
use tswm::input::lanes::Source;
use tswm::integrator::{simulate, LaneResult, Settings};
use tswm::model::Lane;
use tswm::params::{Num, Params};

fn read_lanes(name: &str) -> Vec<Params> {
    let src = Source::open(None, Some(&fixture(name))).unwrap();
    let mut cols = tswm::params::ParamColumns::default();
    src.reader().unwrap().fill(100, &mut cols).unwrap();
    cols.rows()
}

fn run_cpu(params: &[Params]) -> Vec<LaneResult> {
    params
        .iter()
        .map(|p| simulate(&Lane::new(p, &[]), &[], &Settings::default()))
        .collect()
}

/// |a − b| / |b|, 0 when both are 0 or both NaN.
fn rel(a: f64, b: f64) -> f64 {
    if a == b || (a.is_nan() && b.is_nan()) {
        0.0
    } else {
        (a - b).abs() / b.abs()
    }
}

/// The section 7 lanes in gear terms become the wedge's lanes to 1e-9
/// relative; run, they give the wedge lanes' results to 1e-9 relative, and
/// so the fixtures' values within the bounds the wedge lanes keep.
#[test]
fn paper_drive_in_gear_terms_reproduces_the_reference_cases_on_cpu() {
    let gear = read_lanes("paper_gear_lanes.csv");
    let wedge = read_lanes("paper_lanes.csv");
    assert_eq!(gear.len(), 5);
    let mut worst_param = 0.0f64;
    for (i, (g, w)) in gear.iter().zip(&wedge).enumerate() {
        for n in [
            Num::M1,
            Num::M2,
            Num::GammaDeg,
            Num::F2,
            Num::VSync,
            Num::VCrit,
            Num::FCrit,
        ] {
            let d = rel(g.get(n), w.get(n));
            worst_param = worst_param.max(d);
            assert!(
                d < 1e-9,
                "lane {i} {}: {} vs {}",
                n.name(),
                g.get(n),
                w.get(n)
            );
        }
    }
    let (rg, rw) = (run_cpu(&gear), run_cpu(&wedge));
    let mut worst = 0.0f64;
    for (a, b) in rg.iter().zip(&rw) {
        assert_eq!(
            (a.status, a.contact_end, a.switches),
            (b.status, b.contact_end, b.switches)
        );
        let va = a.integrated();
        let vb = b.integrated();
        // Relative to max(1, |value|): some energies are round-off near 0.
        for (x, y) in va.iter().zip(vb) {
            worst = worst.max(rel1(*x, y));
        }
        for (x, y) in [
            (a.eta_direct, b.eta_direct),
            (a.eta_inverse, b.eta_inverse),
            (a.eta_direct_ss, b.eta_direct_ss),
            (a.eta_inverse_ss, b.eta_inverse_ss),
            (a.lock_margin_deg, b.lock_margin_deg),
            (a.t_first_switch, b.t_first_switch),
        ] {
            worst = worst.max(if x.is_nan() && y.is_nan() {
                0.0
            } else {
                rel1(x, y)
            });
        }
    }
    assert!(worst < 1e-9, "gear run vs wedge run: {worst:e}");
    let (dev, dev_t) = check_reference_cases(&rg, 1e-6, 1e-6);
    let eng = crate::engineering::check_engineering(&rg, 1e-6);
    eprintln!(
        "gear terms: parameters within {worst_param:.1e} of the wedge's, results within \
         {worst:.1e} of the wedge run; against the fixtures {dev:.1e} (switch {dev_t:.1e} s), \
         section 10 {eng:.1e}"
    );
}

/// n1_end = v1_end / R1 · 60 / 2π and n2_end = v1_end tan γ / R2 · 60 / 2π,
/// in lanes.csv, with R1 = d1 / 2 and R2 = z2 m_x / 2; empty for a lane
/// without a geometry.
/// The fixture's gear lanes run as a lane table at a reference tolerance
/// (`--tol 1e-12`) reproduce `paper_expected.csv` and
/// `paper_engineering.csv` within 1e-9 of max(1, |value|) in every number
/// and exactly in every word; at the default tolerance the bound is the
/// model's 1e-6 (the test above).
#[test]
fn gear_lanes_reproduce_the_fixtures_to_1e_9_at_a_reference_tolerance() {
    let dir = tempfile::tempdir().unwrap();
    let lanes = fixture("paper_gear_lanes.csv");
    let (_, h, rows) = run_ok(
        &cpu(&[
            "run",
            "--lanes",
            lanes.to_str().unwrap(),
            "--out",
            "o",
            "--no-report",
            "--tol",
            "1e-12",
        ]),
        dir.path(),
    );
    let mut worst = 0.0f64;
    for file in ["paper_expected.csv", "paper_engineering.csv"] {
        let (eh, expected) = read_csv(&fixture(file));
        assert_eq!(rows.len(), expected.len());
        for (row, e) in rows.iter().zip(&expected) {
            for name in eh.iter().filter(|n| *n != "lane") {
                let (want, got) = (col(&eh, e, name), col(&h, row, name));
                match (want.parse::<f64>(), got.parse::<f64>()) {
                    (Ok(w), Ok(g)) => {
                        let d = rel1(g, w);
                        worst = worst.max(d);
                        assert!(
                            d <= 1e-9,
                            "{file} lane {} {name}: {g} vs {w}",
                            col(&eh, e, "lane")
                        );
                    }
                    _ => assert_eq!(got, want, "{file} {name}"),
                }
            }
        }
    }
    eprintln!("gear lanes at --tol 1e-12: worst {worst:.2e} of max(1, |value|)");
}

#[test]
fn shaft_speeds_follow_from_the_pitch_radii() {
    let dir = tempfile::tempdir().unwrap();
    let lanes = fixture("paper_gear_lanes.csv");
    let (_, h, rows) = run_ok(
        &cpu(&["run", "--lanes", lanes.to_str().unwrap(), "--out", "o"]),
        dir.path(),
    );
    let num = |r: &[String], k: &str| col(&h, r, k).parse::<f64>().unwrap();
    let rpm = 60.0 / (2.0 * std::f64::consts::PI);
    let mut moving = 0;
    for r in &rows {
        let (r1, r2) = (num(r, "d1") / 2.0, num(r, "z2") * num(r, "m_x") / 2.0);
        let v = num(r, "v1_end");
        let tan_g = num(r, "gamma_deg").to_radians().tan();
        assert!((num(r, "n1_end") - v / r1 * rpm).abs() <= 1e-12 * (v / r1 * rpm).abs().max(1.0));
        assert!(
            (num(r, "n2_end") - v * tan_g / r2 * rpm).abs()
                <= 1e-12 * (v * tan_g / r2 * rpm).abs().max(1.0)
        );
        // The gear terms given, and the wedge's values they became.
        assert_eq!(col(&h, r, "j1"), "0.6000639999999999");
        assert!((num(r, "m1") - 586.0).abs() < 1e-9);
        moving += (v != 0.0) as usize;
    }
    assert_eq!(moving, 3);
    // Case 1 ends at 3.3958 m/s: 1013 rpm on the worm, 25.3 on the wheel.
    assert!((num(&rows[0], "n1_end") - 1013.35).abs() < 0.01);
    assert!((num(&rows[0], "n2_end") - 1013.35 / 40.0).abs() < 0.001);
    let (h, rows) = run_fixture_lanes(dir.path());
    assert!(rows.iter().all(|r| col(&h, r, "n1_end").is_empty()));
}

/// Runs a sweep file text (and optionally a lane table) that must be
/// refused: exit 2, one line with every `want`, nothing written.
fn refused(sweep: &str, lanes: Option<&str>, want: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.toml"), sweep).unwrap();
    let mut args = vec!["run", "s.toml"];
    if let Some(t) = lanes {
        std::fs::write(dir.path().join("l.csv"), t).unwrap();
        args.extend(["--lanes", "l.csv"]);
    }
    args.extend(["--out", "out", "--backend", "cpu"]);
    rejected(&args, dir.path(), want);
    assert!(!dir.path().join("out").exists(), "nothing may be written");
}

const CATALOGUE: &str = "d1 = 0.064\nz1 = 1\nz2 = 40\nm_x = 0.0064\n";
/// The rest of a drive in gear terms beside [`CATALOGUE`]: the wheel's
/// inertia and the motor (the worm's inertia left to each test).
const WHEEL_AND_MOTOR: &str = "j2 = 168\nn_sync = 1000\nn_crit = 600\nt_crit = 140\n";

#[test]
fn an_inertia_given_both_ways_is_refused() {
    refused(
        &format!("[base]\n{CATALOGUE}j1 = 0.6\nm1 = 586\n"),
        None,
        &["s.toml", "line 6", "j1", "m1 is given too", "not both"],
    );
    refused(
        &format!("[base]\n{CATALOGUE}"),
        Some("j2,m2\n168,10275\n"),
        &["l.csv", "row 1", "j2", "m2 is given too"],
    );
}

#[test]
fn a_torque_given_both_ways_is_refused() {
    refused(
        &format!("[base]\n{CATALOGUE}t2 = 611\nf2 = 4774\n"),
        None,
        &["s.toml", "t2", "f2 is given too"],
    );
    refused(
        &format!("[base]\n{CATALOGUE}motor = \"constant\"\nt1 = 20\nf1 = 600\n"),
        None,
        &["s.toml", "t1", "f1 is given too"],
    );
}

#[test]
fn a_motor_given_both_ways_or_in_part_is_refused() {
    refused(
        &format!("[base]\n{CATALOGUE}n_sync = 1000\nn_crit = 600\nt_crit = 140\nv_sync = 3.35\n"),
        None,
        &["s.toml", "n_sync", "v_sync is given too"],
    );
    refused(
        &format!("[base]\n{CATALOGUE}n_sync = 1000\nt_crit = 140\n"),
        None,
        &[
            "s.toml",
            "n_crit",
            "is missing",
            "n_sync, n_crit and t_crit together",
        ],
    );
    refused(
        &format!("[base]\n{CATALOGUE}n1_0 = 500\nv1_0 = 1\n"),
        None,
        &["s.toml", "n1_0", "v1_0 is given too"],
    );
}

#[test]
fn the_lead_angle_given_both_ways_is_refused() {
    refused(
        &format!("[base]\n{CATALOGUE}gamma_deg = 5.7\n"),
        None,
        &[
            "s.toml",
            "line 6",
            "gamma_deg",
            "given twice",
            "tan gamma = z1 m_x / d1",
        ],
    );
    // On a grid axis beside a catalogue geometry: every lane is refused.
    refused(
        &format!("[base]\n{CATALOGUE}[[grid]]\nparam = \"gamma_deg\"\nvalues = [4, 5]\n"),
        None,
        &["s.toml", "lane 0", "gamma_deg", "given twice"],
    );
}

#[test]
fn a_geometry_given_in_part_or_twice_is_refused() {
    refused(
        "[base]\nd1 = 0.064\nz1 = 1\nz2 = 40\n",
        None,
        &["s.toml", "m_x", "is missing", "all of d1, z1, z2 and m_x"],
    );
    refused(
        &format!("[base]\n{CATALOGUE}r1 = 0.032\nr2 = 0.128\n"),
        None,
        &["s.toml", "r1", "geometry a second time"],
    );
    refused(
        "[base]\nr1 = 0.032\n",
        None,
        &["s.toml", "r2", "is missing", "r1 and r2"],
    );
}

#[test]
fn a_gear_term_without_a_geometry_is_refused() {
    for (key, text) in [
        ("t2", "t2 = 611"),
        ("j1", "j1 = 0.6"),
        ("n1_0", "n1_0 = 100"),
    ] {
        refused(
            &format!("[base]\n{text}\n"),
            None,
            &["s.toml", "line 2", key, "needs the drive's geometry"],
        );
    }
    refused(
        "[base]\nm1 = 586\n",
        Some("t_crit,n_sync,n_crit\n140,1000,600\n"),
        &["l.csv", "row 1", "needs the drive's geometry"],
    );
}

#[test]
fn tooth_counts_must_be_whole() {
    refused(
        "[base]\nd1 = 0.064\nz1 = 1.5\nz2 = 40\nm_x = 0.0064\n",
        None,
        &["s.toml", "line 3", "z1", "whole number in [1, 20]", "1.5"],
    );
    refused(
        &format!("[base]\n{CATALOGUE}"),
        Some("z2\n40.2\n"),
        &["l.csv", "row 1", "z2", "whole number"],
    );
}

#[test]
fn a_converted_value_out_of_range_names_the_gear_term() {
    refused(
        &format!("[base]\n{CATALOGUE}{WHEEL_AND_MOTOR}j1 = 1e-9\n"),
        None,
        &[
            "s.toml",
            "j1",
            "gives m1 = j1 / R1^2",
            "m1 must be in [1e-3, 1e9] kg",
        ],
    );
    refused(
        &format!("[base]\nd1 = 0.01\nz1 = 20\nz2 = 40\nm_x = 0.01\nj1 = 0.6\n{WHEEL_AND_MOTOR}"),
        None,
        &[
            "s.toml",
            "d1, z1, m_x",
            "gives gamma_deg",
            "gamma_deg must be in [0.5, 85] deg",
        ],
    );
}

/// A tolerance on m_x, d1 or j2 moves γ, m1 or m2 lane by lane.
#[test]
fn a_tolerance_on_a_gear_term_moves_the_wedge_per_lane() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = format!(
        "[base]\n{CATALOGUE}j1 = 0.6\n{WHEEL_AND_MOTOR}t2 = -300\nt_end = 0.5\n\
         [sampling]\nmethod = \"monte_carlo\"\nn = 40\nseed = 5\n\
         [[tolerance]]\nparam = \"m_x\"\ndist = \"uniform\"\ntol = 0.0002\n\
         [[tolerance]]\nparam = \"d1\"\ndist = \"normal\"\ntol_rel = 0.01\n\
         [[tolerance]]\nparam = \"j2\"\ndist = \"uniform\"\ntol_rel = 0.1\n"
    );
    std::fs::write(dir.path().join("s.toml"), sweep).unwrap();
    let (_, h, rows) = run_ok(&cpu(&["run", "s.toml", "--out", "o"]), dir.path());
    assert_eq!(rows.len(), 40);
    let num = |r: &[String], k: &str| col(&h, r, k).parse::<f64>().unwrap();
    let mut gammas = Vec::new();
    for r in &rows {
        let (d1, mx, j2) = (num(r, "d1"), num(r, "m_x"), num(r, "j2"));
        let r2 = 40.0 * mx / 2.0;
        let g = (mx / d1).atan().to_degrees();
        assert!(
            (num(r, "gamma_deg") - g).abs() < 1e-12,
            "gamma follows m_x and d1"
        );
        assert!(
            rel(num(r, "m2"), j2 / (r2 * r2)) < 1e-14,
            "m2 follows j2 and m_x"
        );
        assert!(
            rel(num(r, "m1"), 0.6 / (d1 * d1 / 4.0)) < 1e-14,
            "m1 follows d1"
        );
        assert!(rel(num(r, "f2"), -300.0 / r2) < 1e-14, "f2 follows m_x");
        gammas.push(num(r, "gamma_deg"));
    }
    gammas.sort_by(f64::total_cmp);
    assert!(
        gammas[39] - gammas[0] > 0.2,
        "the lead angle varies: {gammas:?}"
    );
    // The resolved sweep gives the same lanes again (no wedge default
    // written beside its gear form).
    let again = dir.path().join("again");
    std::fs::create_dir(&again).unwrap();
    std::fs::copy(
        dir.path().join("o/sweep.resolved.toml"),
        again.join("s.toml"),
    )
    .unwrap();
    let (_, h2, rows2) = run_ok(&cpu(&["run", "s.toml", "--out", "o"]), &again);
    assert_eq!(h, h2);
    assert_eq!(rows, rows2);
}

/// A drive in gear terms without its inertias or its motor would run on
/// the paper's masses and motor (586 kg, 10,275 kg, a 3.35 m/s Kloss
/// motor): refused, naming what is missing, in a sweep file and a lane
/// table alike; with the motor cut from the start no motor is needed.
#[test]
fn a_drive_in_gear_terms_without_inertias_or_a_motor_is_refused() {
    refused(
        &format!("[base]\n{CATALOGUE}t2 = -300\n"),
        None,
        &[
            "s.toml",
            "lane 0",
            "j1",
            "is missing",
            "inertia on the worm shaft",
        ],
    );
    refused(
        &format!("[base]\n{CATALOGUE}j1 = 0.6\nt2 = -300\n"),
        None,
        &["s.toml", "j2", "is missing", "(or m2 in kg)"],
    );
    refused(
        &format!("[base]\n{CATALOGUE}j1 = 0.6\nj2 = 168\nt2 = -300\n"),
        None,
        &["s.toml", "motor", "is missing", "n_sync, n_crit and t_crit"],
    );
    refused(
        "[base]\nt2 = -300\n",
        Some("d1,z1,z2,m_x,m1,m2\n0.064,1,40,0.0064,586,10275\n"),
        &["l.csv", "row 1", "motor", "is missing"],
    );
    // Complete in wedge terms for the inertias, in gear terms for the
    // motor; or the motor cut from the start.
    for extra in [
        "m1 = 586\nm2 = 10275\nn_sync = 1000\nn_crit = 600\nt_crit = 140\n",
        "j1 = 0.6\nj2 = 168\nmotor_off = 0\nt_max = 5\n",
        "j1 = 0.6\nj2 = 168\nmotor = \"constant\"\nt1 = 20\n",
    ] {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join("s.toml"),
            format!("[base]\n{CATALOGUE}t2 = -300\n{extra}"),
        )
        .unwrap();
        run_ok(&cpu(&["run", "s.toml", "--out", "o"]), dir.path());
    }
}
