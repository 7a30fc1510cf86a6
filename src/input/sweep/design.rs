//! A tolerance study and a sensitivity design: what they vary and how a
//! sample's values are drawn.

use super::file::Method;
use crate::input::sampling::{Dist, Permutation, Uniforms};
use crate::input::sobol_seq::SobolSeq;
use crate::params::{Num, Spec};

/// One parameter of a tolerance study.
#[derive(Clone, Copy, Debug)]
pub struct Tolerance {
    /// The parameter.
    pub param: Num,
    /// Its distribution.
    pub dist: Dist,
    /// Half-width of the band, absolute (`tol`) ...
    pub tol: f64,
    /// ... or as a fraction of the nominal value (`tol_rel`).
    pub relative: bool,
}

/// A tolerance study.
#[derive(Clone, Debug)]
pub struct Study {
    /// Sampling method.
    pub method: Method,
    /// Samples per grid point.
    pub n: u64,
    /// Seed of the ChaCha8 stream.
    pub seed: u64,
    /// The varied parameters.
    pub params: Vec<Tolerance>,
    pub(crate) perms: Vec<Permutation>,
    /// A sensitivity design (`[sensitivity]`): `n` is then
    /// `base · (inputs + 2)`.
    pub sensitivity: Option<Box<Sensitivity>>,
}

/// A variance-based sensitivity design (`[sensitivity]`, method `sobol`):
/// at every grid point the Saltelli design over the study's inputs, in
/// row groups of `inputs + 2` lanes (A, AB¹ ... ABᵈ, B).
#[derive(Clone, Debug, PartialEq)]
pub struct Sensitivity {
    /// Base samples N.
    pub base: u64,
    /// Bootstrap resamples (0: no intervals).
    pub bootstrap: usize,
    /// Two-sided coverage of the intervals.
    pub confidence: f64,
    /// The results the report charts (empty: its default).
    pub results: Vec<String>,
    /// The design's points.
    pub(crate) seq: SobolSeq,
}

impl Sensitivity {
    /// Default bootstrap resamples.
    pub(crate) const DEFAULT_BOOTSTRAP: usize = 1000;
    /// Default coverage of the intervals.
    pub(crate) const DEFAULT_CONFIDENCE: f64 = 0.95;
    /// Most resamples.
    pub(crate) const MAX_BOOTSTRAP: usize = 10_000;
    /// Most inputs (the sequence's dimensions hold A and B).
    pub(crate) const MAX_INPUTS: usize = crate::input::sobol_seq::MAX_DIMS / 2;
    /// Most base samples.
    pub(crate) const MAX_BASE: u64 = 1 << 30;
}

// The sequence has 32 bits: a design needs no more base points than it has.
const _: () = assert!(Sensitivity::MAX_BASE <= crate::input::sobol_seq::MAX_POINTS);

/// How a sample's draw moves a parameter from its nominal value.
#[derive(Clone, Copy, Debug)]
pub struct Shift {
    /// Whether a tolerance moves the value at all ([`Shift::NONE`]: no).
    drawn: bool,
    tol: f64,
    relative: bool,
    /// The distribution's quantile of the sample's uniform, in half-widths.
    z: f64,
}

impl Shift {
    /// No tolerance: the nominal value itself.
    pub(crate) const NONE: Shift = Shift {
        drawn: false,
        tol: 0.0,
        relative: false,
        z: 0.0,
    };

    /// The drawn value around `nominal` (`nominal` itself, bit for bit,
    /// without a tolerance).
    pub fn apply(&self, nominal: f64) -> f64 {
        if !self.drawn {
            return nominal;
        }
        let half = if self.relative {
            self.tol * nominal.abs()
        } else {
            self.tol
        };
        nominal + half * self.z
    }
}

impl Study {
    /// Sets the varied parameters of sample `k` (of a grid point) in
    /// `spec`, around the nominal values it holds.
    pub(super) fn draw(&self, k: u64, spec: &mut Spec, u: &mut Uniforms) {
        self.draw_around(k, spec, u, None);
    }

    /// [`Study::draw`], except that the `searched` parameter's tolerance
    /// is not applied but returned: how it moves any nominal value (a
    /// search's drive keeps its draw at every value it is queried at).
    pub(super) fn draw_around(
        &self,
        k: u64,
        spec: &mut Spec,
        u: &mut Uniforms,
        searched: Option<Num>,
    ) -> Shift {
        let dims = self.params.len() as u64;
        u.seek(k, dims);
        let mut shift = Shift::NONE;
        for (d, t) in self.params.iter().enumerate() {
            let q = match (self.method, &self.sensitivity) {
                (Method::Sobol, Some(sn)) => {
                    // Row group j, row m: A (m = 0), A with input m − 1
                    // from B, or B (m = dims + 1).
                    let (j, m) = (k / (dims + 2), (k % (dims + 2)) as usize);
                    let from_b = m == dims as usize + 1 || m == d + 1;
                    let dim = if from_b { dims as usize + d } else { d };
                    sn.seq.point(j, dim)
                }
                (Method::LatinHypercube, _) => {
                    (self.perms[d].apply(k) as f64 + u.next()) / self.n as f64
                }
                _ => u.next(),
            };
            let moved = Shift {
                drawn: true,
                tol: t.tol,
                relative: t.relative,
                z: t.dist.quantile(q),
            };
            if Some(t.param) == searched {
                shift = moved;
                continue;
            }
            let nominal = spec.num[t.param as usize]
                .or_else(|| t.param.default_value())
                .unwrap_or(f64::NAN);
            spec.set(t.param, moved.apply(nominal));
        }
        shift
    }
}
