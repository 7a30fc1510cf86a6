//! Tests of the parallel CSV reader against the `csv` crate's.

use super::*;
use crate::columns::STATUS;
use crate::output::table::Format;

/// The batches of `text` read as `lanes.csv` (every column asked
/// for), or the error's words.
fn read(text: &str) -> std::result::Result<Vec<RecordBatch>, String> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(Format::Csv.file_name());
    std::fs::write(&path, text).unwrap();
    let whole = read_in(&path, WINDOW);
    // Windows smaller than the file, and than a line: the same.
    for w in [1000, 70_000] {
        assert_eq!(
            whole.as_ref().map(|b| rows(b)).map_err(String::clone),
            read_in(&path, w).map(|b| rows(&b))
        );
    }
    whole
}

fn read_in(path: &Path, window: usize) -> std::result::Result<Vec<RecordBatch>, String> {
    let table = columns();
    let wanted: Vec<(usize, &'static str, Kind)> = table
        .iter()
        .enumerate()
        .map(|(i, c)| (i, c.0, c.1))
        .collect();
    let mut out = Vec::new();
    read_windows(
        path,
        &wanted,
        &mut |b| {
            out.push(b.clone());
            Ok(())
        },
        window,
    )
    .map(|_| out)
    .map_err(|e| e.to_string())
}

/// A row of the table: a number, a count or a word in every cell,
/// `k` varying them; `quoted` quotes its words.
fn row(k: usize, quoted: bool) -> String {
    columns()
        .iter()
        .enumerate()
        .map(|(i, c)| match c.1 {
            Kind::Float if (i + k).is_multiple_of(3) => String::new(),
            Kind::Float => format!("{}", 0.5 + (i * k) as f64),
            Kind::Int => (i + k).to_string(),
            Kind::Text if quoted => format!("\"{}\"", word(c.0, k)),
            Kind::Text => word(c.0, k),
        })
        .collect::<Vec<_>>()
        .join(",")
}

/// A word of column `name`: one of its vocabulary's, or of the
/// sweep's own table names, `k` choosing.
fn word(name: &str, k: usize) -> String {
    match crate::output::batch::vocabulary(name) {
        Some(v) => v()[k % v().len()].to_string(),
        None => format!("w{}", k % 2),
    }
}

fn header() -> String {
    columns().iter().map(|c| c.0).collect::<Vec<_>>().join(",")
}

/// Every row of `batches` as text, however the rows split.
fn rows(batches: &[RecordBatch]) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    for b in batches {
        let cols = crate::output::batch::typed(b).unwrap();
        for r in 0..b.num_rows() {
            out.push(cols.iter().map(|c| c.text(r)).collect());
        }
    }
    out
}

/// The parallel reader and the `csv` crate's (which reads a table
/// with quotes) give the same rows, blank lines skipped alike, and
/// the same error on the same row.
#[test]
fn parallel_and_csv_reader_agree() {
    let n = 3000;
    let plain: Vec<String> = (0..n).map(|k| row(k, false)).collect();
    let quoted: Vec<String> = (0..n).map(|k| row(k, k == n - 1)).collect();
    let mut with_blank = plain.clone();
    with_blank.insert(17, String::new());
    let text = |rs: &[String]| format!("{}\n{}\n", header(), rs.join("\n"));
    let a = rows(&read(&text(&plain)).unwrap());
    let b = rows(&read(&text(&quoted)).unwrap());
    let c = rows(&read(&text(&with_blank)).unwrap());
    assert_eq!(a, b);
    assert_eq!(a, c);
    assert_eq!(a.len(), n);
    // No line end after the last row: the same rows.
    let d = rows(&read(text(&plain).trim_end()).unwrap());
    assert_eq!(a, d);
    // A bad cell: one error naming the row and the column, either way.
    for q in [false, true] {
        let mut bad: Vec<String> = (0..n).map(|k| row(k, q)).collect();
        let cells: Vec<&str> = bad[2000].split(',').collect();
        let first_float = columns()
            .iter()
            .position(|c| {
                c.1 == Kind::Float
                    && !cells[columns().iter().position(|x| x.0 == c.0).unwrap()].is_empty()
            })
            .unwrap();
        let mut cells: Vec<String> = cells.iter().map(|s| s.to_string()).collect();
        cells[first_float] = "abc".into();
        bad[2000] = cells.join(",");
        let e = read(&text(&bad)).unwrap_err();
        let name = columns()[first_float].0;
        assert!(
            e.contains("row 2001") && e.contains(name) && e.contains("not a finite number"),
            "{e}"
        );
        // A word its column does not have.
        let mut odd: Vec<String> = (0..n).map(|k| row(k, q)).collect();
        let at = columns().iter().position(|c| c.0 == STATUS).unwrap();
        let mut cells: Vec<String> = odd[2000].split(',').map(String::from).collect();
        cells[at] = "fine".into();
        odd[2000] = cells.join(",");
        let e = read(&text(&odd)).unwrap_err();
        assert!(
            e.contains("row 2001") && e.contains(STATUS) && e.contains("`fine`"),
            "{e}"
        );
        // A row one cell short.
        let mut short: Vec<String> = (0..n).map(|k| row(k, q)).collect();
        short[5] = short[5].rsplit_once(',').unwrap().0.to_string();
        let e = read(&text(&short)).unwrap_err();
        assert!(e.contains("row 6") && e.contains("cells"), "{e}");
    }
}
