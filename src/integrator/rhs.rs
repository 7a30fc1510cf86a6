//! The right-hand side: of one lane ([`rhs`], as the shader has it), and
//! of N lanes at once, component-major, as vector arithmetic
//! (`rhs_lanes`), the same bits lane for lane (a test compares them).

use super::width::lanewise;
use super::NY;
use crate::model::friction::{mu_sliding, tan_series, TAN_SERIES_MAX};
use crate::model::vmath::pow;
use crate::model::{
    motion, motion_parts, FrictionTable, Lane, Mode, FRICTION_PAPER, MOTOR_CONSTANT,
};

/// Right-hand side: derivative of (x1, ẋ1, w_motor, w_load, w_friction,
/// w_p1), and D of the mode. Depends on ẋ1 only: x1 and the works are
/// quadratures. p1 = S1 ẋ1 and p2 = S2 ẋ2 are the powers the bodies put
/// into the mesh (docs/model.md section 10).
#[inline]
pub fn rhs(lane: &Lane, tables: &[FrictionTable], mode: Mode, v: f64) -> ([f64; NY], f64) {
    let m = motion(lane, tables, mode, v);
    let v2 = v * lane.tan_g;
    let (p1, p2) = (m.s1 * v, m.s2 * v2);
    ([v, m.acc, m.f1 * v, lane.f2 * v2, p1 + p2, p1], m.d)
}

/// The mesh powers (p1, p2) from a derivative's components 4 and 5
/// (w_friction's rate p1 + p2, and ∫p1's rate p1): the one place that
/// says which components they are.
#[inline(always)]
pub(crate) fn powers(k4: f64, k5: f64) -> (f64, f64) {
    (k5, k4 - k5)
}

/// The constants of N lanes' right-hand sides in the current modes, one
/// array a constant, so that a loop over the lanes is a loop over vector
/// elements.
pub(crate) struct Coefs<const N: usize> {
    dir: [f64; N],
    sd: [f64; N],
    inv_cos_g: [f64; N],
    tan_g: [f64; N],
    m1: [f64; N],
    m2: [f64; N],
    f2: [f64; N],
    fa: [f64; N],
    fb: [f64; N],
    fc: [f64; N],
    /// Motor force law: 0 off, 1 constant, 2 Kloss.
    motor: [u8; N],
    /// Contact side c of the mode.
    side: [f64; N],
    f1: [f64; N],
    v_sync: [f64; N],
    sigma_k: [f64; N],
    f_crit: [f64; N],
    /// F2/(m2 tan γ), the switching function's constant part.
    load_term: [f64; N],
    /// Lanes under a law other than the paper's (their μ comes from
    /// `mu_sliding`, lane by lane).
    other: [bool; N],
}

impl<const N: usize> Coefs<N> {
    /// The constants of `lane` in `mode`.
    #[inline(always)]
    pub(crate) fn of(lane: &[&Lane; N], mode: &[Mode; N]) -> Coefs<N> {
        let z = [0.0; N];
        let mut c = Coefs {
            dir: z,
            sd: z,
            side: z,
            inv_cos_g: z,
            tan_g: z,
            m1: z,
            m2: z,
            f2: z,
            fa: z,
            fb: z,
            fc: z,
            motor: [0; N],
            f1: z,
            v_sync: z,
            sigma_k: z,
            f_crit: z,
            load_term: z,
            other: [false; N],
        };
        for j in 0..N {
            c.set(j, lane[j], mode[j]);
        }
        c
    }

    /// Column j: the constants of `lane` in `mode` (the batch driver
    /// keeps them from step to step and sets a column only when its
    /// lane or mode changes).
    #[inline(always)]
    pub(crate) fn set(&mut self, j: usize, lane: &Lane, mode: Mode) {
        self.dir[j] = mode.dir as f64;
        self.sd[j] = (mode.side * mode.dir) as f64;
        self.side[j] = mode.side as f64;
        self.inv_cos_g[j] = lane.inv_cos_g;
        self.tan_g[j] = lane.tan_g;
        self.m1[j] = lane.m1;
        self.m2[j] = lane.m2;
        self.f2[j] = lane.f2;
        self.fa[j] = lane.fric_a;
        self.fb[j] = lane.fric_b;
        self.fc[j] = lane.fric_c;
        self.motor[j] = match (mode.motor_on, lane.motor) {
            (false, _) => 0,
            (true, MOTOR_CONSTANT) => 1,
            _ => 2,
        };
        self.f1[j] = lane.f1;
        self.v_sync[j] = lane.v_sync;
        self.sigma_k[j] = lane.sigma_k;
        self.f_crit[j] = lane.f_crit;
        self.load_term[j] = lane.f2 / (lane.m2 * lane.tan_g);
        self.other[j] = lane.friction != FRICTION_PAPER;
    }

