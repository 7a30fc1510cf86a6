// Mirrors src/model/lane.rs: a lane's constants, in f32.

// Keep in sync with `GpuLane` in src/backend/gpu/layout.rs.
struct Lane {
    m1: f32, m2: f32, tan_g: f32, sin_g: f32,
    cos_g: f32, inv_cos_g: f32, f2: f32, motor: u32,
    v_sync: f32, sigma_k: f32, f_crit: f32, f1: f32,
    motor_off: f32, friction: u32, fric_a: f32, fric_b: f32,
    fric_c: f32, mu: f32, mu_s: f32, x1_0: f32,
    v1_0: f32, t_end: f32, t_max: f32, table: u32,
    inv_cos_an: f32, pad0: u32,
}
