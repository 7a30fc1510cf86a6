//! Answers a user can trust: the report of any folder tswm can write (and
//! of one that was tampered with) is a page or one error line, never a
//! panic or a hang; undecided lanes are said to be undecided; folders do
//! not mix; shards are verified. One test per defect found by probing.

mod answers;
mod charts;
mod folders;
mod input;
mod report_input;
mod tampered_shards;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::common::*;

/// Runs the sweep `text` on the CPU into `dir/o` and returns the report.
fn report_of(dir: &Path, text: &str) -> String {
    file(dir, "s.toml", text);
    run_ok(&cpu(&["run", "s.toml", "--out", "o"]), dir);
    std::fs::read_to_string(dir.join("o/report.html")).unwrap()
}

/// `tswm report o` in `dir`, killed after `secs`: its output.
fn report_within(dir: &Path, secs: u64) -> std::process::Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_tswm"))
        .args(["report", "o"])
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(secs) {
            let _ = child.kill();
            panic!("tswm report did not finish in {secs} s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// Replaces the cell of `column` in data row `row` (0-based) of
/// `dir/o/lanes.csv` with `value`.
fn set_cell(dir: &Path, row: usize, column: &str, value: &str) {
    let p = dir.join("o/lanes.csv");
    let text = std::fs::read_to_string(&p).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let i = lines[0].split(',').position(|h| h == column).unwrap();
    let mut cells: Vec<String> = lines[row + 1].split(',').map(str::to_string).collect();
    cells[i] = value.to_string();
    lines[row + 1] = cells.join(",");
    std::fs::write(&p, lines.join("\n") + "\n").unwrap();
}

const SMALL: &str = "[base]\nt_end = 0.3\n[[grid]]\nparam = \"f2\"\nvalues = [-3000.0, 3000.0]\n\
                     [[grid]]\nparam = \"gamma_deg\"\nvalues = [5.0, 10.0]\n";
