//! Shards are verified, not trusted: a merge refuses a shard whose table,
//! traces or resolved sweep was edited, in one line, writing nothing.

use super::*;

/// Shards of a small traced sweep in `dir/s0`, `dir/s1` (the format
/// given), and the arguments of their merge into `dir/m`.
fn traced_shards(dir: &Path, format: &str) {
    file(
        dir,
        "s.toml",
        "[base]\nt_end = 0.4\n[[grid]]\nparam = \"f2\"\nfrom = -5000.0\nto = 5000.0\nn = 40\n\
         [trace]\nlanes = [3, 30]\ndt = 0.01\n",
    );
    for k in 0..2 {
        let (s, o) = (format!("{k}/2"), format!("s{k}"));
        let out = tswm(
            &cpu(&[
                "run", "s.toml", "--shard", &s, "--out", &o, "--format", format,
            ]),
            dir,
        );
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

const MERGE: [&str; 6] = ["merge", "s0", "s1", "--out", "m", "--no-report"];

/// Merging is refused with one line naming the shard, and nothing is
/// written.
fn merge_refused(dir: &Path, want: &[&str]) -> String {
    let line = rejected(&MERGE, dir, want);
    assert!(!dir.join("m/lanes.csv").exists(), "a merge was written");
    line
}

/// Changes the byte at `at` of `path` to another value.
fn flip(path: &Path, at: usize, by: u8) {
    let mut b = std::fs::read(path).unwrap();
    let i = at % b.len();
    b[i] = b[i].wrapping_add(by.max(1));
    std::fs::write(path, b).unwrap();
}

#[test]
fn a_shard_with_text_in_a_number_cell_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    traced_shards(dir.path(), "csv");
    let p = dir.path().join("s1/lanes.csv");
    let text = std::fs::read_to_string(&p).unwrap();
    // Same size: one digit of a number becomes a letter.
    let at = text.lines().next().unwrap().len() + 3;
    let mut b = text.into_bytes();
    assert!(b[at].is_ascii_digit());
    b[at] = b'x';
    std::fs::write(&p, b).unwrap();
    // As written, the table's SHA-256 no longer matches the manifest's.
    merge_refused(
        dir.path(),
        &["s1", "shard 1/2 refused", "lanes.csv is changed"],
    );
    // With the manifest forged to match, the reader's own check refuses
    // the cell, naming the file, the row and the column.
    let m = dir.path().join("s1/shard.toml");
    let manifest = std::fs::read_to_string(&m).unwrap();
    let old = manifest
        .lines()
        .skip_while(|l| *l != "[files.\"lanes.csv\"]")
        .find_map(|l| l.strip_prefix("sha256 = "))
        .unwrap()
        .to_string();
    let new = format!(
        "\"{}\"",
        tswm::output::digest::file_digest(&p).unwrap().sha256
    );
    std::fs::write(&m, manifest.replace(&old, &new)).unwrap();
    merge_refused(
        dir.path(),
        &["s1/lanes.csv", "row 1", "not a finite number"],
    );
}

#[test]
fn a_parquet_shard_with_flipped_bytes_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    traced_shards(dir.path(), "parquet");
    let p = dir.path().join("s0/lanes.parquet");
    let n = std::fs::metadata(&p).unwrap().len() as usize;
    for i in 0..100 {
        flip(&p, 4 + (i * 7919) % (n - 8), 1);
    }
    merge_refused(
        dir.path(),
        &["s0", "shard 0/2 refused", "lanes.parquet is changed"],
    );
}

#[test]
fn an_edited_traces_csv_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    traced_shards(dir.path(), "csv");
    flip(&dir.path().join("s0/traces.csv"), 200, 1);
    merge_refused(dir.path(), &["s0", "traces.csv is changed"]);
}

#[test]
fn a_manifest_without_its_traces_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    traced_shards(dir.path(), "csv");
    let m = dir.path().join("s1/shard.toml");
    let text = std::fs::read_to_string(&m).unwrap();
    let cut: String = text
        .split("\n[files.\"traces.csv\"]")
        .next()
        .unwrap()
        .to_string();
    assert_ne!(cut, text);
    std::fs::write(&m, cut + "\n").unwrap();
    merge_refused(dir.path(), &["s1", "traces.csv"]);
}

#[test]
fn an_edited_resolved_sweep_is_refused_even_with_its_digest() {
    let dir = tempfile::tempdir().unwrap();
    traced_shards(dir.path(), "csv");
    let r = dir.path().join("s0/sweep.resolved.toml");
    let text = std::fs::read_to_string(&r).unwrap();
    let edited = text.replace("t_end = 0.4", "t_end = 0.5");
    assert_ne!(edited, text);
    std::fs::write(&r, &edited).unwrap();
    merge_refused(dir.path(), &["s0", "sweep.resolved.toml is changed"]);
    // The manifest mended to the edited file's digest: the sweep hash
    // still tells.
    let digest = tswm::output::digest::file_digest(&r).unwrap();
    let m = dir.path().join("s0/shard.toml");
    let mut man: tswm::run::shard::Manifest =
        toml::from_str(&std::fs::read_to_string(&m).unwrap()).unwrap();
    man.files.insert("sweep.resolved.toml".into(), digest);
    std::fs::write(&m, man.text()).unwrap();
    merge_refused(dir.path(), &["s0", "does not hash to the sweep hash"]);
}

/// 100 random same-size corruptions of a shard's table, traces or
/// resolved sweep: every one is refused.
#[test]
fn a_hundred_random_same_size_corruptions_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    traced_shards(dir.path(), "csv");
    let files = ["lanes.csv", "traces.csv", "sweep.resolved.toml"];
    let originals: Vec<Vec<(PathBuf, Vec<u8>)>> = (0..2)
        .map(|k| {
            files
                .iter()
                .map(|f| {
                    let p = dir.path().join(format!("s{k}/{f}"));
                    let b = std::fs::read(&p).unwrap();
                    (p, b)
                })
                .collect()
        })
        .collect();
    // A fixed generator: the same corruptions on every run.
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        x
    };
    for case in 0..100 {
        let shard = (next() % 2) as usize;
        let (path, orig) = &originals[shard][(next() % 3) as usize];
        let mut b = orig.clone();
        for _ in 0..1 + next() % 4 {
            let i = (next() % b.len() as u64) as usize;
            b[i] = b[i].wrapping_add(1 + (next() % 255) as u8);
        }
        std::fs::write(path, &b).unwrap();
        let out = tswm(&MERGE, dir.path());
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(
            out.status.code(),
            Some(2),
            "case {case}: {} merged: {err}",
            path.display()
        );
        assert!(err.contains(&format!("s{shard}")), "case {case}: {err}");
        assert!(!dir.path().join("m/lanes.csv").exists());
        std::fs::write(path, orig).unwrap();
    }
    // Mended, the shards merge.
    let out = tswm(&MERGE, dir.path());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
