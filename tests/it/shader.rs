//! The WGSL shader without a GPU: naga validates it, and the structs it
//! shares with the host have the same size and member offsets as their
//! `#[repr(C)]` mirrors in `src/backend/gpu/layout.rs`.

use std::mem::{offset_of, size_of};

use naga::valid::{Capabilities, ValidationFlags, Validator};
use tswm::backend::gpu::layout::{
    GpuControl, GpuGlobals, GpuGlobals64, GpuLane, GpuLane64, GpuState, GpuState64,
};
use tswm::backend::gpu::{SHADER, SHADER_F64};

fn module() -> naga::Module {
    parsed(&SHADER)
}

fn parsed(src: &str) -> naga::Module {
    naga::front::wgsl::parse_str(src).unwrap_or_else(|e| panic!("{}", e.emit_to_string(src)))
}

#[test]
fn shader_parses_and_validates() {
    let m = module();
    Validator::new(ValidationFlags::all(), Capabilities::empty())
        .validate(&m)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(&SHADER)));
    assert!(m.entry_points.iter().any(|e| e.name == "main"));
}

/// The f64 shader is the same files on the f64 prelude: it validates
/// with 64-bit floats (and only with them), and none of its functions
/// calls a transcendental built-in, which SPIR-V does not define for f64.
#[test]
fn the_f64_shader_validates_with_float64_only() {
    let m = parsed(&SHADER_F64);
    Validator::new(ValidationFlags::all(), Capabilities::FLOAT64)
        .validate(&m)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(&SHADER_F64)));
    assert!(
        Validator::new(ValidationFlags::all(), Capabilities::empty())
            .validate(&m)
            .is_err()
    );
    use naga::MathFunction as F;
    for (_, f) in m.functions.iter() {
        for (_, e) in f.expressions.iter() {
            if let naga::Expression::Math { fun, .. } = e {
                assert!(
                    !matches!(
                        fun,
                        F::Exp | F::Log | F::Pow | F::Tan | F::Atan | F::Tanh | F::Sin | F::Cos
                    ),
                    "{:?} calls {fun:?}",
                    f.name
                );
            }
        }
    }
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

macro_rules! host_layouts {
    ($lane:ty, $state:ty, $globals:ty) => {
        [
            (
                "Lane",
                rust_layout!($lane; m1, m2, tan_g, sin_g, cos_g, inv_cos_g, f2, v_sync, sigma_k, f_crit, f1,
                    motor_off, law, mu_s, x1_0, v1_0, t_end, t_max, inv_cos_an, branch_speed, motor, friction,
                    table, steep),
            ),
            (
                "State",
                rust_layout!($state; t_hi, t_lo, h, t_first_switch, flow, flow_c, y, yc, k1, lag, phase,
                    local, pad_r, side, dir, flags, status, switches, reversals, sticks, steps, events, branch, pad),
            ),
            (
                "Globals",
                rust_layout!($globals; n_lanes, budget, max_steps, max_events, n_tables, row_lanes, n_slots,
                    pad0, tol, tol_traj, h_initial, pad_r, table_n, table_vs, table_mu),
            ),
            ("Control", rust_layout!(GpuControl; n_active, next_lane)),
        ]
    };
}

/// The host's structs have the shader's sizes and member offsets, in f32
/// and in f64 (no hidden padding on either side: bytemuck's `Pod` would
/// refuse it on the host).
#[test]
fn host_structs_match_the_shader() {
    let m = module();
    for (name, host) in host_layouts!(GpuLane, GpuState, GpuGlobals) {
        assert_eq!(wgsl_layout(&m, name), host, "{name} in f32");
    }
    let m = parsed(&SHADER_F64);
    for (name, host) in host_layouts!(GpuLane64, GpuState64, GpuGlobals64) {
        assert_eq!(wgsl_layout(&m, name), host, "{name} in f64");
    }
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
    let names = generated_constants(&m, &prelude);
    for (n, v) in TABLEAU {
        assert!(
            matches!(shader_const(&m, n), naga::Literal::F32(x) if x == *v as f32),
            "tableau {n}"
        );
    }
    // The f64 shader's: the same names, the Rust values themselves.
    let m64 = parsed(&SHADER_F64);
    let prelude64 = shader::prelude_of(ShaderReal::F64);
    assert_eq!(generated_constants(&m64, &prelude64), names);
    for (n, v) in TABLEAU {
        assert!(
            matches!(shader_const(&m64, n), naga::Literal::F64(x) if x == *v),
            "tableau {n} in f64"
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
    assert_eq!(
        u32_const(&m, "RESULTS"),
        tswm::integrator::accuracy::RESULTS as u32
    );
    // The error budget is kept in f64 only.
    assert!(matches!(
        shader_const(&m, "KEEP_BUDGET"),
        naga::Literal::Bool(false)
    ));
    assert!(matches!(
        shader_const(&m64, "KEEP_BUDGET"),
        naga::Literal::Bool(true)
    ));
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

use tswm::backend::gpu::{shader, ShaderReal};
use tswm::integrator::Status;

/// The names of the constants of a generated `prelude`, each checked
/// against module `m`: a u32 or a `real` (f32 or f64, by its suffix)
/// whose printed digits read back as naga's value.
fn generated_constants(m: &naga::Module, prelude: &str) -> Vec<String> {
    let mut names = Vec::new();
    for line in prelude.lines().filter_map(|l| l.strip_prefix("const ")) {
        let (name, rest) = line.split_once(": ").unwrap();
        let (ty, value) = rest.split_once(" = ").unwrap();
        let value = value.trim_end_matches(';');
        match (ty, shader_const(m, name)) {
            ("u32", naga::Literal::U32(v)) => {
                assert_eq!(v.to_string() + "u", value, "`const {name}`")
            }
            ("real", naga::Literal::F64(v)) => {
                let printed: f64 = value.strip_suffix("lf").unwrap().parse().unwrap();
                assert_eq!(v.to_bits(), printed.to_bits(), "`const {name}`");
            }
            ("real", naga::Literal::F32(v)) => {
                let printed: f32 = value.strip_suffix('f').unwrap().parse().unwrap();
                assert_eq!(v.to_bits(), printed.to_bits(), "`const {name}`");
            }
            ("bool", naga::Literal::Bool(v)) => assert_eq!(v.to_string(), value, "`const {name}`"),
            (ty, l) => panic!("`const {name}: {ty}` reads as {l:?}"),
        }
        names.push(name.to_string());
    }
    names
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
