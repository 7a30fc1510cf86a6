//! The automaton's functions that take or change a lane's whole state
//! (its start, its moves between contact modes, its time events and the
//! plan of a step), compared in f64: the f64 shader (`SHADER_F64`) and the Rust
//! functions start from the same states, taken along the CPU path's own
//! integration of lanes of every law and motor (cut or running, running
//! on past t_end), and each result (the state after the function, and what
//! it returns) must be the Rust one to 1e-9 of max(1, |value|), with every
//! decision (side, direction, flags, status, counts) the same. In f32 these
//! functions cannot be compared one by one: their decisions rest on
//! thresholds f32 moves. Needs an adapter with 64-bit floats (lavapipe);
//! without one the test says it is skipped, unless TSWM_REQUIRE_GPU=1.

use wgpu::util::DeviceExt;

use super::super::layout::{flags, GpuGlobals64, GpuLane64, GpuState64};
use super::super::SHADER_F64;
use crate::integrator::automaton::*;
use crate::integrator::step::{prepare, time_stop};
use crate::integrator::{attempt, LaneState, Settings, Status};
use crate::model::{FrictionTable, Lane};

/// The functions compared, in the order of their codes in [`ENTRY`].
pub(super) const FUNCTIONS: [&str; 10] = [
    "init",
    "set_side",
    "check_mode",
    "come_to_rest",
    "depart",
    "cut_motor",
    "horizon",
    "reach_time_event",
    "time_stop",
    "prepare",
];

/// Numbers a case returns besides its state.
const OUTS: usize = 4;

/// The entry point: case (lane, function, input state, word) runs the
/// function on the input state and writes the state after it and what it
/// returns. The functions of a trial step and a step attempt have an
/// entry point of their own (`attempt::ATTEMPT`).
pub(super) const ENTRY: &str = concat!(
    state_bindings!(),
    r#"
fn put(n: u32, i: u32, v: f64) { s_res[n].out[i] = v; }

@compute @workgroup_size(64)
fn mirrored_state(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= arrayLength(&s_cases)) { return; }
    let c = s_cases[id.x];
    let l = s_lanes[c.x];
    var st = s_states[c.z];
    let n = id.x;
    switch c.y {
        case 0u: { init(l, &st); }
        case 1u: { set_side(&st, -st.side); }
        case 2u: { check_mode(l, &st); }
        case 3u: { come_to_rest(l, &st); }
        case 4u: { depart(l, &st, select(-1.5lf, 2.5lf, c.w == 1u)); }
        case 5u: { cut_motor(l, &st); }
        case 6u: { put(n, 0u, horizon(l, &st)); }
        case 7u: { reach_time_event(l, &st, time_stop(l, &st)); }
        case 8u: { put(n, 0u, time_stop(l, &st)); }
        case 9u: { let p = prepare(l, &st); put(n, 0u, select(0.0lf, 1.0lf, p.ok)); if (p.ok) { put(n, 1u, p.h); put(n, 2u, p.t_stop); put(n, 3u, select(0.0lf, 1.0lf, p.landing)); } }
        default: {}
    }
    s_res[n].st = st;
}
"#
);

/// A CPU state as the shader holds it (no compensation to carry).
pub(super) fn to_gpu(st: &LaneState) -> GpuState64 {
    let bit = |on: bool, f: u32| if on { f } else { 0 };
    let (phase, local) = st.budget.terms();
    GpuState64 {
        lag: st.budget.lag(),
        phase,
        local,
        t_hi: st.t,
        h: st.h,
        t_first_switch: if st.t_first_switch.is_nan() {
            -1.0
        } else {
            st.t_first_switch
        },
        flow: st.flow,
        y: st.y,
        k1: st.k1,
        side: st.side,
        dir: st.dir,
        flags: bit(st.stuck, flags::STUCK)
            | bit(st.motor_on, flags::MOTOR_ON)
            | bit(st.done, flags::DONE)
            | bit(st.k1_valid, flags::K1_VALID)
            | flags::STARTED
            | bit(st.running_on, flags::RUNNING_ON)
            | bit(st.speeding, flags::SPEEDING),
        status: st.status.code(),
        switches: st.switches,
        reversals: st.reversals,
        sticks: st.sticks,
        steps: st.steps,
        events: st.events,
        branch: st.branch,
        ..GpuState64::default()
    }
}

/// What the Rust function of code `f` makes of `st` (changed in place)
/// and returns, as the entry point writes it.
fn cpu(lane: &Lane, tables: &[FrictionTable], f: usize, w: u32, st: &mut LaneState) -> [f64; OUTS] {
    let mut out = [0.0; OUTS];
    match f {
        0 => *st = init(lane, tables),
        1 => set_side(st, -st.side),
        2 => check_mode(lane, tables, st),
        3 => come_to_rest(lane, tables, st),
        4 => depart(lane, tables, st, if w == 1 { 2.5 } else { -1.5 }),
        5 => cut_motor(lane, tables, st),
        6 => out[0] = horizon(lane, st),
        7 => reach_time_event(lane, tables, st, time_stop(lane, st)),
        8 => out[0] = time_stop(lane, st),
        9 => {
            if let Some(p) = prepare(lane, tables, st) {
                out[..4].copy_from_slice(&[1.0, p.h, p.t_stop, p.landing as u8 as f64]);
            }
        }
        _ => unreachable!("no function of code {f}"),
    }
    out
}

