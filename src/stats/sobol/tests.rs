//! The estimators against analytic indices (Ishigami, Sobol's G).

use super::*;
use crate::input::sobol_seq::SobolSeq;
use std::f64::consts::PI;

/// A Saltelli design of `n` base samples over `d` inputs uniform in
/// (0, 1), on the scrambled Sobol' points a sweep uses (A from the
/// first d dimensions, B from the next d); `f` maps a point to the
/// output.
fn run(d: usize, n: u64, seed: u64, f: impl Fn(&[f64]) -> f64, boot: usize) -> Vec<Index> {
    let seq = SobolSeq::new(2 * d, Some(seed));
    let mut acc = Accumulator::new(d, n);
    let mut y = vec![0.0; d + 2];
    let (mut a, mut b) = (vec![0.0; d], vec![0.0; d]);
    for j in 0..n {
        for i in 0..d {
            a[i] = seq.point(j, i);
            b[i] = seq.point(j, d + i);
        }
        y[0] = f(&a);
        for i in 0..d {
            let mut ab = a.clone();
            ab[i] = b[i];
            y[1 + i] = f(&ab);
        }
        y[d + 1] = f(&b);
        acc.add(j, &y);
    }
    let boot = Bootstrap {
        resamples: boot,
        confidence: 0.95,
        seed,
    };
    acc.indices(&resample_counts(&boot, 0, acc.units()), &boot)
}

fn ishigami(x: &[f64]) -> f64 {
    let (a, b) = (7.0, 0.1);
    let x: Vec<f64> = x.iter().map(|u| -PI + 2.0 * PI * u).collect();
    x[0].sin() + a * x[1].sin().powi(2) + b * x[2].powi(4) * x[0].sin()
}

/// Ishigami, a = 7, b = 0.1 (Ishigami & Homma 1990; values as in
/// SALib's test suite and Saltelli et al. 2008).
const ISHIGAMI_S1: [f64; 3] = [0.3139, 0.4424, 0.0];
const ISHIGAMI_ST: [f64; 3] = [0.5576, 0.4424, 0.2437];

/// Sobol's G function with these a_i: V_i = 1/(3(1 + a_i)²),
/// V = Π(1 + V_i) − 1, S_i = V_i/V, ST_i = V_i Π_{j≠i}(1 + V_j)/V.
const G_A: [f64; 6] = [0.0, 1.0, 4.5, 9.0, 99.0, 99.0];

fn g(x: &[f64]) -> f64 {
    x.iter()
        .zip(G_A)
        .map(|(x, a)| ((4.0 * x - 2.0).abs() + a) / (1.0 + a))
        .product()
}

fn g_analytic() -> (Vec<f64>, Vec<f64>) {
    let vi: Vec<f64> = G_A
        .iter()
        .map(|a| 1.0 / (3.0 * (1.0 + a).powi(2)))
        .collect();
    let v = vi.iter().map(|x| 1.0 + x).product::<f64>() - 1.0;
    let s1 = vi.iter().map(|x| x / v).collect();
    let st = (0..vi.len())
        .map(|i| {
            let rest: f64 = (0..vi.len())
                .filter(|&j| j != i)
                .map(|j| 1.0 + vi[j])
                .product();
            vi[i] * rest / v
        })
        .collect();
    (s1, st)
}

#[test]
fn g_analytic_values_are_salibs() {
    // SALib.test_functions.Sobol_G.sensitivity_index(a) and
    // .total_sensitivity_index(a) for the same a.
    let (s1, st) = g_analytic();
    let want_s1 = [
        0.716342525,
        0.179085631,
        0.0236807446,
        0.00716342525,
        7.16342525e-5,
        7.16342525e-5,
    ];
    let want_st = [
        0.787256894,
        0.24223289,
        0.0343218264,
        0.0104618856,
        1.04964087e-4,
        1.04964087e-4,
    ];
    for i in 0..6 {
        assert!(
            (s1[i] - want_s1[i]).abs() < 1e-9 && (st[i] - want_st[i]).abs() < 1e-9,
            "{i}"
        );
    }
}

/// At N = 2^13 every index within 0.02 of the analytic value, and the
/// 95 % intervals cover it in at least 90 % of 50 seeds.
fn check(d: usize, f: fn(&[f64]) -> f64, s1: &[f64], st: &[f64], name: &str) {
    let seeds = 50;
    let mut covered = vec![(0usize, 0usize); d];
    let mut worst: f64 = 0.0;
    for seed in 0..seeds {
        let idx = run(d, 1 << 13, seed, f, 1000);
        for i in 0..d {
            let e = (idx[i].s1 - s1[i]).abs().max((idx[i].st - st[i]).abs());
            worst = worst.max(e);
            assert!(
                e <= 0.02,
                "{name} seed {seed} input {i}: {:?} vs {} {}",
                idx[i],
                s1[i],
                st[i]
            );
            covered[i].0 += usize::from(idx[i].s1_low <= s1[i] && s1[i] <= idx[i].s1_high);
            covered[i].1 += usize::from(idx[i].st_low <= st[i] && st[i] <= idx[i].st_high);
        }
    }
    eprintln!(
        "{name}: worst deviation {worst:.4}; intervals covering (S1, ST) of {seeds}: {covered:?}"
    );
    for (i, (c1, ct)) in covered.iter().enumerate() {
        assert!(
            *c1 * 10 >= seeds as usize * 9,
            "{name} input {i}: S1 covered {c1} of {seeds}"
        );
        assert!(
            *ct * 10 >= seeds as usize * 9,
            "{name} input {i}: ST covered {ct} of {seeds}"
        );
    }
}

#[test]
fn ishigami_indices_and_intervals() {
    check(3, ishigami, &ISHIGAMI_S1, &ISHIGAMI_ST, "Ishigami");
}

#[test]
fn g_function_indices_and_intervals() {
    let (s1, st) = g_analytic();
    check(6, g, &s1, &st, "G");
}

#[test]
fn an_input_that_does_nothing_has_total_index_zero_exactly() {
    let idx = run(3, 256, 1, |x| x[0] + 2.0 * x[1] * x[1], 200);
    assert_eq!(idx[2].st, 0.0);
    assert_eq!((idx[2].st_low, idx[2].st_high), (0.0, 0.0));
}

#[test]
fn a_constant_output_has_no_indices() {
    let idx = run(2, 64, 1, |_| 3.0, 100);
    assert!(idx
        .iter()
        .all(|i| i.s1.is_nan() && i.st.is_nan() && i.s1_low.is_nan()));
}

#[test]
fn percentiles_interpolate_like_numpy() {
    // numpy.percentile([1, 2, 3, 4], [2.5, 50, 97.5]) = 1.075, 2.5, 3.925
    let mut v = vec![4.0, 1.0, 3.0, 2.0];
    assert!((percentile(&mut v, 0.025) - 1.075).abs() < 1e-12);
    assert!((percentile(&mut v, 0.5) - 2.5).abs() < 1e-12);
    assert!((percentile(&mut v, 0.975) - 3.925).abs() < 1e-12);
}
