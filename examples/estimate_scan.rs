//! How sharp a lane's error estimate (`integrator::accuracy`) is at a
//! given tolerance (docs/performance.md, "One core against heyoka"): 4000
//! random user lanes (seed 11), 2000 paper-like lanes (seed 5) and the
//! first 150 rows of a peer lane table, each run once at each tolerance
//! without refinement and compared with a 1e-13 run. For each tolerance:
//! the steps a lane takes, how many lanes the estimate sends to be
//! refined, the lowest estimate (relative to the bound) of a lane whose
//! error is over the bound, and for weights on the estimate's two terms,
//! how many lanes would be refined and how many over the bound missed.
//!
//!     cargo run --release --example estimate_scan -- lanes.csv 1e-6 1e-7 1e-8

use rayon::prelude::*;
use tswm::integrator::accuracy::{BOUND, LIMIT, RESULTS};
use tswm::integrator::{advance, init, LaneResult, Settings, Status};
use tswm::model::Lane;
use tswm::params::{Num, Spec};

/// A lane's row, and its estimate's phase and local terms, relative to
/// max(1, |value|) of the reference row `b` (after the run).
type Run = (LaneResult, [f64; RESULTS], [f64; RESULTS]);

fn run(l: &Lane, tol: f64) -> Run {
    let set = Settings {
        tol,
        refine: false,
        ..Settings::default()
    };
    let mut st = init(l, &[]);
    advance(l, &[], &set, &mut st, u32::MAX);
    let (phase, local) = st.budget.terms();
    (st.end_state().result(l, &[]), phase, local)
}

fn main() {
    let mut args = std::env::args().skip(1);
    let table = args
        .next()
        .expect("a lane table (heyoka_peer.py --make-lanes)");
    let tols: Vec<f64> = args.map(|a| a.parse().expect("a tolerance")).collect();
    let mut specs = tswm::input::testmodels::random_user_lanes(4000, 11);
    specs.extend(tswm::input::testmodels::paper_like(2000, 5));
    let mut rd = csv::Reader::from_path(&table).expect("the lane table");
    for r in rd.records().take(150) {
        let r = r.expect("a row");
        let mut s = Spec::default();
        let cols = [Num::M1, Num::M2, Num::GammaDeg, Num::F2, Num::TEnd];
        for (k, n) in cols.into_iter().enumerate() {
            s.set(n, r[k].parse().expect("a number"));
        }
        specs.push(s);
    }
    let lanes: Vec<Lane> = specs
        .iter()
        .map(|s| Lane::new(&s.resolve(&[]).unwrap(), &[]))
        .collect();
    let reference: Vec<LaneResult> = lanes.par_iter().map(|l| run(l, 1e-13).0).collect();
    for tol in tols {
        let rows: Vec<Run> = lanes.par_iter().map(|l| run(l, tol)).collect();
        // Per lane: (phase, local, actual) of each result, relative.
        let mut terms = Vec::new();
        let mut steps = 0u64;
        for ((a, phase, local), b) in rows.iter().zip(&reference) {
            steps += u64::from(a.steps);
            let same = (a.status, a.switches, a.reversals, a.sticks)
                == (b.status, b.switches, b.reversals, b.sticks);
            if !same || b.status != Status::Ok {
                continue;
            }
            let (ai, bi) = (a.integrated(), b.integrated());
            let lane: Vec<(f64, f64, f64)> = (0..RESULTS)
                .map(|i| {
                    let sc = bi[i].abs().max(1.0);
                    (phase[i] / sc, local[i] / sc, (ai[i] - bi[i]).abs() / sc)
                })
                .collect();
            terms.push(lane);
        }
        let worst = |l: &[(f64, f64, f64)]| l.iter().map(|t| t.2).fold(0.0, f64::max);
        let est = |l: &[(f64, f64, f64)], wp: f64, wl: f64| {
            l.iter().map(|t| wp * t.0 + wl * t.1).fold(0.0, f64::max)
        };
        let lowest = terms
            .iter()
            .filter(|l| worst(l) > BOUND)
            .map(|l| est(l, 1.0, 1.0) / BOUND)
            .fold(f64::INFINITY, f64::min);
        println!(
            "tol {tol:e}: {:.1} steps a lane; {} of {} lanes over the bound; lowest estimate of \
             those {lowest:.2} x the bound",
            steps as f64 / lanes.len() as f64,
            terms.iter().filter(|l| worst(l) > BOUND).count(),
            terms.len()
        );
        let mut ratios: Vec<f64> = terms
            .iter()
            .flat_map(|l| {
                l.iter()
                    .filter(|t| t.2 > 0.05 * BOUND)
                    .map(|t| t.2 / (t.0 + t.1))
            })
            .collect();
        ratios.sort_by(f64::total_cmp);
        if !ratios.is_empty() {
            let q = |p: f64| ratios[((ratios.len() - 1) as f64 * p) as usize];
            println!(
                "  actual/estimate where actual > 5 % of the bound: {} results, median {:.3}, p99 {:.3}, max {:.3}",
                ratios.len(), q(0.5), q(0.99), q(1.0)
            );
        }
        {
            let mut by = [[0usize; 2]; RESULTS];
            for l in &terms {
                if est(l, 1.0, 1.0) > LIMIT * BOUND && worst(l) < 0.3 * BOUND {
                    let (i, t) = l
                        .iter()
                        .enumerate()
                        .max_by(|a, b| (a.1 .0 + a.1 .1).total_cmp(&(b.1 .0 + b.1 .1)))
                        .unwrap();
                    by[i][usize::from(t.1 > t.0)] += 1;
                }
            }
            println!("  needless refinements by result [phase-dominated, local-dominated]: {by:?}");
        }
        for (wp, wl) in [(1.0, 1.0), (1.0, 0.1), (0.1, 1.0), (0.3, 0.3), (3.0, 0.1)] {
            let refined = terms
                .iter()
                .filter(|l| est(l, wp, wl) > LIMIT * BOUND)
                .count();
            let missed = terms
                .iter()
                .filter(|l| est(l, wp, wl) <= LIMIT * BOUND && worst(l) > BOUND)
                .count();
            println!(
                "  phase x{wp}, local x{wl}: {refined} refined, {missed} over the bound missed"
            );
        }
    }
}
