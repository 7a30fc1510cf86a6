//! Shards and `tswm merge`: a split run joins into exactly what one run
//! writes; a missing, doubled, truncated or foreign shard is refused; a
//! complete shard is not run again; `lanes.parquet` holds what
//! `lanes.csv` holds.

use std::fs;
use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};

use crate::common::{cpu, root, tswm};

fn sweep(name: &str) -> String {
    root().join("sweeps").join(name).display().to_string()
}

/// Runs `tswm`, asserting success; its stdout.
fn ok(args: &[&str], cwd: &Path) -> String {
    let out = tswm(args, cwd);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Runs shards 0..n of `sweep` into `dir/s{k}`; their folders.
fn shards(sweep: &str, n: u64, dir: &Path, extra: &[&str]) -> Vec<PathBuf> {
    (0..n)
        .map(|k| {
            let out = dir.join(format!("s{k}"));
            let spec = format!("{k}/{n}");
            let mut args = cpu(&["run", sweep, "--shard", &spec]);
            let o = out.display().to_string();
            args.extend(["--out", &o]);
            args.extend(extra);
            ok(&args, dir);
            out
        })
        .collect()
}

fn merge_args<'a>(dirs: &'a [String], out: &'a str) -> Vec<&'a str> {
    let mut a = vec!["merge"];
    a.extend(dirs.iter().map(String::as_str));
    a.extend(["--out", out]);
    a
}

fn names(dirs: &[PathBuf]) -> Vec<String> {
    dirs.iter().map(|d| d.display().to_string()).collect()
}

fn bytes(p: &Path) -> Vec<u8> {
    fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// 4 shards merged equal the unsharded run byte for byte: the table,
/// the statistics and the traces.
fn merged_equals_unsharded(name: &str) {
    let t = tempfile::tempdir().unwrap();
    let dir = t.path();
    ok(&cpu(&["run", &sweep(name), "--out", "full"]), dir);
    let parts = shards(&sweep(name), 4, dir, &[]);
    let out = ok(&merge_args(&names(&parts), "merged"), dir);
    assert!(out.contains("from 4 shards"), "{out}");
    for f in ["lanes.csv", "summary.csv", "sensitivity.csv", "traces.csv"] {
        let (a, b) = (dir.join("full").join(f), dir.join("merged").join(f));
        assert_eq!(a.exists(), b.exists(), "{name}: {f}");
        if a.exists() {
            assert!(
                bytes(&a) == bytes(&b),
                "{name}: merged {f} differs from the unsharded one"
            );
        }
    }
    let report = fs::read_to_string(dir.join("merged/report.html")).unwrap();
    assert!(
        report.contains("<svg"),
        "{name}: the merged report has no plot"
    );
    // Shards hold their part only: no statistics or report of their own.
    assert!(!parts[0].join("summary.csv").exists() && !parts[0].join("report.html").exists());
}

#[test]
fn four_shards_of_the_tolerance_study_merge_to_the_unsharded_table() {
    merged_equals_unsharded("tolerance.toml");
}

#[test]
fn four_shards_of_a_sensitivity_design_merge_to_the_unsharded_indices() {
    merged_equals_unsharded("which_tolerance.toml");
}

#[test]
fn four_shards_of_a_grid_merge_to_the_unsharded_table() {
    merged_equals_unsharded("efficiency_map.toml");
}

#[test]
fn traced_lanes_and_empty_shards_merge_too() {
    // Two lanes in four shards: two shards are empty, each traced lane
    // falls in its own shard.
    merged_equals_unsharded("paper.toml");
}

#[test]
fn the_lanes_of_a_shard_do_not_depend_on_the_split() {
    let t = tempfile::tempdir().unwrap();
    let dir = t.path();
    let s = sweep("self_locking.toml");
    ok(&cpu(&["run", &s, "--shard", "1/3", "--out", "a"]), dir);
    ok(&cpu(&["run", &s, "--shard", "2/7", "--out", "b"]), dir);
    let read = |p: &str| crate::common::read_csv(&dir.join(p).join("lanes.csv"));
    let ((h, a), (_, b)) = (read("a"), read("b"));
    let lane = h.iter().position(|c| c == "lane").unwrap();
    let mut common = 0;
    for r in &a {
        if let Some(q) = b.iter().find(|q| q[lane] == r[lane]) {
            assert_eq!(r, q, "lane {} differs between splits", r[lane]);
            common += 1;
        }
    }
    // 1/3 holds lanes 8333..16666, 2/7 lanes 7142..10714.
    assert_eq!(common, 10714 - 8333);
}

/// Shards of the tolerance study in `dir`, for the refusals.
fn refusal_setup(dir: &Path) -> Vec<String> {
    names(&shards(&sweep("tolerance.toml"), 4, dir, &[]))
}

/// `tswm merge` fails with exit 2 and one line naming `named`, and
/// writes nothing.
fn refused(args: &[&str], dir: &Path, named: &str, why: &str) {
    let out = tswm(args, dir);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains(named) && err.contains(why), "{err}");
    assert!(
        !dir.join("out").exists(),
        "a refused merge wrote {}",
        dir.join("out").display()
    );
}

#[test]
fn merge_refuses_a_missing_shard() {
    let t = tempfile::tempdir().unwrap();
    let d = refusal_setup(t.path());
    let given = [d[0].clone(), d[1].clone(), d[3].clone()];
    refused(&merge_args(&given, "out"), t.path(), "shard 2/4", "missing");
    // A shard folder that is not there at all.
    let gone = [
        d[0].clone(),
        d[1].clone(),
        d[2].clone(),
        format!("{}-gone", d[3]),
    ];
    refused(&merge_args(&gone, "out"), t.path(), "s3-gone", "missing");
}

#[test]
fn merge_refuses_a_doubled_shard() {
    let t = tempfile::tempdir().unwrap();
    let d = refusal_setup(t.path());
    let copy = t.path().join("s2-copy");
    fs::create_dir(&copy).unwrap();
    for f in ["lanes.csv", "shard.toml", "sweep.resolved.toml"] {
        fs::copy(Path::new(&d[2]).join(f), copy.join(f)).unwrap();
    }
    let mut given = d.clone();
    given.push(copy.display().to_string());
    refused(
        &merge_args(&given, "out"),
        t.path(),
        "s2-copy",
        "doubled shard",
    );
}

#[test]
fn merge_refuses_a_truncated_shard() {
    let t = tempfile::tempdir().unwrap();
    let d = refusal_setup(t.path());
    let f = Path::new(&d[1]).join("lanes.csv");
    let b = bytes(&f);
    fs::write(&f, &b[..b.len() / 2]).unwrap();
    refused(&merge_args(&d, "out"), t.path(), "s1", "truncated");
    // A shard whose run never finished has no manifest.
    let t2 = tempfile::tempdir().unwrap();
    let d2 = refusal_setup(t2.path());
    fs::remove_file(Path::new(&d2[3]).join("shard.toml")).unwrap();
    refused(&merge_args(&d2, "out"), t2.path(), "s3", "incomplete shard");
}

#[test]
fn merge_refuses_a_foreign_shard() {
    let t = tempfile::tempdir().unwrap();
    let dir = t.path();
    let d = refusal_setup(dir);
    // The same sweep with one value changed is another sweep.
    let text = fs::read_to_string(sweep("tolerance.toml")).unwrap();
    fs::write(
        dir.join("other.toml"),
        text.replace("seed = 20031001", "seed = 7"),
    )
    .unwrap();
    ok(
        &cpu(&["run", "other.toml", "--shard", "2/4", "--out", "other"]),
        dir,
    );
    let given = [d[0].clone(), d[1].clone(), "other".into(), d[3].clone()];
    refused(&merge_args(&given, "out"), dir, "other", "foreign shard");
    // So is a shard of another split of the same sweep.
    ok(
        &cpu(&[
            "run",
            &sweep("tolerance.toml"),
            "--shard",
            "2/5",
            "--out",
            "split5",
        ]),
        dir,
    );
    let given = [d[0].clone(), d[1].clone(), "split5".into(), d[3].clone()];
    refused(&merge_args(&given, "out"), dir, "split5", "foreign shard");
}

#[test]
fn a_complete_shard_is_not_run_again_an_incomplete_one_is_redone() {
    let t = tempfile::tempdir().unwrap();
    let dir = t.path();
    let s = sweep("tolerance.toml");
    let args = cpu(&["run", s.as_str(), "--shard", "1/4", "--out", "s"]);
    ok(&args, dir);
    let table = dir.join("s/lanes.csv");
    let before = fs::metadata(&table).unwrap();
    let content = bytes(&table);
    // The retry finds the complete result: it names it and integrates
    // nothing (the table is the very file written before: same inode,
    // same modification time; a run writes a new file and renames it).
    let out = ok(&args, dir);
    assert!(
        out.contains("already complete") && out.contains("nothing to do"),
        "{out}"
    );
    assert!(!out.contains("lanes/s"), "{out}");
    let after = fs::metadata(&table).unwrap();
    assert_eq!(
        (before.ino(), before.mtime_nsec()),
        (after.ino(), after.mtime_nsec())
    );
    // An incomplete one (a truncated table; no manifest) is redone.
    fs::write(&table, &content[..1000]).unwrap();
    let out = ok(&args, dir);
    assert!(
        out.contains("lanes/s") && !out.contains("already complete"),
        "{out}"
    );
    assert!(bytes(&table) == content);
    fs::remove_file(dir.join("s/shard.toml")).unwrap();
    let out = ok(&args, dir);
    assert!(out.contains("lanes/s"), "{out}");
    assert!(bytes(&table) == content && dir.join("s/shard.toml").exists());
    // Another split into the same folder is not "complete" either.
    let out = ok(
        &cpu(&["run", s.as_str(), "--shard", "1/5", "--out", "s"]),
        dir,
    );
    assert!(out.contains("lanes/s"), "{out}");
}

/// A row's cells as text, None for a null.
type Row = Vec<Option<String>>;

/// Every row of a Parquet file as text cells, read with the Apache
/// implementation's own row API, with the column types.
fn parquet_rows(path: &Path) -> (Vec<(String, String)>, Vec<Row>) {
    use parquet::file::reader::{FileReader, SerializedFileReader};
    use parquet::record::Field;
    let r = SerializedFileReader::new(fs::File::open(path).unwrap()).unwrap();
    let schema = r.metadata().file_metadata().schema_descr_ptr();
    let cols = schema
        .columns()
        .iter()
        .map(|c| {
            let logical = c
                .logical_type_ref()
                .map(|l| format!("{l:?}"))
                .unwrap_or_default();
            (
                c.name().to_string(),
                format!("{:?}{logical}", c.physical_type()),
            )
        })
        .collect();
    let rows = r
        .get_row_iter(None)
        .unwrap()
        .map(|row| {
            row.unwrap()
                .get_column_iter()
                .map(|(_, f)| match f {
                    Field::Null => None,
                    Field::Double(v) => Some(format!("{v:?}")),
                    Field::Long(v) => Some(v.to_string()),
                    Field::Str(s) => Some(s.clone()),
                    other => panic!("unexpected field {other:?}"),
                })
                .collect()
        })
        .collect();
    (cols, rows)
}

/// A Parquet table equals a CSV table value for value: floats bit for
/// bit, nulls where the CSV cell is empty, the same words and counts.
fn assert_same_values(parquet: &Path, csv: &Path) {
    let (cols, prows) = parquet_rows(parquet);
    let (header, crows) = crate::common::read_csv(csv);
    let names: Vec<&str> = cols.iter().map(|c| c.0.as_str()).collect();
    assert_eq!(names, header.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(prows.len(), crows.len());
    for (i, (p, c)) in prows.iter().zip(&crows).enumerate() {
        for (j, (pv, cv)) in p.iter().zip(c).enumerate() {
            let ty = &cols[j].1;
            // An empty cell is a null in every column, words included.
            assert_eq!(
                pv.is_none(),
                cv.is_empty(),
                "row {i} {}: {pv:?} vs `{cv}`",
                cols[j].0
            );
            match pv {
                None => {
                    assert!(!ty.starts_with("INT64"), "{} is never empty", cols[j].0);
                }
                Some(v) if ty.starts_with("DOUBLE") => {
                    let (a, b): (f64, f64) = (v.parse().unwrap(), cv.parse().unwrap());
                    assert_eq!(a.to_bits(), b.to_bits(), "row {i} {}", cols[j].0);
                }
                Some(v) => assert_eq!(v, cv, "row {i} {}", cols[j].0),
            }
        }
    }
    // Typed: counts are integers, words are strings.
    let ty = |n: &str| cols.iter().find(|c| c.0 == n).unwrap().1.clone();
    assert_eq!(ty("lane"), "INT64");
    assert_eq!(ty("steps"), "INT64");
    assert_eq!(ty("w_friction"), "DOUBLE");
    assert!(
        ty("status").starts_with("BYTE_ARRAYString"),
        "{}",
        ty("status")
    );
}

/// pyarrow, an independent reader, sees a null exactly where `lanes.csv`
/// has an empty cell, column by column, words (`hold`, `drive`,
/// `friction_table`, `t_first_switch`, ...) included.
#[test]
fn pyarrow_null_counts_are_the_csvs_empty_cells() {
    const NEEDS: crate::reference::Needs = crate::reference::Needs {
        modules: "pyarrow",
        vars: &["TSWM_PYTHON"],
        install: "pip install pyarrow, or set TSWM_PYTHON",
    };
    let Some(py) = crate::reference::python_for(&NEEDS, "pyarrow's null counts") else {
        return;
    };
    let t = tempfile::tempdir().unwrap();
    let dir = t.path();
    // Motors cut and not (hold and drive each empty somewhere), switches
    // and none, a friction table named on some lanes only.
    fs::write(
        dir.join("s.toml"),
        "[base]\nt_end = 1.5\n[[grid]]\nparam = \"f2\"\nvalues = [-30000.0, -4774.0, 4774.0]\n\
         [[grid]]\nparam = \"motor_off\"\nvalues = [0.5, 5.0]\n\
         [[grid]]\nparam = \"friction\"\nvalues = [\"paper\", \"table\"]\n\
         [friction_table.bronze]\nvs = [0.0, 1.0]\nmu = [0.1, 0.05]\n",
    )
    .unwrap();
    run_both_formats("s.toml", dir);
    let script = r#"
import csv, sys
import pyarrow.parquet as pq
t = pq.read_table("p/lanes.parquet")
rows = list(csv.reader(open("c/lanes.csv")))
head, rows = rows[0], rows[1:]
assert t.column_names == head, (t.column_names, head)
assert t.num_rows == len(rows)
for j, name in enumerate(head):
    empty = sum(1 for r in rows if r[j] == "")
    assert t.column(name).null_count == empty, (name, t.column(name).null_count, empty)
print("ok", sum(t.column(n).null_count for n in head))
"#;
    let out = std::process::Command::new(&py)
        .args(["-c", script])
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn lanes_parquet_holds_the_values_of_lanes_csv() {
    let t = tempfile::tempdir().unwrap();
    let dir = t.path();
    // The tolerance study (every cell set) and the self-locking one, whose
    // unswitched lanes leave t_first_switch empty.
    for name in ["tolerance.toml", "self_locking.toml"] {
        let s = sweep(name);
        ok(&cpu(&["run", &s, "--no-report", "--out", "c"]), dir);
        ok(&cpu(&["run", &s, "--format", "parquet", "--out", "p"]), dir);
        assert_same_values(&dir.join("p/lanes.parquet"), &dir.join("c/lanes.csv"));
        assert!(!dir.join("p/lanes.csv").exists());
        assert!(bytes(&dir.join("c/summary.csv")) == bytes(&dir.join("p/summary.csv")));
        // The report reads either format.
        let page = fs::read_to_string(dir.join("p/report.html")).unwrap();
        assert!(
            page.contains("<svg"),
            "{name}: report of a Parquet run has no plot"
        );
    }
}

#[test]
fn parquet_shards_merge_to_the_unsharded_csv() {
    let t = tempfile::tempdir().unwrap();
    let dir = t.path();
    let s = sweep("tolerance.toml");
    ok(&cpu(&["run", &s, "--no-report", "--out", "full"]), dir);
    let parts = shards(&s, 3, dir, &["--format", "parquet"]);
    // The shards' files, read one after the other, are the table: a
    // dataset readers take as one table without a merge.
    let (header, csv_rows) = crate::common::read_csv(&dir.join("full/lanes.csv"));
    let mut rows = Vec::new();
    for p in &parts {
        let (cols, r) = parquet_rows(&p.join("lanes.parquet"));
        assert_eq!(cols.len(), header.len());
        rows.extend(r);
    }
    assert_eq!(rows.len(), csv_rows.len());
    for (p, c) in rows.iter().zip(&csv_rows) {
        let lane = header.iter().position(|h| h == "lane").unwrap();
        assert_eq!(p[lane].as_deref(), Some(c[lane].as_str()));
    }
    ok(&merge_args(&names(&parts), "merged"), dir);
    assert!(bytes(&dir.join("merged/lanes.csv")) == bytes(&dir.join("full/lanes.csv")));
    ok(
        &[
            &merge_args(&names(&parts), "mp")[..],
            &["--format", "parquet"],
        ]
        .concat(),
        dir,
    );
    assert_same_values(&dir.join("mp/lanes.parquet"), &dir.join("full/lanes.csv"));
    // Merged batch by batch (never through text): the bytes of one run.
    ok(
        &cpu(&[
            "run",
            &s,
            "--no-report",
            "--format",
            "parquet",
            "--out",
            "fp",
        ]),
        dir,
    );
    assert!(bytes(&dir.join("mp/lanes.parquet")) == bytes(&dir.join("fp/lanes.parquet")));
    assert!(bytes(&dir.join("mp/summary.csv")) == bytes(&dir.join("fp/summary.csv")));
}

/// `lanes.parquet`'s bytes do not depend on how the rows reached the
/// writer: a run on one thread or two (other chunks), and merges of 3 and
/// 7 shards (shard ends that cut its row groups and pages anywhere, read
/// back in batches of their own), write the same file, over several row
/// groups.
#[test]
fn parquet_bytes_do_not_depend_on_how_batches_are_cut() {
    let t = tempfile::tempdir().unwrap();
    let dir = t.path();
    // 300,007 short lanes: three row groups of 131,072 rows and a rest.
    let s = dir.join("many.toml");
    fs::write(
        &s,
        "[base]\nt_end = 0.1\n[[grid]]\nparam = \"f2\"\nfrom = -6000.0\nto = 6000.0\nn = 300007\n",
    )
    .unwrap();
    let s = s.display().to_string();
    let pq = ["--no-report", "--format", "parquet"];
    ok(
        &[
            &cpu(&["run", &s, "--threads", "1", "--out", "one"])[..],
            &pq,
        ]
        .concat(),
        dir,
    );
    ok(
        &[
            &cpu(&["run", &s, "--threads", "2", "--out", "two"])[..],
            &pq,
        ]
        .concat(),
        dir,
    );
    let want = bytes(&dir.join("one/lanes.parquet"));
    assert!(bytes(&dir.join("two/lanes.parquet")) == want, "threads");
    for n in [3, 7] {
        let sub = dir.join(format!("by{n}"));
        fs::create_dir(&sub).unwrap();
        let parts = shards(&s, n, &sub, &["--format", "parquet"]);
        let out = format!("m{n}");
        ok(
            &[
                &merge_args(&names(&parts), &out)[..],
                &["--format", "parquet"],
            ]
            .concat(),
            dir,
        );
        assert!(
            bytes(&dir.join(&out).join("lanes.parquet")) == want,
            "{n} shards"
        );
    }
}

/// The word columns of `lanes.parquet` (dictionary-encoded pages, and
/// dictionary columns in its Arrow schema) read as the same strings in
/// pyarrow, polars and DuckDB, and as `lanes.csv` has them.
#[test]
fn parquet_words_read_the_same_in_pyarrow_polars_and_duckdb() {
    const READERS: crate::reference::Needs = crate::reference::Needs {
        modules: "pyarrow, polars, duckdb",
        vars: &["TSWM_PYTHON"],
        install: "pip install pyarrow polars duckdb, or set TSWM_PYTHON",
    };
    let Some(py) = crate::reference::python_for(&READERS, "parquet words in three readers") else {
        return;
    };
    let t = tempfile::tempdir().unwrap();
    let dir = t.path();
    run_both_formats(&sweep("heterogeneous.toml"), dir);
    let code = r#"
import csv, sys
import duckdb, polars as pl, pyarrow.parquet as pq
p, c = sys.argv[1], sys.argv[2]
rows = list(csv.DictReader(open(c)))
t = pq.read_table(p)
md = pq.ParquetFile(p).metadata
words = [f.name for f in t.schema if str(f.type) == "dictionary<values=string, indices=int16, ordered=0>"]
assert {"motor", "friction", "friction_table", "status", "contact_end", "hold", "drive", "path"} <= set(words), words
assert not [f.name for f in t.schema if str(f.type) == "string"], "a word column that is not a dictionary"
df = pl.read_parquet(p)
for w in words:
    i = t.schema.get_field_index(w)
    assert "RLE_DICTIONARY" in md.row_group(0).column(i).encodings, w
    want = [r[w] or None for r in rows]
    a = t.column(w).to_pylist()
    b = df[w].to_list()
    q = 'SELECT "%s" FROM read_parquet(?) ORDER BY lane' % w
    d = [x[0] for x in duckdb.execute(q, [p]).fetchall()]
    assert a == want and b == want and d == want, w
print(len(words), "word columns,", len(rows), "rows")
"#;
    let out = std::process::Command::new(&py)
        .args(["-c", code])
        .arg(dir.join("p/lanes.parquet"))
        .arg(dir.join("c/lanes.csv"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Rows of one run come from one f64 tolerance: a shard run with another
/// `--tol` is refused by the merge, with the two tolerances named.
#[test]
fn merge_refuses_shards_run_at_different_tolerances() {
    let t = tempfile::tempdir().unwrap();
    let dir = t.path();
    let s = sweep("paper.toml");
    ok(&cpu(&["run", &s, "--shard", "0/2", "--out", "a"]), dir);
    ok(
        &cpu(&["run", &s, "--shard", "1/2", "--out", "b", "--tol", "1e-11"]),
        dir,
    );
    let parts = [
        dir.join("a").display().to_string(),
        dir.join("b").display().to_string(),
    ];
    refused(&merge_args(&parts, "out"), dir, &parts[1], "f64 tol 1e-11");
}

/// Every shipped sweep's `lanes.parquet`, read by pyarrow, equals its
/// `lanes.csv` read by pyarrow's CSV reader: the same types, floats bit
/// for bit, nulls where a cell is empty, in the word columns too
/// (`tests/columnar/same_values.py`); and both runs write the same
/// `summary.csv`.
#[test]
fn pyarrow_reads_every_shipped_sweeps_parquet_as_its_csv() {
    const PYARROW: crate::reference::Needs = crate::reference::Needs {
        modules: "pyarrow",
        vars: &["TSWM_PYTHON"],
        install: "pip install pyarrow, or set TSWM_PYTHON",
    };
    let Some(py) = crate::reference::python_for(&PYARROW, "pyarrow_reads_every_shipped_sweeps")
    else {
        return;
    };
    let t = tempfile::tempdir().unwrap();
    let dir = t.path();
    let script = root().join("tests/columnar/same_values.py");
    let mut sweeps: Vec<_> = fs::read_dir(root().join("sweeps"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .filter(|p| !p.ends_with("million.toml")) // 10^6 lanes: too long for a test
        .collect();
    sweeps.sort();
    assert!(sweeps.len() >= 8, "{sweeps:?}");
    for s in &sweeps {
        let s = s.display().to_string();
        run_both_formats(&s, dir);
        let out = std::process::Command::new(&py)
            .arg(&script)
            .arg(dir.join("p/lanes.parquet"))
            .arg(dir.join("c/lanes.csv"))
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{s}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(bytes(&dir.join("c/summary.csv")) == bytes(&dir.join("p/summary.csv")));
    }
}

/// Runs `sweep` in `dir` on the CPU without a report, once to `c`
/// (`lanes.csv`) and once to `p` (`lanes.parquet`).
fn run_both_formats(sweep: &str, dir: &Path) {
    ok(&cpu(&["run", sweep, "--no-report", "--out", "c"]), dir);
    ok(
        &cpu(&[
            "run",
            sweep,
            "--no-report",
            "--format",
            "parquet",
            "--out",
            "p",
        ]),
        dir,
    );
}

/// `lanes.parquet` is laid out as docs/outputs.md says, as pyarrow reads
/// it: row groups of `ROW_GROUP` rows, every page LZ4 (`LZ4_RAW`), the
/// words dictionary-encoded, a minimum and maximum in every row group of
/// the count and word columns that hold a value (pyarrow leaves those of
/// DOUBLE columns out: their IEEE 754 total order is newer than it).
#[test]
fn the_parquet_layout_is_the_documented_one() {
    const PYARROW: crate::reference::Needs = crate::reference::Needs {
        modules: "pyarrow",
        vars: &["TSWM_PYTHON"],
        install: "pip install pyarrow, or set TSWM_PYTHON",
    };
    let Some(py) =
        crate::reference::python_for(&PYARROW, "the_parquet_layout_is_the_documented_one")
    else {
        return;
    };
    let group = tswm::output::table::ROW_GROUP;
    let t = tempfile::tempdir().unwrap();
    let sweep = t.path().join("s.toml");
    let lanes = group + group / 2 + 7;
    fs::write(
        &sweep,
        format!("[base]\nt_end = 1e-4\n[[grid]]\nparam = \"f2\"\nfrom = -5000.0\nto = 5000.0\nn = {lanes}\n"),
    )
    .unwrap();
    let out = t.path().join("out");
    let run = tswm(
        &[
            "run",
            sweep.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--format",
            "parquet",
            "--backend",
            "cpu",
            "--no-report",
        ],
        t.path(),
    );
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let o = std::process::Command::new(&py)
        .arg(root().join("tests/columnar/layout.py"))
        .arg(out.join("lanes.parquet"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8(o.stdout).unwrap();
    let line = |start: &str| -> Vec<String> {
        text.lines()
            .filter(|l| l.starts_with(start))
            .map(String::from)
            .collect()
    };
    assert_eq!(
        line("row_groups "),
        [format!("row_groups {group} {}", lanes - group)]
    );
    assert_eq!(line("codecs "), ["codecs LZ4"]);
    let columns = line("column ");
    assert_eq!(columns.len(), tswm::output::table::columns().len());
    for c in &columns {
        let f: Vec<&str> = c.split(' ').collect();
        let (name, physical, encodings, minmax) = (f[1], f[2], f[3], f[4]);
        let empty = [
            "f1",
            "motor_off",
            "friction_table",
            "mu",
            "t_first_switch",
            "hold",
            "n1_end",
        ];
        if physical == "BYTE_ARRAY" {
            assert!(encodings.contains("RLE_DICTIONARY"), "{c}");
        }
        if physical != "DOUBLE" && !empty.contains(&name) {
            assert_eq!(minmax, "minmax", "{c}");
        }
    }
    // The docs state the same layout.
    let thousands = |n: usize| {
        let s = n.to_string();
        let mut out = String::new();
        for (i, ch) in s.chars().enumerate() {
            if i > 0 && (s.len() - i).is_multiple_of(3) {
                out.push(',');
            }
            out.push(ch);
        }
        out
    };
    for page in ["docs/outputs.md", "docs/cluster.md"] {
        let p = fs::read_to_string(root().join(page))
            .unwrap()
            .replace('\n', " ");
        assert!(
            p.contains(&format!("row groups of {} rows", thousands(group))),
            "{page}"
        );
        assert!(p.contains("LZ4_RAW"), "{page}");
    }
}
