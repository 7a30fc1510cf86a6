//! Helpers shared by the integration tests.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The repository root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The docs/model.md fixtures (reference cases; `SHA256SUMS` pins them).
pub fn fixture(name: &str) -> PathBuf {
    root().join("tests/fixtures").join(name)
}

/// What a finished run of `sweeps/paper.toml` (which traces both its
/// lanes) leaves in its folder, sorted: its files, the folder's marker of
/// them and its lock.
pub const RUN_FILES: [&str; 7] = [
    ".tswm.files",
    ".tswm.lock",
    "lanes.csv",
    "report.html",
    "summary.csv",
    "sweep.resolved.toml",
    "traces.csv",
];

/// Writes `text` to `dir/name`; its path.
pub fn file(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// Runs the `tswm` binary.
pub fn tswm(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tswm"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("run tswm")
}

/// Reads a CSV into a header and rows of strings.
pub fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut rd = csv::Reader::from_path(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let header = rd.headers().unwrap().iter().map(str::to_string).collect();
    let rows = rd
        .records()
        .map(|r| r.unwrap().iter().map(str::to_string).collect())
        .collect();
    (header, rows)
}

/// Column `name` of a row.
pub fn col<'a>(header: &[String], row: &'a [String], name: &str) -> &'a str {
    let i = header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name}"));
    &row[i]
}

/// |a − b| / max(1, |b|): the bound's measure for x1, v1 and energies.
pub fn rel1(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1.0)
}

/// Runs `tswm`, asserts success (showing its stderr otherwise) and reads
/// DIR/o/lanes.csv.
pub fn run_ok(args: &[&str], dir: &Path) -> (Output, Vec<String>, Vec<Vec<String>>) {
    let out = tswm(args, dir);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (h, rows) = read_csv(&dir.join("o/lanes.csv"));
    (out, h, rows)
}

/// Runs the docs/model.md section 7 lane table on the CPU into `dir/o`; the
/// header and rows of its lanes.csv.
pub fn run_fixture_lanes(dir: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let lanes = fixture("paper_lanes.csv");
    let args = [
        "run",
        "--lanes",
        lanes.to_str().unwrap(),
        "--out",
        "o",
        "--backend",
        "cpu",
    ];
    let (_, h, rows) = run_ok(&args, dir);
    (h, rows)
}

/// Checks results of the five docs/model.md section 7 cases against the
/// fixture: identical discrete fields, first switch within `t_bound` s,
/// x1, v1 and the works within `v_bound` of max(1, |value|). Returns the
/// worst value deviation and the worst switch-time deviation.
pub fn check_reference_cases(
    res: &[tswm::integrator::LaneResult],
    t_bound: f64,
    v_bound: f64,
) -> (f64, f64) {
    let (h, expected) = read_csv(&fixture("paper_expected.csv"));
    assert_eq!(res.len(), 5);
    assert_eq!(expected.len(), 5);
    let (mut worst, mut worst_t) = (0.0f64, 0.0f64);
    for (r, e) in res.iter().zip(&expected) {
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
                    (r.t_first_switch - t).abs() <= t_bound,
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
                rel1(got, want) <= v_bound,
                "lane {lane} {name}: {got} vs {want}"
            );
        }
    }
    (worst, worst_t)
}

/// Runs `tswm` and asserts the bad-input contract: exit code 2 and one
/// line on stderr holding every `want`. Returns the line.
pub fn rejected(args: &[&str], cwd: &Path, want: &[&str]) -> String {
    let out = tswm(args, cwd);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(2), "args {args:?}: stderr {err}");
    assert_eq!(
        err.trim_end().lines().count(),
        1,
        "one line expected, got: {err}"
    );
    for w in want {
        assert!(err.contains(w), "`{w}` missing from: {err}");
    }
    err
}

/// A command line run on the f64 CPU path: `args` with `--backend cpu`.
pub fn cpu<'a>(args: &[&'a str]) -> Vec<&'a str> {
    let mut v = args.to_vec();
    v.extend(["--backend", "cpu"]);
    v
}

/// Whether there is no GPU adapter, said as a skip of `test`; with
/// TSWM_REQUIRE_GPU=1 (as in CI) a missing adapter fails the test instead.
pub fn no_gpu(test: &str) -> bool {
    quiet_mesa();
    if !tswm::backend::gpu::adapters().is_empty() {
        return false;
    }
    assert!(
        std::env::var("TSWM_REQUIRE_GPU").as_deref() != Ok("1"),
        "{test}: TSWM_REQUIRE_GPU=1 but there is no GPU adapter"
    );
    skipped(test, "no GPU adapter");
    true
}

/// Says that (part of) a test is skipped and why, straight to stderr so
/// that a passing run shows it (libtest captures `eprintln!`).
pub fn skipped(test: &str, why: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "skipped {test}: {why}");
}

/// Mesa's Vulkan drivers print an error line per device when
/// XDG_RUNTIME_DIR is unset while they probe for a display that compute
/// never needs; `tswm` sets it before opening a device, and so do the
/// tests that open one in-process.
pub fn quiet_mesa() {
    if std::env::var_os("XDG_RUNTIME_DIR").is_none() {
        std::env::set_var("XDG_RUNTIME_DIR", std::env::temp_dir());
    }
}
