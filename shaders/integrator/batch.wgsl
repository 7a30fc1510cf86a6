// Mirrors src/integrator/batch.rs (and the GPU's layout,
// src/backend/gpu/layout.rs): the run's values, the bindings and the entry
// point that works a slot through lanes.

// Keep in sync with `GpuGlobals` in src/backend/gpu/layout.rs.
// The words first, then four reals: the tables start 16-aligned in f32
// and 32-aligned in f64.
struct Globals {
    n_lanes: u32, budget: u32, max_steps: u32, max_events: u32,
    n_tables: u32, row_lanes: u32, n_slots: u32, pad0: u32,
    // The per-step tolerance of the works, and of x1 and v1.
    tol: real, tol_traj: real, h_initial: real, pad_r: real,
    // Points per table; table t's point i is at [t * TABLE_VEC4S + i / 4][i % 4].
    table_n: array<vec4<u32>, 2>,
    table_vs: array<vec4<real>, 64>,
    table_mu: array<vec4<real>, 64>,
}

// Vec4s per table (TABLE_VEC4S): generated into the prelude from
// src/model/friction.rs.

// Keep in sync with `GpuControl` in src/backend/gpu/layout.rs.
struct Control {
    // Slots that still hold an unfinished lane after this dispatch.
    n_active: atomic<u32>,
    // The next lane no slot has taken yet.
    next_lane: atomic<u32>,
}

@group(0) @binding(0) var<uniform> g: Globals;
@group(0) @binding(1) var<storage, read> lanes: array<Lane>;
@group(0) @binding(2) var<storage, read_write> states: array<State>;
@group(0) @binding(3) var<storage, read_write> ctl: Control;
@group(0) @binding(4) var<storage, read_write> slot_lane: array<u32>;

// One slot per invocation, each working through lanes: its lane's state
// stays in `states` between dispatches of at most `g.budget` step
// attempts, and when the lane finishes the slot takes the next lane not
// yet started, so an invocation stays busy until the chunk runs out of
// lanes rather than idling after its own lane ends. Each lane's result
// is in its own slot of `states`, whichever invocation ran it. The
// refill sits inside the one loop of attempts, so the invocations of a
// SIMD group keep stepping together; a second loop for the new lane would
// run it alone, the others masked.
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let slot = gid.x + gid.y * g.row_lanes;
    if (slot >= g.n_slots) { return; }
    var idx = slot_lane[slot];
    if (idx >= g.n_lanes) { return; }
    var st = states[idx];
    let l = lanes[idx];
    if ((st.flags & F_STARTED) == 0u) { init(l, &st); }
    var left = g.budget;
    loop {
        if (((st.flags & F_DONE) != 0u) || left == 0u) { break; }
        left -= 1u;
        attempt(l, &st);
    }
    states[idx] = st;
    if ((st.flags & F_DONE) != 0u) {
        idx = atomicAdd(&ctl.next_lane, 1u);
    }
    slot_lane[slot] = min(idx, g.n_lanes);
    if (idx < g.n_lanes) { atomicAdd(&ctl.n_active, 1u); }
}
