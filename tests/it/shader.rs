//! The WGSL shader without a GPU: naga validates it, and the structs it
//! shares with the host have the same size and member offsets as their
//! `#[repr(C)]` mirrors in `src/backend/gpu/layout.rs`.

use std::mem::{offset_of, size_of};

use naga::valid::{Capabilities, ValidationFlags, Validator};
use tswm::backend::gpu::layout::{GpuControl, GpuGlobals, GpuLane, GpuState};

fn module() -> naga::Module {
    naga::front::wgsl::parse_str(tswm::backend::gpu::SHADER)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(tswm::backend::gpu::SHADER)))
}

#[test]
fn shader_parses_and_validates() {
    let m = module();
    Validator::new(ValidationFlags::all(), Capabilities::empty())
        .validate(&m)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(tswm::backend::gpu::SHADER)));
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
        motor_off, friction, fric_a, fric_b, fric_c, mu, mu_s, x1_0, v1_0, t_end, t_max, table, inv_cos_an, pad0);
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
/// status codes, event codes and the Dormand–Prince tableau.
#[test]
fn shared_constants_match_the_shader() {
    use tswm::backend::gpu::layout::flags;
    use tswm::integrator::events::EventFn;
    use tswm::integrator::stepper as dp;
    use tswm::integrator::Status;
    use tswm::model;
    let m = module();
    let codes: &[(&str, u32)] = &[
        ("MOTOR_KLOSS", model::MOTOR_KLOSS),
        ("MOTOR_CONSTANT", model::MOTOR_CONSTANT),
        ("FRICTION_PAPER", model::FRICTION_PAPER),
        ("FRICTION_COULOMB", model::FRICTION_COULOMB),
        ("FRICTION_TABLE", model::FRICTION_TABLE),
        ("FRICTION_AGMA", model::FRICTION_AGMA),
        ("F_STUCK", flags::STUCK),
        ("F_MOTOR_ON", flags::MOTOR_ON),
        ("F_DONE", flags::DONE),
        ("F_K1_VALID", flags::K1_VALID),
        ("F_STARTED", flags::STARTED),
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
        ("F_RUNNING_ON", flags::RUNNING_ON),
        ("F_SPEEDING", flags::SPEEDING),
        ("F_UPPER", flags::UPPER),
        ("EV_BRANCH", EventFn::Branch as u32),
        ("TABLE_VEC4S", (model::MAX_TABLE_POINTS / 4) as u32),
    ];
    for &(name, want) in codes {
        assert_eq!(u32_const(&m, name), want, "shader `const {name}`");
    }
    // Every status the host knows has its code in the shader, once.
    let mut seen: Vec<u32> = codes[11..17].iter().map(|c| c.1).collect();
    assert!(codes[11].0 == "S_OK" && codes[16].0 == "S_STEP_UNDERFLOW");
    seen.sort();
    assert_eq!(seen, Status::ALL.map(|s| s.code()));

    let tableau: &[(&str, f64)] = &[
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
    ];
    // The agma law's constants.
    use tswm::model::friction as fr;
    let agma: &[(&str, f64)] = &[
        ("FT_PER_MIN_PER_M_PER_S", fr::FT_PER_MIN_PER_M_PER_S),
        ("AGMA_LOW_A", fr::AGMA_LOW_A),
        ("AGMA_LOW_B", fr::AGMA_LOW_B),
        ("AGMA_LOW_E", fr::AGMA_LOW_E),
        ("AGMA_HIGH_A", fr::AGMA_HIGH_A),
        ("AGMA_HIGH_B", fr::AGMA_HIGH_B),
        ("AGMA_HIGH_E", fr::AGMA_HIGH_E),
        ("AGMA_HIGH_C", fr::AGMA_HIGH_C),
        ("AGMA_JUMP_M_S", fr::AGMA_JUMP_M_S),
    ];
    for &(name, want) in tableau.iter().chain(agma) {
        match shader_const(&m, name) {
            naga::Literal::F32(v) => assert_eq!(v, want as f32, "shader `const {name}`"),
            l => panic!("`const {name}` is not an f32: {l:?}"),
        }
    }
}
