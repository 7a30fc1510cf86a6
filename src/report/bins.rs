//! Where a grid value sits along a figure's axis: a list of values in
//! ascending order, and long axes binned.

use crate::input::sweep::{Axis, AxisValues};

/// Index `i` of `len` into `bins` bins.
pub(super) fn bin(i: u64, len: u64, bins: u64) -> usize {
    if len <= bins {
        i as usize
    } else {
        (i as u128 * bins as u128 / len as u128) as usize
    }
}

/// Where each value of a grid axis sits along a figure's axis: a list of
/// numbers in ascending order (a list may be given in any order, and an
/// axis reads left to right), a range or words as given.
#[derive(Clone, Debug)]
pub(super) struct Positions(Option<Vec<u64>>);

impl Positions {
    /// The positions of axis `a`'s values.
    pub(super) fn of(a: &Axis) -> Positions {
        match &a.values {
            AxisValues::List(v) if v.windows(2).any(|w| w[1] < w[0]) => {
                let mut order: Vec<usize> = (0..v.len()).collect();
                order.sort_by(|&i, &j| v[i].total_cmp(&v[j]));
                let mut pos = vec![0u64; v.len()];
                for (p, &i) in order.iter().enumerate() {
                    pos[i] = p as u64;
                }
                Positions(Some(pos))
            }
            _ => Positions(None),
        }
    }

    /// The position of value `i`.
    pub(super) fn at(&self, i: u64) -> u64 {
        match &self.0 {
            Some(p) => p[i as usize],
            None => i,
        }
    }
}

/// The axis value shown for each bin (its first grid value), in the
/// order of [`Positions`].
pub(super) fn bin_values(a: &Axis, bins: u64) -> Vec<f64> {
    let len = a.len();
    let n = len.min(bins);
    let sorted: Option<Vec<f64>> = match &a.values {
        AxisValues::List(v) => {
            let mut s = v.clone();
            s.sort_by(f64::total_cmp);
            Some(s)
        }
        _ => None,
    };
    let value = |i: u64| {
        sorted
            .as_ref()
            .map_or_else(|| a.value(i), |s| s[i as usize])
    };
    (0..n)
        .map(|b| {
            value(if len <= bins {
                b
            } else {
                (b as u128 * len as u128).div_ceil(bins as u128) as u64
            })
        })
        .collect()
}
