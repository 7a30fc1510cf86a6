//! The WGSL shader without a GPU: naga validates it, and the structs it
//! shares with the host have the same size and member offsets as their
//! `#[repr(C)]` mirrors in `src/gpu/layout.rs`.

use std::mem::{offset_of, size_of};

use naga::valid::{Capabilities, ValidationFlags, Validator};
use tswm::gpu::layout::{GpuGlobals, GpuLane, GpuState};

fn module() -> naga::Module {
    naga::front::wgsl::parse_str(tswm::gpu::SHADER)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(tswm::gpu::SHADER)))
}

#[test]
fn shader_parses_and_validates() {
    let m = module();
    Validator::new(ValidationFlags::all(), Capabilities::empty())
        .validate(&m)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(tswm::gpu::SHADER)));
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
        motor_off, friction, fric_a, fric_b, fric_c, mu, mu_s, x1_0, v1_0, t_end, pad0, pad1);
    assert_eq!(wgsl_layout(&m, "Lane"), lane);
    let state = rust_layout!(GpuState; t_hi, t_lo, h, t_first_switch, y, yc, k1, side, dir, flags, status, switches,
        reversals, sticks, steps, events, pad0, pad1, pad2, pad3);
    assert_eq!(wgsl_layout(&m, "State"), state);
    let globals = rust_layout!(GpuGlobals; n_lanes, budget, max_steps, max_events, tol, h_initial, table_n, row_lanes,
        table_vs, table_mu);
    assert_eq!(wgsl_layout(&m, "Globals"), globals);
}

/// Status codes written by the shader decode to the CPU path's statuses.
#[test]
fn status_codes_match_the_shader() {
    for st in tswm::integrator::Status::ALL {
        let name = match st {
            tswm::integrator::Status::Ok => "S_OK",
            tswm::integrator::Status::Inconsistent => "S_INCONSISTENT",
            tswm::integrator::Status::NonFinite => "S_NONFINITE",
            tswm::integrator::Status::MaxSteps => "S_MAX_STEPS",
            tswm::integrator::Status::MaxEvents => "S_MAX_EVENTS",
            tswm::integrator::Status::StepUnderflow => "S_STEP_UNDERFLOW",
        };
        let want = format!("const {name}: u32 = {}u;", st.code());
        assert!(tswm::gpu::SHADER.contains(&want), "shader lacks `{want}`");
    }
}
