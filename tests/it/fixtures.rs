//! docs/model.md section 7: the five reference cases, from the shared fixtures,
//! through the lane-table path and the CPU backend.

use crate::common::*;
use tswm::input::lanes::Source;
use tswm::integrator::{simulate, Settings};
use tswm::model::Lane;

/// Discrete fields must be identical; times within 1e-6 s; x1, v1 and
/// energies within 1e-6 relative to max(1, |value|) .
#[test]
fn model_md_reference_cases_on_cpu() {
    let src = Source::open(None, Some(&fixture("paper_lanes.csv"))).unwrap();
    let mut params = Vec::new();
    src.reader().unwrap().fill(100, &mut params).unwrap();
    let res: Vec<_> = params
        .iter()
        .map(|p| simulate(&Lane::new(p, &[]), &[], &Settings::default()))
        .collect();
    let (worst, worst_t) = check_reference_cases(&res, 1e-6, 1e-6);
    eprintln!("CPU, docs/model.md cases: worst value deviation {worst:.2e}, first switch off by {worst_t:.2e} s");
}

/// The copies under tests/fixtures are the shared fixtures, unchanged.
#[test]
fn fixture_copies_match_shared() {
    let shared = root().join("../shared/fixtures");
    if !shared.exists() {
        skipped(
            "fixture_copies_match_shared",
            &format!(
                "{} not found (the copies under tests/fixtures are used)",
                shared.display()
            ),
        );
        return;
    }
    for f in [
        "paper_lanes.csv",
        "paper_expected.csv",
        "paper_engineering.csv",
        "paper_trace.csv",
        "paper_gear_lanes.csv",
    ] {
        assert_eq!(
            std::fs::read(shared.join(f)).unwrap(),
            std::fs::read(fixture(f)).unwrap(),
            "{f}"
        );
    }
}
