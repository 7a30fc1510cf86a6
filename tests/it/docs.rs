//! The docs against the code: every parameter and every result column is
//! documented, and the docs name none that does not exist; the README is
//! a front door; no page refers to anything outside the repository.

use std::collections::BTreeSet;
use std::path::Path;

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
    known.extend(tswm::integrator::Drive::ALL.map(|d| d.name().to_string()));
    known.extend(tswm::integrator::Recheck::ALL.map(|r| r.name().to_string()));
    known.extend(tswm::columns::SEARCH.iter().map(|c| c.name.to_string()));
    known.extend(tswm::integrator::SearchStatus::ALL.map(|s| s.name().to_string()));
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
        // system calls
        "sync_file_range",
        // the keys of Python's tswm.devices()
        "chunk_lanes",
        "device_type",
        "part_lanes",
        "parts_in_flight",
        "shader_f64",
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
    // The kernel's functions and those the shader mirrors, as code names them.
    known.extend(tswm::model::kernel::KERNEL.map(str::to_string));
    known.extend(
        tswm::backend::gpu::shader::MIRRORED
            .iter()
            .map(|s| s.to_string()),
    );
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
    // The f64 shader functions docs/gpu.md names, as the file defines them.
    known.extend(
        include_str!("../../shaders/f64/math.wgsl")
            .lines()
            .filter_map(|l| l.strip_prefix("fn "))
            .filter_map(|l| l.split('(').next())
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
            readme.contains(&format!("```sh\n{cmd}\n"))
                || readme.contains(&format!("\n{cmd}\n```")),
            "the README lacks `{cmd}` in a shell block"
        );
    }
    // Installed with the versions the tests ran; the table key as the
    // sweep file spells it.
    assert!(readme.contains("cargo install --locked --path ."));
    assert!(!readme.contains("cargo install --path"));
    assert!(readme.contains("[friction_table.NAME]") && !readme.contains("[tables."));
    let ci = page(".ci/run");
    assert!(
        ci.contains("\ncargo test --release\n"),
        ".ci/run does not run the README's tests"
    );
    for (name, text) in pages() {
        let outside = concat!("..", "/shared");
        assert!(!text.contains(outside), "{name} refers to {outside}");
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

/// A fenced block of a page: its page, first line number, info string
/// (`toml`, `sh`, `python`, `sql`, `text`, ...) and text.
struct Block {
    page: String,
    line: usize,
    lang: String,
    text: String,
}

/// The pages whose snippets run: the README and the user's docs.
fn user_pages() -> Vec<(String, String)> {
    pages()
        .into_iter()
        .filter(|(n, _)| n == "README.md" || n.starts_with("docs/"))
        .collect()
}

/// Every fenced block of `page`.
fn blocks(name: &str, page: &str) -> Vec<Block> {
    let mut out = Vec::new();
    let mut open: Option<Block> = None;
    for (i, l) in page.lines().enumerate() {
        match (&mut open, l.strip_prefix("```")) {
            (None, Some(lang)) => {
                open = Some(Block {
                    page: name.to_string(),
                    line: i + 1,
                    lang: lang.trim().to_string(),
                    text: String::new(),
                })
            }
            (Some(_), Some(_)) => out.extend(open.take()),
            (Some(b), None) => {
                b.text += l;
                b.text.push('\n');
            }
            (None, None) => {}
        }
    }
    assert!(open.is_none(), "{name}: a fence left open");
    out
}

/// The file name a TOML block gives itself in its first line
/// (`# map.toml: ...`).
fn toml_name(b: &Block) -> Option<String> {
    let first = b.text.lines().next()?.strip_prefix("# ")?;
    let name = first.split([':', ' ']).next()?;
    name.ends_with(".toml").then(|| name.to_string())
}

/// Whether a block says it is only part of a file (`# fragment`).
fn fragment(b: &Block) -> bool {
    b.text
        .lines()
        .next()
        .is_some_and(|l| l.starts_with("# fragment"))
}

/// A folder to run a page's snippets in: the shipped sweeps and examples
/// where the docs expect them, and the page's named TOML blocks written
/// as their files.
fn snippet_dir(page: &[Block]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for d in ["sweeps", "examples", "benches"] {
        std::os::unix::fs::symlink(root().join(d), dir.path().join(d)).unwrap();
    }
    for b in page.iter().filter(|b| b.lang == "toml" && !fragment(b)) {
        if let Some(n) = toml_name(b) {
            std::fs::write(dir.path().join(n), &b.text).unwrap();
        }
    }
    dir
}

/// Runs one command line of a snippet in `dir`: `tswm ...` with the
/// binary under test; a `cargo ...` or `pip ...` line is one `.ci/run`
/// runs as written. No shell: a snippet's line is a command and its
/// arguments.
fn run_line(b: &Block, line: &str, dir: &Path) {
    let at = format!("{} line {}: `{line}`", b.page, b.line);
    let words: Vec<&str> = line.split_whitespace().collect();
    assert!(
        !line.contains(['|', '&', ';', '"', '\'', '$', '>', '<']),
        "{at}: a snippet's command is one command, no shell syntax"
    );
    match words.first() {
        Some(&"tswm") => {
            let out = crate::common::tswm(&words[1..], dir);
            assert!(
                out.status.success(),
                "{at}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        Some(&"cargo") | Some(&"pip") => assert!(
            page(".ci/run").lines().any(|l| l.trim() == line),
            "{at}: .ci/run does not run it as written"
        ),
        _ => panic!("{at}: not a tswm, cargo or pip command"),
    }
}

/// Every TOML block of the README and docs/ that is not marked `# fragment`
/// is a whole sweep file and runs as written.
#[test]
fn every_toml_block_runs_as_written() {
    let mut ran = 0;
    for (name, text) in user_pages() {
        let bs = blocks(&name, &text);
        let dir = snippet_dir(&bs);
        for (i, b) in bs.iter().enumerate() {
            if b.lang != "toml" || fragment(b) {
                continue;
            }
            let file = toml_name(b).unwrap_or_else(|| {
                let f = format!("block{i}.toml");
                std::fs::write(dir.path().join(&f), &b.text).unwrap();
                f
            });
            let out_dir = format!("toml-out-{i}");
            let out = crate::common::tswm(&["run", &file, "--out", &out_dir], dir.path());
            assert!(
                out.status.success(),
                "{name} line {}: the sweep does not run: {}",
                b.line,
                String::from_utf8_lossy(&out.stderr)
            );
            ran += 1;
        }
    }
    assert!(ran >= 6, "{ran} sweeps ran");
}

/// Every `sh` block of the README and docs/ runs as written, line by line
/// in the page's order (a block that needs what no test machine has, a
/// cluster say, says so in its first line); commands live in `sh`
/// blocks, never in indented ones, so none escapes.
#[test]
fn every_shell_block_runs_as_written() {
    let mut ran = 0;
    for (name, text) in user_pages() {
        let bs = blocks(&name, &text);
        for b in &bs {
            assert!(
                !b.lang.is_empty(),
                "{name} line {}: a block says what it holds (toml, sh, python, sql, text)",
                b.line
            );
        }
        // An indented block holds no command.
        for l in text.lines().filter(|l| l.starts_with("    ")) {
            let t = l.trim_start();
            assert!(
                !(t.starts_with("tswm ") || t.starts_with("cargo ") || t.starts_with("python")),
                "{name}: a command in an indented block: `{t}` (put it in an sh block)"
            );
        }
        let dir = snippet_dir(&bs);
        for b in bs.iter().filter(|b| b.lang == "sh") {
            if let Some(why) = b
                .text
                .lines()
                .next()
                .and_then(|l| l.strip_prefix("# needs"))
            {
                crate::common::skipped(&format!("{name} line {}", b.line), &format!("needs{why}"));
                continue;
            }
            for line in b.text.lines().map(str::trim) {
                if line.is_empty() || line.starts_with('#') {
                    continue;
                }
                run_line(b, line.split(" #").next().unwrap().trim(), dir.path());
                ran += 1;
            }
        }
    }
    assert!(ran >= 10, "{ran} commands ran");
}

/// Every `python` block (and DuckDB `sql` block) of the README and docs/
/// runs as written, after the runs its first line names (`# after: tswm
/// run ...`), with the Python of `.ci/run` (pandas, polars, pyarrow,
/// duckdb, SALib).
#[test]
fn every_python_and_sql_block_runs_as_written() {
    const NEEDS: crate::reference::Needs = crate::reference::Needs {
        modules: "pandas, polars, pyarrow, duckdb, SALib",
        vars: &["TSWM_PYTHON"],
        install: "pip install pandas polars pyarrow duckdb SALib, or set TSWM_PYTHON",
    };
    const NEEDS_TSWM: crate::reference::Needs = crate::reference::Needs {
        modules: "tswm, pandas, polars, pyarrow, dask.distributed, dask.dataframe",
        vars: &["TSWM_PYTHON"],
        install: "pip install ./python \"dask[distributed,dataframe]\" in it, or set TSWM_PYTHON",
    };
    let Some(py) = crate::reference::python_for(&NEEDS, "the docs' Python snippets") else {
        return;
    };
    // The snippets of the Python package need it installed (.ci/run does).
    let with_tswm = std::cell::OnceCell::new();
    let mut ran = 0;
    for (name, text) in user_pages() {
        let bs = blocks(&name, &text);
        for b in bs.iter().filter(|b| b.lang == "python" || b.lang == "sql") {
            let py = if b.text.contains("import tswm") {
                let found = with_tswm.get_or_init(|| {
                    crate::reference::python_for(
                        &NEEDS_TSWM,
                        "the docs' snippets of tswm in Python",
                    )
                });
                match found {
                    Some(p) => p,
                    None => continue,
                }
            } else {
                &py
            };
            let dir = snippet_dir(&bs);
            let first = b.text.lines().next().unwrap_or("");
            if let Some(cmds) = first
                .strip_prefix("# after: ")
                .or(first.strip_prefix("-- after: "))
            {
                for c in cmds.split("; ") {
                    run_line(b, c.trim(), dir.path());
                }
            }
            let code = if b.lang == "python" {
                b.text.clone()
            } else {
                let sql: String = b
                    .text
                    .lines()
                    .filter(|l| !l.starts_with("--"))
                    .collect::<Vec<_>>()
                    .join("\n");
                format!(
                    "import duckdb\nfor s in {sql:?}.split(';'):\n    if s.strip():\n        duckdb.sql(s).fetchall()\n"
                )
            };
            let out = std::process::Command::new(py)
                .args(["-c", &code])
                .current_dir(dir.path())
                .output()
                .unwrap();
            assert!(
                out.status.success(),
                "{name} line {}: {}",
                b.line,
                String::from_utf8_lossy(&out.stderr)
            );
            ran += 1;
        }
    }
    assert!(ran >= 4, "{ran} snippets ran");
    if with_tswm.get().is_some_and(Option::is_some) {
        assert!(
            ran >= 14,
            "{ran} snippets ran, those of tswm in Python with them"
        );
    }
}

/// A user who clones the repository has no folder beside it: no test
/// reads one or mentions it (the fixtures are pinned by their digests).
#[test]
fn no_test_looks_outside_the_repository() {
    let outside = concat!("..", "/shared");
    let mut found = Vec::new();
    for dir in ["tests", "benches", "examples", "src"] {
        let mut stack = vec![root().join(dir)];
        while let Some(d) = stack.pop() {
            for e in std::fs::read_dir(&d).unwrap().flatten() {
                let p = e.path();
                if p.is_dir() {
                    stack.push(p);
                } else if let Ok(t) = std::fs::read_to_string(&p) {
                    if t.contains(outside) {
                        found.push(p.display().to_string());
                    }
                }
            }
        }
    }
    assert!(found.is_empty(), "{found:?}");
}
