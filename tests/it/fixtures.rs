//! MODEL.md section 7: the five reference cases, from the shared fixtures,
//! through the lane-table path and the CPU backend.

use crate::common::*;
use tswm::integrator::{simulate, Settings};
use tswm::lanes::Source;
use tswm::model::Lane;

/// Discrete fields must be identical; times within 1e-6 s; x1, v1 and
/// energies within 1e-6 relative to max(1, |value|) (issue 2).
#[test]
fn model_md_reference_cases_on_cpu() {
    let src = Source::table(&fixture("paper_lanes.csv"), None).unwrap();
    let mut params = Vec::new();
    src.reader().unwrap().fill(100, &mut params).unwrap();
    let (h, expected) = read_csv(&fixture("paper_expected.csv"));
    assert_eq!(params.len(), 5);
    assert_eq!(expected.len(), 5);
    let (mut worst, mut worst_t) = (0.0f64, 0.0f64);
    for (p, e) in params.iter().zip(&expected) {
        let r = simulate(&Lane::new(p, None), None, &Settings::default());
        let lane = col(&h, e, "lane");
        assert_eq!(r.status.name(), col(&h, e, "status"), "lane {lane}");
        assert_eq!(
            r.switches.to_string(),
            col(&h, e, "switches"),
            "lane {lane}"
        );
        assert_eq!(
            r.reversals.to_string(),
            col(&h, e, "reversals"),
            "lane {lane}"
        );
        assert_eq!(r.sticks.to_string(), col(&h, e, "sticks"), "lane {lane}");
        assert_eq!(
            r.contact_end.name(),
            col(&h, e, "contact_end"),
            "lane {lane}"
        );
        match col(&h, e, "t_first_switch") {
            "" => assert!(r.t_first_switch.is_nan(), "lane {lane}"),
            t => {
                let t: f64 = t.parse().unwrap();
                worst_t = worst_t.max((r.t_first_switch - t).abs());
                assert!(
                    (r.t_first_switch - t).abs() <= 1e-6,
                    "lane {lane}: {} vs {t}",
                    r.t_first_switch
                );
                // The paper's own figure: the first switch at 0.486 s.
                assert!((r.t_first_switch - 0.486).abs() < 0.001);
            }
        }
        for (name, got) in [
            ("x1_end", r.x1_end),
            ("v1_end", r.v1_end),
            ("w_motor", r.w_motor),
            ("w_load", r.w_load),
            ("w_friction", r.w_friction),
        ] {
            let want: f64 = col(&h, e, name).parse().unwrap();
            worst = worst.max(rel1(got, want));
            assert!(
                rel1(got, want) <= 1e-6,
                "lane {lane} {name}: {got} vs {want}"
            );
        }
    }
    eprintln!("CPU, MODEL.md cases: worst value deviation {worst:.2e}, first switch off by {worst_t:.2e} s");
}

/// The copies under tests/fixtures are the shared fixtures, unchanged.
#[test]
fn fixture_copies_match_shared() {
    let shared = root().join("../shared/fixtures");
    if !shared.exists() {
        eprintln!(
            "skipped: {} not found (the copies under tests/fixtures are used)",
            shared.display()
        );
        return;
    }
    for f in ["paper_lanes.csv", "paper_expected.csv"] {
        assert_eq!(
            std::fs::read(shared.join(f)).unwrap(),
            std::fs::read(fixture(f)).unwrap(),
            "{f}"
        );
    }
}
