//! The docs against the code: every parameter and every result column is
//! documented, and the docs name none that does not exist; the README is
//! a front door; no page refers to anything outside the repository.

use std::collections::BTreeSet;

use crate::common::root;
use tswm::params::Param;

/// The pages a user or maintainer reads.
fn pages() -> Vec<(String, String)> {
    let mut v: Vec<std::path::PathBuf> = std::fs::read_dir(root().join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    v.extend(["README.md", "ARCHITECTURE.md", "CONTRIBUTING.md"].map(|f| root().join(f)));
    v.sort();
    v.into_iter()
        .map(|p| {
            let name = p.strip_prefix(root()).unwrap().display().to_string();
            (name, std::fs::read_to_string(&p).unwrap())
        })
        .collect()
}

fn page(name: &str) -> String {
    std::fs::read_to_string(root().join(name)).unwrap()
}

/// Snake-case names in backticks: what a page names as a parameter,
/// column, key or word of the tool.
fn named(text: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for part in text.split('`').skip(1).step_by(2) {
        let snake = part.contains('_')
            && part.chars().next().is_some_and(|c| c.is_ascii_lowercase())
            && part
                .chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
        if snake {
            out.insert(part.to_string());
        }
    }
    out
}

#[test]
fn every_parameter_and_column_is_documented() {
    let guide = page("docs/guide.md");
    for p in Param::COLUMNS {
        assert!(
            guide.contains(&format!("| `{}` |", p.name())),
            "docs/guide.md has no row for the parameter {}",
            p.name()
        );
    }
    let outputs = page("docs/outputs.md");
    for c in tswm::columns::results() {
        assert!(
            outputs.contains(&format!("| `{}` |", c.name)),
            "docs/outputs.md has no row for the column {}",
            c.name
        );
    }
}

/// A name in backticks that looks like a parameter or column is one: a
/// misspelled or removed name fails here. The other names the pages use
/// (keys of a sweep file, words of the tool, code, crates) are listed.
#[test]
fn the_docs_name_no_parameter_or_column_that_does_not_exist() {
    let mut known: BTreeSet<String> = Param::COLUMNS
        .iter()
        .map(|p| p.name().to_string())
        .collect();
    known.extend(tswm::columns::results().iter().map(|c| c.name.to_string()));
    known.extend(tswm::integrator::Status::ALL.map(|s| s.name().to_string()));
    known.extend(tswm::integrator::Hold::ALL.map(|h| h.name().to_string()));
    known.extend(tswm::integrator::Recheck::ALL.map(|r| r.name().to_string()));
    let other = [
        // sweep-file keys and values
        "at_least",
        "tol_rel",
        "friction_table",
        "monte_carlo",
        "latin_hypercube",
        // the model's symbols as code spells them
        "mu_s",
        // code named in the maintainers' pages
        "finish_step",
        "locate_root",
        "mu_sliding",
        "try_step",
        "lane_spec",
        // crates
        "rand_chacha",
        "rand_core",
        "fearless_simd",
        // wgpu's limits, which `tswm devices` prints
        "max_buffer_size",
        "max_compute_workgroups_per_dimension",
        "max_storage_buffer_binding_size",
    ];
    known.extend(other.map(str::to_string));
    known.extend(
        tswm::stats::summary::SUMMARY_COLUMNS
            .split(',')
            .map(str::to_string),
    );
    known.extend(
        tswm::stats::sensitivity::SENSITIVITY_COLUMNS
            .split(',')
            .map(str::to_string),
    );
    let mut unknown = Vec::new();
    for (name, text) in pages() {
        for n in named(&text) {
            if !known.contains(&n) {
                unknown.push(format!("{name}: `{n}`"));
            }
        }
    }
    assert!(
        unknown.is_empty(),
        "names no parameter, column or known word: {unknown:#?}"
    );
}

#[test]
fn the_readme_is_a_front_door_and_no_page_looks_outside_the_repository() {
    let readme = page("README.md");
    assert!(
        readme.lines().count() <= 250,
        "README.md has {} lines",
        readme.lines().count()
    );
    for cmd in [
        "cargo run --release -- run sweeps/paper.toml",
        "cargo test --release",
    ] {
        assert!(
            readme.contains(&format!("    {cmd}\n")),
            "the README lacks `{cmd}`"
        );
    }
    let ci = page(".ci/run");
    assert!(
        ci.contains("\ncargo test --release\n"),
        ".ci/run does not run the README's tests"
    );
    for (name, text) in pages() {
        assert!(!text.contains("../shared"), "{name} refers to ../shared");
        // A commit id: 7 to 40 hex digits in backticks.
        for part in text.split('`').skip(1).step_by(2) {
            let hex = part.len() >= 7
                && part.len() <= 40
                && part
                    .chars()
                    .all(|c| c.is_ascii_hexdigit() && !c.is_ascii_uppercase())
                && part.chars().any(|c| c.is_ascii_alphabetic());
            assert!(!hex, "{name} names a commit: {part}");
        }
    }
}
