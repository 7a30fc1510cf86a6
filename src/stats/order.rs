//! Order statistics of critical values known to brackets: a share
//! boundary's ranks (which order statistic it is, and which bound a
//! distribution-free 95 % interval), and an order statistic's bracket
//! from the drives' brackets.
//!
//! A drive's critical value c lies in (lo, hi]. The t-th smallest critical
//! value then lies in (L_t, U_t], L_t the t-th smallest lo and U_t the
//! t-th smallest hi (a drive whose lo is below L_t ... each of the t
//! drives with the smallest hi has c <= U_t, so c_(t) <= U_t; likewise at
//! least n - t + 1 drives have lo >= L_t, so c_(t) > L_t).
//!
//! The interval: with B ~ Binomial(n, q) the number of drives whose c is
//! at most the population's q-quantile x_q, P(c_(r) <= x_q) = P(B >= r)
//! and P(x_q < c_(s)) = P(B <= s - 1); r and s are chosen so that each
//! tail is at most 2.5 % (the method of Hahn and Meeker, *Statistical
//! Intervals*, section 5.2), which needs no assumption about the
//! distribution of c (only that it is continuous).

use crate::integrator::Side;

/// Two-sided coverage of the interval.
pub(crate) const COVERAGE: f64 = 0.95;

/// The ranks (1-based, among n drives) of a share boundary: the order
/// statistic that is the boundary, the two that bound its two-sided 95 %
/// interval and the one of its one-sided 95 % bound (0: none, too few
/// drives for that confidence).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ranks {
    /// The boundary's order statistic.
    pub k: usize,
    /// The interval's lower end (0: none).
    pub lo: usize,
    /// Its upper end (0: none).
    pub hi: usize,
    /// The one-sided bound: below the boundary for `Side::Below` (the
    /// boundary is at least it), above for `Side::Above` (at most it);
    /// 0: none.
    pub bound: usize,
    /// The quantile q of the critical values the boundary estimates.
    pub q: f64,
}

/// P(B <= k) for B ~ Binomial(n, p), summed in logs (no overflow for
/// n up to 10^7).
#[cfg(test)]
pub(crate) fn binomial_cdf(k: i64, n: usize, p: f64) -> f64 {
    if k < 0 {
        return 0.0;
    }
    if k as usize >= n {
        return 1.0;
    }
    let (lp, lq) = (p.ln(), (1.0 - p).ln());
    // ln C(n, i) by the recurrence ln C(n, i) = ln C(n, i-1) + ln((n-i+1)/i).
    let mut ln_c = 0.0f64;
    let mut sum = 0.0f64;
    for i in 0..=k as usize {
        if i > 0 {
            ln_c += ((n - i + 1) as f64).ln() - (i as f64).ln();
        }
        sum += (ln_c + i as f64 * lp + (n - i) as f64 * lq).exp();
    }
    sum.min(1.0)
}

/// P(B <= 0), P(B <= 1), ... for B ~ Binomial(n, p): [`binomial_cdf`]
/// of each k in turn, value for value, each term added once (a scan over
/// k costs n terms, not n²/2).
struct Cdf {
    n: usize,
    lp: f64,
    lq: f64,
    ln_c: f64,
    sum: f64,
    i: usize,
}

impl Cdf {
    fn new(n: usize, p: f64) -> Cdf {
        Cdf {
            n,
            lp: p.ln(),
            lq: (1.0 - p).ln(),
            ln_c: 0.0,
            sum: 0.0,
            i: 0,
        }
    }
}

impl Iterator for Cdf {
    type Item = f64;
    fn next(&mut self) -> Option<f64> {
        let (n, i) = (self.n, self.i);
        if i > n {
            return None;
        }
        self.i += 1;
        if i >= n {
            return Some(1.0);
        }
        if i > 0 {
            self.ln_c += ((n - i + 1) as f64).ln() - (i as f64).ln();
        }
        self.sum += (self.ln_c + i as f64 * self.lp + (n - i) as f64 * self.lq).exp();
        Some(self.sum.min(1.0))
    }
}

