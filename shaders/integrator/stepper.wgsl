// Mirrors src/integrator/stepper.rs: one Dormand–Prince 5(4) trial step,
// its error norm and its dense output.

// Dormand-Prince 5(4): the tableau (A*, E*, D*) is generated into the prelude from
// `TABLEAU` in src/integrator/stepper.rs.

fn stage2_v(v0: real, h: real, k1: real) -> real {
    return v0 + h * (A21 * k1);
}
fn stage3_v(v0: real, h: real, k1: real, k2: real) -> real {
    return v0 + h * (A31 * k1 + A32 * k2);
}
fn stage4_v(v0: real, h: real, k1: real, k2: real, k3: real) -> real {
    return v0 + h * (A41 * k1 + A42 * k2 + A43 * k3);
}
fn stage5_v(v0: real, h: real, k1: real, k2: real, k3: real, k4: real) -> real {
    return v0 + h * (A51 * k1 + A52 * k2 + A53 * k3 + A54 * k4);
}
fn stage6_v(v0: real, h: real, k1: real, k2: real, k3: real, k4: real, k5: real) -> real {
    return v0 + h * (A61 * k1 + A62 * k2 + A63 * k3 + A64 * k4 + A65 * k5);
}

fn increment(h: real, k1: real, k3: real, k4: real, k5: real, k6: real) -> real {
    return h * (A71 * k1 + A73 * k3 + A74 * k4 + A75 * k5 + A76 * k6);
}

fn error_term(h: real, k1: real, k3: real, k4: real, k5: real, k6: real, k7: real) -> real {
    return h * (E1 * k1 + E3 * k3 + E4 * k4 + E5 * k5 + E6 * k6 + E7 * k7);
}

fn error_scale(tol: real, y0: real, y1: real) -> real {
    return tol * (1.0 + max(abs(y0), abs(y1)));
}

fn dense_coeffs(v0: real, v1: real, h: real, k1: real, k3: real, k4: real, k5: real, k6: real, k7: real) -> array<real, 5> {
    let r2 = v1 - v0;
    let r3 = h * k1 - r2;
    let r4 = r2 - h * k7 - r3;
    return array<real, 5>(v0, r2, r3, r4, dense_r5(h, k1, k3, k4, k5, k6, k7));
}

fn dense_r5(h: real, k1: real, k3: real, k4: real, k5: real, k6: real, k7: real) -> real {
    return h * (D1 * k1 + D3 * k3 + D4 * k4 + D5 * k5 + D6 * k6 + D7 * k7);
}

struct Trial {
    y1: array<real, NY>,
    y1c: array<real, NY>,
    k7: array<real, NY>,
    err: real,
    dense: array<real, 5>,
    // increments of the integrals of p1 and p2, and the last coefficient
    // of their dense outputs, for `step_flow`
    dw: vec2<real>,
    dw_r4: vec2<real>,
    // the embedded error estimate of each component and, last, of the
    // integral of p2 (absolute; the error budget adds them up)
    est: array<real, NY + 1u>,
    // D at the step's end (the mode is inconsistent where it is <= 0)
    d_end: real,
}

// Compensated (Kahan) y1 = y + dy of component i; the value is y1 - y1c.
fn step_component(tr: ptr<function, Trial>, i: u32, dy: real, y: real, yc: real) {
    let yy = dy - yc;
    let s = y + yy;
    (*tr).y1c[i] = (s - y) - yy;
    (*tr).y1[i] = s;
}

// The error scale s held within the error budget's cap c (`caps`, which
// floors it).
fn capped(s: real, c: real) -> real { return min(s, c); }

