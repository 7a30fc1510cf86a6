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
//! saves the input to `fuzz/crashes/`. `tests/it/fuzz.rs` replays the
//! corpus in CI.
//!
//!     cargo run --release --example fuzz -- sweep|lanes|report|merge SECONDS [SEED]

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use tswm::input::lanes::Source;
use tswm::input::sampling::Uniforms;

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

/// Reads one input; Err(why) when the contract is broken.
pub fn read_one(target: &str, bytes: &[u8], scratch: &Path) -> Result<(), String> {
    let outcome = std::panic::catch_unwind(|| match target {
        "sweep" => match std::str::from_utf8(bytes) {
            Ok(text) => tswm::input::sweep::Sweep::parse(Path::new("fuzz.toml"), text)
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

/// The folders the `report` and `merge` targets mutate: a run (`run`)
/// and its two shards (`s0`, `s1`), written once by the production code.
fn base_folders(base: &Path) {
    std::fs::create_dir_all(base).unwrap();
    let sweep = base.join("s.toml");
    std::fs::write(
        &sweep,
        "[base]\nf2 = -4774.0\nt_end = 0.4\nmotor_off = 0.2\nt_max = 1.0\n\
         [[grid]]\nparam = \"gamma_deg\"\nvalues = [3.0, 6.0, 20.0]\n\
         [sampling]\nmethod = \"monte_carlo\"\nn = 8\nseed = 3\n\
         [[tolerance]]\nparam = \"f2\"\ndist = \"normal\"\ntol_rel = 0.2\n\
         [trace]\nlanes = [1, 17]\ndt = 0.01\n\
         [report]\nrequire = \"hold = held\"\nat_least = 0.9\n",
    )
    .unwrap();
    let lanes = tswm::cli::LanesArgs {
        sweep: Some(sweep),
        lanes: None,
        threads: Some(1),
        tol: None,
    };
    // A sensitivity design, for the report's reading of sensitivity.csv.
    let sens = base.join("sens.toml");
    std::fs::write(
        &sens,
        "[base]\nfriction = \"coulomb\"\nmu = 0.06\nmu_static = 0.09\nmotor_off = 0.0\nt_end = 0.2\n\
         [[grid]]\nparam = \"f2\"\nvalues = [-4000.0, 4000.0]\n\
         [sensitivity]\nmethod = \"sobol\"\nn = 16\nseed = 4\nbootstrap = 20\n\
         [[tolerance]]\nparam = \"gamma_deg\"\ndist = \"uniform\"\ntol = 2.0\n\
         [[tolerance]]\nparam = \"mu_static\"\ndist = \"uniform\"\ntol = 0.02\n",
    )
    .unwrap();
    let sens = tswm::cli::LanesArgs {
        sweep: Some(sens),
        lanes: None,
        threads: Some(1),
        tol: None,
    };
    for (out, shard, lanes) in [
        ("run", None, &lanes),
        ("s0", Some("0/2"), &lanes),
        ("s1", Some("1/2"), &lanes),
        ("sens", None, &sens),
    ] {
        let out = base.join(out);
        let flags = tswm::cli::RunFlags {
            out,
            backend: tswm::backend::Choice::Cpu,
            trace: Vec::new(),
            trace_dt: None,
            no_report: true,
            shard: shard.map(str::to_string),
            format: tswm::output::table::Format::Csv,
        };
        tswm::commands::run::run(lanes, &flags, &Default::default()).expect("the base run");
    }
}

/// Copies the files of folder `from` into a new folder `to`.
fn copy_folder(from: &Path, to: &Path) {
    let _ = std::fs::remove_dir_all(to);
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        if e.path().is_file() {
            std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
        }
    }
}

/// The files of a run or shard folder a mutation may hit.
const FOLDER_FILES: [&str; 6] = [
    "lanes.csv",
    "traces.csv",
    "sweep.resolved.toml",
    "summary.csv",
    "sensitivity.csv",
    "shard.toml",
];

/// Mutates one file of the copies in `scratch` of the base folders; for
/// `merge`, sometimes mends the manifest's digest of the file. Returns
/// the file mutated and its new bytes.
fn mutate_folder(
    u: &mut Uniforms,
    base: &Path,
    scratch: &Path,
    target: &str,
) -> (PathBuf, Vec<u8>) {
    let pick = |u: &mut Uniforms, n: usize| ((u.next() * n as f64) as usize).min(n - 1);
    let folders: &[&str] = if target == "report" {
        &["run", "sens"]
    } else {
        &["s0", "s1"]
    };
    for f in folders {
        copy_folder(&base.join(f), &scratch.join(f));
    }
    let folder = folders[pick(u, folders.len())];
    let name = loop {
        let n = FOLDER_FILES[pick(u, FOLDER_FILES.len())];
        if scratch.join(folder).join(n).exists() {
            break n;
        }
    };
    let path = scratch.join(folder).join(name);
    let corpus = vec![std::fs::read(&path).unwrap()];
    let bytes = mutate(u, &corpus);
    std::fs::write(&path, &bytes).unwrap();
    if target == "merge" && name != "shard.toml" && u.next() < 0.5 {
        // A forged manifest: the mutated rows themselves get read.
        let m = scratch.join(folder).join("shard.toml");
        if let Ok(Some(mut man)) = tswm::run::shard::Manifest::read(&scratch.join(folder)) {
            if let Ok(d) = tswm::output::digest::file_digest(&path) {
                man.files.insert(name.to_string(), d);
                std::fs::write(m, man.text()).unwrap();
            }
        }
    }
    (path, bytes)
}

/// Runs the report or the merge on the mutated folders; Err(why) when the
/// contract is broken (a panic, an error of more than one line, an error
/// other than bad input, more than 60 s).
pub fn run_folder(target: &str, scratch: &Path) -> Result<(), String> {
    let (tx, rx) = std::sync::mpsc::channel();
    let scratch = scratch.to_path_buf();
    let target = target.to_string();
    std::thread::spawn(move || {
        let r = std::panic::catch_unwind(|| {
            if target == "report" {
                tswm::report::build(&scratch.join("run"))
                    .and_then(|_| tswm::report::build(&scratch.join("sens")))
                    .map(|_| ())
            } else {
                let _ = std::fs::remove_dir_all(scratch.join("m"));
                tswm::run::merge::merge(
                    &[scratch.join("s0"), scratch.join("s1")],
                    &scratch.join("m"),
                    tswm::output::table::Format::Csv,
                    true,
                )
                .map(|_| ())
            }
        });
        let _ = tx.send(r);
    });
    match rx.recv_timeout(Duration::from_secs(60)) {
        Err(_) => Err("took over 60 s".into()),
        Ok(Err(_)) => Err("panicked".into()),
        Ok(Ok(Ok(()))) => Ok(()),
        Ok(Ok(Err(e))) => {
            let msg = e.to_string();
            if msg.contains(['\n', '\r']) {
                Err(format!("error of more than one line: {msg:?}"))
            } else if e.exit_code() != 2 {
                Err(format!(
                    "not a bad-input error (exit {}): {msg}",
                    e.exit_code()
                ))
            } else {
                Ok(())
            }
        }
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let target = args.get(1).map(String::as_str).unwrap_or("sweep");
    let secs: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(60);
    let seed: u64 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1);
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fuzz");
    let folders = target == "report" || target == "merge";
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
    std::panic::set_hook(Box::new(|_| {}));
    let mut u = Uniforms::new(seed);
    let start = Instant::now();
    let (mut n, mut bad) = (0u64, 0u64);
    while start.elapsed() < Duration::from_secs(secs) {
        n += 1;
        let (input, outcome) = if folders {
            let (path, bytes) = mutate_folder(&mut u, &base, &scratch, target);
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            (
                [name.as_bytes(), b"\n", &bytes].concat(),
                run_folder(target, &scratch),
            )
        } else {
            let input = mutate(&mut u, &corpus);
            let o = read_one(target, &input, &scratch_file);
            (input, o)
        };
        if let Err(why) = outcome {
            bad += 1;
            let dir = root.join("crashes");
            std::fs::create_dir_all(&dir).unwrap();
            std::fs::write(dir.join(format!("{target}-{seed}-{n}")), &input).unwrap();
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
    if bad > 0 {
        std::process::exit(1);
    }
}

/// A scratch folder of this process.
fn tempfile_dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("tswm-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}
