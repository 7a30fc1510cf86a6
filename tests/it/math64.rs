//! The f64 functions of the shader (`shaders/f64/math.wgsl`: exp, pow
//! and tan from arithmetic, because the GPU's own are undefined for
//! f64) against Rust's std, each within 4 ulp
//! over 10^6 arguments of its used range, run on an adapter with 64-bit
//! floats in shaders (lavapipe has them). Without one the test says why
//! it is skipped, unless TSWM_REQUIRE_GPU=1 (as in CI).

use tswm::input::sampling::Uniforms;

use crate::common::{quiet_mesa, skipped};

/// Arguments a function.
const N: usize = 1_000_000;

/// The entry point: lane i reads its 4 arguments (exp's x, pow's x and y,
/// tan's x) and writes the 3 values.
const ENTRY: &str = r#"
@group(0) @binding(0) var<storage, read> args: array<f64>;
@group(0) @binding(1) var<storage, read_write> out: array<f64>;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x + id.y * 65535u * 64u;
    if (i >= arrayLength(&out) / 3u) {
        return;
    }
    out[3u * i] = exp_64(args[4u * i]);
    out[3u * i + 1u] = pow_64(args[4u * i + 1u], args[4u * i + 2u]);
    out[3u * i + 2u] = tan_64(args[4u * i + 3u]);
}
"#;

/// Distance in units in the last place (same sign assumed; 0 for equal).
fn ulps(a: f64, b: f64) -> u64 {
    if a == b || (a.is_nan() && b.is_nan()) {
        return 0;
    }
    (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs()
}

/// An adapter's device with SHADER_F64, or why there is none.
fn device() -> Result<(wgpu::Device, wgpu::Queue), String> {
    quiet_mesa();
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    desc.backends = wgpu::Backends::PRIMARY;
    let inst = wgpu::Instance::new(desc);
    let adapters = pollster::block_on(inst.enumerate_adapters(wgpu::Backends::PRIMARY));
    let a = adapters
        .into_iter()
        .find(|a| a.features().contains(wgpu::Features::SHADER_F64))
        .ok_or("no GPU adapter with 64-bit floats in shaders (SHADER_F64)")?;
    let limits = wgpu::Limits {
        max_storage_buffer_binding_size: a.limits().max_storage_buffer_binding_size,
        max_buffer_size: a.limits().max_buffer_size,
        ..wgpu::Limits::downlevel_defaults()
    };
    pollster::block_on(a.request_device(&wgpu::DeviceDescriptor {
        label: Some("math64"),
        required_features: wgpu::Features::SHADER_F64,
        required_limits: limits,
        ..Default::default()
    }))
    .map_err(|e| e.to_string())
}

/// The shader's 3 values of each lane of `args` (4 a lane).
fn run(dev: &wgpu::Device, queue: &wgpu::Queue, args: &[f64]) -> Vec<f64> {
    use wgpu::util::DeviceExt;
    let n = args.len() / 4;
    let src = format!("{}{ENTRY}", include_str!("../../shaders/f64/math.wgsl"));
    let scope = dev.push_error_scope(wgpu::ErrorFilter::Validation);
    let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("math64"),
        source: wgpu::ShaderSource::Wgsl(src.into()),
    });
    let pipe = dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("math64"),
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    if let Some(e) = pollster::block_on(scope.pop()) {
        panic!("shaders/f64/math.wgsl does not compile: {e}");
    }
    let input = dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::cast_slice(args),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let size = (n * 3 * 8) as u64;
    let output = dev.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let read = dev.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipe.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: input.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: output.as_entire_binding(),
            },
        ],
    });
    let mut enc = dev.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipe);
        pass.set_bind_group(0, &bind, &[]);
        let groups = n.div_ceil(64) as u32;
        pass.dispatch_workgroups(groups.min(65535), groups.div_ceil(65535), 1);
    }
    enc.copy_buffer_to_buffer(&output, 0, &read, 0, size);
    queue.submit([enc.finish()]);
    read.slice(..).map_async(wgpu::MapMode::Read, |_| {});
    dev.poll(wgpu::PollType::wait_indefinitely()).unwrap();
    let view = read
        .slice(..)
        .get_mapped_range()
        .expect("the read-back buffer mapped");
    bytemuck::cast_slice::<u8, f64>(&view).to_vec()
}