/// The ranks of the boundary of `at_least` of `n` drives whose
/// requirement is met on `side` of their critical values.
///
/// Below (met for x < c): the share meeting at x is #(c_i > x) / n, at
/// least `at_least` while x < c_(m + 1) with m = floor(n (1 - at_least)):
/// the boundary is c_(m + 1), the population's (1 - at_least)-quantile.
/// Above (met for x >= c): the share is #(c_i <= x) / n, at least
/// `at_least` from c_(k), k = ceil(n at_least): the at_least-quantile.
pub(crate) fn boundary_ranks(n: usize, at_least: f64, side: Side) -> Ranks {
    let (k, q) = match side {
        Side::Below => {
            let m = (n as f64 * (1.0 - at_least) + 1e-9).floor() as usize;
            ((m + 1).min(n), 1.0 - at_least)
        }
        Side::Above => {
            let k = (n as f64 * at_least - 1e-9).ceil() as usize;
            (k.clamp(1, n), at_least)
        }
    };
    let tail = (1.0 - COVERAGE) / 2.0;
    // Largest r with P(B <= r - 1) <= tail: P(c_(r) <= x_q) >= 1 - tail.
    let lower = |alpha: f64| -> usize {
        (1..=n)
            .zip(Cdf::new(n, q))
            .take_while(|&(_, c)| c <= alpha)
            .last()
            .map_or(0, |(r, _)| r)
    };
    // Smallest s with P(B <= s - 1) >= 1 - tail: P(x_q < c_(s)) >= 1 - tail.
    let upper = |alpha: f64| -> usize {
        (1..=n)
            .zip(Cdf::new(n, q))
            .find(|&(_, c)| c >= 1.0 - alpha)
            .map_or(0, |(s, _)| s)
    };
    let one = 1.0 - COVERAGE;
    Ranks {
        k,
        lo: lower(tail),
        hi: upper(tail),
        bound: match side {
            Side::Below => lower(one),
            Side::Above => upper(one),
        },
        q,
    }
}

/// The t-th smallest (1-based) of `v` (reordered; NaN sorts last).
pub(crate) fn kth(v: &mut [f64], t: usize) -> f64 {
    if t == 0 || t > v.len() {
        return f64::NAN;
    }
    let (_, x, _) = v.select_nth_unstable_by(t - 1, f64::total_cmp);
    *x
}

/// The bracket (L, U] of the t-th smallest critical value, from the
/// drives' brackets `los` and `his` (reordered).
pub(crate) fn order_bracket(los: &mut [f64], his: &mut [f64], t: usize) -> (f64, f64) {
    (kth(los, t), kth(his, t))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_running_cdf_is_the_cdf_of_each_k() {
        for (n, p) in [(1, 0.5), (10, 0.3), (100, 0.01), (2000, 0.99), (2000, 0.5)] {
            for (k, c) in Cdf::new(n, p).enumerate() {
                assert_eq!(
                    c.to_bits(),
                    binomial_cdf(k as i64, n, p).to_bits(),
                    "{n} {p} {k}"
                );
            }
            assert_eq!(Cdf::new(n, p).count(), n + 1);
        }
    }

    #[test]
    fn the_binomial_cdf_is_the_sum_of_its_terms() {
        // n = 10, p = 0.3: P(B <= 2) = 0.3827827864 (a table value).
        assert!((binomial_cdf(2, 10, 0.3) - 0.382_782_786_4).abs() < 1e-9);
        assert_eq!(binomial_cdf(10, 10, 0.3), 1.0);
        assert_eq!(binomial_cdf(-1, 10, 0.3), 0.0);
    }

    /// The ranks of the median of 100: the textbook interval is the 40th
    /// to the 61st order statistic (95 %: P(40 <= B <= 60) >= 0.95).
    #[test]
    fn the_median_of_100_is_bounded_by_the_textbook_ranks() {
        let r = boundary_ranks(100, 0.5, Side::Above);
        assert_eq!((r.k, r.lo, r.hi), (50, 40, 61));
        let tail_lo = binomial_cdf(r.lo as i64 - 1, 100, 0.5);
        let tail_hi = 1.0 - binomial_cdf(r.hi as i64 - 1, 100, 0.5);
        assert!(tail_lo <= 0.025 && tail_hi <= 0.025);
        assert!(1.0 - tail_lo - tail_hi >= 0.95);
    }

    #[test]
    fn a_boundary_met_below_is_the_low_tail() {
        // 99 % of 2000 drives met below: the 21st smallest critical value.
        let r = boundary_ranks(2000, 0.99, Side::Below);
        assert_eq!(r.k, 21);
        assert!(r.lo < r.k && r.k < r.hi && r.bound < r.k && r.bound >= r.lo);
    }

    #[test]
    fn an_order_statistic_lies_in_its_bracket() {
        let c = [0.3, 0.1, 0.7, 0.5, 0.9];
        let mut lo: Vec<f64> = c.iter().map(|x| x - 0.05).collect();
        let mut hi: Vec<f64> = c.iter().map(|x| x + 0.02).collect();
        let (l, u) = order_bracket(&mut lo, &mut hi, 2);
        assert!(l < 0.3 && 0.3 <= u);
    }
}
