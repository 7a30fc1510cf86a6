//! A lane's cost on the GPU (its step count), predicted from its
//! parameters by a linear model learnt during the run, so that a part's
//! lanes can be ordered by it.
//!
//! Why: a slot whose lane finishes takes the next lane only at the end of
//! a dispatch, and the invocations of a SIMD group (a warp) step together
//! until the last of them is done; a lane that ends early idles beside
//! its neighbours for the rest of the dispatch. Lanes that take alike
//! numbers of steps, side by side, end together and refill together.
//! Sorting by t_end alone leaves the lanes that never move (stuck at the
//! start with the motor on to the end: no steps at all) among long ones,
//! and the lead angle and load change a lane's steps by a tenth either
//! way.
//!
//! The model: steps ≈ β · x(lane), where x holds 1, t_end, three hinges
//! min(t_end, k) (k: the quartiles of the first lanes' t_end, so the
//! start-up transient bends the line wherever it ends), a stuck-at-rest
//! flag, and each parameter that varies among the first lanes,
//! standardised, alone and times t_end. It is fitted by ridge least
//! squares on the normal equations, which are summed over lanes as they
//! come back (at most [`LEARN_PER_CALL`] per call), so memory is fixed
//! and the model keeps learning. Before it has learnt anything the key
//! is t_end. The key orders lanes only: a lane's result does not depend
//! on where it runs, so a poor prediction costs time, never a number.

use crate::model::{stick_test, Lane};

/// Lanes learnt from per call of [`CostModel::learn`] at most (evenly
/// spread): enough for a model of a few dozen terms, and cheap beside
/// the lanes' integration.
pub const LEARN_PER_CALL: usize = 8192;

/// Lanes the model must have learnt from before it replaces t_end.
pub(crate) const MIN_LEARNT: usize = 256;

/// Raw parameters a lane's cost may depend on (besides t_end).
const N_RAW: usize = 19;

fn raw(l: &Lane) -> [f64; N_RAW] {
    let r = [
        l.m1,
        l.m2,
        l.tan_g,
        l.f2,
        l.motor.code() as f64,
        l.v_sync,
        l.sigma_k,
        l.f_crit,
        l.f1,
        l.t_end - l.motor_off.min(l.t_end),
        l.friction.code() as f64,
        l.law[0],
        l.law[1],
        l.law[2],
        l.law[3],
        l.law[4],
        l.mu_s,
        l.x1_0,
        l.v1_0,
    ];
    r.map(|v| if v.is_finite() { v } else { 0.0 })
}

/// True when a lane sticks at t = 0 and its motor stays on to t_end: it
/// never moves, so it takes no steps at all (docs/model.md section 4: a stuck
/// lane leaves rest only when a force changes, and with the motor on at
/// rest none does).
pub(crate) fn never_moves(l: &Lane) -> bool {
    l.v1_0 == 0.0 && l.motor_off >= l.t_end && stick_test(l, true).0
}

/// The terms of the model, fixed by the first lanes it sees.
#[derive(Clone, Debug)]
struct Basis {
    knots: [f64; 3],
    /// (raw index, mean, standard deviation) of each varying parameter.
    varying: Vec<(usize, f64, f64)>,
}

impl Basis {
    /// The terms for the lanes `lanes[which]`.
    fn of(lanes: &[Lane], which: &[usize]) -> Basis {
        let mut t: Vec<f64> = which.iter().map(|&i| lanes[i].t_end).collect();
        t.sort_by(f64::total_cmp);
        let q = |p: f64| t[((t.len() - 1) as f64 * p).round() as usize];
        // Welford's mean and variance of each raw parameter, one pass.
        let mut mean = [0.0; N_RAW];
        let mut m2 = [0.0; N_RAW];
        for (k, &i) in which.iter().enumerate() {
            let r = raw(&lanes[i]);
            for j in 0..N_RAW {
                let d = r[j] - mean[j];
                mean[j] += d / (k + 1) as f64;
                m2[j] += d * (r[j] - mean[j]);
            }
        }
        let n = which.len() as f64;
        let mut varying = Vec::new();
        for j in 0..N_RAW {
            let sd = (m2[j] / n).sqrt();
            if sd > 1e-9 * (mean[j].abs() + 1e-300) && sd.is_finite() {
                varying.push((j, mean[j], sd));
            }
        }
        Basis {
            knots: [q(0.25), q(0.5), q(0.75)],
            varying,
        }
    }

    fn len(&self) -> usize {
        6 + 2 * self.varying.len()
    }

