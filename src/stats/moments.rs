//! Running moments of a column's finite values (count, mean, sum of
//! squared deviations, min, max) by Welford's update, for many columns
//! side by side ([`add_columns`]; the one-value update `Moments::add`,
//! which the tests hold it to, is the same arithmetic): each column's
//! values still go in one after another
//! in the same order, so the moments are the same bits either way, but
//! eight columns' updates run as the elements of one vector, and their
//! divisions overlap instead of each waiting on the one before.

use crate::integrator::width::{best_isa, Isa};
use crate::lanewise::by_lane;

/// The running moments of a column's finite values.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Moments {
    /// Finite values added.
    pub count: u64,
    /// Their mean.
    pub mean: f64,
    /// The sum of their squared deviations from the mean.
    pub m2: f64,
    /// The smallest (0 while none).
    pub min: f64,
    /// The largest (0 while none).
    pub max: f64,
}

impl Moments {
    /// Adds `x`; a value that is not finite is left out. Welford's
    /// update: stable for any count.
    #[cfg(test)]
    #[inline]
    pub fn add(&mut self, x: f64) {
        if !x.is_finite() {
            return;
        }
        self.count += 1;
        let d = x - self.mean;
        self.mean += d / self.count as f64;
        self.m2 += d * (x - self.mean);
        if self.count == 1 {
            (self.min, self.max) = (x, x);
        } else {
            self.min = self.min.min(x);
            self.max = self.max.max(x);
        }
    }

    /// The sample standard deviation (NaN below two values).
    pub fn std(&self) -> f64 {
        if self.count > 1 {
            (self.m2 / (self.count - 1) as f64).sqrt()
        } else {
            f64::NAN
        }
    }
}

/// Columns updated together, one a vector element.
const W: usize = 8;

/// The moments of [`W`] columns, one a vector element; the count as f64
/// (exact below 2^53, as `Moments::add` converts it).
#[derive(Clone, Copy)]
struct Block {
    n: [f64; W],
    mean: [f64; W],
    m2: [f64; W],
    min: [f64; W],
    max: [f64; W],
}

impl Block {
    fn load(ms: &[Moments]) -> Block {
        let at = |f: fn(&Moments) -> f64| std::array::from_fn(|j| ms.get(j).map_or(0.0, f));
        Block {
            n: at(|m| m.count as f64),
            mean: at(|m| m.mean),
            m2: at(|m| m.m2),
            min: at(|m| m.min),
            max: at(|m| m.max),
        }
    }

    fn store(&self, ms: &mut [Moments]) {
        for (j, m) in ms.iter_mut().enumerate() {
            *m = Moments {
                count: self.n[j] as u64,
                mean: self.mean[j],
                m2: self.m2[j],
                min: self.min[j],
                max: self.max[j],
            };
        }
    }

    /// [`Moments::add`] of `x[j]` to column j, every j at once: each
    /// column's new values computed, then kept where its value is finite.
    ///
    /// Written element-wise over whole arrays, each step a loop of its
    /// own, so that it compiles to vector instructions.
    #[inline(always)]
    fn add(&mut self, x: &[f64; W]) {
        let keep = |j: usize| x[j].is_finite();
        let n: [f64; W] = by_lane(|j| self.n[j] + 1.0);
        let d: [f64; W] = by_lane(|j| x[j] - self.mean[j]);
        let mean: [f64; W] = by_lane(|j| self.mean[j] + d[j] / n[j]);
        let m2: [f64; W] = by_lane(|j| self.m2[j] + d[j] * (x[j] - mean[j]));
        // `f64::min` and `max` of a finite value, as they compare: the
        // value where it is lower (higher), else the one held.
        self.min = by_lane(|j| {
            if keep(j) & ((n[j] == 1.0) | (x[j] < self.min[j])) {
                x[j]
            } else {
                self.min[j]
            }
        });
        self.max = by_lane(|j| {
            if keep(j) & ((n[j] == 1.0) | (x[j] > self.max[j])) {
                x[j]
            } else {
                self.max[j]
            }
        });
        self.n = by_lane(|j| if keep(j) { n[j] } else { self.n[j] });
        self.mean = by_lane(|j| if keep(j) { mean[j] } else { self.mean[j] });
        self.m2 = by_lane(|j| if keep(j) { m2[j] } else { self.m2[j] });
    }
}

/// Adds the rows of `xs` (one slice a column, each as long as the first)
/// to `ms` (one a column), row after row: the same as Welford's update
/// of each column's values in order, one at a time, bit for bit (a test
/// compares them).
pub fn add_columns(ms: &mut [Moments], xs: &[&[f64]]) {
    add_columns_on(best_isa(), ms, xs)
}

