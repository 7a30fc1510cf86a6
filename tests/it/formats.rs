//! Every table format registered in `Format::table` (the one place a
//! format is listed) writes what it reads back, and merges shards into the
//! bytes of one run: a new format is held to both by being registered.

use std::path::Path;

use arrow_array::RecordBatch;
use clap::ValueEnum;
use tswm::output::table::{columns, read_batches, Format};

use crate::common::{cpu, root, tswm};

fn ok(args: &[&str], cwd: &Path) {
    let out = tswm(args, cwd);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Every column of the table in `dir`, as read back, one batch.
fn table(dir: &Path) -> RecordBatch {
    let names: Vec<&str> = columns().iter().map(|c| c.0).collect();
    let mut got = Vec::new();
    read_batches(dir, &names, |b| {
        got.push(b.clone());
        Ok(())
    })
    .unwrap();
    arrow_select::concat::concat_batches(&got[0].schema(), &got).unwrap()
}

#[test]
fn every_format_reads_back_its_rows_and_merges_to_one_run() {
    let t = tempfile::tempdir().unwrap();
    let dir = t.path();
    // Every friction law, motors cut, lanes that hold and lanes that run:
    // words of every column, empty cells.
    let s = root()
        .join("sweeps/friction_laws.toml")
        .display()
        .to_string();
    let mut first: Option<RecordBatch> = None;
    for f in Format::value_variants() {
        let name = f.to_possible_value().unwrap().get_name().to_string();
        let full = format!("{name}-full");
        ok(
            &cpu(&["run", &s, "--no-report", "--format", &name, "--out", &full]),
            dir,
        );
        let back = table(&dir.join(&full));
        match &first {
            // The same values, nulls and words as every other format.
            Some(want) => {
                assert_eq!(back.num_columns(), want.num_columns());
                for (i, c) in columns().iter().enumerate() {
                    assert_eq!(
                        back.column(i).to_data(),
                        want.column(i).to_data(),
                        "{name}: column {}",
                        c.0
                    );
                }
            }
            None => first = Some(back),
        }
        let mut parts = Vec::new();
        for k in 0..3 {
            let (spec, out) = (format!("{k}/3"), format!("{name}-s{k}"));
            ok(
                &cpu(&[
                    "run", &s, "--shard", &spec, "--format", &name, "--out", &out,
                ]),
                dir,
            );
            parts.push(out);
        }
        let merged = format!("{name}-merged");
        let mut args = vec!["merge"];
        args.extend(parts.iter().map(String::as_str));
        args.extend(["--out", &merged, "--no-report", "--format", &name]);
        ok(&args, dir);
        for file in [f.file_name(), "summary.csv"] {
            assert!(
                std::fs::read(dir.join(&merged).join(file)).unwrap()
                    == std::fs::read(dir.join(&full).join(file)).unwrap(),
                "{name}: {file} of the merge is not the run's"
            );
        }
    }
}
