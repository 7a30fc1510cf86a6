//! Rows of `lanes.csv` from a batch: the cells of each row joined by
//! commas, floats as their shortest round-trip text, empty cells empty.
//! Blocks of rows are formatted in parallel into buffers that are reused
//! from chunk to chunk (no allocation per row or cell), then written in
//! order.
//!
//! Most columns of a sweep's rows hold one value over a block (the
//! parameters it does not vary, the cells its laws leave empty): a block
//! is first laid out as a template, each run of such columns one piece
//! of text (commas included), so a row costs only its varying cells.

use arrow_array::{Array, RecordBatch};

use crate::error::Result;
use crate::output::batch::{typed, Col};
use crate::output::float_text::push_f64;

/// Rows a task formats: big enough that a task's overhead is nothing
/// beside its rows, small enough to share a chunk among every thread.
const BLOCK: usize = 1024;

/// Appends row `i`'s cell of `col` (nothing for an empty cell).
#[inline]
fn push_cell(out: &mut Vec<u8>, col: &Col<'_>, i: usize) {
    match col {
        Col::F(a) => {
            if a.is_valid(i) {
                push_f64(out, a.value(i));
            }
        }
        Col::I(a) => out.extend_from_slice(itoa::Buffer::new().format(a.value(i)).as_bytes()),
        Col::S(a) => {
            if a.is_valid(i) {
                out.extend_from_slice(a.value(i).as_bytes());
            }
        }
    }
}

/// Whether `col` holds one cell over `rows` (the same value, or empty
/// throughout).
fn fixed(col: &Col<'_>, rows: std::ops::Range<usize>) -> bool {
    let first = rows.start;
    match col {
        Col::F(a) => {
            let v = a.values();
            let bits = v[first].to_bits();
            let valid = a.is_valid(first);
            rows.clone().all(|i| a.is_valid(i) == valid)
                && (!valid || v[rows].iter().all(|x| x.to_bits() == bits))
        }
        Col::I(a) => {
            let v = a.values();
            v[rows].iter().all(|&x| x == v[first])
        }
        Col::S(a) => {
            let w = a.is_valid(first).then(|| a.value(first));
            rows.into_iter()
                .all(|i| a.is_valid(i).then(|| a.value(i)) == w)
        }
    }
}

/// One piece of a block's row: text every row has, or a column whose
/// cell is formatted row by row.
enum Piece {
    /// `text[range]` of the template.
    Text(std::ops::Range<usize>),
    /// A varying column.
    Cell(usize),
}

/// A block's rows laid out: fixed text and varying cells, in order.
#[derive(Default)]
struct Template {
    text: Vec<u8>,
    pieces: Vec<Piece>,
}

impl Template {
    /// The layout of `cols` over `rows`.
    fn of(&mut self, cols: &[Col<'_>], rows: std::ops::Range<usize>) {
        self.text.clear();
        self.pieces.clear();
        let mut start = 0;
        for (c, col) in cols.iter().enumerate() {
            if c > 0 {
                self.text.push(b',');
            }
            if fixed(col, rows.clone()) {
                push_cell(&mut self.text, col, rows.start);
            } else {
                self.pieces.push(Piece::Text(start..self.text.len()));
                self.pieces.push(Piece::Cell(c));
                start = self.text.len();
            }
        }
        self.text.push(b'\n');
        self.pieces.push(Piece::Text(start..self.text.len()));
    }

    /// Appends rows `rows` of `cols` to `out`.
    fn rows(&self, cols: &[Col<'_>], rows: std::ops::Range<usize>, out: &mut Vec<u8>) {
        for i in rows {
            for p in &self.pieces {
                match p {
                    Piece::Text(r) => out.extend_from_slice(&self.text[r.clone()]),
                    Piece::Cell(c) => push_cell(out, &cols[*c], i),
                }
            }
        }
    }
}

/// Buffers for the blocks of a chunk, kept from chunk to chunk.
#[derive(Default)]
pub struct CsvBlocks {
    blocks: Vec<(Vec<u8>, Template)>,
}

impl CsvBlocks {
    /// Formats the rows of `batch` on `pool`, then hands the text to
    /// `write`, block by block, in row order.
    pub fn format(
        &mut self,
        pool: &rayon::ThreadPool,
        batch: &RecordBatch,
        mut write: impl FnMut(&[u8]) -> Result<()>,
    ) -> Result<()> {
        use rayon::prelude::*;
        let cols = typed(batch)?;
        let n = batch.num_rows();
        let count = n.div_ceil(BLOCK);
        if self.blocks.len() < count {
            self.blocks.resize_with(count, Default::default);
        }
        pool.install(|| {
            self.blocks[..count]
                .par_iter_mut()
                .enumerate()
                .for_each(|(b, (out, template))| {
                    let rows = b * BLOCK..((b + 1) * BLOCK).min(n);
                    out.clear();
                    template.of(&cols, rows.clone());
                    template.rows(&cols, rows, out);
                })
        });
        for (out, _) in &self.blocks[..count] {
            write(out)?;
        }
        Ok(())
    }
}
