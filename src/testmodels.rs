//! Lane sets with known character, shared by tests and benchmarks: the
//! paper-like lanes of the throughput figures (the same as the `auto`
//! trial's) and random lanes drawn as a user would for accuracy checks.

use crate::params::{FrictionKind, Num, Spec};
use crate::sampling::Uniforms;

pub use crate::backend::paper_like;

/// Random lanes drawn as a user would: lead angle 2 to 25 deg, loads
/// ±9 kN, masses ±50 %, both friction laws, a motor cut-off in about a
/// third of the lanes, t_end 1 to 4 s.
pub fn random_user_lanes(n: usize, seed: u64) -> Vec<Spec> {
    let mut u = Uniforms::new(seed);
    (0..n)
        .map(|i| {
            u.seek(i as u64, 8);
            let mut s = Spec::default();
            s.set(Num::GammaDeg, 2.0 + 23.0 * u.next());
            s.set(Num::F2, -9000.0 + 18000.0 * u.next());
            s.set(Num::M1, 586.0 * (0.5 + u.next()));
            s.set(Num::M2, 10275.0 * (0.5 + u.next()));
            let t_end = 1.0 + 3.0 * u.next();
            s.set(Num::TEnd, t_end);
            if u.next() < 0.35 {
                s.set(Num::MotorOff, t_end * u.next());
            } else {
                u.next();
            }
            if u.next() < 0.5 {
                s.friction = Some(FrictionKind::Coulomb);
                // Bronze-wheel range; static friction up to 30 % above sliding.
                let mu = 0.02 + 0.1 * u.next();
                s.set(Num::Mu, mu);
                s.set(Num::MuStatic, mu * (1.0 + 0.3 * u.next()));
            }
            s
        })
        .collect()
}
