//! Lane sets with known character, shared by tests and benchmarks: the
//! paper-like lanes of the throughput figures (the same as the `auto`
//! trial's) and random lanes drawn as a user would for accuracy checks.

use crate::input::sampling::Uniforms;
use crate::params::{FrictionKind, Num, Spec};

/// Paper-like lanes: the paper's design (Kloss motor, paper friction,
/// start at rest, t_end 2 s) with the load spread uniformly over ±6 kN, so
/// lanes cover direct and inverse flow, switches and stalls. The `auto`
/// trial runs them; the throughput benchmarks too.
pub fn paper_like(n: usize, seed: u64) -> Vec<Spec> {
    let mut u = Uniforms::new(seed);
    (0..n)
        .map(|i| {
            u.seek(i as u64, 1);
            let mut s = Spec::default();
            s.set(Num::F2, -6000.0 + 12000.0 * u.next());
            s
        })
        .collect()
}

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

/// Long horizons with stiff motors: random user lanes with t_end 20 to
/// 300 s, lead angle 2 to 35 deg and a Kloss critical slip log-uniform
/// from 0.4 down to 3e-5 (v_crit close to v_sync), where f32 loses lanes.
pub fn long_stiff_lanes(n: usize, seed: u64) -> Vec<Spec> {
    let mut u = Uniforms::new(seed ^ 0x5eed);
    let mut specs = random_user_lanes(n, seed);
    for (i, s) in specs.iter_mut().enumerate() {
        u.seek(i as u64, 4);
        let t_end = 20.0 + 280.0 * u.next();
        s.set(Num::TEnd, t_end);
        if s.num[Num::MotorOff as usize].is_some() {
            s.set(Num::MotorOff, t_end * u.next());
        } else {
            u.next();
        }
        s.set(Num::GammaDeg, 2.0 + 33.0 * u.next());
        let sk = (0.4f64.ln() + (3e-5f64.ln() - 0.4f64.ln()) * u.next()).exp();
        s.set(Num::VCrit, 3.35 * (1.0 - sk));
    }
    specs
}

/// Extremely stiff motors started at synchronous speed: v_crit within
/// 0.5e-4 to 1.5e-4 m/s of v_sync, loads around the paper's, t_end 6 s
/// and 20 s in turn. In f32 these exhaust the GPU's dispatch budget or
/// lose the lane.
pub fn stiff_at_sync_lanes(n: usize) -> Vec<Spec> {
    (0..n)
        .map(|i| {
            let mut s = Spec::default();
            s.set(Num::VCrit, 3.35 - 1e-4 * (0.5 + i as f64 / n as f64));
            s.set(Num::V10, 3.35);
            s.set(Num::F2, -4774.0 + 200.0 * (i % 7) as f64);
            s.set(Num::TEnd, if i % 2 == 0 { 6.0 } else { 20.0 });
            s
        })
        .collect()
}
