//! The f64 functions of the shader (`shaders/f64/math.wgsl`: ln, exp,
//! pow and tan from arithmetic, because the GPU's own are undefined for
//! f64) against the Rust ones the f64 CPU path calls, each within 4 ulp
//! over 10^6 arguments of its used range, run on an adapter with 64-bit
//! floats in shaders (lavapipe has them). Without one the test says why
//! it is skipped, unless TSWM_REQUIRE_GPU=1 (as in CI).

use tswm::input::sampling::Uniforms;
use tswm::model::vmath;

use crate::common::{quiet_mesa, skipped};

/// Arguments a function.
const N: usize = 1_000_000;

/// The entry point: lane i reads its 5 arguments (ln's x, exp's x, pow's
/// x and y, tan's x) and writes the 4 values.
const ENTRY: &str = r#"
@group(0) @binding(0) var<storage, read> args: array<f64>;
@group(0) @binding(1) var<storage, read_write> out: array<f64>;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x + id.y * 65535u * 64u;
    if (i >= arrayLength(&out) / 4u) {
        return;
    }
    out[4u * i] = ln_64(args[5u * i]);
    out[4u * i + 1u] = exp_64(args[5u * i + 1u]);
    out[4u * i + 2u] = pow_64(args[5u * i + 2u], args[5u * i + 3u]);
    out[4u * i + 3u] = tan_64(args[5u * i + 4u]);
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

/// The shader's 4 values of each lane of `args` (5 a lane).
fn run(dev: &wgpu::Device, queue: &wgpu::Queue, args: &[f64]) -> Vec<f64> {
    use wgpu::util::DeviceExt;
    let n = args.len() / 5;
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
    let size = (n * 4 * 8) as u64;
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
fn the_shaders_f64_functions_are_within_4_ulp_of_the_cpu_paths() {
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
    let mut args = Vec::with_capacity(5 * N);
    for i in 0..N {
        // ln: every exponent half the time, else the sliding speeds the
        // laws raise to a power (0.1 µm/s to 10 km/s).
        args.push(if i % 2 == 0 {
            10f64.powf(-300.0 + 600.0 * u.next())
        } else {
            10f64.powf(-12.0 + 16.0 * u.next())
        });
        // exp: its whole range.
        args.push(-745.0 + 1454.0 * u.next());
        // pow: a sliding speed to an exponent in (0, 5] (the laws' b, e, δ).
        args.push(10f64.powf(-12.0 + 16.0 * u.next()));
        args.push(5.0 * (1.0 - u.next()));
        // tan: friction angles and their sums with a lead angle, |x| < 1.55.
        args.push(-1.55 + 3.1 * u.next());
    }
    let got = run(&dev, &queue, &args);
    let mut worst = [(0u64, 0.0f64); 4];
    for i in 0..N {
        let a = &args[5 * i..5 * i + 5];
        let want = [
            vmath::ln(a[0]),
            vmath::exp(a[1]),
            vmath::pow(a[2], a[3]),
            a[4].tan(),
        ];
        for f in 0..4 {
            let d = ulps(got[4 * i + f], want[f]);
            if d > worst[f].0 {
                worst[f] = (d, a[if f == 3 { 4 } else { f.min(2) }]);
            }
        }
    }
    // Every function's figure first (seen with --nocapture), then the bound.
    let names = ["ln", "exp", "pow", "tan"];
    for (f, name) in names.iter().enumerate() {
        use std::io::Write;
        let _ = writeln!(
            std::io::stderr(),
            "f64 shader {name}: worst {} ulp, at {:e}",
            worst[f].0,
            worst[f].1
        );
    }
    let over: Vec<String> = names
        .iter()
        .zip(&worst)
        .filter(|(_, w)| w.0 > 4)
        .map(|(name, w)| format!("{name}: {} ulp from the CPU path's at {:e}", w.0, w.1))
        .collect();
    assert!(over.is_empty(), "{over:?}");
    // The edges: ln at 0 and below, exp past its range, 0^y.
    let edges = [
        0.0, 710.0, 0.0, 2.0, 0.0, //
        -1.0, -746.0, 0.0, 0.0, 1.0, //
        5e-324, 709.7, 1.0, 0.612, -0.7,
    ];
    let got = run(&dev, &queue, &edges);
    assert_eq!(got[0], f64::NEG_INFINITY);
    assert_eq!(got[1], f64::INFINITY);
    assert_eq!(got[2], 0.0);
    assert!(got[4].is_nan());
    assert_eq!(got[5], 0.0);
    assert_eq!(got[6], 1.0);
    assert!(
        ulps(got[8], vmath::ln(5e-324)) <= 4,
        "ln of the least subnormal"
    );
    assert!(ulps(got[9], vmath::exp(709.7)) <= 4);
    assert!(ulps(got[11], (-0.7f64).tan()) <= 4);
}
