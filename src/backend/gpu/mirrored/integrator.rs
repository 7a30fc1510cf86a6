//! The integrator's scalar functions that the shader mirrors (the
//! Dormand–Prince stages, increment, error term and scale, dense output,
//! the step-size control, the energy flow's split), compared by what they
//! compute on random arguments over the ranges a lane's steps see (speeds
//! to ±5 m/s, steps from 1e-6 to 0.1 s, derivatives from 1e-3 to 1e3 of
//! either sign, zeros among them) and on the edges (a zero error, a
//! crossing at an end): each value within f32's bound, 2e-5 of the scale
//! of its terms, of the Rust function's, and each decision (a landing, a
//! crossing, the side of a split) the same unless its quantity is within
//! that bound of its threshold. The one difference by design, the step
//! underflow's threshold (1e-7 of max(t, 1) in f32, 1e-15 in f64), is
//! checked against the shader's own threshold.

use super::{values, Run, Tally, BOUND};
use crate::backend::gpu::shader::STEP_UNDERFLOW;
use crate::input::sampling::Uniforms;
use crate::integrator::accuracy::rates;
use crate::integrator::control::{retry_size, step_factor, step_size, H_INITIAL};
use crate::integrator::events::dense_v;
use crate::integrator::flow::{agrees, crosses, dense_slope, dense_w, split, split_whole};
use crate::integrator::stepper::{
    dense_coeffs, dense_r5, error_scale, error_term, increment, stage2_v, stage3_v, stage4_v,
    stage5_v, stage6_v,
};

/// Numbers a case: v0, h, k1..k7, and the increment dw and last
/// coefficient r4 of the dense output of ∫p a split is given.
const A: usize = 11;

/// Values a case: see `ENTRY`.
const K: usize = 41;

pub(super) const ENTRY: &str = r#"
@compute @workgroup_size(64)
fn mirrored_steps(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if (i >= arrayLength(&d_cases)) {
        return;
    }
    let b = i * 11u;
    let v0 = d_args[b];
    let h = d_args[b + 1u];
    let k1 = d_args[b + 2u];
    let k2 = d_args[b + 3u];
    let k3 = d_args[b + 4u];
    let k4 = d_args[b + 5u];
    let k5 = d_args[b + 6u];
    let k6 = d_args[b + 7u];
    let k7 = d_args[b + 8u];
    let steep = (d_cases[i].x & 1u) != 0u;
    let o = i * 41u;
    d_out[o] = stage2_v(v0, h, k1);
    d_out[o + 1u] = stage3_v(v0, h, k1, k2);
    d_out[o + 2u] = stage4_v(v0, h, k1, k2, k3);
    d_out[o + 3u] = stage5_v(v0, h, k1, k2, k3, k4);
    d_out[o + 4u] = stage6_v(v0, h, k1, k2, k3, k4, k5);
    d_out[o + 5u] = increment(h, k1, k3, k4, k5, k6);
    d_out[o + 6u] = error_term(h, k1, k3, k4, k5, k6, k7);
    d_out[o + 7u] = error_scale(1e-6, v0, k7);
    let dc = dense_coeffs(v0, k7, h, k1, k3, k4, k5, k6, k7);
    for (var j = 0u; j < 5u; j++) {
        d_out[o + 8u + j] = dc[j];
    }
    d_out[o + 13u] = dense_r5(h, k1, k3, k4, k5, k6, k7);
    d_out[o + 14u] = step_factor(k1 * k1);
    let ss = step_size(h, steep, sign(k2), v0, k3, abs(k4));
    d_out[o + 15u] = ss.h;
    d_out[o + 16u] = select(0.0, 1.0, ss.landing);
    let rt = retry_size(h, abs(k5), abs(k6));
    d_out[o + 17u] = rt.h;
    d_out[o + 18u] = select(0.0, 1.0, rt.underflow);
    let r = array<real, 5>(v0, k1, k2, k3, k4);
    let th = fract(abs(k5));
    d_out[o + 19u] = dense_v(r, th);
    d_out[o + 20u] = dense_slope(r, th);
    let sp = split(dense_w(d_args[b + 9u], h, k6, k7, d_args[b + 10u]), k6, k7);
    d_out[o + 21u] = sp.x;
    d_out[o + 22u] = sp.y;
    d_out[o + 23u] = select(0.0, 1.0, crosses(k6, k7));
    let sw = split_whole(k1, k6, k7);
    d_out[o + 24u] = sw.x;
    d_out[o + 25u] = sw.y;
    let dw = dense_w(k1, h, k2, k3, k4);
    for (var j = 0u; j < 5u; j++) {
        d_out[o + 26u + j] = dw[j];
    }
    d_out[o + 31u] = sp.z;
    let rr = rates(array<real, NY>(k1, k2, k3, k4, k5, k6));
    for (var j = 0u; j < RESULTS; j++) {
        d_out[o + 32u + j] = rr[j];
    }
}
"#;

