// Mirrors src/model/kernel.rs: the per-lane formulas, each written once,
// under the same names (a test checks the names on both sides).

fn kloss(v_sync: real, sigma_k: real, f_crit: real, v: real) -> real {
    let sigma = (v_sync - v) / v_sync;
    let sk = sigma_k;
    return 2.0 * f_crit * sigma * sk / (sigma * sigma + sk * sk);
}

fn motor_force_of(motor: u32, on: bool, f1: real, v_sync: real, sigma_k: real, f_crit: real, v: real) -> real {
    if (!on) { return 0.0; }
    if (motor == MOTOR_CONSTANT) { return f1; }
    return kloss(v_sync, sigma_k, f_crit, v);
}

fn paper_rho(fa: real, fb: real, fc: real, vs: real) -> real {
    // pow(0, b) is not defined in WGSL: Vs^b = 0 at rest.
    var pw: real = 0.0;
    if (vs > 0.0) { pw = pow_r(vs, fb); }
    return (PI / 180.0) / (fa * pw + fc);
}

fn sliding_speed(dir: real, v: real, inv_cos_g: real) -> real {
    return max(dir * v, 0.0) * inv_cos_g;
}

fn load_term(f2: real, m2: real, tan_g: real) -> real {
    return f2 / (m2 * tan_g);
}

fn switching(f1: real, m1: real, load: real) -> real {
    return f1 / m1 - load;
}

// (p, q) of ψ = −p/q.
fn psi_parts(tan_g: real, t: real) -> vec2<real> {
    return vec2<real>(tan_g + t, 1.0 - tan_g * t);
}

// `Motion` without ψ, which no part of the shader reads.
struct Motion { acc: real, d: real, f1: real, s1: real, s2: real }

fn motion_parts(f1: real, t: real, tan_g: real, m1: real, m2: real, f2: real) -> Motion {
    let pq = psi_parts(tan_g, t);
    let p = pq.x;
    let q = pq.y;
    let dq = m1 * q + p * m2 * tan_g;
    let acc = (f1 * q + p * f2) / dq;
    return Motion(acc, dq / q, f1, f1 - m1 * acc, f2 - m2 * tan_g * acc);
}
