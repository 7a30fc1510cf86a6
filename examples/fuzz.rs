//! A mutation fuzzer for the two readers of user input: sweep files and
//! lane tables. (`cargo fuzz` needs a nightly toolchain; this runs on
//! stable.) Inputs are mutated from the corpus in `fuzz/corpus/` (byte
//! flips, insertions and deletions, tokens a user might mistype, lines
//! spliced from other inputs) and read by the production readers. A panic,
//! or an error that is not one line, fails the run and saves the input to
//! `fuzz/crashes/`. `tests/it/fuzz.rs` replays the corpus in CI.
//!
//!     cargo run --release --example fuzz -- sweep|lanes SECONDS [SEED]

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use tswm::lanes::Source;
use tswm::sampling::Uniforms;

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

/// Reads one input; Err(why) when the contract is broken.
pub fn read_one(target: &str, bytes: &[u8], scratch: &Path) -> Result<(), String> {
    let outcome = std::panic::catch_unwind(|| match target {
        "sweep" => match std::str::from_utf8(bytes) {
            Ok(text) => tswm::sweep::Sweep::parse(Path::new("fuzz.toml"), text)
                .err()
                .map(|e| e.to_string()),
            Err(_) => None,
        },
        _ => {
            std::fs::write(scratch, bytes).expect("scratch file");
            Source::open(None, Some(scratch))
                .err()
                .map(|e| e.to_string())
        }
    });
    match outcome {
        Err(_) => Err("panicked".into()),
        Ok(Some(msg)) if msg.contains('\n') || msg.contains('\r') => {
            Err(format!("error of more than one line: {msg:?}"))
        }
        Ok(_) => Ok(()),
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let target = args.get(1).map(String::as_str).unwrap_or("sweep");
    let secs: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(60);
    let seed: u64 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1);
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fuzz");
    let corpus: Vec<Vec<u8>> = std::fs::read_dir(root.join("corpus").join(target))
        .expect("corpus folder")
        .map(|e| std::fs::read(e.unwrap().path()).unwrap())
        .collect();
    let scratch = std::env::temp_dir().join(format!("tswm-fuzz-{}.csv", std::process::id()));
    std::panic::set_hook(Box::new(|_| {}));
    let mut u = Uniforms::new(seed);
    let start = Instant::now();
    let (mut n, mut bad) = (0u64, 0u64);
    while start.elapsed() < Duration::from_secs(secs) {
        let input = mutate(&mut u, &corpus);
        n += 1;
        if let Err(why) = read_one(target, &input, &scratch) {
            bad += 1;
            let dir = root.join("crashes");
            std::fs::create_dir_all(&dir).unwrap();
            std::fs::write(dir.join(format!("{target}-{seed}-{n}")), &input).unwrap();
            eprintln!("input {n}: {why}");
        }
    }
    let _ = std::fs::remove_file(&scratch);
    println!(
        "fuzz {target}: {n} inputs in {:.0} s (seed {seed}), {bad} broke the contract",
        start.elapsed().as_secs_f64()
    );
    if bad > 0 {
        std::process::exit(1);
    }
}
