//! Reproduces the choice of the f64 path's tolerance (docs/numerics.md): 3000 random user lanes (seed 11) at each given per-step
//! tolerance against the same lanes at 1e-13, with the accuracy measure of docs/numerics.md
//! (s for switch times; relative to max(1, |value|) otherwise).
//!
//!     cargo run --release --example tolerance_scan -- 1e-8 2e-8

use rayon::prelude::*;
use tswm::integrator::{simulate, Settings};
use tswm::model::Lane;

fn main() {
    let tols: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse().expect("a tolerance"))
        .collect();
    let specs = tswm::input::testmodels::random_user_lanes(3000, 11);
    let lanes: Vec<Lane> = specs
        .iter()
        .map(|s| Lane::new(&s.resolve(&[]).unwrap(), &[]))
        .collect();
    let reference: Vec<_> = lanes
        .par_iter()
        .map(|l| {
            simulate(
                l,
                &[],
                &Settings {
                    tol: 1e-13,
                    refine: false,
                    ..Settings::default()
                },
            )
        })
        .collect();
    for tol in tols {
        let set = Settings {
            tol,
            ..Settings::default()
        };
        let (mut worst, mut worst_lane, mut over, mut differ, mut steps) = (0.0f64, 0, 0, 0, 0u64);
        for (i, (l, b)) in lanes.iter().zip(&reference).enumerate() {
            let a = simulate(l, &[], &set);
            steps += a.steps as u64;
            if (a.status, a.switches, a.reversals, a.sticks, a.contact_end)
                != (b.status, b.switches, b.reversals, b.sticks, b.contact_end)
            {
                differ += 1;
                continue;
            }
            let rel = |x: f64, y: f64| (x - y).abs() / y.abs().max(1.0);
            let mut w = [
                rel(a.x1_end, b.x1_end),
                rel(a.v1_end, b.v1_end),
                rel(a.w_motor, b.w_motor),
                rel(a.w_load, b.w_load),
                rel(a.w_friction, b.w_friction),
            ]
            .into_iter()
            .fold(0.0, f64::max);
            if a.switches > 0 {
                w = w.max((a.t_first_switch - b.t_first_switch).abs());
            }
            if w > 1e-6 {
                over += 1;
            }
            if w > worst {
                worst = w;
                worst_lane = i;
            }
        }
        println!(
            "tol {tol:e}: worst {worst:.2e} (lane {worst_lane}), lanes over 1e-6: {over}, \
             discrete fields differ: {differ}, mean steps {:.1}",
            steps as f64 / lanes.len() as f64
        );
    }
}