fn try_step(l: Lane, m: Mode, y: array<real, NY>, yc: array<real, NY>, k1: array<real, NY>, h: real, tol: real, tol_traj: real, cap: array<real, NY>) -> Trial {
    let v0 = y[1];
    let k2 = rhs(l, m, stage2_v(v0, h, k1[1])).k;
    let k3 = rhs(l, m, stage3_v(v0, h, k1[1], k2[1])).k;
    let k4 = rhs(l, m, stage4_v(v0, h, k1[1], k2[1], k3[1])).k;
    let k5 = rhs(l, m, stage5_v(v0, h, k1[1], k2[1], k3[1], k4[1])).k;
    let k6 = rhs(l, m, stage6_v(v0, h, k1[1], k2[1], k3[1], k4[1], k5[1])).k;
    var tr: Trial;
    // Written out component by component (constant indices): with a loop
    // over the components lavapipe's compiler keeps these arrays in
    // memory and runs ten times slower.
    step_component(&tr, 0u, increment(h, k1[0], k3[0], k4[0], k5[0], k6[0]), y[0], yc[0]);
    step_component(&tr, 1u, increment(h, k1[1], k3[1], k4[1], k5[1], k6[1]), y[1], yc[1]);
    step_component(&tr, 2u, increment(h, k1[2], k3[2], k4[2], k5[2], k6[2]), y[2], yc[2]);
    step_component(&tr, 3u, increment(h, k1[3], k3[3], k4[3], k5[3], k6[3]), y[3], yc[3]);
    step_component(&tr, 4u, increment(h, k1[4], k3[4], k4[4], k5[4], k6[4]), y[4], yc[4]);
    step_component(&tr, 5u, increment(h, k1[5], k3[5], k4[5], k5[5], k6[5]), y[5], yc[5]);
    let end = rhs(l, m, tr.y1[1]);
    tr.k7 = end.k;
    tr.d_end = end.d;
    var err: real = 0.0;
    tr.est[0] = abs(error_term(h, k1[0], k3[0], k4[0], k5[0], k6[0], tr.k7[0]));
    err = max(err, tr.est[0] / capped(error_scale(tol_traj, y[0], tr.y1[0]), cap[0]));
    tr.est[1] = abs(error_term(h, k1[1], k3[1], k4[1], k5[1], k6[1], tr.k7[1]));
    err = max(err, tr.est[1] / capped(error_scale(tol_traj, y[1], tr.y1[1]), cap[1]));
    tr.est[2] = abs(error_term(h, k1[2], k3[2], k4[2], k5[2], k6[2], tr.k7[2]));
    err = max(err, tr.est[2] / capped(error_scale(tol, y[2], tr.y1[2]), cap[2]));
    tr.est[3] = abs(error_term(h, k1[3], k3[3], k4[3], k5[3], k6[3], tr.k7[3]));
    err = max(err, tr.est[3] / capped(error_scale(tol, y[3], tr.y1[3]), cap[3]));
    tr.est[4] = abs(error_term(h, k1[4], k3[4], k4[4], k5[4], k6[4], tr.k7[4]));
    err = max(err, tr.est[4] / capped(error_scale(tol, y[4], tr.y1[4]), cap[4]));
    tr.est[5] = abs(error_term(h, k1[5], k3[5], k4[5], k5[5], k6[5], tr.k7[5]));
    err = max(err, tr.est[5] / capped(error_scale(tol, y[5], tr.y1[5]), cap[5]));
    // NaN and infinity fail this test: the step is rejected.
    if (!(err <= 3.0e38)) { err = 3.0e38; }
    tr.err = err;
    tr.dense = dense_coeffs(v0, tr.y1[1], h, k1[1], k3[1], k4[1], k5[1], k6[1], tr.k7[1]);
    // The quadratures of p1 and p2 (`powers`).
    let k7 = tr.k7;
    let q1 = powers(k1[4], k1[5]).y;
    let q3 = powers(k3[4], k3[5]).y;
    let q4 = powers(k4[4], k4[5]).y;
    let q5 = powers(k5[4], k5[5]).y;
    let q6 = powers(k6[4], k6[5]).y;
    let q7 = powers(k7[4], k7[5]).y;
    tr.dw = vec2<real>(increment(h, k1[5], k3[5], k4[5], k5[5], k6[5]), increment(h, q1, q3, q4, q5, q6));
    tr.dw_r4 = vec2<real>(dense_r5(h, k1[5], k3[5], k4[5], k5[5], k6[5], k7[5]),
        dense_r5(h, q1, q3, q4, q5, q6, q7));
    if (KEEP_BUDGET) {
        tr.est[NY] = abs(error_term(h, q1, q3, q4, q5, q6, q7));
    }
    return tr;
}
