//! The friction laws of docs/model.md section 5 as the wedge feels them:
//! each law's μ(Vs) (declared in [`super::laws`]) turned into tan ρ, with
//! the flank's pressure angle folded in for the laws that give a
//! coefficient; and the friction tables of the `table` law.

use super::kernel::paper_rho;
use super::laws::{agma_mu, stribeck_mu, FrictionKind};
use super::Lane;

/// Most friction tables one run may hold (the GPU keeps them all in one
/// fixed-size uniform).
pub const MAX_TABLES: usize = 8;

/// Most points a friction table may hold (fixed so the GPU can keep it in a
/// fixed-size uniform).
pub const MAX_TABLE_POINTS: usize = 32;

/// μ(Vs) as points, interpolated linearly and held constant past its ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionTable {
    /// Number of points used.
    pub n: usize,
    /// Sliding speeds, m/s, strictly increasing, the first >= 0.
    pub vs: [f64; MAX_TABLE_POINTS],
    /// Friction coefficients, >= 0.
    pub mu: [f64; MAX_TABLE_POINTS],
}

impl FrictionTable {
    /// Builds a table; errors say what is allowed.
    pub fn new(vs: &[f64], mu: &[f64]) -> Result<Self, String> {
        if vs.len() != mu.len() {
            return Err(format!(
                "vs has {} points but mu has {}; they must match",
                vs.len(),
                mu.len()
            ));
        }
        if vs.len() < 2 || vs.len() > MAX_TABLE_POINTS {
            return Err(format!(
                "needs 2 to {MAX_TABLE_POINTS} points, got {}",
                vs.len()
            ));
        }
        let mut t = FrictionTable {
            n: vs.len(),
            vs: [0.0; MAX_TABLE_POINTS],
            mu: [0.0; MAX_TABLE_POINTS],
        };
        for i in 0..vs.len() {
            if !vs[i].is_finite() || !mu[i].is_finite() {
                return Err(format!("point {} is not finite", i + 1));
            }
            if vs[i] < 0.0 || (i > 0 && vs[i] <= vs[i - 1]) {
                return Err(format!(
                    "vs must start >= 0 and increase strictly (point {})",
                    i + 1
                ));
            }
            if mu[i] < 0.0 {
                return Err(format!("mu must be >= 0 (point {})", i + 1));
            }
            t.vs[i] = vs[i];
            t.mu[i] = mu[i];
        }
        Ok(t)
    }

    /// μ on piece `k` at sliding speed `vs`: piece 0 holds μ at the first
    /// point, piece n (past the last point) μ at the last, and piece k
    /// between them is the line through points k − 1 and k, extended past
    /// them (a step is frozen on its piece, so that its right-hand side is
    /// smooth; the table's kinks are events). On its own piece, the same
    /// bits as [`FrictionTable::mu_at`].
    #[inline]
    pub fn mu_on(&self, k: u32, vs: f64) -> f64 {
        let (k, n) = (k as usize, self.n);
        if k == 0 {
            return self.mu[0];
        }
        if k >= n {
            return self.mu[n - 1];
        }
        let w = (vs - self.vs[k - 1]) / (self.vs[k] - self.vs[k - 1]);
        self.mu[k - 1] + w * (self.mu[k] - self.mu[k - 1])
    }

    /// The piece sliding speed `vs` is on: the number of table speeds at
    /// or below it (a speed on a point belongs to the piece above it, the
    /// one a rising speed enters).
    #[inline]
    pub fn piece_of(&self, vs: f64) -> u32 {
        self.vs[..self.n].iter().filter(|&&p| p <= vs).count() as u32
    }

    /// The sliding speeds bounding piece `k`: (−∞, ∞) past the ends.
    #[inline]
    pub fn edges(&self, k: u32) -> (f64, f64) {
        let (k, n) = (k as usize, self.n);
        let lo = if k == 0 {
            f64::NEG_INFINITY
        } else {
            self.vs[k.min(n) - 1]
        };
        let hi = if k >= n { f64::INFINITY } else { self.vs[k] };
        (lo, hi)
    }

    /// μ at sliding speed `vs` (linear between points, constant outside).
    #[inline]
    pub fn mu_at(&self, vs: f64) -> f64 {
        let n = self.n;
        if vs <= self.vs[0] {
            return self.mu[0];
        }
        for i in 1..n {
            if vs < self.vs[i] {
                let w = (vs - self.vs[i - 1]) / (self.vs[i] - self.vs[i - 1]);
                return self.mu[i - 1] + w * (self.mu[i] - self.mu[i - 1]);
            }
        }
        self.mu[n - 1]
    }
}

/// The wedge's sliding friction tan ρ at sliding speed `vs` >= 0: the
/// lane's law on its slots (`lane.law`, the law's parameters in the
/// parameter table's order). For the laws that give a coefficient μ,
/// tan ρ = μ / cos αn (the flank's normal force is N / cos αn). `branch`:
/// the piece of the law the step is frozen on ([`branch_of`]), for a law
/// of several.
///
/// `vs` may be below 0: inside a step the mode is frozen, and past a rest
/// the step overshoots, dir·ẋ1 / cos γ is negative. A table reads its
/// piece's line there too, which keeps the right-hand side smooth through
/// the rest (read at 0, a table's first piece has a kink at the rest that
/// the step's dense output does not follow: a rest located 3e-7 s late
/// at the default tolerance, and the lane's works 9e-6 off after it); the
/// other laws read their speed at 0.
#[inline]
pub fn mu_sliding(lane: &Lane, tables: &[FrictionTable], vs: f64, branch: u32) -> f64 {
    let s = &lane.law;
    // Past a rest the laws but a table read their speed at 0.
    let mu = match lane.friction {
        FrictionKind::Paper => return tan_small(paper_rho(s[0], s[1], s[2], vs.max(0.0))),
        FrictionKind::Coulomb => s[0],
        // No such table: NaN makes the lane `nonfinite`, never a number.
        FrictionKind::Table => tables
            .get(lane.table as usize)
            .map_or(f64::NAN, |t| t.mu_on(branch, vs)),
        FrictionKind::Agma => agma_mu(vs.max(0.0), branch == 1),
        FrictionKind::Stribeck => stribeck_mu(s, vs.max(0.0)),
    };
    mu * lane.inv_cos_an
}