    /// Lane j's motor force at speed `v`: `motor_force`'s arithmetic.
    #[inline(always)]
    fn motor_force(&self, j: usize, v: f64) -> f64 {
        let sigma = (self.v_sync[j] - v) / self.v_sync[j];
        let sk = self.sigma_k[j];
        let kloss = 2.0 * self.f_crit[j] * sigma * sk / (sigma * sigma + sk * sk);
        match self.motor[j] {
            0 => 0.0,
            1 => self.f1[j],
            _ => kloss,
        }
    }

    /// The switch event's function c·φ(ẋ1) of each lane whose motor
    /// force is `f1` (at the speed φ is wanted at, as `rhs_lanes`
    /// returns it): `events::event_value`'s arithmetic, as vector code.
    #[inline(always)]
    pub(crate) fn switching(&self, f1: &[f64; N]) -> [f64; N] {
        lanewise(|j| self.side[j] * (f1[j] / self.m1[j] - self.load_term[j]))
    }
}

/// The right-hand sides of N lanes at speeds `v`, component-major
/// (`k[i][j]`: component i of lane j): `rhs`'s arithmetic, operation for
/// operation (a test compares the bits), written as loops over the lanes
/// so that they compile to vector instructions. Returns the lanes' motor
/// forces at `v` (for the switching function).
#[inline(always)]
pub(crate) fn rhs_lanes<const N: usize>(
    c: &Coefs<N>,
    lane: &[&Lane; N],
    tables: &[FrictionTable],
    mode: &[Mode; N],
    v: &[f64; N],
    k: &mut [[f64; N]; NY],
) -> [f64; N] {
    let mut vs = [0.0; N];
    let mut f1s = [0.0; N];
    let mut rho = [0.0; N];
    let mut mu = [0.0; N];
    for j in 0..N {
        vs[j] = (c.dir[j] * v[j]).max(0.0) * c.inv_cos_g[j];
    }
    // The paper law's pow only where a lane has it.
    if c.other.iter().any(|o| !o) {
        for j in 0..N {
            rho[j] = (std::f64::consts::PI / 180.0) / (c.fa[j] * pow(vs[j], c.fb[j]) + c.fc[j]);
            mu[j] = tan_series(rho[j]);
        }
    }
    for j in 0..N {
        // The rare lanes off the vector's path: another law, or a
        // friction angle past the series' range.
        if c.other[j] {
            mu[j] = mu_sliding(lane[j], tables, vs[j], mode[j].upper);
        } else if rho[j].abs() > TAN_SERIES_MAX {
            mu[j] = rho[j].tan();
        }
    }
    for j in 0..N {
        let f1 = c.motor_force(j, v[j]);
        f1s[j] = f1;
        let t = c.sd[j] * mu[j];
        let m = motion_parts(f1, t, c.tan_g[j], c.m1[j], c.m2[j], c.f2[j]);
        let v2 = v[j] * c.tan_g[j];
        let (p1, p2) = (m.s1 * v[j], m.s2 * v2);
        k[0][j] = v[j];
        k[1][j] = m.acc;
        k[2][j] = m.f1 * v[j];
        k[3][j] = c.f2[j] * v2;
        k[4][j] = p1 + p2;
        k[5][j] = p1;
    }
    f1s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::sampling::Uniforms;
    use crate::params::{Num, Spec};

    /// `rhs_lanes` gives `rhs`'s bits, and `Coefs::switching` the switch
    /// event's, lane by lane, for every law, motor and mode, whatever the
    /// lanes beside it.
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
                upper: u.next() < 0.5,
            });
            let v: [f64; 8] =
                std::array::from_fn(|j| if j == 3 { 0.0 } else { -6.0 + 12.0 * u.next() });
            let mut k = [[0.0; 8]; NY];
            let c = Coefs::of(&lane, &mode);
            let f1 = rhs_lanes(&c, &lane, &[], &mode, &v, &mut k);
            let g = c.switching(&f1);
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
}
