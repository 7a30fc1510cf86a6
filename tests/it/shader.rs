//! The WGSL shader without a GPU: naga validates it, and the structs it
//! shares with the host have the same size and member offsets as their
//! `#[repr(C)]` mirrors in `src/backend/gpu/layout.rs`.

use std::mem::{offset_of, size_of};

use naga::valid::{Capabilities, ValidationFlags, Validator};
use tswm::backend::gpu::layout::{GpuControl, GpuGlobals, GpuLane, GpuState};

fn module() -> naga::Module {
    naga::front::wgsl::parse_str(&tswm::backend::gpu::SHADER)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(&tswm::backend::gpu::SHADER)))
}

#[test]
fn shader_parses_and_validates() {
    let m = module();
    Validator::new(ValidationFlags::all(), Capabilities::empty())
        .validate(&m)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(&tswm::backend::gpu::SHADER)));
    assert!(m.entry_points.iter().any(|e| e.name == "main"));
}

/// (size, [(member, offset)]) of a WGSL struct.
fn wgsl_layout(m: &naga::Module, name: &str) -> (u32, Vec<(String, u32)>) {
    for (_, ty) in m.types.iter() {
        if ty.name.as_deref() == Some(name) {
            if let naga::TypeInner::Struct { members, span } = &ty.inner {
                return (
                    *span,
                    members
                        .iter()
                        .map(|mm| (mm.name.clone().unwrap_or_default(), mm.offset))
                        .collect(),
                );
            }
        }
    }
    panic!("struct {name} not in the shader");
}

macro_rules! rust_layout {
    ($t:ty; $($f:ident),* $(,)?) => {
        (size_of::<$t>() as u32, vec![$((stringify!($f).to_string(), offset_of!($t, $f) as u32)),*])
    };
}

#[test]
fn host_structs_match_the_shader() {
    let m = module();
    let lane = rust_layout!(GpuLane; m1, m2, tan_g, sin_g, cos_g, inv_cos_g, f2, motor, v_sync, sigma_k, f_crit, f1,
        motor_off, friction, law, mu_s, x1_0, v1_0, t_end, t_max, table, inv_cos_an, steep, branch_speed);
    assert_eq!(wgsl_layout(&m, "Lane"), lane);
    let state = rust_layout!(GpuState; t_hi, t_lo, h, t_first_switch, flow, flow_c, y, yc, k1, side, dir, flags,
        status, switches, reversals, sticks, steps, events, pad0, pad1, pad2, pad3, pad4);
    assert_eq!(wgsl_layout(&m, "State"), state);
    let globals = rust_layout!(GpuGlobals; n_lanes, budget, max_steps, max_events, tol, h_initial, n_tables, row_lanes,
        n_slots, pad0, pad1, pad2, table_n, table_vs, table_mu);
    assert_eq!(wgsl_layout(&m, "Globals"), globals);
    let control = rust_layout!(GpuControl; n_active, next_lane);
    assert_eq!(wgsl_layout(&m, "Control"), control);
}

/// The value of the shader's module-scope `const NAME`, as naga's
/// constant evaluator left it.
fn shader_const(m: &naga::Module, name: &str) -> naga::Literal {
    let c = m
        .constants
        .iter()
        .map(|(_, c)| c)
        .find(|c| c.name.as_deref() == Some(name))
        .unwrap_or_else(|| panic!("the shader has no `const {name}`"));
    match m.global_expressions[c.init] {
        naga::Expression::Literal(l) => l,
        ref e => panic!("`const {name}` is not a literal: {e:?}"),
    }
}

fn u32_const(m: &naga::Module, name: &str) -> u32 {
    match shader_const(m, name) {
        naga::Literal::U32(v) => v,
        l => panic!("`const {name}` is not a u32: {l:?}"),
    }
}

/// Every constant the shader shares with the host: law codes, flag bits,
/// status codes, event codes, the Dormand–Prince tableau, the agma law
/// and the f32 limits.
#[test]
fn shared_constants_match_the_shader() {
    let m = module();
    for (name, want) in shared_u32() {
        assert_eq!(u32_const(&m, &name), want, "shader `const {name}`");
    }
    for (name, want) in shared_f32() {
        match shader_const(&m, name) {
            naga::Literal::F32(v) => assert_eq!(v, want, "shader `const {name}`"),
            l => panic!("`const {name}` is not an f32: {l:?}"),
        }
    }
    // Every status the host knows has its code in the shader, once.
    let mut seen: Vec<u32> = shared_u32()
        .into_iter()
        .filter(|(n, _)| n.starts_with("S_"))
        .map(|(_, c)| c)
        .collect();
    seen.sort();
    assert_eq!(seen, Status::ALL.map(|s| s.code()));
}

use tswm::integrator::Status;