/// Input states: every third state along the CPU path's integration of
/// each lane, from its start to its end or 150 attempts.
pub(super) fn states(
    lanes: &[Lane],
    tables: &[FrictionTable],
    set: &Settings,
) -> Vec<(usize, LaneState)> {
    let mut out = Vec::new();
    for (i, l) in lanes.iter().enumerate() {
        let mut st = init(l, tables);
        for k in 0..150 {
            if k % 3 == 0 {
                out.push((i, st));
            }
            if st.done {
                break;
            }
            attempt(l, tables, set, &mut st);
        }
    }
    out
}

/// The values of a state compared, as (name, value); the discrete ones
/// as words.
pub(super) fn state_values(s: &GpuState64) -> (Vec<(String, f64)>, String) {
    let mut v = vec![("t".to_string(), s.t_hi - s.t_lo), ("h".into(), s.h)];
    v.push(("first switch".into(), s.t_first_switch.max(-1.0)));
    for i in 0..6 {
        v.push((format!("y{i}"), s.y[i] - s.yc[i]));
        if s.flags & flags::K1_VALID != 0 {
            v.push((format!("k1[{i}]"), s.k1[i]));
        }
    }
    for i in 0..4 {
        v.push((format!("flow{i}"), s.flow[i] - s.flow_c[i]));
    }
    let status = if s.flags & flags::DONE != 0 {
        s.status
    } else {
        0
    };
    let words = format!(
        "side {} dir {} flags {:b} status {status} switches {} reversals {} sticks {} steps {} events {}",
        s.side, s.dir, s.flags & !(flags::FLOW_TURN | flags::JUST_SWITCHED | flags::GRAZE), s.switches, s.reversals, s.sticks, s.steps, s.events
    );
    (v, words)
}

/// The lanes the states are taken from: every law and motor, with a
/// friction table, motors cut inside the run, and runs on past t_end.
pub(super) fn test_lanes() -> (Vec<Lane>, Vec<FrictionTable>) {
    let tables =
        vec![FrictionTable::new(&[0.0, 0.1, 1.0, 5.0], &[0.08, 0.05, 0.04, 0.035]).unwrap()];
    let mut lanes = super::model::lanes(&tables);
    for (i, l) in lanes.iter_mut().enumerate() {
        match i % 3 {
            0 => l.motor_off = 0.3 * l.t_end,
            1 => l.t_max = l.t_end + 2.0,
            _ => {}
        }
    }
    (lanes, tables)
}

#[test]
fn the_shaders_state_functions_compute_what_the_rust_ones_do_in_f64() {
    let (lanes, tables) = test_lanes();
    let set = super::super::layout::f64_settings(&Settings::default());
    let inputs = states(&lanes, &tables, &set);
    let mut cases = Vec::new();
    for (k, (li, _)) in inputs.iter().enumerate() {
        for f in 0..FUNCTIONS.len() as u32 {
            cases.push([*li as u32, f, k as u32, (k % 2) as u32]);
        }
    }
    let Some((after, outs)) = run(
        ("mirrored_state", ENTRY),
        &Settings::default(),
        &lanes,
        &tables,
        &inputs,
        &cases,
    ) else {
        return;
    };
    let mut worst = vec![0.0f64; FUNCTIONS.len()];
    let mut bad = Vec::new();
    for (n, c) in cases.iter().enumerate() {
        let (li, f, k) = (c[0] as usize, c[1] as usize, c[2] as usize);
        let mut st = inputs[k].1;
        let want = cpu(&lanes[li], &tables, f, c[3], &mut st);
        let (wv, ww) = state_values(&to_gpu(&st));
        let (gv, gw) = state_values(&after[n]);
        let what = format!("{} on lane {li}, state {k}", FUNCTIONS[f]);
        if ww != gw || wv.len() != gv.len() {
            bad.push(format!("{what}: rust {ww}, shader {gw}"));
            continue;
        }
        let got = &outs[n * OUTS..(n + 1) * OUTS];
        let pairs = wv
            .iter()
            .zip(&gv)
            .map(|((name, a), (_, b))| (name.clone(), *a, *b));
        let returns = (0..OUTS).map(|i| (format!("out {i}"), want[i], got[i]));
        for (name, a, b) in pairs.chain(returns) {
            let d = if a == b {
                0.0
            } else {
                (a - b).abs() / a.abs().max(1.0)
            };
            let d = if d.is_nan() { f64::INFINITY } else { d };
            worst[f] = worst[f].max(d);
            if d > 1e-9 {
                bad.push(format!("{what}: {name} rust {a:e}, shader {b:e}"));
            }
        }
    }
    for (f, w) in FUNCTIONS.iter().zip(&worst) {
        eprintln!("{f}: worst {w:.1e}");
    }
    bad.truncate(20);
    assert!(
        bad.is_empty(),
        "{} cases of {}: {bad:#?}",
        bad.len(),
        cases.len()
    );
    // The statuses the input states end in: the cases reach them.
    let ended: std::collections::BTreeSet<u32> = inputs
        .iter()
        .filter(|(_, s)| s.done)
        .map(|(_, s)| s.status.code())
        .collect();
    assert!(ended.contains(&Status::Ok.code()));
}