const NAMES: [&str; K] = [
    "stage2_v",
    "stage3_v",
    "stage4_v",
    "stage5_v",
    "stage6_v",
    "increment",
    "error_term",
    "error_scale",
    "dense_coeffs[0]",
    "dense_coeffs[1]",
    "dense_coeffs[2]",
    "dense_coeffs[3]",
    "dense_coeffs[4]",
    "dense_r5",
    "step_factor",
    "step_size.h",
    "step_size.landing",
    "retry_size.h",
    "retry_size.underflow",
    "dense_v",
    "dense_slope",
    "split.in",
    "split.out",
    "crosses",
    "split_whole.in",
    "split_whole.out",
    "dense_w[0]",
    "dense_w[1]",
    "dense_w[2]",
    "dense_w[3]",
    "dense_w[4]",
    "split_error",
    "rates[0]",
    "rates[1]",
    "rates[2]",
    "rates[3]",
    "rates[4]",
    "rates[5]",
    "rates[6]",
    "rates[7]",
    "rates[8]",
];

/// A derivative: 1e-3 to 1e3 of either sign, 0 one time in 16.
fn deriv(u: &mut Uniforms) -> f64 {
    let m = 10f64.powf(-3.0 + 6.0 * u.next());
    let s = if u.next() < 0.5 { -1.0 } else { 1.0 };
    if u.next() < 1.0 / 16.0 {
        0.0
    } else {
        s * m
    }
}

/// The Rust values of a case `a` (v0, h, k1..k7), with the scale each is
/// held to (0: a decision, with the margin of its quantity to its
/// threshold, relative to that quantity's scale, in the third place).
fn cpu(a: &[f64; A], steep: bool) -> Vec<(f64, f64, f64)> {
    let [v0, h, k1, k2, k3, k4, k5, k6, k7, dw, r4] = *a;
    let ks = k1.abs() + k2.abs() + k3.abs() + k4.abs() + k5.abs() + k6.abs() + k7.abs();
    let stage = v0.abs() + h * ks;
    let mut out = vec![
        (stage2_v(v0, h, k1), stage, 0.0),
        (stage3_v(v0, h, k1, k2), stage, 0.0),
        (stage4_v(v0, h, k1, k2, k3), stage, 0.0),
        (stage5_v(v0, h, k1, k2, k3, k4), stage, 0.0),
        (stage6_v(v0, h, k1, k2, k3, k4, k5), stage, 0.0),
        (increment(h, k1, k3, k4, k5, k6), h * ks, 0.0),
        (error_term(h, k1, k3, k4, k5, k6, k7), h * ks, 0.0),
        (error_scale(1e-6, v0, k7), error_scale(1e-6, v0, k7), 0.0),
    ];
    let dense = v0.abs() + k7.abs() + h * ks;
    out.extend(dense_coeffs(v0, k7, h, k1, k3, k4, k5, k6, k7).map(|c| (c, dense, 0.0)));
    out.push((dense_r5(h, k1, k3, k4, k5, k6, k7), h * ks, 0.0));
    out.push((step_factor(k1 * k1), 1.0, 0.0));
    let dir = if k2 > 0.0 {
        1.0
    } else if k2 < 0.0 {
        -1.0
    } else {
        0.0
    };
    let (hs, landing) = step_size(h, steep, dir, v0, k3, k4.abs());
    let mut h_try = h;
    if steep && k3 * dir < 0.0 {
        h_try = h_try.min((0.5 * (-v0 / k3)).max(H_INITIAL));
    }
    out.push((hs, hs, 0.0));
    out.push((
        f64::from(u8::from(landing)),
        0.0,
        (h_try - k4.abs()) / h_try,
    ));
    let (hr, _) = retry_size(h, k5.abs(), k6.abs());
    // The shader's threshold (f32's; the f64 path's is 1e-15).
    let edge = f64::from(STEP_UNDERFLOW) * k6.abs().max(1.0);
    out.push((hr, hr, 0.0));
    out.push((f64::from(u8::from(hr < edge)), 0.0, (hr - edge) / edge));
    let r = [v0, k1, k2, k3, k4];
    let rs = r.iter().map(|x| x.abs()).sum::<f64>() * 4.0;
    let th = k5.abs().fract();
    out.push((dense_v(&r, th), rs, 0.0));
    out.push((dense_slope(&r, th), rs, 0.0));
    // A split of ∫p over a step where p goes from k6 to k7, as a lane's
    // dense output of it (dense_w) gives it: the parts to f32's bound of
    // what flowed, h (|p0| + |p_end|), or of the increment where it is
    // larger (p of the other sign inside the step).
    let (sp, sp_err) = split(&dense_w(dw, h, k6, k7, r4), k6, k7);
    let flowed = (h * (k6.abs() + k7.abs())).max(dw.abs());
    out.push((sp[0], flowed, 0.0));
    out.push((sp[1], flowed, 0.0));
    out.push((
        f64::from(u8::from(crosses(k6, k7))),
        0.0,
        (k6 * k7) / (k6 * k6 + k7 * k7).max(1e-300),
    ));
    let sw = split_whole(k1, k6, k7);
    out.push((sw[0], k1.abs(), 0.0));
    out.push((sw[1], k1.abs(), 0.0));
    let w = k1.abs() + h * (k2.abs() + k3.abs()) + k4.abs();
    out.extend(dense_w(k1, h, k2, k3, k4).map(|c| (c, w, 0.0)));
    // The split's error bound, θ²(1−θ)²|r4| at the zero θ: to f32's
    // bound of |r4| (the zero is bisected in f32, found by Illinois here);
    // where the increment has the other sign than p at the ends, the sum
    // of the dense output's coefficients' sizes: to f32's bound of that.
    let err_scale = if agrees(dw, k6, k7) || crosses(k6, k7) {
        r4.abs()
    } else {
        dense_w(dw, h, k6, k7, r4).iter().map(|c| c.abs()).sum()
    };
    out.push((sp_err, err_scale, 0.0));
    let rs = rates(&[k1, k2, k3, k4, k5, k6].map(|v| [v]));
    let pk = k5.abs() + k6.abs();
    for (i, r) in rs.iter().enumerate() {
        out.push((r[0], if i < 5 { r[0].abs() } else { pk }, 0.0));
    }
    out
}