/// The integer constants the shader shares with the host, by name.
fn shared_u32() -> Vec<(String, u32)> {
    use tswm::backend::gpu::layout::flags;
    use tswm::integrator::events::EventFn;
    // (The law codes are generated: `shader::prelude`.)
    let mut out: Vec<(String, u32)> = Vec::new();
    let codes: &[(&str, u32)] = &[
        ("F_STUCK", flags::STUCK),
        ("F_MOTOR_ON", flags::MOTOR_ON),
        ("F_DONE", flags::DONE),
        ("F_K1_VALID", flags::K1_VALID),
        ("F_STARTED", flags::STARTED),
        ("F_RUNNING_ON", flags::RUNNING_ON),
        ("F_SPEEDING", flags::SPEEDING),
        ("F_UPPER", flags::UPPER),
        ("F_FLOW_TURN", flags::FLOW_TURN),
        ("S_OK", Status::Ok as u32),
        ("S_INCONSISTENT", Status::Inconsistent as u32),
        ("S_NONFINITE", Status::NonFinite as u32),
        ("S_MAX_STEPS", Status::MaxSteps as u32),
        ("S_MAX_EVENTS", Status::MaxEvents as u32),
        ("S_STEP_UNDERFLOW", Status::StepUnderflow as u32),
        ("NY", tswm::integrator::NY as u32),
        ("EV_SWITCH", EventFn::Switch as u32),
        ("EV_REST", EventFn::Rest as u32),
        ("EV_SPEEDING", EventFn::Speeding as u32),
        ("EV_BRANCH", EventFn::Branch as u32),
        ("TABLE_VEC4S", (tswm::model::MAX_TABLE_POINTS / 4) as u32),
    ];
    out.extend(codes.iter().map(|&(n, v)| (n.to_string(), v)));
    out
}

/// The f32 constants the shader shares with the host, by name.
fn shared_f32() -> Vec<(&'static str, f32)> {
    use tswm::backend::gpu::shader as gpu;
    use tswm::integrator::stepper as dp;
    use tswm::model::laws as fr;
    let f64s: &[(&str, f64)] = &[
        ("A21", dp::A21),
        ("A31", dp::A31),
        ("A32", dp::A32),
        ("A41", dp::A41),
        ("A42", dp::A42),
        ("A43", dp::A43),
        ("A51", dp::A51),
        ("A52", dp::A52),
        ("A53", dp::A53),
        ("A54", dp::A54),
        ("A61", dp::A61),
        ("A62", dp::A62),
        ("A63", dp::A63),
        ("A64", dp::A64),
        ("A65", dp::A65),
        ("A71", dp::A71),
        ("A73", dp::A73),
        ("A74", dp::A74),
        ("A75", dp::A75),
        ("A76", dp::A76),
        ("E1", dp::E1),
        ("E3", dp::E3),
        ("E4", dp::E4),
        ("E5", dp::E5),
        ("E6", dp::E6),
        ("E7", dp::E7),
        ("D1", dp::D1),
        ("D3", dp::D3),
        ("D4", dp::D4),
        ("D5", dp::D5),
        ("D6", dp::D6),
        ("D7", dp::D7),
        // The agma law's constants.
        ("FT_PER_MIN_PER_M_PER_S", fr::FT_PER_MIN_PER_M_PER_S),
        ("AGMA_LOW_A", fr::AGMA_LOW_A),
        ("AGMA_LOW_B", fr::AGMA_LOW_B),
        ("AGMA_LOW_E", fr::AGMA_LOW_E),
        ("AGMA_HIGH_A", fr::AGMA_HIGH_A),
        ("AGMA_HIGH_B", fr::AGMA_HIGH_B),
        ("AGMA_HIGH_E", fr::AGMA_HIGH_E),
        ("AGMA_HIGH_C", fr::AGMA_HIGH_C),
        ("PI", std::f64::consts::PI),
    ];
    let mut out: Vec<(&str, f32)> = f64s.iter().map(|&(n, v)| (n, v as f32)).collect();
    // Limits whose f32 value differs from the f64 path's: the host states
    // them in `backend::gpu::shader`.
    out.extend([
        ("STEP_UNDERFLOW", gpu::STEP_UNDERFLOW),
        ("ROOT_THETA_TOL", gpu::ROOT_THETA_TOL),
        ("P_ZERO_TOL", gpu::P_ZERO_TOL),
    ]);
    out
}

/// No name means two things: a shader constant whose name is also a
/// constant of `src/` is one of the shared constants the test above
/// compares, or is generated from the Rust (`shader::prelude`); the rest
/// are the shader's own.
#[test]
fn a_shader_constant_named_as_a_host_constant_is_compared() {
    let m = module();
    let rust = rust_const_names();
    let compared: Vec<String> = shared_u32()
        .into_iter()
        .map(|(n, _)| n)
        .chain(shared_f32().into_iter().map(|(n, _)| n.to_string()))
        .collect();
    let prelude = tswm::backend::gpu::shader::prelude();
    let generated: Vec<&str> = prelude
        .lines()
        .filter_map(|l| l.strip_prefix("const ")?.split(':').next())
        .collect();
    assert!(generated.contains(&"FRICTION_AGMA") && generated.contains(&"LAW_SLOTS"));
    let mut bad = Vec::new();
    for (_, c) in m.constants.iter() {
        let Some(name) = c.name.as_deref() else {
            continue;
        };
        if rust.contains(name) && !compared.iter().any(|n| n == name) && !generated.contains(&name)
        {
            bad.push(name.to_string());
        }
    }
    assert!(
        bad.is_empty(),
        "shader constants named as host constants, not compared: {bad:?}"
    );
    // And every shared one exists in the shader.
    for n in &compared {
        shader_const(&m, n);
    }
}

/// The names of `const NAME` items anywhere under `src/`.
fn rust_const_names() -> std::collections::BTreeSet<String> {
    fn walk(dir: &std::path::Path, out: &mut std::collections::BTreeSet<String>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|x| x == "rs") {
                let text = std::fs::read_to_string(&p).unwrap();
                for (i, _) in text.match_indices("const ") {
                    let name: String = text[i + 6..]
                        .chars()
                        .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                        .collect();
                    if !name.is_empty() && text[i + 6 + name.len()..].starts_with(':') {
                        out.insert(name);
                    }
                }
            }
        }
    }
    let mut out = Default::default();
    walk(&crate::common::root().join("src"), &mut out);
    out
}
