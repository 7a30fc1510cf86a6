//! Accuracy of the f64 path on lanes drawn as a user would draw them
//! (`testmodels::random_user_lanes`): against the same model integrated at
//! a tolerance five orders tighter, and against the energy balance.

use crate::common::rel1;
use rayon::prelude::*;
use tswm::input::testmodels::random_user_lanes;
use tswm::integrator::{simulate, LaneResult, Settings};
use tswm::model::Lane;

const N: usize = 2000;

fn discrete(
    r: &LaneResult,
) -> (
    tswm::integrator::Status,
    u32,
    u32,
    u32,
    tswm::integrator::Contact,
) {
    (r.status, r.switches, r.reversals, r.sticks, r.contact_end)
}

/// within 1e-6 (s for switch times; relative to max(1, |value|)
/// for x1, v1 and energies) of a high-accuracy integration, with identical
/// discrete fields on at least 99 % of lanes.
#[test]
fn random_lanes_match_a_tight_reference() {
    let specs = random_user_lanes(N, 2026);
    let reference = Settings {
        tol: 1e-13,
        refine: false,
        ..Settings::default()
    };
    let pairs: Vec<(LaneResult, LaneResult)> = specs
        .par_iter()
        .map(|s| {
            let l = Lane::new(&s.resolve(&[]).unwrap(), &[]);
            (
                simulate(&l, &[], &Settings::default()),
                simulate(&l, &[], &reference),
            )
        })
        .collect();
    let mut same = 0;
    let mut worst = (0.0f64, 0usize, "");
    for (i, (a, b)) in pairs.iter().enumerate() {
        if discrete(a) != discrete(b) {
            eprintln!(
                "lane {i}: discrete fields differ: {:?} vs {:?}",
                discrete(a),
                discrete(b)
            );
            continue;
        }
        same += 1;
        for (name, x, y) in [
            ("x1_end", a.x1_end, b.x1_end),
            ("v1_end", a.v1_end, b.v1_end),
            ("w_motor", a.w_motor, b.w_motor),
            ("w_load", a.w_load, b.w_load),
            ("w_friction", a.w_friction, b.w_friction),
        ] {
            if rel1(x, y) > worst.0 {
                worst = (rel1(x, y), i, name);
            }
        }
        if a.switches > 0 && (a.t_first_switch - b.t_first_switch).abs() > worst.0 {
            worst = (
                (a.t_first_switch - b.t_first_switch).abs(),
                i,
                "t_first_switch",
            );
        }
    }
    eprintln!(
        "{same}/{N} lanes with identical discrete fields; worst deviation {:.3e} (lane {}, {})",
        worst.0, worst.1, worst.2
    );
    assert!(
        same as f64 >= 0.99 * N as f64,
        "only {same} of {N} lanes agree in their discrete fields"
    );
    assert!(
        worst.0 <= 1e-6,
        "lane {} {}: deviation {:e} > 1e-6",
        worst.1,
        worst.2,
        worst.0
    );
    // The draw must exercise every regime the bound is claimed for.
    let count = |f: &dyn Fn(&LaneResult) -> bool| pairs.iter().filter(|(a, _)| f(a)).count();
    assert!(count(&|r| r.switches > 0) > N / 20);
    assert!(count(&|r| r.reversals > 0) > N / 50);
    assert!(count(&|r| r.sticks > 0) > N / 50);
}

/// docs/model.md section 6: w_motor + w_load − w_friction = ½ (m1 + m2 tan²γ) ẋ1²
/// (from rest), the three works being integrated separately.
#[test]
fn energy_balances_on_random_lanes() {
    let specs = random_user_lanes(N, 77);
    let worst = specs
        .par_iter()
        .map(|s| {
            let p = s.resolve(&[]).unwrap();
            let l = Lane::new(&p, &[]);
            let r = simulate(&l, &[], &Settings::default());
            assert!(
                r.w_friction >= -1e-6,
                "friction work must not be negative: {}",
                r.w_friction
            );
            let ke =
                0.5 * (l.m1 + l.m2 * l.tan_g * l.tan_g) * (r.v1_end * r.v1_end - l.v1_0 * l.v1_0);
            let scale = [
                1.0,
                r.w_motor.abs(),
                r.w_load.abs(),
                r.w_friction.abs(),
                ke.abs(),
            ]
            .into_iter()
            .fold(0.0, f64::max);
            (r.w_motor + r.w_load - r.w_friction - ke).abs() / scale
        })
        .reduce(|| 0.0, f64::max);
    eprintln!("worst energy-balance residual over {N} lanes: {worst:.3e}");
    assert!(worst <= 1e-6, "energy balance off by {worst:e}");
}

/// Interleaving changes nothing: every field, bit for bit.
#[test]
fn simulate_batch_equals_simulate() {
    use tswm::integrator::{simulate, simulate_batch, RowPath, Settings};
    use tswm::model::{FrictionTable, Lane};
    use tswm::params::{FrictionKind, Num};

    let table = FrictionTable::new(&[0.0, 0.5, 2.0, 5.0], &[0.13, 0.07, 0.05, 0.04]).unwrap();
    let mut specs = tswm::input::testmodels::random_user_lanes(300, 5);
    for (i, s) in specs.iter_mut().enumerate().filter(|(i, _)| i % 5 == 0) {
        s.friction = Some(FrictionKind::Table);
        s.num[Num::Mu as usize] = None;
        s.num[Num::MuStatic as usize] = None;
        s.set(Num::F2, -3000.0 + 20.0 * i as f64);
    }
    let lanes: Vec<Lane> = specs
        .iter()
        .map(|s| {
            Lane::new(
                &s.resolve(&[tswm::params::TableName::UNNAMED]).unwrap(),
                std::slice::from_ref(&table),
            )
        })
        .collect();
    let set = Settings::default();
    let mut out = vec![simulate(&lanes[0], std::slice::from_ref(&table), &set); lanes.len()];
    simulate_batch(&lanes, std::slice::from_ref(&table), &set, &mut out);
    for (l, got) in lanes.iter().zip(&out) {
        let want = simulate(l, std::slice::from_ref(&table), &set);
        assert_eq!(format!("{want:?}"), format!("{got:?}"));
    }
    // Some of them are run again (the batch's second, interleaved pass).
    let refined = out.iter().filter(|r| r.path == RowPath::Refined).count();
    assert!(refined > 0, "no lane refined");
}
