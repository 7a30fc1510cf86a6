//! Replays the fuzz corpus (`fuzz/corpus/`, and any saved failures in
//! `fuzz/crashes/`) through the sweep-file and lane-table readers: no
//! panic, and every error is one line. `examples/fuzz.rs` generates the
//! malformed inputs.

use std::path::Path;

use crate::common::root;

fn replay(target: &str, path: &Path, scratch: &Path) {
    let bytes = std::fs::read(path).unwrap();
    let err = std::panic::catch_unwind(|| match target {
        "sweep" => std::str::from_utf8(&bytes)
            .ok()
            .and_then(|t| tswm::input::sweep::Sweep::parse(Path::new("fuzz.toml"), t).err())
            .map(|e| e.to_string()),
        _ => {
            std::fs::write(scratch, &bytes).unwrap();
            tswm::input::lanes::Source::open(None, Some(scratch))
                .err()
                .map(|e| e.to_string())
        }
    })
    .unwrap_or_else(|_| panic!("{} panicked", path.display()));
    if let Some(msg) = err {
        assert!(!msg.contains(['\n', '\r']), "{}: {msg:?}", path.display());
    }
}

#[test]
fn fuzz_corpus_replays_without_panic() {
    let dir = tempfile::tempdir().unwrap();
    let scratch = dir.path().join("lanes.csv");
    let mut n = 0;
    for target in ["sweep", "lanes"] {
        for sub in ["corpus", "crashes"] {
            let folder = root().join("fuzz").join(sub).join(target);
            let Ok(entries) = std::fs::read_dir(&folder) else {
                continue;
            };
            for e in entries {
                replay(target, &e.unwrap().path(), &scratch);
                n += 1;
            }
        }
    }
    assert!(n >= 8, "the corpus holds {n} inputs");
}
