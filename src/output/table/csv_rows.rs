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
use crate::output::float_text::{put_f64, MOST_BYTES};
use crate::output::short_bytes::{self, Room};

/// Rows a task formats: big enough that a task's overhead is nothing
/// beside its rows, small enough to share a chunk among every thread.
const BLOCK: usize = 1024;

/// Hands row `i`'s cell of `col` to `put` (nothing for an empty cell).
#[inline(always)]
fn cell(col: &Col<'_>, i: usize, put: impl FnOnce(&[u8])) {
    match col {
        Col::F(a) => {
            if a.is_valid(i) {
                put_f64(a.value(i), put);
            }
        }
        Col::I(a) => put(itoa::Buffer::new().format(a.value(i)).as_bytes()),
        Col::S(..) => put(col.word(i).as_bytes()),
    }
}

/// Appends row `i`'s cell of `col` (nothing for an empty cell).
fn push_cell(out: &mut Vec<u8>, col: &Col<'_>, i: usize) {
    cell(col, i, |s| short_bytes::push(out, s));
}

/// Most bytes a cell of `col` takes: a float's text at most
/// [`MOST_BYTES`], a count's 20 (`-9223372036854775808`), a word the
/// longest of its column's words.
fn cell_most(col: &Col<'_>) -> usize {
    match col {
        Col::F(_) => MOST_BYTES,
        Col::I(_) => 20,
        Col::S(_, words) => (0..words.len())
            .map(|k| words.value_length(k) as usize)
            .max()
            .unwrap_or(0),
    }
}

/// Whether `col` holds one cell over `rows` (the same value, or empty
/// throughout). Whole runs of values are compared at a time (a block is
/// mostly columns that do hold one cell: a sweep's fixed parameters, the
/// cells its laws leave empty).
fn fixed(col: &Col<'_>, rows: std::ops::Range<usize>) -> bool {
    let (first, n) = (rows.start, rows.len());
    let a: &dyn Array = match col {
        Col::F(a) => *a,
        Col::I(a) => *a,
        Col::S(a, _) => *a,
    };
    let empty = a
        .nulls()
        .map_or(0, |b| n - b.inner().slice(first, n).count_set_bits());
    if empty == n {
        return true;
    }
    if empty > 0 {
        return false;
    }
    match col {
        Col::F(a) => same(&a.values()[rows], |x| x.to_bits()),
        Col::I(a) => same(&a.values()[rows], |x| x),
        // One key is one word (a results batch's keys are its words'
        // codes).
        Col::S(a, _) => same(&a.keys().values()[rows], |x| x),
    }
}

/// Whether every value of `v` has the key of the first: 64 values at a
/// time, compared without a branch among them.
fn same<T: Copy, K: PartialEq>(v: &[T], key: impl Fn(T) -> K) -> bool {
    let Some(&head) = v.first() else {
        return true;
    };
    let k = key(head);
    v.chunks(64)
        .all(|c| c.iter().fold(true, |all, &x| all & (key(x) == k)))
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
    /// Most bytes a row takes.
    most: usize,
}

impl Template {
    /// The layout of `cols` over `rows`.
    fn of(&mut self, cols: &[Col<'_>], rows: std::ops::Range<usize>) {
        self.text.clear();
        self.pieces.clear();
        self.most = 0;
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
                self.most += cell_most(col);
                start = self.text.len();
            }
        }
        self.text.push(b'\n');
        self.pieces.push(Piece::Text(start..self.text.len()));
        self.most += self.text.len();
    }

    /// Writes rows `rows` of `cols` into `out` from its start; the bytes
    /// written. Before each row `out` is grown to leave room for a row's
    /// most (only as far as that: the bytes it zeroes are bytes the
    /// process holds), and it is never shrunk, so that after the first
    /// chunks it is neither grown nor cleared.
    fn rows(&self, cols: &[Col<'_>], rows: std::ops::Range<usize>, out: &mut Vec<u8>) -> usize {
        let mut at = 0;
        for i in rows {
            if out.len() < at + self.most {
                out.resize(at + self.most, 0);
            }
            let mut room = Room::new(out, at);
            for p in &self.pieces {
                match p {
                    Piece::Text(r) => room.put(&self.text[r.clone()]),
                    Piece::Cell(c) => cell(&cols[*c], i, |s| room.put(s)),
                }
            }
            at = room.at();
        }
        at
    }
}

