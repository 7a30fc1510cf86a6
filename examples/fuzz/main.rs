//! A mutation fuzzer for every reader of input: sweep files and lane
//! tables (`sweep`, `lanes`), and the output folders that `tswm report`
//! and `tswm merge` read (`report`, `merge`). (`cargo fuzz` needs a
//! nightly toolchain; this runs on stable.)
//!
//! `sweep` and `lanes` mutate the corpus in `fuzz/corpus/` (byte flips,
//! insertions and deletions, tokens a user might mistype, lines spliced
//! from other inputs) and read each input with the production reader.
//! `report` and `merge` write a real run (a small traced tolerance study,
//! whole and in two shards) once, then mutate one of its files at a time
//! (the table, summary, traces, resolved sweep, a shard's manifest; for
//! half of the merge inputs the manifest's digest is mended to match, so
//! the rows themselves are read) and run the report or the merge on it.
//!
//! A panic, an error that is not one line, an error that is not bad input
//! (exit code 2), or an input that takes over 60 s fails the run and
//! saves the input to `fuzz/crashes/TARGET/` (not in git). `replay`
//! says what each saved input gives; `minimise` shrinks one to the
//! smallest input with the same outcome, for `fuzz/regressions/`, which
//! `tests/it/fuzz.rs` replays with the corpus.
//!
//!     cargo run --release --example fuzz -- sweep|lanes|report|merge SECONDS [SEED]
//!     cargo run --release --example fuzz -- replay TARGET FILE...
//!     cargo run --release --example fuzz -- minimise TARGET FILE OUT

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use tswm::input::sampling::Uniforms;

mod targets;
use targets::{
    base_folders, on_folders, read_one, replay, run_folder, FolderInput, Outcome, FOLDER_FILES,
    TARGETS,
};

const TOKENS: &[&str] = &[
    "\"",
    ",",
    "\n",
    "\r\n",
    "=",
    "[",
    "]",
    "[[grid]]",
    "[base]",
    "[sampling]",
    "[[tolerance]]",
    "[friction_table]",
    "param",
    "values",
    "from",
    "to",
    "n",
    "seed",
    "method",
    "dist",
    "tol",
    "tol_rel",
    "scale",
    "m1",
    "m2",
    "gamma_deg",
    "f2",
    "motor",
    "friction",
    "mu",
    "mu_static",
    "v1_0",
    "t_end",
    "motor_off",
    "v_crit",
    "1e39",
    "-0",
    "nan",
    "inf",
    "-inf",
    "1e308",
    "1e-320",
    "0",
    "-1",
    "90",
    "18446744073709551615",
    "9223372036854775808",
    "-9223372036854775809",
    "0x10",
    "1_000",
    "\"\"",
    "'",
    "#",
    "\u{0}",
    "\u{feff}",
    "é",
    "table",
    "coulomb",
    "kloss",
    "constant",
    "log",
    "linear",
    "monte_carlo",
    "latin_hypercube",
    "normal",
    "uniform",
    "triangular",
    "{",
    "}",
    ".",
    "1.7976931348623157e308",
    "-1.7e308",
    "4000000000",
    "-3",
    "held",
    "coasting",
    "stick",
    "ok",
    "nonfinite",
    ",,,,",
    "held = 1",
    "require",
    "at_least",
    "agma",
    "alpha_n_deg",
    "friction_table",
    "[friction_table.bronze]",
    "\"bronze\"",
    "d1",
    "z1",
    "z2",
    "m_x",
    "r1",
    "r2",
    "j1",
    "j2",
    "t1",
    "t2",
    "n_sync",
    "n_crit",
    "t_crit",
    "n1_0",
    "1.5",
    "44.9999",
];