/// The states after each case and the numbers it returns, from the f64
/// shader with `entry` (its name, its source) at settings `set` on the
/// first adapter with 64-bit floats; None (said as a skip) when there is
/// none.
pub(super) fn run(
    entry: (&str, &str),
    set: &Settings,
    lanes: &[Lane],
    tables: &[FrictionTable],
    inputs: &[(usize, LaneState)],
    cases: &[[u32; 4]],
) -> Option<(Vec<GpuState64>, Vec<f64>)> {
    let dev = match super::super::Gpu::open(false, super::super::ShaderReal::F64) {
        Ok(d) => d,
        Err(e) => {
            assert!(
                std::env::var("TSWM_REQUIRE_GPU").as_deref() != Ok("1"),
                "TSWM_REQUIRE_GPU=1 but {e}"
            );
            use std::io::Write;
            let _ = writeln!(std::io::stderr(), "skipped {}: {e}", entry.0);
            return None;
        }
    };
    let d = &dev.device;
    let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(entry.0),
        source: wgpu::ShaderSource::Wgsl(format!("{}{}", SHADER_F64.as_str(), entry.1).into()),
    });
    let pipe = d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(entry.0),
        layout: None,
        module: &module,
        entry_point: Some(entry.0),
        compilation_options: Default::default(),
        cache: None,
    });
    let init = |bytes: &[u8], usage| {
        d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: None,
            contents: bytes,
            usage,
        })
    };
    use wgpu::BufferUsages as U;
    let globals = GpuGlobals64::new(set, tables);
    let l64: Vec<GpuLane64> = lanes.iter().map(GpuLane64::from).collect();
    let s64: Vec<GpuState64> = inputs.iter().map(|(_, s)| to_gpu(s)).collect();
    // A case's record: its state after, then its OUTS numbers.
    let record = std::mem::size_of::<GpuState64>() + OUTS * 8;
    let res_bytes = (cases.len() * record) as u64;
    let plain = |size, usage| {
        d.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size,
            usage,
            mapped_at_creation: false,
        })
    };
    let bufs = [
        init(bytemuck::bytes_of(&globals), U::UNIFORM),
        init(bytemuck::cast_slice(&l64), U::STORAGE),
        init(bytemuck::cast_slice(&s64), U::STORAGE),
        init(bytemuck::cast_slice(cases), U::STORAGE),
        plain(res_bytes, U::STORAGE | U::COPY_SRC),
    ];
    let read = plain(res_bytes, U::MAP_READ | U::COPY_DST);
    let group = |g: u32, bs: &[&wgpu::Buffer]| {
        let entries: Vec<wgpu::BindGroupEntry> = (0u32..)
            .zip(bs)
            .map(|(binding, b)| wgpu::BindGroupEntry {
                binding,
                resource: b.as_entire_binding(),
            })
            .collect();
        d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipe.get_bind_group_layout(g),
            entries: &entries,
        })
    };
    let b0 = group(0, &[&bufs[0]]);
    let b1 = group(1, &[&bufs[1], &bufs[2], &bufs[3], &bufs[4]]);
    let mut enc = d.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipe);
        pass.set_bind_group(0, &b0, &[]);
        pass.set_bind_group(1, &b1, &[]);
        pass.dispatch_workgroups(cases.len().div_ceil(64) as u32, 1, 1);
    }
    enc.copy_buffer_to_buffer(&bufs[4], 0, &read, 0, res_bytes);
    dev.queue.submit([enc.finish()]);
    read.slice(..).map_async(wgpu::MapMode::Read, |_| {});
    d.poll(wgpu::PollType::wait_indefinitely())
        .expect("the GPU finished");
    let bytes = read
        .slice(..)
        .get_mapped_range()
        .expect("read back")
        .to_vec();
    let (mut after, mut outs) = (Vec::new(), Vec::new());
    for r in bytes.chunks_exact(record) {
        let (st, out) = r.split_at(std::mem::size_of::<GpuState64>());
        after.push(bytemuck::pod_read_unaligned::<GpuState64>(st));
        outs.extend(out.chunks_exact(8).map(bytemuck::pod_read_unaligned::<f64>));
    }
    Some((after, outs))
}
