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
