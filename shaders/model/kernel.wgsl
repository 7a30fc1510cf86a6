// Mirrors src/model/kernel.rs: the per-lane formulas, each written once,
// under the same names (a test checks the names on both sides).

fn kloss(v_sync: f32, sigma_k: f32, f_crit: f32, v: f32) -> f32 {
    let sigma = (v_sync - v) / v_sync;
    let sk = sigma_k;
    return 2.0 * f_crit * sigma * sk / (sigma * sigma + sk * sk);
}

fn motor_force_of(motor: u32, on: bool, f1: f32, v_sync: f32, sigma_k: f32, f_crit: f32, v: f32) -> f32 {
    if (!on) { return 0.0; }
    if (motor == MOTOR_CONSTANT) { return f1; }
    return kloss(v_sync, sigma_k, f_crit, v);
}

fn paper_rho(fa: f32, fb: f32, fc: f32, vs: f32) -> f32 {
    // pow(0, b) is not defined in WGSL: Vs^b = 0 at rest.
    var pw = 0.0;
    if (vs > 0.0) { pw = pow(vs, fb); }
    return (PI / 180.0) / (fa * pw + fc);
}

fn sliding_speed(dir: f32, v: f32, inv_cos_g: f32) -> f32 {
    return max(dir * v, 0.0) * inv_cos_g;
}

fn load_term(f2: f32, m2: f32, tan_g: f32) -> f32 {
    return f2 / (m2 * tan_g);
}

fn switching(f1: f32, m1: f32, load: f32) -> f32 {
    return f1 / m1 - load;
}

// (p, q) of ψ = −p/q.
fn psi_parts(tan_g: f32, t: f32) -> vec2<f32> {
    return vec2<f32>(tan_g + t, 1.0 - tan_g * t);
}

// `Motion` without ψ, which no part of the shader reads.
struct Motion { acc: f32, d: f32, f1: f32, s1: f32, s2: f32 }

fn motion_parts(f1: f32, t: f32, tan_g: f32, m1: f32, m2: f32, f2: f32) -> Motion {
    let pq = psi_parts(tan_g, t);
    let p = pq.x;
    let q = pq.y;
    let dq = m1 * q + p * m2 * tan_g;
    let acc = (f1 * q + p * f2) / dq;
    return Motion(acc, dq / q, f1, f1 - m1 * acc, f2 - m2 * tan_g * acc);
}