#[test]
fn the_shaders_f64_functions_are_within_4_ulp_of_std() {
    let (dev, queue) = match device() {
        Ok(d) => d,
        Err(e) => {
            assert!(
                std::env::var("TSWM_REQUIRE_GPU").as_deref() != Ok("1"),
                "TSWM_REQUIRE_GPU=1 but {e}"
            );
            return skipped("the f64 shader functions", &e);
        }
    };
    let mut u = Uniforms::new(64);
    let mut args = Vec::with_capacity(4 * N);
    for _ in 0..N {
        // exp: its whole range.
        args.push(-745.0 + 1454.0 * u.next());
        // pow: a sliding speed (0.1 µm/s to 10 km/s, log-uniform) to an
        // exponent in [-5, 5] (the laws' b, e and δ; the step control's -1/5).
        args.push(10f64.powf(-12.0 + 16.0 * u.next()));
        args.push(10.0 * u.next() - 5.0);
        // tan: friction angles and their sums with a lead angle, |x| < 1.55.
        args.push(-1.55 + 3.1 * u.next());
    }
    let got = run(&dev, &queue, &args);
    let mut worst = [(0u64, 0.0f64, 0.0f64); 3];
    for i in 0..N {
        let a = &args[4 * i..4 * i + 4];
        let want = [a[0].exp(), a[1].powf(a[2]), a[3].tan()];
        let at = [(a[0], 0.0), (a[1], a[2]), (a[3], 0.0)];
        for f in 0..3 {
            let d = ulps(got[3 * i + f], want[f]);
            if d > worst[f].0 {
                worst[f] = (d, at[f].0, at[f].1);
            }
        }
    }
    // Every function's figure first (seen with --nocapture), then the bound.
    let names = ["exp", "pow", "tan"];
    for (f, name) in names.iter().enumerate() {
        use std::io::Write;
        let _ = writeln!(
            std::io::stderr(),
            "f64 shader {name}: worst {} ulp, at {:e} ({:e})",
            worst[f].0,
            worst[f].1,
            worst[f].2
        );
    }
    let over: Vec<String> = names
        .iter()
        .zip(&worst)
        .filter(|(_, w)| w.0 > 4)
        .map(|(name, w)| format!("{name}: {} ulp from std's at {:e}", w.0, w.1))
        .collect();
    assert!(over.is_empty(), "{over:?}");
    // The edges: exp past its range, 0^y, x^0, a negative x, a subnormal x.
    let edges = [
        710.0, 0.0, 2.0, 0.0, //
        -746.0, 0.0, 0.0, 0.0, //
        709.7, -1.0, 0.5, -0.7, //
        0.0, 0.0, -0.2, 0.0, //
        0.0, 5e-324, 0.612, 0.0, //
        0.0, 1.0, 3.7, 0.0,
    ];
    let got = run(&dev, &queue, &edges);
    assert_eq!(got[0], f64::INFINITY);
    assert_eq!(got[1], 0.0);
    assert_eq!(got[3], 0.0);
    assert_eq!(got[4], 1.0);
    assert!(ulps(got[6], 709.7f64.exp()) <= 4);
    assert!(got[7].is_nan());
    assert!(ulps(got[8], (-0.7f64).tan()) <= 4);
    assert_eq!(got[10], f64::INFINITY);
    assert!(
        ulps(got[13], 5e-324f64.powf(0.612)) <= 4,
        "pow of the least subnormal"
    );
    assert_eq!(got[16], 1.0);
}
