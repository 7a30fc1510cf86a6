// Mirrors src/model/lane.rs: a lane's constants, in f32.

// `GpuLane` in src/backend/gpu/layout.rs (a test holds the layouts
// together). `law`: the friction law's parameters, in the parameter
// table's order; LAW_SLOTS comes from the generated prelude.
struct Lane {
    m1: f32, m2: f32, tan_g: f32, sin_g: f32,
    cos_g: f32, inv_cos_g: f32, f2: f32, motor: u32,
    v_sync: f32, sigma_k: f32, f_crit: f32, f1: f32,
    motor_off: f32, friction: u32, law: array<f32, LAW_SLOTS>,
    mu_s: f32, x1_0: f32, v1_0: f32, t_end: f32,
    t_max: f32, table: u32, inv_cos_an: f32, steep: u32,
    branch_speed: f32,
}

// Whether the lane's friction law has two branches (`branch_speed` is
// "never", 3e38, for a law with one: WGSL may assume no infinities).
fn has_branches(l: Lane) -> bool {
    return l.branch_speed < 1.0e38;
}

fn above_branch(l: Lane, vs: f32) -> bool {
    return vs > l.branch_speed;
}
