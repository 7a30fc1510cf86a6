//! Rows of `lanes.csv` from a batch: the cells of each row joined by
//! commas, floats as their shortest round-trip text, empty cells empty.
//! Blocks of rows are formatted in parallel into buffers that are reused
//! from chunk to chunk (no allocation per row or cell), then written in
//! order.

use arrow_array::{Array, RecordBatch};

use crate::error::Result;
use crate::output::batch::{typed, Col};
use crate::output::float_text::push_f64;

/// Rows a task formats: big enough that a task's overhead is nothing
/// beside its rows, small enough to share a chunk among every thread.
const BLOCK: usize = 1024;

/// The last float a column spelled, and its text: a parameter a sweep
/// holds fixed (most columns of most rows) is copied, not formatted.
#[derive(Clone, Copy)]
struct Memo {
    bits: u64,
    len: u8,
    text: [u8; 32],
}

const NONE: Memo = Memo {
    // A NaN's bits: never a present value's (nulls are not spelled).
    bits: u64::MAX,
    len: 0,
    text: [0; 32],
};

/// Appends the first `len` bytes of `text` to `out` with one fixed-size
/// copy (a call to `memcpy` per cell costs more than the cell's text).
#[inline]
fn copy_short(out: &mut Vec<u8>, text: &[u8; 32], len: usize) {
    out.reserve(text.len());
    let at = out.len();
    // SAFETY: 32 bytes past `at` are reserved and all 32 are written;
    // `len <= 32` of them are counted.
    unsafe {
        std::ptr::copy_nonoverlapping(text.as_ptr(), out.as_mut_ptr().add(at), text.len());
        out.set_len(at + len.min(text.len()));
    }
}

/// Appends rows `rows` of `cols` to `out`, each ended by a newline.
fn format_rows(
    cols: &[Col<'_>],
    rows: std::ops::Range<usize>,
    memo: &mut Vec<Memo>,
    out: &mut Vec<u8>,
) {
    memo.clear();
    memo.resize(cols.len(), NONE);
    for i in rows {
        for (c, (col, m)) in cols.iter().zip(memo.iter_mut()).enumerate() {
            if c > 0 {
                out.push(b',');
            }
            match col {
                Col::F(a) => {
                    if a.is_valid(i) {
                        let v = a.value(i);
                        if v.to_bits() != m.bits {
                            let start = out.len();
                            push_f64(out, v);
                            let t = &out[start..];
                            if t.len() <= m.text.len() {
                                m.bits = v.to_bits();
                                m.len = t.len() as u8;
                                m.text[..t.len()].copy_from_slice(t);
                            }
                        } else {
                            copy_short(out, &m.text, m.len as usize);
                        }
                    }
                }
                Col::I(a) => {
                    out.extend_from_slice(itoa::Buffer::new().format(a.value(i)).as_bytes())
                }
                Col::S(a) => {
                    if a.is_valid(i) {
                        out.extend_from_slice(a.value(i).as_bytes());
                    }
                }
            }
        }
        out.push(b'\n');
    }
}

/// Buffers for the blocks of a chunk, kept from chunk to chunk.
#[derive(Default)]
pub struct CsvBlocks {
    blocks: Vec<(Vec<u8>, Vec<Memo>)>,
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
                .for_each(|(b, (out, memo))| {
                    out.clear();
                    format_rows(&cols, b * BLOCK..((b + 1) * BLOCK).min(n), memo, out);
                })
        });
        for (out, _) in &self.blocks[..count] {
            write(out)?;
        }
        Ok(())
    }
}