/// [`add_columns`] with the instructions of `isa`. Panics when this core
/// lacks them.
fn add_columns_on(isa: Isa, ms: &mut [Moments], xs: &[&[f64]]) {
    assert_eq!(ms.len(), xs.len(), "one moments a column");
    assert!(
        crate::integrator::width::isas().contains(&isa),
        "this core has no {isa:?} instructions"
    );
    match isa {
        // SAFETY: checked above: the core has the features.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 => unsafe { on_avx512(ms, xs) },
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2 => unsafe { on_avx2(ms, xs) },
        _ => blocks(ms, xs, |b, rows| rows.iter().for_each(|x| b.add(x))),
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl,avx2,fma")]
unsafe fn on_avx512(ms: &mut [Moments], xs: &[&[f64]]) {
    // SAFETY: this function runs only where the features are.
    blocks(ms, xs, |b, rows| unsafe { vectors::tile_avx512(b, rows) })
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn on_avx2(ms: &mut [Moments], xs: &[&[f64]]) {
    // SAFETY: this function runs only where the features are.
    blocks(ms, xs, |b, rows| unsafe { vectors::tile_avx2(b, rows) })
}

/// Rows a [`blocks`] tile holds: its columns' values are copied into it
/// row by row (a row one vector), then added.
const TILE: usize = 64;

/// [`add_columns`], [`W`] columns at a time, [`TILE`] rows at a time,
/// each tile's rows added by `add`.
#[inline(always)]
fn blocks(ms: &mut [Moments], xs: &[&[f64]], add: impl Fn(&mut Block, &[[f64; W]])) {
    let rows = xs.first().map_or(0, |x| x.len());
    let mut tile = [[f64::NAN; W]; TILE];
    for (ms, xs) in ms.chunks_mut(W).zip(xs.chunks(W)) {
        let mut b = Block::load(ms);
        // Columns past the last fill no vector element: NaN, left out.
        tile.iter_mut().for_each(|t| *t = [f64::NAN; W]);
        for start in (0..rows).step_by(TILE) {
            let n = TILE.min(rows - start);
            for (j, col) in xs.iter().enumerate() {
                for (t, &v) in tile[..n].iter_mut().zip(&col[start..start + n]) {
                    t[j] = v;
                }
            }
            add(&mut b, &tile[..n]);
        }
        b.store(ms);
    }
}

/// [`Block::add`] as explicit vector instructions, row after row of a
/// tile, the block's moments held in registers throughout: the same
/// operations in the same order on each element, so the same bits.
#[cfg(target_arch = "x86_64")]
mod vectors {
    use super::{Block, W};
    use std::arch::x86_64::*;

    /// AVX-512: a block's eight columns one vector.
    #[target_feature(enable = "avx512f,avx512dq")]
    pub(super) unsafe fn tile_avx512(b: &mut Block, rows: &[[f64; W]]) {
        let one = _mm512_set1_pd(1.0);
        let inf = _mm512_set1_pd(f64::INFINITY);
        // SAFETY: each array holds W = 8 values, one vector.
        let load = |a: &[f64; W]| unsafe { _mm512_loadu_pd(a.as_ptr()) };
        let (mut n, mut mean, mut m2) = (load(&b.n), load(&b.mean), load(&b.m2));
        let (mut min, mut max) = (load(&b.min), load(&b.max));
        for r in rows {
            let x = load(r);
            let keep = _mm512_cmp_pd_mask::<_CMP_LT_OQ>(_mm512_abs_pd(x), inf);
            let n1 = _mm512_add_pd(n, one);
            let d = _mm512_sub_pd(x, mean);
            let mean1 = _mm512_add_pd(mean, _mm512_div_pd(d, n1));
            let m21 = _mm512_add_pd(m2, _mm512_mul_pd(d, _mm512_sub_pd(x, mean1)));
            let first = _mm512_cmp_pd_mask::<_CMP_EQ_OQ>(n1, one);
            let lower = _mm512_cmp_pd_mask::<_CMP_LT_OQ>(x, min);
            let higher = _mm512_cmp_pd_mask::<_CMP_GT_OQ>(x, max);
            min = _mm512_mask_mov_pd(min, keep & (first | lower), x);
            max = _mm512_mask_mov_pd(max, keep & (first | higher), x);
            n = _mm512_mask_mov_pd(n, keep, n1);
            mean = _mm512_mask_mov_pd(mean, keep, mean1);
            m2 = _mm512_mask_mov_pd(m2, keep, m21);
        }
        // SAFETY: as the loads.
        let store = |a: &mut [f64; W], v| unsafe { _mm512_storeu_pd(a.as_mut_ptr(), v) };
        store(&mut b.n, n);
        store(&mut b.mean, mean);
        store(&mut b.m2, m2);
        store(&mut b.min, min);
        store(&mut b.max, max);
    }

    /// AVX2: a block's eight columns two vectors of four.
    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn tile_avx2(b: &mut Block, rows: &[[f64; W]]) {
        let one = _mm256_set1_pd(1.0);
        let inf = _mm256_set1_pd(f64::INFINITY);
        let abs = _mm256_castsi256_pd(_mm256_set1_epi64x(i64::MAX));
        // SAFETY: each half is 4 of an array's W = 8 values.
        let load = |a: &[f64; W], h: usize| unsafe { _mm256_loadu_pd(a.as_ptr().add(4 * h)) };
        let store = |a: &mut [f64; W], h: usize, v| unsafe {
            _mm256_storeu_pd(a.as_mut_ptr().add(4 * h), v)
        };
        for h in 0..2 {
            let (mut n, mut mean, mut m2) = (load(&b.n, h), load(&b.mean, h), load(&b.m2, h));
            let (mut min, mut max) = (load(&b.min, h), load(&b.max, h));
            for r in rows {
                let x = load(r, h);
                let keep = _mm256_cmp_pd::<_CMP_LT_OQ>(_mm256_and_pd(x, abs), inf);
                let n1 = _mm256_add_pd(n, one);
                let d = _mm256_sub_pd(x, mean);
                let mean1 = _mm256_add_pd(mean, _mm256_div_pd(d, n1));
                let m21 = _mm256_add_pd(m2, _mm256_mul_pd(d, _mm256_sub_pd(x, mean1)));
                let first = _mm256_cmp_pd::<_CMP_EQ_OQ>(n1, one);
                let lower = _mm256_cmp_pd::<_CMP_LT_OQ>(x, min);
                let higher = _mm256_cmp_pd::<_CMP_GT_OQ>(x, max);
                let pick = |old, new, m| _mm256_blendv_pd(old, new, m);
                min = pick(min, x, _mm256_and_pd(keep, _mm256_or_pd(first, lower)));
                max = pick(max, x, _mm256_and_pd(keep, _mm256_or_pd(first, higher)));
                n = pick(n, n1, keep);
                mean = pick(mean, mean1, keep);
                m2 = pick(m2, m21, keep);
            }
            store(&mut b.n, h, n);
            store(&mut b.mean, h, mean);
            store(&mut b.m2, h, m2);
            store(&mut b.min, h, min);
            store(&mut b.max, h, max);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand_core::{Rng, SeedableRng};

    /// Many columns side by side give the moments of each column added
    /// one value at a time, bit for bit: values of every magnitude and
    /// sign, empty (NaN) and infinite cells, columns of one value, and
    /// column counts that fill no, one or several vectors.
    #[test]
    fn columns_side_by_side_are_each_column_alone() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        for cols in [1, 3, 8, 9, 21, 24] {
            for rows in [0, 1, 2, 7, 1000] {
                let xs: Vec<Vec<f64>> = (0..cols)
                    .map(|c| {
                        (0..rows)
                            .map(|_| {
                                let u = rng.next_u64();
                                match (c + (u % 7) as usize) % 9 {
                                    0 => f64::NAN,
                                    1 if u % 13 == 0 => f64::INFINITY,
                                    2 => 4.25,
                                    3 if u % 5 == 0 => 0.0,
                                    3 if u % 5 == 1 => -0.0,
                                    _ => {
                                        let m = (u >> 11) as f64 / (1u64 << 53) as f64;
                                        let e = ((u >> 3) % 40) as i32 - 20;
                                        (m - 0.3) * 10f64.powi(e)
                                    }
                                }
                            })
                            .collect()
                    })
                    .collect();
                let mut one = vec![Moments::default(); cols];
                for (m, x) in one.iter_mut().zip(&xs) {
                    x.iter().for_each(|&v| m.add(v));
                }
                // In two batches, as a run hands them over, on every
                // instruction set of this core.
                for isa in crate::integrator::width::isas() {
                    let mut many = vec![Moments::default(); cols];
                    let half = rows / 2;
                    let a: Vec<&[f64]> = xs.iter().map(|x| &x[..half]).collect();
                    let b: Vec<&[f64]> = xs.iter().map(|x| &x[half..]).collect();
                    add_columns_on(isa, &mut many, &a);
                    add_columns_on(isa, &mut many, &b);
                    same(
                        &one,
                        &many,
                        &format!("{isa:?}, {cols} columns, {rows} rows"),
                    );
                }
            }
        }
    }

    /// The same moments, bit for bit.
    fn same(one: &[Moments], many: &[Moments], case: &str) {
        for (p, q) in one.iter().zip(many) {
            assert_eq!(p.count, q.count, "{case}");
            for (x, y) in [
                (p.mean, q.mean),
                (p.m2, q.m2),
                (p.min, q.min),
                (p.max, q.max),
            ] {
                assert_eq!(x.to_bits(), y.to_bits(), "{case}");
            }
        }
    }

    /// The moments against a two-pass textbook computation.
    #[test]
    fn moments_are_the_textbook_ones() {
        let x = [2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0];
        let mut m = Moments::default();
        x.iter().for_each(|&v| m.add(v));
        assert_eq!(m.count, 8);
        assert_eq!(m.mean, 5.0);
        // Sample variance 32 / 7.
        assert!((m.std() - (32.0f64 / 7.0).sqrt()).abs() < 1e-15);
        assert_eq!((m.min, m.max), (2.0, 9.0));
    }
}
