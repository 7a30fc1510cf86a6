//! docs/model.md section 10: energies each body puts into the mesh and takes
//! out of it, both efficiencies, and the static self-locking margin.

use crate::common::*;
use rayon::prelude::*;
use tswm::input::lanes::Source;
use tswm::integrator::{simulate, LaneResult, Settings};
use tswm::model::Lane;

fn fixture_lanes() -> Vec<tswm::params::Params> {
    let src = Source::open(None, Some(&fixture("paper_lanes.csv"))).unwrap();
    let mut cols = tswm::params::ParamColumns::default();
    src.reader().unwrap().fill(100, &mut cols).unwrap();
    cols.rows()
}

/// The section 10 columns against `paper_engineering.csv`: energies
/// within `bound` of max(1, |value|), efficiencies and the margin within
/// `bound` absolute, empty cells where the fixture's are. Returns the
/// worst deviation.
pub fn check_engineering(res: &[LaneResult], bound: f64) -> f64 {
    let (h, expected) = read_csv(&fixture("paper_engineering.csv"));
    assert_eq!(res.len(), expected.len());
    let mut worst = 0.0f64;
    for (r, e) in res.iter().zip(&expected) {
        let lane = col(&h, e, "lane");
        assert_eq!(r.status.name(), col(&h, e, "status"), "lane {lane}");
        for (name, got, energy) in [
            ("w1_in", r.w1_in, true),
            ("w1_out", r.w1_out, true),
            ("w2_in", r.w2_in, true),
            ("w2_out", r.w2_out, true),
            ("eta_direct", r.eta_direct, false),
            ("eta_inverse", r.eta_inverse, false),
            ("eta_direct_ss", r.eta_direct_ss, false),
            ("eta_inverse_ss", r.eta_inverse_ss, false),
            ("lock_margin_deg", r.lock_margin_deg, false),
        ] {
            match col(&h, e, name) {
                "" => assert!(got.is_nan(), "lane {lane} {name}: {got}, empty expected"),
                want => {
                    let want: f64 = want.parse().unwrap();
                    let d = if energy {
                        rel1(got, want)
                    } else {
                        (got - want).abs()
                    };
                    worst = worst.max(d);
                    assert!(d <= bound, "lane {lane} {name}: {got} vs {want}");
                }
            }
        }
    }
    worst
}

#[test]
fn engineering_columns_reproduce_the_fixture_on_cpu() {
    let res: Vec<_> = fixture_lanes()
        .iter()
        .map(|p| simulate(&Lane::new(p, &[]), &[], &Settings::default()))
        .collect();
    let worst = check_engineering(&res, 1e-6);
    eprintln!("CPU, section 10 fixture: worst deviation {worst:.2e} (bound 1e-6)");
}

/// Every row of a run carries the columns after `eta_end` and `steps`.
#[test]
fn lanes_csv_has_the_engineering_columns() {
    let dir = tempfile::tempdir().unwrap();
    let (h, rows) = run_fixture_lanes(dir.path());
    let at = |c: &str| h.iter().position(|x| x == c).unwrap();
    assert_eq!(at("w1_in"), at("steps") + 1);
    assert_eq!(at("lock_margin_deg"), at("w1_in") + 8);
    let (eh, expected) = read_csv(&fixture("paper_engineering.csv"));
    for (row, e) in rows.iter().zip(&expected) {
        assert_eq!(
            col(&h, row, "eta_inverse").is_empty(),
            col(&eh, e, "eta_inverse").is_empty()
        );
    }
}

/// w1_in − w1_out + w2_in − w2_out = w_friction, the four integrated apart.
#[test]
fn mesh_energies_add_up_to_the_heat() {
    let specs = tswm::input::testmodels::random_user_lanes(2000, 404);
    let worst = specs
        .par_iter()
        .map(|s| {
            let r = simulate(
                &Lane::new(&s.resolve(&[]).unwrap(), &[]),
                &[],
                &Settings::default(),
            );
            let sum = r.w1_in - r.w1_out + r.w2_in - r.w2_out;
            rel1(sum, r.w_friction)
        })
        .reduce(|| 0.0, f64::max);
    eprintln!(
        "worst |w1_in - w1_out + w2_in - w2_out - w_friction| / max(1, w_friction): {worst:.2e}"
    );
    assert!(worst <= 1e-6, "{worst:e}");
}

/// Steady direct flow: eta_direct tends to eta_direct_ss (case 2 of
/// docs/model.md runs in a-a at nearly constant speed by its end).
#[test]
fn steady_direct_flow_approaches_the_steady_efficiency() {
    let mut s = tswm::params::Spec::default();
    s.set(tswm::params::Num::F2, -4774.0);
    s.set(tswm::params::Num::TEnd, 60.0);
    let r = simulate(
        &Lane::new(&s.resolve(&[]).unwrap(), &[]),
        &[],
        &Settings::default(),
    );
    assert!(
        (r.eta_direct - r.eta_direct_ss).abs() < 0.005,
        "{} vs {}",
        r.eta_direct,
        r.eta_direct_ss
    );
}
