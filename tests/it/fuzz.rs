//! Replays the fuzzer's inputs through the readers they were made for:
//! the corpus (`fuzz/corpus/`), the minimised findings kept as
//! regressions (`fuzz/regressions/`), and any inputs a local fuzzing run
//! saved (`fuzz/crashes/`, not in git). Each must be read, or refused as
//! bad input in one line: no panic, no error of more than one line, no
//! other error, no hang. The findings that were defects have tests of
//! their own, below. `examples/fuzz/` makes the inputs; its readers
//! (`targets.rs`) are the ones used here.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::common::root;

#[path = "../../examples/fuzz/targets.rs"]
#[allow(dead_code)]
mod targets;

use targets::{Outcome, TARGETS};

/// The files of `fuzz/SUB/TARGET/`, sorted (none when it is not there).
fn inputs(sub: &str, target: &str) -> Vec<PathBuf> {
    let dir = root().join("fuzz").join(sub).join(target);
    let mut v: Vec<PathBuf> = match std::fs::read_dir(&dir) {
        Ok(entries) => entries.map(|e| e.unwrap().path()).collect(),
        Err(_) => Vec::new(),
    };
    v.sort();
    v
}

/// The base output folders the `report` and `merge` inputs replace a
/// file of, written once per test binary.
fn base() -> &'static Path {
    static BASE: std::sync::OnceLock<tempfile::TempDir> = std::sync::OnceLock::new();
    BASE.get_or_init(|| {
        let d = tempfile::tempdir().unwrap();
        targets::base_folders(d.path());
        d
    })
    .path()
}

/// What reading one input of `target` gives.
fn replay(target: &str, path: &Path) -> Outcome {
    let input = std::fs::read(path).unwrap();
    let scratch = tempfile::tempdir().unwrap();
    targets::replay(target, &input, base(), scratch.path())
}

#[test]
fn every_fuzz_input_is_read_or_refused_in_one_line() {
    let mut counts = [0usize; 3];
    for target in TARGETS {
        for (k, sub) in ["corpus", "regressions", "crashes"].into_iter().enumerate() {
            for path in inputs(sub, target) {
                if let Err(why) = replay(target, &path) {
                    panic!("{}: {why}", path.display());
                }
                counts[k] += 1;
            }
        }
    }
    let [corpus, regressions, crashes] = counts;
    // Said past the test harness's capture: how much was replayed.
    let _ = writeln!(
        std::io::stderr(),
        "fuzz replay: {} inputs ({corpus} corpus, {regressions} regressions, \
         {crashes} saved by a local fuzzing run), each read or refused in one line",
        corpus + regressions + crashes
    );
    assert!(corpus >= 18, "the corpus holds {corpus} inputs");
    assert!(
        regressions >= 13,
        "fuzz/regressions/ holds {regressions} inputs"
    );
}

/// The one-line refusal of the regression input `target/name`.
fn refusal(target: &str, name: &str) -> String {
    let path = root().join("fuzz/regressions").join(target).join(name);
    match replay(target, &path) {
        Ok(Some(msg)) => msg,
        other => panic!("{}: {other:?}", path.display()),
    }
}

// The first findings (the lane-table and sweep readers): an input's line
// break echoed in the error made it two lines.

#[test]
fn a_line_break_in_a_lane_table_cell_is_shown_as_backslash_n() {
    let msg = refusal("lanes", "line_break_in_a_cell.csv");
    assert!(
        msg.contains("row 2 (line 3): gamma_deg: `2\\n0` holds a line break"),
        "{msg}"
    );
}

#[test]
fn a_line_break_in_a_lane_table_header_is_shown_as_backslash_n() {
    let msg = refusal("lanes", "line_break_in_the_header.csv");
    assert!(
        msg.contains("line 1: g\\n") && msg.contains("unknown column"),
        "{msg}"
    );
}

#[test]
fn a_quote_left_open_says_so_in_one_line() {
    let msg = refusal("lanes", "quote_never_closed.csv");
    assert!(
        msg.contains("line 1: a quote (\") is opened and never closed"),
        "{msg}"
    );
}

#[test]
fn a_carriage_return_in_a_sweep_word_is_shown_as_backslash_r() {
    let msg = refusal("sweep", "carriage_return_in_a_word.toml");
    assert!(
        msg.starts_with("fuzz.toml: line 9: unknown variant `in_hype\\rcube`"),
        "{msg}"
    );
}

// The report's finding: a `sensitivity.csv` that is not UTF-8 was an
// internal error (exit 1), not bad input.

#[test]
fn a_sensitivity_csv_that_is_not_utf8_is_bad_input() {
    let msg = refusal("report", "not_utf8_sensitivity.csv");
    assert!(
        msg.contains("sensitivity.csv: line 10: s1_low:") && msg.contains("not a tswm table"),
        "{msg}"
    );
}

// The merge's finding: a shard's `traces.csv` that is not UTF-8 (its
// digest mended to match) was an internal error, not bad input.

#[test]
fn a_shard_trace_that_is_not_utf8_is_bad_input() {
    let msg = refusal("merge", "not_utf8_traces.csv");
    assert!(
        msg.ends_with("s0/traces.csv: not UTF-8 text: not a tswm traces.csv; run the shard again"),
        "{msg}"
    );
}
