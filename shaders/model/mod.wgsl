// Mirrors src/model/mod.rs: the model of one lane, from the kernel's
// formulas and the lane's constants.

fn motor_force(l: Lane, v1: real, motor_on: bool) -> real {
    return motor_force_of(l.motor, motor_on, l.f1, l.v_sync, l.sigma_k, l.f_crit, v1);
}

fn phi(l: Lane, v1: real, motor_on: bool) -> real {
    return switching(motor_force(l, v1, motor_on), l.m1, load_term(l.f2, l.m2, l.tan_g));
}

fn side_of(p: real) -> i32 {
    if (p >= 0.0) { return 1; }
    return -1;
}

// Keep in sync with `Mode` in src/model/mod.rs.
struct Mode { side: i32, dir: i32, motor_on: bool, branch: u32 }

fn motion(l: Lane, m: Mode, v1: real) -> Motion {
    let f1 = motor_force(l, v1, m.motor_on);
    // Signed: past a rest a table reads its line (`mu_sliding`).
    let t = real(m.side * m.dir) * mu_sliding(l, real(m.dir) * v1 * l.inv_cos_g, m.branch);
    return motion_parts(f1, t, l.tan_g, l.m1, l.m2, l.f2);
}

// x: sticks, y: T
fn stick_test(l: Lane, motor_on: bool) -> vec2<real> {
    let f1 = motor_force(l, 0.0, motor_on);
    let n = abs(l.f2 * l.cos_g - f1 * l.sin_g);
    let t = f1 * l.cos_g + l.f2 * l.sin_g;
    return vec2<real>(select(real(0.0), real(1.0), abs(t) <= l.mu_s * n), t);
}
