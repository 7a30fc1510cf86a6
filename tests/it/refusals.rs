//! A refused command leaves the folder exactly as it was: no lock file,
//! no marker, no removed partial file, nothing created. A property test
//! over random folder states and refused `run`, `report` and `merge`
//! commands: each is refused (exit code 2, one line), and the folder's
//! every entry (name, kind, bytes, permissions, modification time) is the
//! same after as before.

use std::collections::BTreeMap;
use std::path::Path;

use crate::common::{cpu, root, tswm};

/// What a folder holds, recursively: path -> (is a folder, bytes,
/// permissions, modification time). None when it does not exist.
type Snapshot = Option<BTreeMap<String, (bool, Vec<u8>, u32, std::time::SystemTime)>>;

fn snapshot(dir: &Path) -> Snapshot {
    use std::os::unix::fs::PermissionsExt as _;
    if !dir.exists() {
        return None;
    }
    let mut out = BTreeMap::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let e = e.unwrap();
            let p = e.path();
            let meta = std::fs::symlink_metadata(&p).unwrap();
            let rel = p.strip_prefix(dir).unwrap().to_string_lossy().into_owned();
            let bytes = if meta.is_file() {
                std::fs::read(&p).unwrap()
            } else {
                Vec::new()
            };
            if meta.is_dir() {
                todo.push(p.clone());
            }
            out.insert(
                rel,
                (
                    meta.is_dir(),
                    bytes,
                    meta.permissions().mode(),
                    meta.modified().unwrap(),
                ),
            );
        }
    }
    Some(out)
}

/// The folder states a command may meet.
#[derive(Clone, Copy, Debug)]
enum State {
    Missing,
    Empty,
    UsersFile,
    EarlierRun,
    EarlierRunAndUsersFile,
    /// An earlier run that a kill interrupted: its partial file is left.
    KilledRun,
    /// A folder of sweep files (as `tswm report sweeps` met).
    Sweeps,
    /// A folder with a sub-folder and a file that looks partial but is
    /// the user's.
    Nested,
}

const STATES: [State; 8] = [
    State::Missing,
    State::Empty,
    State::UsersFile,
    State::EarlierRun,
    State::EarlierRunAndUsersFile,
    State::KilledRun,
    State::Sweeps,
    State::Nested,
];

/// Makes `dir/name` in `state` (a finished run's folder is copied from
/// `run`, made once).
fn make(dir: &Path, name: &str, state: State, run: &Path) {
    let d = dir.join(name);
    let copy_run = || {
        std::fs::create_dir_all(&d).unwrap();
        for e in std::fs::read_dir(run).unwrap() {
            let e = e.unwrap();
            std::fs::copy(e.path(), d.join(e.file_name())).unwrap();
        }
    };
    match state {
        State::Missing => {}
        State::Empty => std::fs::create_dir(&d).unwrap(),
        State::UsersFile => {
            std::fs::create_dir(&d).unwrap();
            std::fs::write(d.join("notes.txt"), "my notes\n").unwrap();
        }
        State::EarlierRun => copy_run(),
        State::EarlierRunAndUsersFile => {
            copy_run();
            std::fs::write(d.join("report.pdf"), "%PDF").unwrap();
        }
        State::KilledRun => {
            copy_run();
            std::fs::write(d.join(".lanes.csv.4194304-0.partial"), "lane,sta").unwrap();
        }
        State::Sweeps => {
            std::fs::create_dir(&d).unwrap();
            for s in ["paper.toml", "tolerance.toml"] {
                std::fs::copy(root().join("sweeps").join(s), d.join(s)).unwrap();
            }
        }
        State::Nested => {
            std::fs::create_dir_all(d.join("sub")).unwrap();
            std::fs::write(d.join("sub/a.csv"), "x\n1\n").unwrap();
            std::fs::write(d.join(".notes.partial"), "mine").unwrap();
        }
    }
}