fn mutate(u: &mut Uniforms, corpus: &[Vec<u8>]) -> Vec<u8> {
    let pick = |u: &mut Uniforms, n: usize| ((u.next() * n as f64) as usize).min(n - 1);
    let mut b = corpus[pick(u, corpus.len())].clone();
    for _ in 0..1 + pick(u, 6) {
        let at = if b.is_empty() {
            0
        } else {
            pick(u, b.len() + 1)
        };
        match pick(u, 6) {
            0 if !b.is_empty() => {
                let i = at.min(b.len() - 1);
                b[i] ^= 1 << pick(u, 8);
            }
            1 if !b.is_empty() => {
                let end = (at + 1 + pick(u, 8)).min(b.len());
                b.drain(at.min(b.len())..end);
            }
            2 => {
                let t = TOKENS[pick(u, TOKENS.len())].as_bytes();
                b.splice(at..at, t.iter().copied());
            }
            3 => {
                // A line from another input.
                let other = &corpus[pick(u, corpus.len())];
                let lines: Vec<&[u8]> = other.split(|&c| c == b'\n').collect();
                let mut l = lines[pick(u, lines.len())].to_vec();
                l.push(b'\n');
                b.splice(at..at, l);
            }
            4 => b.insert(at, (u.next() * 256.0) as u8),
            _ => {
                let t = TOKENS[pick(u, TOKENS.len())].as_bytes();
                let end = (at + t.len()).min(b.len());
                b.splice(at..end, t.iter().copied());
            }
        }
    }
    b
}

/// Mutates one file of a target's base folders (for `merge`, sometimes
/// mending the manifest's digest of the file).
fn mutate_folder(u: &mut Uniforms, base: &Path, target: &str) -> FolderInput {
    let pick = |u: &mut Uniforms, n: usize| ((u.next() * n as f64) as usize).min(n - 1);
    let folders = targets::folders(target);
    let folder = folders[pick(u, folders.len())];
    let file = loop {
        let n = FOLDER_FILES[pick(u, FOLDER_FILES.len())];
        if base.join(folder).join(n).exists() {
            break n;
        }
    };
    let corpus = vec![std::fs::read(base.join(folder).join(file)).unwrap()];
    let bytes = mutate(u, &corpus);
    let mended = target == "merge" && file != "shard.toml" && u.next() < 0.5;
    FolderInput {
        folder: folder.to_string(),
        file: file.to_string(),
        mended,
        bytes,
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let mode = args.get(1).map(String::as_str).unwrap_or("sweep");
    std::panic::set_hook(Box::new(|_| {}));
    let code = match mode {
        "replay" => replay_files(&args[2..]),
        "minimise" => minimise_file(&args[2..]),
        _ => fuzz(&args[1..]),
    };
    std::process::exit(code);
}

/// The fuzzer's folder in the repository.
fn fuzz_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fuzz")
}

/// A target named on the command line, or exit 2 with what is allowed.
fn target_arg(a: Option<&String>) -> &'static str {
    let t = a.map(String::as_str).unwrap_or("sweep");
    TARGETS.into_iter().find(|&k| k == t).unwrap_or_else(|| {
        eprintln!(
            "fuzz: unknown target {t:?}; allowed: {}",
            TARGETS.join(", ")
        );
        std::process::exit(2)
    })
}

/// `TARGET SECONDS [SEED]`: mutates and reads inputs for SECONDS; each
/// one that breaks the contract is saved to `fuzz/crashes/TARGET/`.
fn fuzz(args: &[String]) -> i32 {
    let target = target_arg(args.first());
    let secs: u64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(60);
    let seed: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(1);
    let root = fuzz_root();
    let folders = on_folders(target);
    let corpus: Vec<Vec<u8>> = if folders {
        Vec::new()
    } else {
        std::fs::read_dir(root.join("corpus").join(target))
            .expect("corpus folder")
            .map(|e| std::fs::read(e.unwrap().path()).unwrap())
            .collect()
    };
    let tmp = tempfile_dir();
    let base = tmp.join("base");
    if folders {
        base_folders(&base);
    }
    let scratch = tmp.join("scratch");
    let scratch_file = tmp.join("lanes.csv");
    let mut u = Uniforms::new(seed);
    let start = Instant::now();
    let (mut n, mut bad) = (0u64, 0u64);
    while start.elapsed() < Duration::from_secs(secs) {
        n += 1;
        let (input, outcome) = if folders {
            let f = mutate_folder(&mut u, &base, target);
            f.apply(target, &base, &scratch);
            (f.encode(), run_folder(target, &scratch))
        } else {
            let input = mutate(&mut u, &corpus);
            let o = read_one(target, &input, &scratch_file);
            (input, o)
        };
        if let Err(why) = outcome {
            bad += 1;
            // Saved per target, as the replay test reads them; the folder
            // is not in git (a finding becomes a minimised input in
            // fuzz/regressions/, see CONTRIBUTING.md).
            let dir = root.join("crashes").join(target);
            std::fs::create_dir_all(&dir).unwrap();
            std::fs::write(dir.join(format!("{seed}-{n}")), &input).unwrap();
            eprintln!("input {n}: {why}");
            if why.contains("60 s") {
                break;
            }
        }
    }
    let _ = std::fs::remove_dir_all(&tmp);
    println!(
        "fuzz {target}: {n} inputs in {:.0} s (seed {seed}), {bad} broke the contract",
        start.elapsed().as_secs_f64()
    );
    i32::from(bad > 0)
}