    fn terms(&self, l: &Lane, x: &mut Vec<f64>) {
        let t = l.t_end;
        let r = raw(l);
        x.clear();
        x.extend([1.0, t]);
        x.extend(self.knots.map(|k| t.min(k)));
        x.push(if l.v1_0 == 0.0 && stick_test(l, l.motor_off > 0.0).0 {
            1.0
        } else {
            0.0
        });
        for &(j, mean, sd) in &self.varying {
            let z = (r[j] - mean) / sd;
            x.extend([z, z * t]);
        }
    }
}

/// The online model of a lane's step count on the GPU.
#[derive(Clone, Debug, Default)]
pub struct CostModel {
    basis: Option<Basis>,
    /// Σ x xᵀ (row-major, upper triangle filled) and Σ x·steps over the
    /// lanes learnt.
    xtx: Vec<f64>,
    xty: Vec<f64>,
    learnt: usize,
    beta: Option<Vec<f64>>,
    x: Vec<f64>,
}

impl CostModel {
    /// A model that has learnt nothing (its key is t_end).
    pub fn new() -> CostModel {
        CostModel::default()
    }

    /// Whether the model has learnt enough to replace t_end.
    pub fn trained(&self) -> bool {
        self.beta.is_some()
    }

    /// Sort keys, one per index in `which`: the predicted steps (t_end
    /// until trained); −∞ for lanes that never move.
    pub fn keys(&mut self, lanes: &[Lane], which: &[usize], out: &mut Vec<f64>) {
        if self.basis.is_none() && !which.is_empty() {
            self.basis = Some(Basis::of(lanes, which));
        }
        out.clear();
        let mut x = std::mem::take(&mut self.x);
        for &i in which {
            let l = &lanes[i];
            let k = if never_moves(l) {
                f64::NEG_INFINITY
            } else {
                match (&self.basis, &self.beta) {
                    (Some(b), Some(beta)) => {
                        b.terms(l, &mut x);
                        x.iter().zip(beta).map(|(a, b)| a * b).sum()
                    }
                    _ => l.t_end,
                }
            };
            out.push(k);
        }
        self.x = x;
    }

    /// Learns from lanes that ran: `steps[k]` is the step count of
    /// `lanes[which[k]]`. Lanes that never move are left out (their key
    /// does not come from the model).
    pub fn learn(&mut self, lanes: &[Lane], which: &[usize], steps: &[u32]) {
        let Some(b) = &self.basis else { return };
        let p = b.len();
        if self.xtx.len() != p * p {
            self.xtx = vec![0.0; p * p];
            self.xty = vec![0.0; p];
        }
        let stride = which.len().div_ceil(LEARN_PER_CALL).max(1);
        let mut x = std::mem::take(&mut self.x);
        for k in (0..which.len()).step_by(stride) {
            let l = &lanes[which[k]];
            if never_moves(l) {
                continue;
            }
            b.terms(l, &mut x);
            let y = steps[k] as f64;
            for r in 0..p {
                let xr = x[r];
                self.xty[r] += xr * y;
                let row = &mut self.xtx[r * p + r..(r + 1) * p];
                for (a, &xc) in row.iter_mut().zip(&x[r..]) {
                    *a += xr * xc;
                }
            }
            self.learnt += 1;
        }
        self.x = x;
        if self.learnt >= MIN_LEARNT.max(4 * p) {
            if let Some(beta) = ridge(&self.xtx, &self.xty, p) {
                self.beta = Some(beta);
            }
        }
    }
}

/// Solves (A + λI) β = b for the symmetric A whose upper triangle is
/// given, λ a millionth of A's mean diagonal (terms that do not vary
/// among the lanes learnt get no weight instead of a singular system),
/// by Cholesky; None when A is empty or not positive.
fn ridge(upper: &[f64], b: &[f64], p: usize) -> Option<Vec<f64>> {
    let trace: f64 = (0..p).map(|i| upper[i * p + i]).sum();
    if !(trace > 0.0) || !trace.is_finite() {
        return None;
    }
    let lambda = 1e-6 * trace / p as f64;
    // L Lᵀ = A + λI, L lower triangular (row-major).
    let mut l = vec![0.0; p * p];
    for i in 0..p {
        for j in 0..=i {
            let a = if i == j {
                upper[i * p + i] + lambda
            } else {
                upper[j * p + i]
            };
            let s = a - (0..j).map(|k| l[i * p + k] * l[j * p + k]).sum::<f64>();
            if i == j {
                if !(s > 0.0) {
                    return None;
                }
                l[i * p + i] = s.sqrt();
            } else {
                l[i * p + j] = s / l[j * p + j];
            }
        }
    }
    let mut y = vec![0.0; p];
    for i in 0..p {
        y[i] = (b[i] - (0..i).map(|k| l[i * p + k] * y[k]).sum::<f64>()) / l[i * p + i];
    }
    let mut beta = vec![0.0; p];
    for i in (0..p).rev() {
        beta[i] = (y[i] - (i + 1..p).map(|k| l[k * p + i] * beta[k]).sum::<f64>()) / l[i * p + i];
    }
    beta.iter().all(|v| v.is_finite()).then_some(beta)
}

