//! The sweep's lanes: grid order, the resolved sweep, log axes and strata.

use super::*;
use crate::error::Result;
use crate::params::Num;
use std::path::Path;

fn parse(t: &str) -> Result<Sweep> {
    Sweep::parse(Path::new("s.toml"), t)
}

#[test]
fn grid_is_row_major_first_axis_slowest() {
    let s = parse(
        "[[grid]]\nparam = \"f2\"\nvalues = [1, 2]\n[[grid]]\nparam = \"gamma_deg\"\nfrom = 5\nto = 15\nn = 3\n",
    )
    .unwrap();
    assert_eq!(s.lane_count(), 6);
    let mut u = s.uniforms();
    let got: Vec<(f64, f64)> = (0..6)
        .map(|i| {
            let sp = s.lane_spec(i, &mut u);
            (
                sp.num[crate::params::Num::F2 as usize].unwrap(),
                sp.num[Num::GammaDeg as usize].unwrap(),
            )
        })
        .collect();
    assert_eq!(
        got,
        vec![
            (1.0, 5.0),
            (1.0, 10.0),
            (1.0, 15.0),
            (2.0, 5.0),
            (2.0, 10.0),
            (2.0, 15.0)
        ]
    );
}

/// sweep.resolved.toml stands for exactly the same lanes.
#[test]
fn resolved_sweep_gives_the_same_lanes() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("sweeps");
    for f in [
        "paper.toml",
        "efficiency_map.toml",
        "tolerance.toml",
        "million.toml",
    ] {
        let a = Sweep::from_file(&root.join(f)).unwrap();
        let text = toml::to_string(&a.resolved_toml()).unwrap();
        let b = Sweep::parse(Path::new("resolved"), &text)
            .unwrap_or_else(|e| panic!("{f}: {e}\n{text}"));
        assert_eq!(a.lane_count(), b.lane_count(), "{f}");
        let (mut ua, mut ub) = (a.uniforms(), b.uniforms());
        let n = a.lane_count();
        for i in (0..n).step_by((n / 500).max(1) as usize) {
            let pa = a.lane_spec(i, &mut ua).resolve(&a.tables.names).unwrap();
            let pb = b.lane_spec(i, &mut ub).resolve(&b.tables.names).unwrap();
            assert_eq!(format!("{pa:?}"), format!("{pb:?}"), "{f} lane {i}");
        }
    }
}

#[test]
fn log_axis_hits_its_ends() {
    let s =
        parse("[[grid]]\nparam = \"mu\"\nfrom = 0.01\nto = 1\nn = 3\nscale = \"log\"\n").unwrap();
    let v: Vec<f64> = (0..3).map(|i| s.axes[0].value(i)).collect();
    assert!(
        (v[0] - 0.01).abs() < 1e-15 && (v[1] - 0.1).abs() < 1e-15 && (v[2] - 1.0).abs() < 1e-14
    );
}

#[test]
fn latin_hypercube_puts_one_sample_in_each_stratum() {
    let s = parse(
        "[sampling]\nmethod = \"latin_hypercube\"\nn = 50\nseed = 3\n\
         [[tolerance]]\nparam = \"m1\"\ndist = \"uniform\"\ntol = 50\n",
    )
    .unwrap();
    let mut u = s.uniforms();
    let mut hit = [0; 50];
    for i in 0..50 {
        let m1 = s.lane_spec(i, &mut u).num[Num::M1 as usize].unwrap();
        // uniform on 586 ± 50: stratum of width 100/50 = 2 kg
        hit[((m1 - 536.0) / 2.0) as usize] += 1;
    }
    assert!(hit.iter().all(|&h| h == 1), "{hit:?}");
}

/// A search's drive (its draws with the searched parameter left out, then
/// the parameter set through its shift) is the lane `lane_spec_at` gives,
/// value for value: Monte Carlo, Latin hypercube and a grid, with absolute
/// and relative tolerances on the searched parameter and without one,
/// at values of either sign (-0.0 included).
#[test]
fn a_search_drive_is_the_lane_at_each_value() {
    let study = |method: &str, on: &str| {
        format!(
            "[[grid]]\nparam = \"mu\"\nvalues = [0.03, 0.06]\n\
             [sampling]\nmethod = \"{method}\"\nn = 16\nseed = 9\n\
             [[tolerance]]\nparam = \"mu_static\"\ndist = \"uniform\"\ntol_rel = 0.2\n\
             {on}\
             [[tolerance]]\nparam = \"gamma_deg\"\ndist = \"normal\"\ntol = 0.3\n"
        )
    };
    let f2_rel = "[[tolerance]]\nparam = \"f2\"\ndist = \"normal\"\ntol_rel = 0.1\n";
    let f2_abs = "[[tolerance]]\nparam = \"f2\"\ndist = \"uniform\"\ntol = 250.0\n";
    let base = "[base]\nfriction = \"coulomb\"\nmu_static = 0.08\n";
    let sweeps = [
        format!("{base}{}", study("monte_carlo", f2_rel)),
        format!("{base}{}", study("latin_hypercube", f2_abs)),
        format!("{base}{}", study("monte_carlo", "")),
        format!("{base}[[grid]]\nparam = \"mu\"\nvalues = [0.03, 0.06]\n"),
    ];
    for text in &sweeps {
        let s = parse(text).unwrap();
        for x in [-6000.0, -0.0, 0.0, 1234.5, 6000.0] {
            for i in 0..s.lane_count() {
                let (mut a, mut b) = (Spec::default(), Spec::default());
                s.lane_spec_at(i, Some((Num::F2, x)), &mut s.uniforms(), &mut a);
                let shift = s.search_drive(i, Num::F2, &mut s.uniforms(), &mut b);
                b.set(Num::F2, shift.apply(x));
                let bits = |sp: &Spec| sp.num.map(|v| v.map(f64::to_bits));
                assert_eq!(bits(&a), bits(&b), "lane {i} at {x}: {text}");
                assert_eq!((a.motor, a.friction), (b.motor, b.friction));
            }
        }
    }
}