/// A command that is refused in `state` for the folder `o` (None where
/// this command would be accepted there), with the words its line holds.
fn refused(cmd: usize, state: State) -> Option<(Vec<&'static str>, &'static str)> {
    use State::*;
    let holds_foreign = matches!(state, UsersFile | EarlierRunAndUsersFile | Sweeps | Nested);
    let is_run = matches!(state, EarlierRun | KilledRun);
    match cmd {
        // A sweep with a bad parameter: refused before any folder.
        0 => Some((cpu(&["run", "bad.toml", "--out", "o"]), "gamma_deg")),
        // A good sweep into a folder of someone else's files.
        1 if holds_foreign => Some((
            cpu(&["run", "good.toml", "--out", "o"]),
            "holds files tswm did not write",
        )),
        // A traced lane the sweep does not have.
        2 => Some((
            cpu(&["run", "good.toml", "--out", "o", "--trace", "7"]),
            "--trace",
        )),
        // A lane table with a bad row.
        3 => Some((cpu(&["run", "--lanes", "bad.csv", "--out", "o"]), "bad.csv")),
        // The report of a folder that is not a run.
        4 if !is_run && !matches!(state, EarlierRunAndUsersFile) => {
            Some((vec!["report", "o"], "o"))
        }
        // A merge of folders that are not shards, into o.
        5 => Some((vec!["merge", "good.toml", "--out", "o"], "good.toml")),
        // A shard that does not exist.
        6 => Some((
            cpu(&["run", "good.toml", "--shard", "3/2", "--out", "o"]),
            "--shard",
        )),
        _ => None,
    }
}

#[test]
fn a_refused_command_leaves_the_folder_exactly_as_it_was() {
    let dir = tempfile::tempdir().unwrap();
    let base = dir.path();
    std::fs::write(base.join("bad.toml"), "[base]\ngamma_deg = 95.0\n").unwrap();
    std::fs::write(base.join("good.toml"), "[base]\nt_end = 0.1\n").unwrap();
    std::fs::write(base.join("bad.csv"), "gamma_deg,f2\n5.0,1.0\n5.0,x\n").unwrap();
    let out = tswm(&cpu(&["run", "good.toml", "--out", "run"]), base);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let run = base.join("run");
    // Random pairs of a folder state and a command, seeded.
    let mut seed: u64 = 0x7e57_f01d;
    let mut next = |n: usize| {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 33) % n as u64) as usize
    };
    let (mut tried, mut kinds) = (0, std::collections::BTreeSet::new());
    for case in 0..120 {
        let state = STATES[next(STATES.len())];
        let cmd = next(7);
        let Some((args, word)) = refused(cmd, state) else {
            continue;
        };
        let case_dir = base.join(format!("c{case}"));
        std::fs::create_dir(&case_dir).unwrap();
        for f in ["bad.toml", "good.toml", "bad.csv"] {
            std::fs::copy(base.join(f), case_dir.join(f)).unwrap();
        }
        make(&case_dir, "o", state, &run);
        let before = snapshot(&case_dir.join("o"));
        let out = tswm(&args, &case_dir);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(
            out.status.code(),
            Some(2),
            "{state:?} {args:?}: refused expected, got {err}"
        );
        assert_eq!(
            err.trim_end().lines().count(),
            1,
            "{state:?} {args:?}: {err}"
        );
        assert!(
            err.contains(word),
            "{state:?} {args:?}: `{word}` missing: {err}"
        );
        let after = snapshot(&case_dir.join("o"));
        assert!(
            before == after,
            "{state:?} {args:?} ({err}): the folder changed: before {:?}, after {:?}",
            before.as_ref().map(|m| m.keys().collect::<Vec<_>>()),
            after.as_ref().map(|m| m.keys().collect::<Vec<_>>())
        );
        tried += 1;
        kinds.insert((format!("{state:?}"), cmd));
    }
    // The draw covers the ground: many refusals, of most kinds.
    assert!(tried >= 60, "{tried} refusals tried");
    assert!(kinds.len() >= 30, "{} kinds of refusal tried", kinds.len());
}
