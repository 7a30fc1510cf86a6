//! The right-hand side of W lanes at once, component-major, from the
//! model's equation of motion ([`crate::model::motions`]); the one-lane
//! [`rhs`] is its W = 1 case.

use super::components::NY;
use crate::model::{motions, Coefs, FrictionTable, Lane};

/// The right-hand sides of W lanes at speeds `v`, component-major
/// (`k[i][j]`: component i of lane j): the derivative of (x1, ẋ1,
/// w_motor, w_load, w_friction, w_p1). Depends on ẋ1 only: x1 and the
/// works are quadratures. p1 = S1 ẋ1 and p2 = S2 ẋ2 are the powers the
/// bodies put into the mesh (docs/model.md section 10). Returns the
/// lanes' motor forces at `v` (for the switching function); `d` gets
/// each lane's D (the one-lane path checks the mode with it).
#[inline(always)]
pub fn rhs_lanes<const W: usize>(
    c: &Coefs<W>,
    lane: &[&Lane; W],
    tables: &[FrictionTable],
    v: &[f64; W],
    k: &mut [[f64; W]; NY],
    mut d: impl FnMut(usize, f64),
) -> [f64; W] {
    let mut f1s = [0.0; W];
    motions(c, lane, tables, v, |j, m| {
        f1s[j] = m.f1;
        let v2 = v[j] * c.tan_g[j];
        let (p1, p2) = (m.s1 * v[j], m.s2 * v2);
        k[0][j] = v[j];
        k[1][j] = m.acc;
        k[2][j] = m.f1 * v[j];
        k[3][j] = c.f2[j] * v2;
        k[4][j] = p1 + p2;
        k[5][j] = p1;
        d(j, m.d);
    });
    f1s
}

/// Right-hand side of one lane in `mode` at speed `v`: its derivative and
/// D of the mode ([`rhs_lanes`] of one lane).
#[inline]
pub fn rhs(
    lane: &Lane,
    tables: &[FrictionTable],
    mode: crate::model::Mode,
    v: f64,
) -> ([f64; NY], f64) {
    let c = Coefs::of(&[lane], &[mode]);
    let mut k = [[0.0; 1]; NY];
    let mut d = 0.0;
    rhs_lanes(&c, &[lane], tables, &[v], &mut k, |_, dj| d = dj);
    (k.map(|c| c[0]), d)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::sampling::Uniforms;
    use crate::model::Mode;
    use crate::params::{Num, Spec};

    /// `rhs_lanes` of 8 lanes gives each lane's bits of one lane alone,
    /// and of the model's formulas written out here (an independent
    /// composition), and `Coefs::switch_values` the switch event's, lane
    /// by lane, for every law, motor and mode, whatever the lanes beside it.
    #[test]
    fn the_lanes_right_hand_side_is_rhs_bit_for_bit() {
        let mut u = Uniforms::new(9);
        let laws = ["paper", "coulomb", "agma"];
        for round in 0..200 {
            let lanes: Vec<Lane> = (0..8)
                .map(|j| {
                    let mut s = Spec::default();
                    s.set(Num::GammaDeg, 1.0 + 30.0 * u.next());
                    s.set(Num::F2, -8000.0 + 16000.0 * u.next());
                    let law = (round + j) % 3;
                    let _ = s.set_text(crate::params::Param::Friction, laws[law]);
                    match law {
                        0 => s.set(Num::FricB, 0.1 + 2.0 * u.next()),
                        1 => s.set(Num::Mu, 0.05),
                        _ => {}
                    }
                    if (round + j) % 5 == 0 {
                        s.motor = Some(crate::params::MotorKind::Constant);
                        s.set(Num::F1, 3000.0 * u.next());
                    }
                    Lane::new(&s.resolve(&[]).unwrap(), &[])
                })
                .collect();
            let lane: [&Lane; 8] = std::array::from_fn(|j| &lanes[j]);
            let mode: [Mode; 8] = std::array::from_fn(|j| Mode {
                side: if u.next() < 0.5 { 1 } else { -1 },
                dir: if u.next() < 0.5 { 1 } else { -1 },
                motor_on: (round + j) % 4 != 0,
                branch: u32::from(u.next() < 0.5),
            });
            let v: [f64; 8] =
                std::array::from_fn(|j| if j == 3 { 0.0 } else { -6.0 + 12.0 * u.next() });
            let mut k = [[0.0; 8]; NY];
            let c = Coefs::of(&lane, &mode);
            let f1 = rhs_lanes(&c, &lane, &[], &v, &mut k, |_, _| {});
            let g = c.switch_values(&f1);
            for j in 0..8 {
                let want = crate::integrator::events::event_value(
                    lane[j],
                    &[],
                    mode[j],
                    crate::integrator::events::EventFn::Switch,
                    v[j],
                );
                assert_eq!(g[j].to_bits(), want.to_bits(), "round {round} lane {j}");
                let (want, _) = rhs(lane[j], &[], mode[j], v[j]);
                assert_eq!(
                    want,
                    written_out(lane[j], mode[j], v[j]),
                    "round {round} lane {j}"
                );
                for i in 0..NY {
                    assert_eq!(
                        k[i][j].to_bits(),
                        want[i].to_bits(),
                        "round {round} lane {j} component {i}"
                    );
                }
            }
        }
    }

    /// The right-hand side as docs/model.md section 3 states it, composed
    /// here from the laws (not from the kernel's functions).
    fn written_out(l: &Lane, mode: crate::model::Mode, v: f64) -> [f64; NY] {
        use crate::model::{FrictionKind, MotorKind};
        let f1 = match (mode.motor_on, l.motor) {
            (false, _) => 0.0,
            (true, MotorKind::Constant) => l.f1,
            (true, MotorKind::Kloss) => {
                let s = (l.v_sync - v) / l.v_sync;
                2.0 * l.f_crit * s * l.sigma_k / (s * s + l.sigma_k * l.sigma_k)
            }
        };
        let vs = (mode.dir as f64 * v).max(0.0) * l.inv_cos_g;
        let [a, b, c, ..] = l.law;
        let mu = match l.friction {
            FrictionKind::Paper => {
                let rho =
                    (std::f64::consts::PI / 180.0) / (a * crate::model::vmath::pow(vs, b) + c);
                crate::model::tan_small(rho)
            }
            FrictionKind::Coulomb => a * l.inv_cos_an,
            _ => crate::model::agma_mu(vs, mode.branch == 1) * l.inv_cos_an,
        };
        let t = (mode.side * mode.dir) as f64 * mu;
        let (p, q) = (l.tan_g + t, 1.0 - l.tan_g * t);
        let dq = l.m1 * q + p * l.m2 * l.tan_g;
        let acc = (f1 * q + p * l.f2) / dq;
        let (s1, s2) = (f1 - l.m1 * acc, l.f2 - l.m2 * l.tan_g * acc);
        let v2 = v * l.tan_g;
        let (p1, p2) = (s1 * v, s2 * v2);
        [v, acc, f1 * v, l.f2 * v2, p1 + p2, p1]
    }
}
