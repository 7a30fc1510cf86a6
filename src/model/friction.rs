//! The friction laws of docs/model.md section 5: the paper's fit, a
//! constant μ, a table μ(Vs), and AGMA's curve for a steel worm on a
//! bronze wheel; each gives tan ρ, the wedge's friction, with the flank's
//! pressure angle folded in for the laws that give a coefficient.

use super::kernel::paper_rho;
use super::{FrictionKind, Lane};

/// Most friction tables one run may hold (the GPU keeps them all in one
/// fixed-size uniform).
pub const MAX_TABLES: usize = 8;

/// ft/min in one m/s: the `agma` law is stated in ft/min.
pub const FT_PER_MIN_PER_M_PER_S: f64 = 196.850_393_700_787_4;
/// The `agma` law's static coefficient μs.
pub const AGMA_MU_STATIC: f64 = 0.150;
/// Sliding speed, ft/min, where the `agma` curve changes branch (and jumps
/// by 2 %).
pub const AGMA_JUMP_FT_MIN: f64 = 10.0;
/// Lower branch (0 < Vs <= 10 ft/min): μ = A exp(−B Vs^E).
pub const AGMA_LOW_A: f64 = 0.124;
/// See [`AGMA_LOW_A`].
pub const AGMA_LOW_B: f64 = 0.074;
/// See [`AGMA_LOW_A`].
pub const AGMA_LOW_E: f64 = 0.645;
/// Upper branch (Vs > 10 ft/min): μ = A exp(−B Vs^E) + C.
pub const AGMA_HIGH_A: f64 = 0.103;
/// See [`AGMA_HIGH_A`].
pub const AGMA_HIGH_B: f64 = 0.110;
/// See [`AGMA_HIGH_A`].
pub const AGMA_HIGH_E: f64 = 0.450;
/// See [`AGMA_HIGH_A`].
pub const AGMA_HIGH_C: f64 = 0.012;
/// [`AGMA_JUMP_FT_MIN`] in m/s (0.0508).
pub const AGMA_JUMP_M_S: f64 = AGMA_JUMP_FT_MIN / FT_PER_MIN_PER_M_PER_S;

/// The `agma` law's sliding μ at `vs` (m/s) on the branch `upper` (Vs
/// above 10 ft/min) or the lower one. Inside a step the branch is frozen
/// (the mode's), so the right-hand side stays smooth and the jump is
/// located as an event; [`agma_upper`] says which branch a speed is on.
#[inline]
pub fn agma_mu(vs: f64, upper: bool) -> f64 {
    let v = vs.max(0.0) * FT_PER_MIN_PER_M_PER_S;
    if upper {
        AGMA_HIGH_A * (-AGMA_HIGH_B * v.powf(AGMA_HIGH_E)).exp() + AGMA_HIGH_C
    } else {
        AGMA_LOW_A * (-AGMA_LOW_B * v.powf(AGMA_LOW_E)).exp()
    }
}

/// Whether sliding speed `vs` (m/s) is on the `agma` law's upper branch.
#[inline]
pub fn agma_upper(vs: f64) -> bool {
    vs > AGMA_JUMP_M_S
}

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

/// The wedge's sliding friction tan ρ at sliding speed `vs` >= 0. For the
/// laws that give a coefficient μ (coulomb, table, agma) tan ρ = μ / cos αn
/// (the flank's normal force is N / cos αn); `lane.mu` holds coulomb's
/// already divided. `upper`: the `agma` branch the step is frozen on.
#[inline]
pub fn mu_sliding(lane: &Lane, tables: &[FrictionTable], vs: f64, upper: bool) -> f64 {
    match lane.friction {
        FrictionKind::Paper => tan_small(paper_rho(lane.fric_a, lane.fric_b, lane.fric_c, vs)),
        FrictionKind::Coulomb => lane.mu,
        FrictionKind::Table => {
            // No such table: NaN makes the lane `nonfinite`, never a number.
            tables
                .get(lane.table as usize)
                .map_or(f64::NAN, |t| t.mu_at(vs))
                * lane.inv_cos_an
        }
        FrictionKind::Agma => agma_mu(vs, upper) * lane.inv_cos_an,
    }
}

/// tan ρ at sliding speed `vs` on the branch that speed is on: the law as
/// a function of speed alone, for results read at one speed.
#[inline]
pub fn mu_at(lane: &Lane, tables: &[FrictionTable], vs: f64) -> f64 {
    mu_sliding(lane, tables, vs, agma_upper(vs))
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
pub const TAN_SERIES_MAX: f64 = 0.15;

/// The Taylor series of tan x to x^15 (exact for |x| <= [`TAN_SERIES_MAX`]).
#[inline(always)]
pub fn tan_series(x: f64) -> f64 {
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

    /// The table of docs/model.md section 5, to 1e-5.
    #[test]
    fn agma_law_gives_the_model_table() {
        let rows: [(f64, bool, f64); 10] = [
            (0.01, false, 0.11058),
            (0.0508, false, 0.08944),
            (0.0508, true, 0.08754),
            (0.1, true, 0.07964),
            (0.5, true, 0.05526),
            (1.0, true, 0.04349),
            (2.0, true, 0.03241),
            (5.0, true, 0.02093),
            (10.0, true, 0.01565),
            (20.0, true, 0.01307),
        ];
        for (vs, upper, want) in rows {
            let mu = agma_mu(vs, upper);
            assert!((mu - want).abs() < 1e-5, "{vs} m/s: {mu} (want {want})");
            if vs != 0.0508 {
                assert_eq!(agma_upper(vs), upper, "{vs} m/s");
            }
        }
        // 10 ft/min is 0.0508 m/s, on the lower branch; just above, the upper.
        assert!((AGMA_JUMP_M_S - 0.0508).abs() < 1e-12);
        assert!(!agma_upper(AGMA_JUMP_M_S) && agma_upper(AGMA_JUMP_M_S * (1.0 + 1e-12)));
        // The jump is 2 %.
        let (lo, hi) = (agma_mu(AGMA_JUMP_M_S, false), agma_mu(AGMA_JUMP_M_S, true));
        assert!(((lo - hi) / lo - 0.0213).abs() < 1e-3);
    }
}
