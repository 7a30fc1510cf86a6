//! A scrambled Sobol' sequence: the points of a sensitivity design.
//!
//! Why Sobol' points and not independent draws: the Saltelli design's
//! estimators converge like 1/N on a low-discrepancy sequence against
//! 1/√N on random points; at the same cost an index is several times
//! closer to its value (on Ishigami at N = 2^13, about 0.002 against
//! 0.012), which is the point of a sensitivity study. The sequence is
//! Sobol's, with Joe and Kuo's direction numbers (2008, "new-joe-kuo-6":
//! primitive polynomials and initial values, as published), taken in Gray
//! code order like SciPy's `qmc.Sobol`; each dimension is scrambled by a
//! random digital shift (an XOR with a 32-bit word) drawn from the sweep's
//! seeded ChaCha8 stream, so a seed gives one design and another seed an
//! independent one. Point `j` is computed directly from `j` (O(32) per
//! coordinate), so a lane's values depend only on the seed and its index.

use super::sampling::Uniforms;

/// Dimensions the table holds: a design over D inputs uses 2·D.
pub(crate) const MAX_DIMS: usize = 64;

/// Most base points (the sequence's 32 bits).
pub(crate) const MAX_POINTS: u64 = 1 << 32;

/// Joe and Kuo's direction numbers for dimensions 2 to 64: the primitive
/// polynomial (with its leading and constant terms, as bits) and the
/// initial values m_1 ... m_s. The first dimension is van der Corput's.
#[rustfmt::skip]
const JOE_KUO: [(u32, &[u32]); MAX_DIMS - 1] = [
    (3, &[1]),
    (7, &[1, 3]),
    (11, &[1, 3, 1]),
    (13, &[1, 1, 1]),
    (19, &[1, 1, 3, 3]),
    (25, &[1, 3, 5, 13]),
    (37, &[1, 1, 5, 5, 17]),
    (41, &[1, 1, 5, 5, 5]),
    (47, &[1, 1, 7, 11, 19]),
    (55, &[1, 1, 5, 1, 1]),
    (59, &[1, 1, 1, 3, 11]),
    (61, &[1, 3, 5, 5, 31]),
    (67, &[1, 3, 3, 9, 7, 49]),
    (91, &[1, 1, 1, 15, 21, 21]),
    (97, &[1, 3, 1, 13, 27, 49]),
    (103, &[1, 1, 1, 15, 7, 5]),
    (109, &[1, 3, 1, 15, 13, 25]),
    (115, &[1, 1, 5, 5, 19, 61]),
    (131, &[1, 3, 7, 11, 23, 15, 103]),
    (137, &[1, 3, 7, 13, 13, 15, 69]),
    (143, &[1, 1, 3, 13, 7, 35, 63]),
    (145, &[1, 3, 5, 9, 1, 25, 53]),
    (157, &[1, 3, 1, 13, 9, 35, 107]),
    (167, &[1, 3, 1, 5, 27, 61, 31]),
    (171, &[1, 1, 5, 11, 19, 41, 61]),
    (185, &[1, 3, 5, 3, 3, 13, 69]),
    (191, &[1, 1, 7, 13, 1, 19, 1]),
    (193, &[1, 3, 7, 5, 13, 19, 59]),
    (203, &[1, 1, 3, 9, 25, 29, 41]),
    (211, &[1, 3, 5, 13, 23, 1, 55]),
    (213, &[1, 3, 7, 3, 13, 59, 17]),
    (229, &[1, 3, 1, 3, 5, 53, 69]),
    (239, &[1, 1, 5, 5, 23, 33, 13]),
    (241, &[1, 1, 7, 7, 1, 61, 123]),
    (247, &[1, 1, 7, 9, 13, 61, 49]),
    (253, &[1, 3, 3, 5, 3, 55, 33]),
    (285, &[1, 3, 1, 15, 31, 13, 49, 245]),
    (299, &[1, 3, 5, 15, 31, 59, 63, 97]),
    (301, &[1, 3, 1, 11, 11, 11, 77, 249]),
    (333, &[1, 3, 1, 11, 27, 43, 71, 9]),
    (351, &[1, 1, 7, 15, 21, 11, 81, 45]),
    (355, &[1, 3, 7, 3, 25, 31, 65, 79]),
    (357, &[1, 3, 1, 1, 19, 11, 3, 205]),
    (361, &[1, 1, 5, 9, 19, 21, 29, 157]),
    (369, &[1, 3, 7, 11, 1, 33, 89, 185]),
    (391, &[1, 3, 3, 3, 15, 9, 79, 71]),
    (397, &[1, 3, 7, 11, 15, 39, 119, 27]),
    (425, &[1, 1, 3, 1, 11, 31, 97, 225]),
    (451, &[1, 1, 1, 3, 23, 43, 57, 177]),
    (463, &[1, 3, 7, 7, 17, 17, 37, 71]),
    (487, &[1, 3, 1, 5, 27, 63, 123, 213]),
    (501, &[1, 1, 3, 5, 11, 43, 53, 133]),
    (529, &[1, 3, 5, 5, 29, 17, 47, 173, 479]),
    (539, &[1, 3, 3, 11, 3, 1, 109, 9, 69]),
    (545, &[1, 1, 1, 5, 17, 39, 23, 5, 343]),
    (557, &[1, 3, 1, 5, 25, 15, 31, 103, 499]),
    (563, &[1, 1, 1, 11, 11, 17, 63, 105, 183]),
    (601, &[1, 1, 5, 11, 9, 29, 97, 231, 363]),
    (607, &[1, 1, 5, 15, 19, 45, 41, 7, 383]),
    (617, &[1, 3, 7, 7, 31, 19, 83, 137, 221]),
    (623, &[1, 1, 1, 3, 23, 15, 111, 223, 83]),
    (631, &[1, 1, 5, 13, 31, 15, 55, 25, 161]),
    (637, &[1, 1, 3, 13, 25, 47, 39, 87, 257]),
];