/// Buffers for the blocks of a chunk, kept from chunk to chunk: each
/// block's text (the first of its bytes written) and layout.
#[derive(Default)]
pub struct CsvBlocks {
    blocks: Vec<(Vec<u8>, usize, Template)>,
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
                .for_each(|(b, (out, len, template))| {
                    let rows = b * BLOCK..((b + 1) * BLOCK).min(n);
                    template.of(&cols, rows.clone());
                    *len = template.rows(&cols, rows, out);
                })
        });
        for (out, len, _) in &self.blocks[..count] {
            write(&out[..*len])?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::batch::Key;
    use arrow_array::{DictionaryArray, Float64Array, Int64Array};
    use rand_core::{Rng, SeedableRng};

    /// No cell takes more than `cell_most` says: the longest float texts,
    /// the extreme counts and the longest word of a column.
    #[test]
    fn no_cell_is_longer_than_its_room() {
        let floats = Float64Array::from(vec![
            -f64::MIN_POSITIVE,
            f64::MIN,
            -1.2345678901234567e-300,
            -0.00012345678901234567,
            -9.999999999999998e15,
            -5e-324,
        ]);
        let ints = Int64Array::from(vec![i64::MIN, i64::MAX, -1]);
        let words: DictionaryArray<Key> = vec![Some("ok"), Some("max_events"), None]
            .into_iter()
            .collect();
        let words = Col::of(&words).unwrap();
        for col in [Col::F(&floats), Col::I(&ints), words] {
            let most = cell_most(&col);
            for i in 0..col.len() {
                let mut t = Vec::new();
                push_cell(&mut t, &col, i);
                assert!(t.len() <= most, "{} bytes, room {most}", t.len());
            }
        }
    }

    /// `fixed` against its definition (every row's cell the same text),
    /// on random columns of each type with runs of one value, empty
    /// cells and words of equal and unequal length, over random ranges.
    #[test]
    fn fixed_is_every_cell_the_same() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let words = ["", "aa", "bb", "stick", "runs", "ab"];
        for case in 0..3000 {
            let n = 1 + (rng.next_u64() % 300) as usize;
            // Few distinct values, so that whole ranges often agree.
            let kinds = 1 + rng.next_u64() % 3;
            let pick: Vec<u64> = (0..n)
                .map(|_| {
                    if rng.next_u64() % 8 == 0 {
                        rng.next_u64() % kinds
                    } else {
                        0
                    }
                })
                .collect();
            let floats = Float64Array::from_iter(
                pick.iter()
                    .map(|&k| (k != 2).then_some(if k == 1 { -0.0 } else { 0.0 })),
            );
            let ints = Int64Array::from_iter_values(pick.iter().map(|&k| k as i64));
            let strs: DictionaryArray<Key> = pick
                .iter()
                .map(|&k| {
                    let w = words[(k as usize + case) % words.len()];
                    (!w.is_empty()).then_some(w)
                })
                .collect();
            let a = (rng.next_u64() as usize) % n;
            let b = a + 1 + (rng.next_u64() as usize) % (n - a);
            let strs = Col::of(&strs).unwrap();
            for col in [Col::F(&floats), Col::I(&ints), strs] {
                let mut texts = (a..b).map(|i| {
                    let mut t = Vec::new();
                    push_cell(&mut t, &col, i);
                    t
                });
                let first = texts.next().unwrap();
                let want = texts.all(|t| t == first);
                assert_eq!(fixed(&col, a..b), want, "case {case}, rows {a}..{b}");
            }
        }
    }
}
