// Mirrors src/model/lane.rs: a lane's constants, in the shader's `real`
// (f32, or f64 where the adapter has it: the prelude says which).

// `GpuLane` in src/backend/gpu/layout.rs (a test holds the layouts
// together). `law`: the friction law's parameters, in the parameter
// table's order; LAW_SLOTS comes from the generated prelude. The u32
// fields come last, so that no real is out of its alignment in f64.
struct Lane {
    m1: real, m2: real, tan_g: real, sin_g: real,
    cos_g: real, inv_cos_g: real, f2: real, v_sync: real,
    sigma_k: real, f_crit: real, f1: real, motor_off: real,
    law: array<real, LAW_SLOTS>,
    mu_s: real, x1_0: real, v1_0: real, t_end: real,
    t_max: real, inv_cos_an: real, branch_speed: real,
    motor: u32, friction: u32, table: u32, steep: u32,
}

// `branch_speed` is "never", 3e38, for a law without one: WGSL may
// assume no infinities.
fn above_branch(l: Lane, vs: real) -> bool {
    return vs > l.branch_speed;
}