/// The first `max` lanes of `sweeps/heterogeneous.toml` (lanes of very
/// unlike length: t_end 0.2 to 7.8 s) in sweep order, and the same lanes
/// sorted by their f64 step counts (all cores): the two orders the GPU's
/// refill benchmarks compare.
pub fn heterogeneous_and_sorted(
    max: usize,
) -> (Vec<crate::params::Params>, Vec<crate::params::Params>) {
    use crate::backend::cpu::run_cpu_lanes;
    use crate::integrator::Settings;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("sweeps/heterogeneous.toml");
    let src =
        crate::input::lanes::Source::open(Some(&path), None).expect("sweeps/heterogeneous.toml");
    let mut params = crate::params::ParamColumns::default();
    src.reader()
        .and_then(|mut r| r.fill(max, &mut params))
        .expect("sweeps/heterogeneous.toml's lanes");
    let pool = rayon::ThreadPoolBuilder::new()
        .build()
        .expect("a thread pool");
    let mut results = Vec::new();
    run_cpu_lanes(&pool, &Settings::default(), &params, &[], &mut results);
    let mut order: Vec<usize> = (0..params.len()).collect();
    order.sort_by_key(|&i| results[i].steps);
    let sorted = order.iter().map(|&i| params.params(i)).collect();
    (
        (0..params.len()).map(|i| params.params(i)).collect(),
        sorted,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::{Num, Spec};

    fn lane(gamma_deg: f64, f2: f64, t_end: f64) -> Lane {
        let mut s = Spec::default();
        s.set(Num::GammaDeg, gamma_deg);
        s.set(Num::F2, f2);
        s.set(Num::TEnd, t_end);
        Lane::new(&s.resolve(&[]).unwrap(), &[])
    }

    #[test]
    fn ridge_solves_a_small_system() {
        // A = [[4, 2], [2, 3]], b = A·[1, −2] = [0, −4].
        let beta = ridge(&[4.0, 2.0, 0.0, 3.0], &[0.0, -4.0], 2).unwrap();
        assert!(
            (beta[0] - 1.0).abs() < 1e-5 && (beta[1] + 2.0).abs() < 1e-5,
            "{beta:?}"
        );
        assert!(ridge(&[0.0; 4], &[0.0; 2], 2).is_none());
    }

    #[test]
    fn the_model_learns_a_cost_that_is_linear_in_its_terms() {
        // A made-up cost of the kind steps have: a start-up part and a
        // rate that both depend on the load. The model holds such costs
        // exactly, so its keys must order lanes as the cost does.
        let lanes: Vec<Lane> = (0..2000)
            .map(|i| {
                let u = (i as f64 * 0.618034).fract();
                let v = (i as f64 * 0.754878).fract();
                lane(
                    6.0 + 10.0 * u,
                    -4000.0 + 8000.0 * v,
                    0.2 + 5.0 * ((i * 7919) % 2000) as f64 / 2000.0,
                )
            })
            .collect();
        let cost = |l: &Lane| 30.0 + 0.002 * l.f2 + (5.0 + 0.0005 * l.f2) * l.t_end;
        let which: Vec<usize> = (0..lanes.len()).collect();
        let mut m = CostModel::new();
        let mut keys = Vec::new();
        m.keys(&lanes, &which, &mut keys);
        assert!(!m.trained());
        assert!(which.iter().zip(&keys).all(|(&i, &k)| k == lanes[i].t_end));
        let steps: Vec<u32> = lanes.iter().map(|l| (cost(l) * 1000.0) as u32).collect();
        m.learn(&lanes, &which, &steps);
        assert!(m.trained());
        m.keys(&lanes, &which, &mut keys);
        for (&i, &k) in which.iter().zip(&keys) {
            let want = cost(&lanes[i]) * 1000.0;
            assert!(
                (k - want).abs() < 1e-3 * want,
                "lane {i}: {k} against {want}"
            );
        }
    }

    #[test]
    fn lanes_that_never_move_have_the_lowest_key() {
        // docs/model.md's stall case: F2 = −30 kN holds the drive at rest.
        let lanes = vec![lane(5.710593, 4774.0, 2.0), lane(5.710593, -30000.0, 2.0)];
        assert!(never_moves(&lanes[1]) && !never_moves(&lanes[0]));
        let mut keys = Vec::new();
        CostModel::new().keys(&lanes, &[0, 1], &mut keys);
        assert_eq!(keys, vec![2.0, f64::NEG_INFINITY]);
    }
}
