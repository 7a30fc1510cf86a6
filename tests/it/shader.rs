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

/// The constants the shader shares with the host are generated from the
/// Rust declarations (`shader::prelude`), none kept by hand: each has the
/// value of its declaration as naga reads it (the f32 ones through their
/// printed digits), every status, event, flag and tableau coefficient is
/// there once, and no shader file declares a constant named as one of
/// `src/` (it would be a second, hand-kept copy).
#[test]
fn shared_constants_are_generated_from_the_rust() {
    use tswm::backend::gpu::layout::flags;
    use tswm::integrator::events::EventFn;
    use tswm::integrator::stepper::TABLEAU;
    let m = module();
    let prelude = tswm::backend::gpu::shader::prelude();
    let mut names = Vec::new();
    for line in prelude.lines().filter_map(|l| l.strip_prefix("const ")) {
        let (name, rest) = line.split_once(": ").unwrap();
        let (ty, value) = rest.split_once(" = ").unwrap();
        let value = value.trim_end_matches(';');
        match (ty, shader_const(&m, name)) {
            ("u32", naga::Literal::U32(v)) => {
                assert_eq!(v.to_string() + "u", value, "`const {name}`")
            }
            ("f32", naga::Literal::F32(v)) => {
                let printed: f32 = value.trim_end_matches('f').parse().unwrap();
                assert_eq!(v.to_bits(), printed.to_bits(), "`const {name}`");
            }
            (ty, l) => panic!("`const {name}: {ty}` reads as {l:?}"),
        }
        names.push(name.to_string());
    }
    for (n, v) in TABLEAU {
        assert!(
            matches!(shader_const(&m, n), naga::Literal::F32(x) if x == *v as f32),
            "tableau {n}"
        );
    }
    let mut statuses: Vec<u32> = Status::ALL
        .map(|st| u32_const(&m, &format!("S_{}", st.name().to_uppercase())))
        .to_vec();
    statuses.sort();
    assert_eq!(statuses, Status::ALL.map(|s| s.code()));
    for e in EventFn::ALL {
        assert_eq!(
            u32_const(&m, &format!("EV_{}", format!("{e:?}").to_uppercase())),
            e as u32
        );
    }
    for (n, v) in flags::ALL {
        assert_eq!(u32_const(&m, &format!("F_{n}")), *v, "flag {n}");
    }
    assert_eq!(
        u32_const(&m, "NY"),
        tswm::integrator::NY as u32,
        "the state's components"
    );
    // No hand-kept copy: a shader file's constant named as one of `src/`.
    let rust = rust_const_names();
    let files = tswm::backend::gpu::SHADER
        .strip_prefix(prelude.as_str())
        .unwrap()
        .to_string();
    let kept: Vec<&str> = files
        .lines()
        .filter_map(|l| l.strip_prefix("const ")?.split(':').next())
        .filter(|n| rust.contains(*n) || names.iter().any(|g| g == n))
        .collect();
    assert!(
        kept.is_empty(),
        "shader files declare constants the Rust declares (generate them): {kept:?}"
    );
}

use tswm::integrator::Status;

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
