//! The fuzz targets' readers, shared by the fuzzer (`main.rs`) and the
//! replay test (`tests/it/fuzz.rs`, which includes this file): how one
//! input of each target is read, and what breaks the contract (a panic,
//! an error of more than one line, an error other than bad input, more
//! than 60 s).
//!
//! Inputs of `sweep` and `lanes` are the file's bytes. Inputs of `report`
//! and `merge` are one mutated file of an output folder: a first line
//! `FOLDER/FILE` (`FOLDER/FILE mended` when the shard's manifest was
//! mended to the file's digest, so that its rows are read), then the
//! file's bytes ([`FolderInput`]).

use std::path::Path;
use std::time::Duration;

use tswm::input::lanes::Source;

/// The fuzz targets, in the order the replay reads them.
pub const TARGETS: [&str; 4] = ["sweep", "lanes", "report", "merge"];

/// Whether a target's inputs are files of output folders.
pub fn on_folders(target: &str) -> bool {
    target == "report" || target == "merge"
}

/// The folders of the base run a target mutates.
pub fn folders(target: &str) -> &'static [&'static str] {
    if target == "report" {
        &["run", "sens"]
    } else {
        &["s0", "s1"]
    }
}

/// One input of the `report` or `merge` target: which file of which
/// folder it replaces, whether the manifest was mended, and the bytes.
#[derive(Clone, Debug, PartialEq)]
pub struct FolderInput {
    /// `run`, `sens`, `s0` or `s1`.
    pub folder: String,
    /// One of [`FOLDER_FILES`].
    pub file: String,
    /// The shard's manifest holds the mutated file's digest.
    pub mended: bool,
    /// The file's new bytes.
    pub bytes: Vec<u8>,
}

impl FolderInput {
    /// The input as it is saved: the header line, then the bytes.
    pub fn encode(&self) -> Vec<u8> {
        let mended = if self.mended { " mended" } else { "" };
        let head = format!("{}/{}{mended}\n", self.folder, self.file);
        [head.as_bytes(), &self.bytes].concat()
    }

    /// An input read back; None when its header is not one.
    pub fn decode(input: &[u8]) -> Option<FolderInput> {
        let nl = input.iter().position(|&b| b == b'\n')?;
        let head = std::str::from_utf8(&input[..nl]).ok()?;
        let (path, mended) = match head.strip_suffix(" mended") {
            Some(p) => (p, true),
            None => (head, false),
        };
        let (folder, file) = path.split_once('/')?;
        FOLDER_FILES.contains(&file).then(|| FolderInput {
            folder: folder.to_string(),
            file: file.to_string(),
            mended,
            bytes: input[nl + 1..].to_vec(),
        })
    }

    /// Copies the target's base folders into `scratch` and puts this
    /// input in place (mending the manifest when it says so).
    pub fn apply(&self, target: &str, base: &Path, scratch: &Path) {
        for f in folders(target) {
            copy_folder(&base.join(f), &scratch.join(f));
        }
        let dir = scratch.join(&self.folder);
        let path = dir.join(&self.file);
        std::fs::write(&path, &self.bytes).unwrap();
        if self.mended {
            // A forged manifest: the mutated rows themselves get read.
            if let Ok(Some(mut man)) = tswm::run::shard::Manifest::read(&dir) {
                if let Ok(d) = tswm::output::digest::file_digest(&path) {
                    man.files.insert(self.file.clone(), d);
                    std::fs::write(dir.join("shard.toml"), man.text()).unwrap();
                }
            }
        }
    }
}

/// Reads one saved input of `target`. `base` holds [`base_folders`] (for
/// `report` and `merge`), `scratch` is a folder of the caller's to work in.
pub fn replay(target: &str, input: &[u8], base: &Path, scratch: &Path) -> Outcome {
    std::fs::create_dir_all(scratch).unwrap();
    if !on_folders(target) {
        return read_one(target, input, &scratch.join("lanes.csv"));
    }
    let Some(f) = FolderInput::decode(input) else {
        return Err("not a folder input (no FOLDER/FILE line)".into());
    };
    f.apply(target, base, scratch);
    run_folder(target, scratch)
}

/// What reading one input gave: None when it was read, the one line of
/// a bad-input error; Err(why) when the contract is broken.
pub type Outcome = Result<Option<String>, String>;

/// Reads one input of `sweep` or `lanes` (a lane table is written to
/// `scratch` first).
pub fn read_one(target: &str, bytes: &[u8], scratch: &Path) -> Outcome {
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
        Ok(msg) => Ok(msg),
    }
}

/// The folders the `report` and `merge` targets mutate: a run (`run`)
/// and its two shards (`s0`, `s1`), written once by the production code.
pub fn base_folders(base: &Path) {
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
        precision: tswm::backend::Precision::Auto,
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
        precision: tswm::backend::Precision::Auto,
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
            dry_run: false,
        };
        // `execute`, not `run`: the same run without its summary line.
        let shard = flags.shard.as_deref().map(tswm::run::shard::Shard::parse);
        let shard = shard.transpose().expect("a shard");
        let part = |n: u64, unit: u64| shard.map_or((0, n), |s| s.range_in(n, unit));
        let show = Default::default();
        let plan = lanes.plan_part(&part, &show).expect("the base sweep");
        tswm::commands::run::execute(plan, shard, &flags, &show, false).expect("the base run");
    }
}

/// Copies the files of folder `from` into a new folder `to`.
pub fn copy_folder(from: &Path, to: &Path) {
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
pub const FOLDER_FILES: [&str; 6] = [
    "lanes.csv",
    "traces.csv",
    "sweep.resolved.toml",
    "summary.csv",
    "sensitivity.csv",
    "shard.toml",
];

/// Runs the report or the merge on the folders in `scratch`.
pub fn run_folder(target: &str, scratch: &Path) -> Outcome {
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
        Ok(Ok(Ok(()))) => Ok(None),
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
                Ok(Some(msg))
            }
        }
    }
}