/// `replay TARGET FILE...`: what reading each saved input gives, a line
/// each (`read`, `bad input: ...`, or `BROKE: ...`); exit 1 when one broke
/// the contract.
fn replay_files(args: &[String]) -> i32 {
    let target = target_arg(args.first());
    let tmp = tempfile_dir();
    let base = tmp.join("base");
    if on_folders(target) {
        base_folders(&base);
    }
    let mut broke = 0;
    for f in &args[1..] {
        let input = std::fs::read(f).unwrap_or_else(|e| panic!("{f}: {e}"));
        let o = replay(target, &input, &base, &tmp.join("scratch"));
        broke += i32::from(o.is_err());
        println!("{f}\t{}", said(&o));
    }
    let _ = std::fs::remove_dir_all(&tmp);
    i32::from(broke > 0)
}

/// An outcome in one line.
fn said(o: &Outcome) -> String {
    match o {
        Ok(None) => "read".into(),
        Ok(Some(msg)) => format!("bad input: {msg}"),
        Err(why) => format!("BROKE: {why}"),
    }
}

/// What a minimised input must keep of an outcome: whether it was read,
/// refused or broke the contract, the message's closing words with their
/// numbers masked (the words that say what is wrong; the start echoes the
/// input, which shrinking changes), and whether the echo holds a line
/// break (shown as `\n` or `\r`) or bytes that are not UTF-8 (shown as
/// U+FFFD): what the findings so far were about.
fn kind(o: &Outcome) -> String {
    let text = said(o);
    let (what, msg) = text.split_once(':').unwrap_or((&text, ""));
    let tail: String = msg
        .chars()
        .rev()
        .take(60)
        .collect::<Vec<_>>()
        .into_iter()
        .rev()
        .collect();
    let tail: String = tail
        .chars()
        .map(|c| if c.is_ascii_digit() { '#' } else { c })
        .collect();
    let breaks = msg.contains("\\n") || msg.contains("\\r");
    let bytes = msg.contains('\u{fffd}');
    format!("{what} (line break echoed: {breaks}, not UTF-8: {bytes}): ...{tail}")
}

/// `minimise TARGET FILE OUT`: the smallest input found (by removing
/// chunks of bytes, halving their size down to one byte) whose outcome
/// is the same as FILE's up to its numbers, written to OUT.
fn minimise_file(args: &[String]) -> i32 {
    let target = target_arg(args.first());
    let (Some(file), Some(out)) = (args.get(1), args.get(2)) else {
        eprintln!("fuzz: minimise TARGET FILE OUT");
        return 2;
    };
    let tmp = tempfile_dir();
    let base = tmp.join("base");
    if on_folders(target) {
        base_folders(&base);
    }
    let scratch = tmp.join("scratch");
    let input = std::fs::read(file).unwrap();
    // A folder input keeps its header line whole.
    let head = if on_folders(target) {
        input.iter().position(|&b| b == b'\n').map_or(0, |i| i + 1)
    } else {
        0
    };
    let outcome = |body: &[u8]| {
        let whole = [&input[..head], body].concat();
        kind(&replay(target, &whole, &base, &scratch))
    };
    let want = outcome(&input[head..]);
    let mut body = input[head..].to_vec();
    let mut chunk = body.len().max(1);
    while chunk >= 1 {
        let mut at = 0;
        while at < body.len() {
            let end = (at + chunk).min(body.len());
            let cut = [&body[..at], &body[end..]].concat();
            if outcome(&cut) == want {
                body = cut;
            } else {
                at = end;
            }
        }
        if chunk == 1 {
            break;
        }
        chunk /= 2;
    }
    std::fs::write(out, [&input[..head], &body[..]].concat()).unwrap();
    println!(
        "{file}: {} bytes to {}: {want}",
        input.len() - head,
        body.len()
    );
    let _ = std::fs::remove_dir_all(&tmp);
    0
}

/// A scratch folder of this process.
fn tempfile_dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("tswm-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}