#[test]
fn the_shaders_step_functions_compute_what_the_rust_ones_do() {
    let mut u = Uniforms::new(31);
    let mut args32 = Vec::new();
    let mut cases = Vec::new();
    let mut want = Vec::new();
    for i in 0..20_000u32 {
        let mut a = [0.0; A];
        a[0] = -5.0 + 10.0 * u.next();
        a[1] = 10f64.powf(-6.0 + 5.0 * u.next());
        for k in a.iter_mut().take(9).skip(2) {
            *k = deriv(&mut u);
        }
        if i % 50 == 0 {
            // A crossing at an end, and a zero error.
            a[7] = 0.0;
            a[2] = 0.0;
        }
        // ∫p over the step: about its trapezoid, a curvature well inside it.
        a[9] = a[1] * 0.5 * (a[7] + a[8]) * (0.9 + 0.2 * u.next());
        a[10] = 0.05 * a[1] * a[7].abs().min(a[8].abs()) * (2.0 * u.next() - 1.0);
        if i % 50 == 25 {
            // p leaves a zero at the step's end the other way: p0 small,
            // p_end 0, the increment of the other sign (`split_against`).
            a[7] *= 1e-3;
            a[8] = 0.0;
            a[9] = -a[9].abs() * a[7].signum();
        }
        // The case as the shader sees it: its numbers in f32.
        let a = a.map(|x| f64::from(x as f32));
        args32.extend(a.map(|x| x as f32));
        let steep = i % 2 == 0;
        cases.push([u32::from(steep), 0, 0, 0]);
        want.push((a, cpu(&a, steep)));
    }
    let lanes = [crate::model::Lane::new(
        &crate::params::Spec::default().resolve(&[]).unwrap(),
        &[],
    )];
    let run = Run {
        entry: ENTRY,
        name: "mirrored_steps",
        lanes: &lanes,
        tables: &[],
        cases: &cases,
        args: &args32,
        outs: K,
    };
    let Some(got) = values(&run) else {
        return;
    };
    let mut tally = Tally::new(NAMES.len());
    for (i, (a, w)) in want.iter().enumerate() {
        for (k, &(c, scale, margin)) in w.iter().enumerate() {
            let near = margin.abs() <= BOUND;
            tally.add(k, f64::from(got[i * K + k]), c, scale, near, || {
                format!("{}: args {a:?}", NAMES[k])
            });
        }
    }
    tally.report("mirrored steps", &NAMES);
}
