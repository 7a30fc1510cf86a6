//! `lanes.csv` read back as batches of the asked-for columns, parsed in
//! parallel: the file is read a window at a time, each window cut at
//! line ends into a piece a thread, each piece's cells split at commas
//! and only the asked-for ones parsed; the pieces' batches are handed on
//! in order. A table `tswm` wrote has no quotes and no carriage returns;
//! from a window holding either, the rest of the file is read by the
//! `csv` crate's reader one record at a time (quoted cells may hold
//! commas and line ends), with the same errors.

use std::fs::File;
use std::io::{Cursor, Read};
use std::path::Path;
use std::sync::Arc;

use arrow_array::RecordBatch;
use arrow_schema::{Field, Schema, SchemaRef};

use super::reading::{not_ours, open, Builder, Wanted, BATCH_ROWS};
use super::{columns, Kind};
use crate::error::{Error, Result};
use crate::output::batch::columns_for;
use crate::output::batch::data_type;

/// Bytes read at a time (a window's pieces in flight, memory bounded).
const WINDOW: usize = 16 << 20;

/// A row's error in a piece: its record number in the piece (from 1),
/// the column named (None for the row) and what is wrong.
type PieceError = (u64, Option<&'static str>, String);

/// Reads `path` (a `lanes.csv`), columns `wanted`, handing `each` its
/// batches in row order.
pub(super) fn read_csv(
    path: &Path,
    wanted: &Wanted,
    each: &mut impl FnMut(&RecordBatch) -> Result<()>,
) -> Result<()> {
    read_windows(path, wanted, each, WINDOW)
}

/// [`read_csv`], `window` bytes read at a time.
fn read_windows(
    path: &Path,
    wanted: &Wanted,
    each: &mut impl FnMut(&RecordBatch) -> Result<()>,
    window: usize,
) -> Result<()> {
    let schema: SchemaRef = Arc::new(Schema::new(
        wanted
            .iter()
            .map(|(_, n, k)| Field::new(*n, data_type(*k), *k != Kind::Int))
            .collect::<Vec<_>>(),
    ));
    let mut file = open(path)?;
    let io = |e: std::io::Error| Error::io(path, e);
    let mut buf: Vec<u8> = Vec::with_capacity(window + (1 << 16));
    let (mut rows, mut lines) = (0u64, 0u64);
    let mut header = true;
    // The header's cells: the table's, with or without a search's columns.
    let mut width = 0;
    loop {
        let had = buf.len();
        buf.resize(had + window, 0);
        let got = read_full(&mut file, &mut buf[had..]).map_err(io)?;
        buf.truncate(had + got);
        let end = got == 0;
        if buf.contains(&b'"') || buf.contains(&b'\r') {
            // Quotes or carriage returns: the `csv` reader from here on.
            let rest = Cursor::new(std::mem::take(&mut buf)).chain(file);
            return read_serial(
                path,
                rest,
                (header, rows, lines, width),
                wanted,
                &schema,
                each,
            );
        }
        // Whole lines only; the last, unended one waits for more bytes.
        let cut = if end {
            buf.len()
        } else {
            match buf.iter().rposition(|&b| b == b'\n') {
                Some(i) => i + 1,
                None => continue,
            }
        };
        let mut body = &buf[..cut];
        if header {
            let line_end = body.iter().position(|&b| b == b'\n').unwrap_or(body.len());
            width = check_header(path, &body[..line_end])?;
            body = &body[(line_end + 1).min(body.len())..];
            header = false;
            lines += 1;
        }
        (rows, lines) = parse_window(path, body, (rows, lines, width), wanted, &schema, each)?;
        buf.drain(..cut);
        if end {
            return Ok(());
        }
    }
}

/// Fills `buf` from `r` as far as it goes; the bytes read (fewer only at
/// the end of the file).
fn read_full(r: &mut File, buf: &mut [u8]) -> std::io::Result<usize> {
    let mut n = 0;
    while n < buf.len() {
        match r.read(&mut buf[n..])? {
            0 => break,
            k => n += k,
        }
    }
    Ok(n)
}

/// The header line must name the table's columns, in order (a search's
/// table has its columns after them); its width.
fn check_header(path: &Path, line: &[u8]) -> Result<usize> {
    let names: Vec<&[u8]> = line.split(|&b| b == b',').collect();
    let table = columns_for(names.len() > columns().len());
    if names.len() != table.len() || names.iter().zip(&table).any(|(h, c)| *h != c.0.as_bytes()) {
        return Err(not_ours(path));
    }
    Ok(table.len())
}

/// Parses a window's whole lines (rows `rows + 1..`, after `lines`
/// lines), a piece a thread, handing the pieces' batches on in order; the
/// rows and lines read so far.
fn parse_window(
    path: &Path,
    body: &[u8],
    (mut rows, mut lines, width): (u64, u64, usize),
    wanted: &Wanted,
    schema: &SchemaRef,
    each: &mut impl FnMut(&RecordBatch) -> Result<()>,
) -> Result<(u64, u64)> {
    use rayon::prelude::*;
    let threads = rayon::current_num_threads().max(1);
    // A piece a thread, of at most 8 MB (a batch's memory bounded).
    let want = (body.len() / threads).clamp(1, 8 << 20);
    let mut pieces = Vec::new();
    let mut at = 0;
    while at < body.len() {
        let mut end = (at + want).min(body.len());
        while end < body.len() && body[end - 1] != b'\n' {
            end += 1;
        }
        pieces.push(&body[at..end]);
        at = end;
    }
    let parsed: Vec<std::result::Result<(RecordBatch, u64), PieceError>> = pieces
        .par_iter()
        .map(|p| parse_piece(p, width, wanted, schema))
        .collect();
    for b in parsed {
        match b {
            Ok((b, n)) => {
                rows += b.num_rows() as u64;
                lines += n;
                each(&b)?;
            }
            Err((r, col, m)) => {
                return Err(Error::input(
                    path,
                    Some(format!("row {}", rows + r)),
                    Some(col.unwrap_or("")),
                    m,
                ))
            }
        }
    }
    Ok((rows, lines))
}

/// One piece's lines (no quotes, no carriage returns) as a batch, and
/// its lines; empty lines skipped, as the `csv` reader skips them.
fn parse_piece(
    piece: &[u8],
    width: usize,
    wanted: &Wanted,
    schema: &SchemaRef,
) -> std::result::Result<(RecordBatch, u64), PieceError> {
    let mut builders: Vec<Builder> = wanted.iter().map(|w| Builder::of(w.1, w.2)).collect();
    let mut row = 0u64;
    for line in piece.split(|&b| b == b'\n').filter(|l| !l.is_empty()) {
        row += 1;
        let mut next = wanted.iter().zip(builders.iter_mut()).peekable();
        let mut cells = 0;
        for (i, cell) in line.split(|&b| b == b',').enumerate() {
            cells += 1;
            if let Some(((_, name, _), b)) = next.next_if(|((c, _, _), _)| *c == i) {
                b.push(cell).map_err(|m| (row, Some(*name), m))?;
            }
        }
        if cells != width {
            let m = format!("has {cells} cells, the table's header {width}; not a tswm table");
            return Err((row, None, m));
        }
    }
    let cols = builders.iter_mut().map(Builder::finish).collect();
    let lines = piece.iter().filter(|&&b| b == b'\n').count() as u64;
    RecordBatch::try_new(schema.clone(), cols)
        .map(|b| (b, lines))
        .map_err(|e| (row, None, e.to_string()))
}

/// Reads the rest of a table from `rd` with the `csv` crate's reader,
/// its header first when `header`; rows `row + 1..`, after `lines`
/// lines (an error's line is the file's).
fn read_serial(
    path: &Path,
    rd: impl Read,
    (header, mut row, lines, width): (bool, u64, u64, usize),
    wanted: &Wanted,
    schema: &SchemaRef,
    each: &mut impl FnMut(&RecordBatch) -> Result<()>,
) -> Result<()> {
    // Flexible: a row of another length gets the error the parallel
    // reader gives (its row, its cells and the header's).
    let mut rd = csv::ReaderBuilder::new()
        .has_headers(header)
        .flexible(true)
        .buffer_capacity(1 << 20)
        .from_reader(rd);
    let width = if header {
        let head = rd
            .byte_headers()
            .map_err(|e| Error::input(path, None, None, format!("not a tswm table: {e}")))?;
        let line: Vec<u8> = head.iter().collect::<Vec<_>>().join(&b","[..]);
        check_header(path, &line)?
    } else {
        width
    };
    let mut builders: Vec<Builder> = wanted.iter().map(|w| Builder::of(w.1, w.2)).collect();
    let mut rec = csv::ByteRecord::new();
    let mut filled = 0usize;
    let mut flush = |builders: &mut Vec<Builder>| -> Result<()> {
        let cols = builders.iter_mut().map(Builder::finish).collect();
        let b = RecordBatch::try_new(schema.clone(), cols)
            .map_err(|e| Error::Internal(format!("batch of {}: {e}", path.display())))?;
        each(&b)
    };
    while rd.read_byte_record(&mut rec).map_err(|e| {
        let line = e.position().map(|p| format!("line {}", lines + p.line()));
        Error::input(path, line, None, format!("not a tswm table: {e}"))
    })? {
        row += 1;
        let at = || Some(format!("row {row}"));
        if rec.len() != width {
            return Err(Error::input(
                path,
                at(),
                Some(""),
                format!(
                    "has {} cells, the table's header {width}; not a tswm table",
                    rec.len(),
                ),
            ));
        }
        for ((i, name, _), b) in wanted.iter().zip(builders.iter_mut()) {
            b.push(&rec[*i])
                .map_err(|m| Error::input(path, at(), Some(name), m))?;
        }
        filled += 1;
        if filled == BATCH_ROWS {
            flush(&mut builders)?;
            filled = 0;
        }
    }
    if filled > 0 {
        flush(&mut builders)?;
    }
    Ok(())
}

#[cfg(test)]
#[path = "csv_read_tests.rs"]
mod tests;
