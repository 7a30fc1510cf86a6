//! Exact quantiles of a kept sample: type 7 of a sorted sample, and the
//! same quantiles of an unsorted one by selecting only the order
//! statistics they need (`summary.csv`'s P1 to P99 of each group).

/// The exact q-quantile of a sorted, non-empty sample: linear interpolation
/// between the order statistics around rank q·(n − 1) (Hyndman and Fan's
/// type 7, the default of numpy and pandas).
pub fn exact(sorted: &[f64], q: f64) -> f64 {
    let r = q * (sorted.len() - 1) as f64;
    let (lo, hi) = (r.floor() as usize, r.ceil() as usize);
    sorted[lo] + (r - lo as f64) * (sorted[hi] - sorted[lo])
}

/// total_cmp's key: the bits as a signed integer, the magnitude bits
/// flipped where the sign is set; an involution, so it maps back too.
#[inline]
fn key(b: i64) -> i64 {
    b ^ (((b >> 63) as u64) >> 1) as i64
}

/// The exact `probs`-quantiles ([`exact`]) of the finite values of
/// `values`, in `probs`' order; None when none is finite. Only the order
/// statistics the quantiles interpolate between are put in place (by
/// selection, on integers of `total_cmp`'s order), not the whole sample:
/// the same values as [`exact`] of the sorted sample, in a few linear
/// passes rather than a sort.
pub fn exact_finite(values: &[f64], probs: &[f64]) -> Option<Vec<f64>> {
    let mut k: Vec<i64> = values
        .iter()
        .filter(|x| x.is_finite())
        .map(|x| key(x.to_bits() as i64))
        .collect();
    let n = k.len();
    if n == 0 {
        return None;
    }
    let rank = |q: f64| q * (n - 1) as f64;
    let mut ranks: Vec<usize> = probs
        .iter()
        .flat_map(|&q| [rank(q).floor() as usize, rank(q).ceil() as usize])
        .collect();
    ranks.sort_unstable();
    ranks.dedup();
    select_ranks(&mut k, 0, &ranks);
    let at = |i: usize| f64::from_bits(key(k[i]) as u64);
    Some(
        probs
            .iter()
            .map(|&q| {
                let r = rank(q);
                let (lo, hi) = (r.floor() as usize, r.ceil() as usize);
                at(lo) + (r - lo as f64) * (at(hi) - at(lo))
            })
            .collect(),
    )
}

/// Puts the order statistics of `ranks` (sorted, distinct, each in
/// `offset..offset + k.len()`) of `k` in place: the middle rank first,
/// then those below it in the part below, those above in the part above.
fn select_ranks(k: &mut [i64], offset: usize, ranks: &[usize]) {
    if ranks.is_empty() {
        return;
    }
    let m = ranks.len() / 2;
    let at = ranks[m] - offset;
    k.select_nth_unstable(at);
    let (below, rest) = k.split_at_mut(at);
    select_ranks(below, offset, &ranks[..m]);
    select_ranks(&mut rest[1..], ranks[m] + 1, &ranks[m + 1..]);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::quantile::PROBS;

    /// [`exact_finite`] is [`exact`] of the finite values sorted by
    /// `total_cmp`, to the bit: random samples with ties, signed zeros,
    /// NaN, infinities, subnormals and magnitudes over the whole range,
    /// of every size from none to a few hundred, at `summary.csv`'s
    /// probabilities and at random ones (the extremes included).
    #[test]
    fn exact_finite_is_exact_of_the_sorted_finite_values() {
        use rand_core::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let special = [
            0.0,
            -0.0,
            f64::NAN,
            f64::INFINITY,
            -f64::INFINITY,
            5e-324,
            -5e-324,
            1.5,
        ];
        for case in 0..4000 {
            let n = (rng.next_u64() % 300) as usize;
            let v: Vec<f64> = (0..n)
                .map(|_| {
                    let r = rng.next_u64();
                    match case % 4 {
                        0 => special[(r % 8) as usize],
                        // Any bits: every sign, exponent and NaN payload.
                        1 => f64::from_bits(r),
                        // Few distinct values: runs of ties.
                        2 => (r % 5) as f64 - 2.0,
                        _ => (r >> 11) as f64 / (1u64 << 53) as f64 - 0.5,
                    }
                })
                .collect();
            let mut probs = PROBS.to_vec();
            if case % 2 == 1 {
                probs = (0..1 + rng.next_u64() % 6)
                    .map(|_| match rng.next_u64() % 4 {
                        0 => 0.0,
                        1 => 1.0,
                        _ => (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64,
                    })
                    .collect();
            }
            let mut sorted: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
            sorted.sort_by(f64::total_cmp);
            let want: Option<Vec<u64>> = (!sorted.is_empty())
                .then(|| probs.iter().map(|&q| exact(&sorted, q).to_bits()).collect());
            let got = exact_finite(&v, &probs).map(|g| g.iter().map(|x| x.to_bits()).collect());
            assert_eq!(
                got, want,
                "case {case}, {n} values, probabilities {probs:?}"
            );
        }
    }

    #[test]
    fn exact_matches_type_7() {
        // numpy.quantile([1, 2, 3, 4], 0.5) = 2.5; 0.01 -> 1.03.
        let s = [1.0, 2.0, 3.0, 4.0];
        assert_eq!(exact(&s, 0.5), 2.5);
        assert!((exact(&s, 0.01) - 1.03).abs() < 1e-15);
        assert_eq!(exact(&[7.0], 0.99), 7.0);
    }
}