/// The direction numbers of the first `dims` dimensions and their shifts.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct SobolSeq {
    v: Vec<[u32; 32]>,
    shift: Vec<u32>,
}

impl SobolSeq {
    /// The sequence over `dims` (≤ [`MAX_DIMS`]) dimensions, scrambled by
    /// shifts from `seed`; `seed = None` leaves it unscrambled (tests).
    pub fn new(dims: usize, seed: Option<u64>) -> SobolSeq {
        assert!(dims <= MAX_DIMS, "at most {MAX_DIMS} dimensions");
        let mut v = Vec::with_capacity(dims);
        for d in 0..dims {
            let mut dv = [0u32; 32];
            if d == 0 {
                for (i, x) in dv.iter_mut().enumerate() {
                    *x = 1 << (31 - i);
                }
            } else {
                let (poly, init) = JOE_KUO[d - 1];
                let s = init.len();
                let mut m = [0u32; 32];
                m[..s].copy_from_slice(init);
                for i in s..32 {
                    // m_i = 2a_1 m_{i-1} ^ 4a_2 m_{i-2} ^ ... ^ 2^s m_{i-s} ^ m_{i-s}
                    let mut x = m[i - s] ^ (m[i - s] << s);
                    for k in 1..s {
                        if (poly >> (s - k)) & 1 == 1 {
                            x ^= m[i - k] << k;
                        }
                    }
                    m[i] = x;
                }
                for i in 0..32 {
                    dv[i] = m[i] << (31 - i);
                }
            }
            v.push(dv);
        }
        let shift = match seed {
            Some(seed) => {
                let mut u = Uniforms::keyed(seed, *b"tswm-sq\0", 0);
                (0..dims)
                    .map(|_| (u.next() * 4_294_967_296.0) as u32)
                    .collect()
            }
            None => vec![0; dims],
        };
        SobolSeq { v, shift }
    }

    /// Coordinate `dim` of point `j` (Gray code order), strictly inside
    /// (0, 1): the 32-bit value's cell centre.
    pub fn point(&self, j: u64, dim: usize) -> f64 {
        let g = (j ^ (j >> 1)) as u32;
        let mut x = self.shift[dim];
        let v = &self.v[dim];
        let mut bits = g;
        while bits != 0 {
            let b = bits.trailing_zeros() as usize;
            x ^= v[b];
            bits &= bits - 1;
        }
        (f64::from(x) + 0.5) / 4_294_967_296.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unscrambled_points_are_scipys() {
        // scipy.stats.qmc.Sobol(4, scramble=False).random(8), exact
        // multiples of 1/8 (here the cell centre adds 2^-33).
        let want = [
            [0.0, 0.0, 0.0, 0.0],
            [0.5, 0.5, 0.5, 0.5],
            [0.75, 0.25, 0.25, 0.25],
            [0.25, 0.75, 0.75, 0.75],
            [0.375, 0.375, 0.625, 0.875],
            [0.875, 0.875, 0.125, 0.375],
            [0.625, 0.125, 0.875, 0.625],
            [0.125, 0.625, 0.375, 0.125],
        ];
        let s = SobolSeq::new(4, None);
        for (j, row) in want.iter().enumerate() {
            for (d, w) in row.iter().enumerate() {
                let got = s.point(j as u64, d) - 0.5 / 4_294_967_296.0;
                assert_eq!(got, *w, "point {j} dim {d}");
            }
        }
    }

    #[test]
    fn the_last_dimensions_are_scipys() {
        // scipy.stats.qmc.Sobol(64, scramble=False).random(1024)[j, 58:64] * 2**32
        let want: [(u64, [u32; 6]); 4] = [
            (
                3,
                [
                    1073741824, 1073741824, 3221225472, 1073741824, 1073741824, 1073741824,
                ],
            ),
            (
                100,
                [
                    1778384896, 704643072, 2113929216, 100663296, 1979711488, 2785017856,
                ],
            ),
            (
                517,
                [
                    1874853888, 2243952640, 3569352704, 4223664128, 4206886912, 717225984,
                ],
            ),
            (
                1023,
                [
                    3124756480, 1514143744, 440401920, 843055104, 3393191936, 171966464,
                ],
            ),
        ];
        let s = SobolSeq::new(MAX_DIMS, None);
        for (j, row) in want {
            for (k, w) in row.iter().enumerate() {
                let got = s.point(j, 58 + k) * 4_294_967_296.0 - 0.5;
                assert_eq!(got, f64::from(*w), "point {j} dim {}", 58 + k);
            }
        }
    }

    #[test]
    fn every_dimension_is_balanced_on_powers_of_two() {
        // A (0, m, s)-net property: each of 2^k equal intervals holds
        // 2^(m−k) of the first 2^m points, scrambled or not.
        let s = SobolSeq::new(MAX_DIMS, Some(7));
        for d in 0..MAX_DIMS {
            let mut c = [0u32; 16];
            for j in 0..1024 {
                c[(s.point(j, d) * 16.0) as usize] += 1;
            }
            assert!(c.iter().all(|&x| x == 64), "dim {d}: {c:?}");
        }
    }
}