/// tan ρ at sliding speed `vs` on the branch that speed is on: the law as
/// a function of speed alone, for results read at one speed.
#[inline]
pub fn mu_at(lane: &Lane, tables: &[FrictionTable], vs: f64) -> f64 {
    mu_sliding(lane, tables, vs, branch_of(lane, tables, vs))
}

/// The branch of the lane's friction law that sliding speed `vs` is on:
/// for `agma` 1 above its branch speed (10 ft/min), else 0; for `table`
/// the piece between its speeds ([`FrictionTable::piece_of`]); 0 for a
/// law of one piece. A step is frozen on its branch, and the law's kinks
/// and jumps between branches are events (`EventFn::Branch`).
#[inline]
pub fn branch_of(lane: &Lane, tables: &[FrictionTable], vs: f64) -> u32 {
    match lane.friction {
        FrictionKind::Table => tables
            .get(lane.table as usize)
            .map_or(0, |t| t.piece_of(vs)),
        _ => u32::from(lane.above_branch(vs)),
    }
}

/// The sliding speeds bounding the lane's branch `branch`, (lo, hi):
/// the branch event is where the speed leaves them. (−∞, ∞) for a law
/// of one piece.
#[inline]
pub fn branch_edges(lane: &Lane, tables: &[FrictionTable], branch: u32) -> (f64, f64) {
    let (never_below, never_above) = (f64::NEG_INFINITY, f64::INFINITY);
    match lane.friction {
        FrictionKind::Table => tables
            .get(lane.table as usize)
            .map_or((never_below, never_above), |t| t.edges(branch)),
        // A law of one branch has no branch speed (+∞) and branch 0.
        _ if branch == 0 => (never_below, lane.branch_speed),
        _ => (lane.branch_speed, never_above),
    }
}

/// tan x, by its Taylor series up to x^15 where that is exact to the last
/// bit (|x| <= 0.15 rad, 8.6°: friction angles of real worm gears), else
/// by the library. About twice as fast as `f64::tan` on the hot path.
#[inline]
pub fn tan_small(x: f64) -> f64 {
    if x.abs() > TAN_SERIES_MAX {
        return x.tan();
    }
    tan_series(x)
}

/// Where [`tan_series`] is tan to the last bit.
pub(crate) const TAN_SERIES_MAX: f64 = 0.15;

/// The Taylor series of tan x to x^15 (exact for |x| <= [`TAN_SERIES_MAX`]).
#[inline(always)]
pub(crate) fn tan_series(x: f64) -> f64 {
    let x2 = x * x;
    let p = 929569.0 / 638512875.0;
    let p = p * x2 + 21844.0 / 6081075.0;
    let p = p * x2 + 1382.0 / 155925.0;
    let p = p * x2 + 62.0 / 2835.0;
    let p = p * x2 + 17.0 / 315.0;
    let p = p * x2 + 2.0 / 15.0;
    let p = p * x2 + 1.0 / 3.0;
    x + x * x2 * p
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Spec;

    fn paper() -> Lane {
        Lane::new(&Spec::default().resolve(&[]).unwrap(), &[])
    }

    #[test]
    fn paper_friction_law_matches_model_md() {
        let l = paper();
        let rho = |vs: f64| mu_at(&l, &[], vs).atan().to_degrees();
        assert!((rho(0.0) - 1.0 / 0.14).abs() < 1e-12); // 7.14 deg
        assert!((rho(1.0) - 3.18).abs() < 0.005);
        // docs/model.md: "ρ(3.4 m/s) ≈ 2°" (1.97° by the formula).
        assert!((rho(3.4) - 2.0).abs() < 0.05);
    }

    #[test]
    fn tan_small_is_exact_where_used() {
        for i in 0..=3000 {
            let x = -0.15 + 0.3 * i as f64 / 3000.0;
            assert!(
                (tan_small(x) - x.tan()).abs() <= 2.0 * f64::EPSILON * x.tan().abs(),
                "{x}"
            );
        }
        assert_eq!(tan_small(0.5), 0.5f64.tan());
    }

    #[test]
    fn table_interpolates_and_clamps() {
        let t = FrictionTable::new(&[0.0, 1.0, 3.0], &[0.1, 0.06, 0.04]).unwrap();
        assert_eq!(t.mu_at(0.0), 0.1);
        assert!((t.mu_at(0.5) - 0.08).abs() < 1e-15);
        assert!((t.mu_at(2.0) - 0.05).abs() < 1e-15);
        assert_eq!(t.mu_at(10.0), 0.04);
        assert!(FrictionTable::new(&[1.0, 0.5], &[0.1, 0.1]).is_err());
    }
}
