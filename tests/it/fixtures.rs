//! docs/model.md section 7: the five reference cases, from the fixtures,
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
    let mut cols = tswm::params::ParamColumns::default();
    src.reader().unwrap().fill(100, &mut cols).unwrap();
    let params = cols.rows();
    let res: Vec<_> = params
        .iter()
        .map(|p| simulate(&Lane::new(p, &[]), &[], &Settings::default()))
        .collect();
    let (worst, worst_t) = check_reference_cases(&res, 1e-6, 1e-6);
    eprintln!("CPU, docs/model.md cases: worst value deviation {worst:.2e}, first switch off by {worst_t:.2e} s");
}

/// The reference fixtures are the ones the model's reference values were
/// computed for, unchanged: each file's SHA-256 is the one recorded in
/// `tests/fixtures/SHA256SUMS` beside them.
#[test]
fn the_fixtures_are_unchanged() {
    use sha2::{Digest, Sha256};
    let sums = std::fs::read_to_string(fixture("SHA256SUMS")).unwrap();
    let mut n = 0;
    for line in sums.lines() {
        let (want, name) = line.split_once("  ").expect("`DIGEST  NAME` lines");
        let got: String = Sha256::digest(std::fs::read(fixture(name)).unwrap())
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect();
        assert_eq!(got, want, "{name} changed");
        n += 1;
    }
    assert_eq!(n, 5, "five fixtures");
}
