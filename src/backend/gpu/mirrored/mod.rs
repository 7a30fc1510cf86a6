//! Differential tests of the shader against the Rust it mirrors: each
//! function the shader shares with the CPU path (`shader::MIRRORED` and
//! the model's kernel) is run by a small compute entry point beside the
//! shader's own, on a grid of inputs, and its values held to the Rust
//! function's to f32's bound. This file is the harness: an adapter's
//! device, the shader joined with a test's entry point, and the buffers
//! a case reads (lanes, words, numbers) and writes (numbers). Without an
//! adapter a test says why it is skipped, unless TSWM_REQUIRE_GPU=1 (as
//! in CI), where it fails.

/// The buffers the f64 state tests' entry points read (lanes, input
/// states, cases) and write (the state after each case and the numbers
/// it returns), as WGSL: `state::ENTRY` and `attempt::ATTEMPT` start
/// with it.
macro_rules! state_bindings {
    () => {
        r#"
@group(1) @binding(0) var<storage, read> s_lanes: array<Lane>;
@group(1) @binding(1) var<storage, read> s_states: array<State>;
@group(1) @binding(2) var<storage, read> s_cases: array<vec4<u32>>;
struct StateOut { st: State, out: array<f64, 4> }
@group(1) @binding(3) var<storage, read_write> s_res: array<StateOut>;
"#
    };
}

mod attempt;
mod integrator;
mod model;
mod state;

/// Mirrored functions reached through another that the tests call, and
/// that caller: compared by what the caller computes at every case that
/// takes them (a crossing of the split, the equation of motion's parts,
/// and the parts of a step attempt, whose cases include rejections,
/// acceptances, events and lanes that finish: `attempt`).
const THROUGH: &[(&str, &str)] = &[
    ("split_crossing", "split"),
    ("split_error", "split"),
    ("agrees", "split"),
    ("split_against", "split"),
    ("motion_parts", "motion"),
    ("try_step", "attempt"),
    ("earliest_event", "attempt"),
    ("step_flow", "attempt"),
    ("finish_step", "attempt"),
    ("add_flow", "attempt"),
    ("step_to_event", "attempt"),
    ("add_step", "attempt"),
    ("add_split", "attempt"),
    ("caps", "attempt"),
    ("capped", "attempt"),
    ("powers", "rates"),
    ("parts", "rates"),
    ("above_branch", "branch_of"),
    ("branch_edges", "event_value"),
    ("branch_value", "event_value"),
    ("crossed_edge", "locate_root"),
    ("left_upwards", "attempt"),
];

/// Mirrored functions not yet compared by what they compute, and why:
/// none.
const NOT_YET: &[&str] = &[];

/// Every function the shader mirrors (`shader::MIRRORED` and the
/// kernel's formulas) is called by a test's entry point, reached through
/// one (`THROUGH`), or listed as not yet compared (`NOT_YET`), and no
/// function is both: a new mirrored function needs a comparison or a
/// line saying why it has none.
#[test]
fn every_mirrored_function_is_compared_or_said_not_to_be() {
    let called = |f: &str| {
        [
            model::ENTRY,
            integrator::ENTRY,
            state::ENTRY,
            attempt::ATTEMPT,
        ]
        .iter()
        .any(|e| e.contains(&format!("{f}(")))
    };
    let all = super::shader::MIRRORED
        .iter()
        .chain(crate::model::kernel::KERNEL.iter());
    let mut missing = Vec::new();
    for f in all {
        let through = THROUGH.iter().any(|(g, by)| g == f && called(by));
        if (called(f) || through) == NOT_YET.contains(f) {
            missing.push(*f);
        }
    }
    assert!(
        missing.is_empty(),
        "compared and listed as not, or neither: {missing:?}"
    );
    // The state functions' test names every one it compares.
    for f in state::FUNCTIONS {
        assert!(super::shader::MIRRORED.contains(&f), "{f}");
    }
}

use wgpu::util::DeviceExt;

use super::layout::{GpuGlobals, GpuLane};
use super::SHADER;
use crate::integrator::Settings;
use crate::model::{FrictionTable, Lane};

/// The buffers every test entry point reads and writes (group 1; group 0
/// binding 0 is the shader's own globals, `g`, which some functions read).
const BINDINGS: &str = r#"
@group(1) @binding(0) var<storage, read> d_lanes: array<Lane>;
@group(1) @binding(1) var<storage, read> d_cases: array<vec4<u32>>;
@group(1) @binding(2) var<storage, read> d_args: array<f32>;
@group(1) @binding(3) var<storage, read_write> d_out: array<f32>;
"#;

/// What a test runs: its entry point `name` (WGSL after [`BINDINGS`]),
/// the lanes, the friction tables in the globals, each case's words
/// (`d_cases`) and `args` numbers a case (`d_args`), and `outs` values a
/// case written to `d_out`.
pub(super) struct Run<'a> {
    pub entry: &'a str,
    pub name: &'a str,
    pub lanes: &'a [Lane],
    pub tables: &'a [FrictionTable],
    pub cases: &'a [[u32; 4]],
    pub args: &'a [f32],
    pub outs: usize,
}

/// The values `run` writes, `outs` a case; None when there is no adapter
/// (the test says it is skipped).
pub(super) fn values(run: &Run) -> Option<Vec<f32>> {
    match device() {
        Ok((dev, queue)) => Some(dispatch(&dev, &queue, run)),
        Err(e) => {
            assert!(
                std::env::var("TSWM_REQUIRE_GPU").as_deref() != Ok("1"),
                "{}: TSWM_REQUIRE_GPU=1 but {e}",
                run.name
            );
            use std::io::Write;
            let _ = writeln!(std::io::stderr(), "skipped {}: {e}", run.name);
            None
        }
    }
}

fn device() -> Result<(wgpu::Device, wgpu::Queue), String> {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    desc.backends = wgpu::Backends::PRIMARY;
    let inst = wgpu::Instance::new(desc);
    let a = pollster::block_on(inst.enumerate_adapters(wgpu::Backends::PRIMARY))
        .into_iter()
        .next()
        .ok_or("there is no GPU adapter")?;
    pollster::block_on(a.request_device(&wgpu::DeviceDescriptor {
        label: Some("mirrored"),
        required_limits: wgpu::Limits::downlevel_defaults(),
        ..Default::default()
    }))
    .map_err(|e| e.to_string())
}

fn layout_entry(binding: u32, ty: wgpu::BufferBindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// The shader joined with the test's entry point, compiled, and the
/// layouts of its two bind groups.
fn pipeline(
    dev: &wgpu::Device,
    run: &Run,
) -> (
    wgpu::ComputePipeline,
    wgpu::BindGroupLayout,
    wgpu::BindGroupLayout,
) {
    use wgpu::BufferBindingType::{Storage, Uniform};
    let g0 = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: None,
        entries: &[layout_entry(0, Uniform)],
    });
    let ro = Storage { read_only: true };
    let g1 = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: None,
        entries: &[
            layout_entry(0, ro),
            layout_entry(1, ro),
            layout_entry(2, ro),
            layout_entry(3, Storage { read_only: false }),
        ],
    });
    let layout = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: None,
        bind_group_layouts: &[Some(&g0), Some(&g1)],
        immediate_size: 0,
    });
    let scope = dev.push_error_scope(wgpu::ErrorFilter::Validation);
    let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(run.name),
        source: wgpu::ShaderSource::Wgsl(
            format!("{}{BINDINGS}{}", SHADER.as_str(), run.entry).into(),
        ),
    });
    let pipe = dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(run.name),
        layout: Some(&layout),
        module: &module,
        entry_point: Some(run.name),
        compilation_options: Default::default(),
        cache: None,
    });
    if let Some(e) = pollster::block_on(scope.pop()) {
        panic!(
            "{}: the shader with its entry point does not compile: {e}",
            run.name
        );
    }
    (pipe, g0, g1)
}

fn dispatch(dev: &wgpu::Device, queue: &wgpu::Queue, run: &Run) -> Vec<f32> {
    let (pipe, g0, g1) = pipeline(dev, run);
    let init = |bytes: &[u8], usage| {
        dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: None,
            contents: bytes,
            usage,
        })
    };
    let storage = wgpu::BufferUsages::STORAGE;
    let globals = GpuGlobals::new(&Settings::default(), run.tables);
    // A binding may not be empty: a test passes a lane at least, and a
    // number stands in for none.
    assert!(!run.lanes.is_empty(), "{}: no lane", run.name);
    let lanes: Vec<GpuLane> = run.lanes.iter().map(GpuLane::from).collect();
    let args: Vec<f32> = if run.args.is_empty() {
        vec![0.0]
    } else {
        run.args.to_vec()
    };
    let bufs = [
        init(bytemuck::bytes_of(&globals), wgpu::BufferUsages::UNIFORM),
        init(bytemuck::cast_slice(&lanes), storage),
        init(bytemuck::cast_slice(run.cases), storage),
        init(bytemuck::cast_slice(&args), storage),
    ];
    let size = (run.cases.len() * run.outs * 4) as u64;
    let out = dev.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size,
        usage: storage | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let read = dev.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let group = |layout: &wgpu::BindGroupLayout, bufs: &[&wgpu::Buffer]| {
        let entries: Vec<wgpu::BindGroupEntry> = (0u32..)
            .zip(bufs)
            .map(|(binding, b)| wgpu::BindGroupEntry {
                binding,
                resource: b.as_entire_binding(),
            })
            .collect();
        dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout,
            entries: &entries,
        })
    };
    let b0 = group(&g0, &[&bufs[0]]);
    let b1 = group(&g1, &[&bufs[1], &bufs[2], &bufs[3], &out]);
    let mut enc = dev.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipe);
        pass.set_bind_group(0, &b0, &[]);
        pass.set_bind_group(1, &b1, &[]);
        pass.dispatch_workgroups(run.cases.len().div_ceil(64) as u32, 1, 1);
    }
    enc.copy_buffer_to_buffer(&out, 0, &read, 0, size);
    queue.submit([enc.finish()]);
    read.slice(..).map_async(wgpu::MapMode::Read, |_| {});
    dev.poll(wgpu::PollType::wait_indefinitely())
        .expect("the GPU finished");
    let view = read.slice(..).get_mapped_range().expect("read back");
    bytemuck::cast_slice::<u8, f32>(&view).to_vec()
}

/// f32's bound on a value, relative to the scale of its terms.
pub(super) const BOUND: f64 = 2e-5;

/// The worst deviation of each value of a test, and its first cases
/// over [`BOUND`].
pub(super) struct Tally {
    worst: Vec<f64>,
    bad: Vec<String>,
}

impl Tally {
    pub(super) fn new(values: usize) -> Tally {
        Tally {
            worst: vec![0.0; values],
            bad: Vec::new(),
        }
    }

    /// Value `k` of a case: the shader's `g` against the Rust's `c`,
    /// relative to `scale`; a decision (`scale` 0) must be the same
    /// unless its quantity is `near` its threshold. Equal values count as
    /// equal, infinities included, and so does "never": +∞ in f64, 3e38 in
    /// the shader (which may assume there are no infinities). `case`
    /// describes the case for the message.
    pub(super) fn add(
        &mut self,
        k: usize,
        g: f64,
        c: f64,
        scale: f64,
        near: bool,
        case: impl FnOnce() -> String,
    ) {
        let dev = if g == c || (c.is_infinite() && g * c.signum() >= 1e38) {
            0.0
        } else if scale == 0.0 {
            if near {
                0.0
            } else {
                f64::INFINITY
            }
        } else {
            (g - c).abs() / scale
        };
        self.worst[k] = self.worst[k].max(dev);
        if !(dev <= BOUND) && self.bad.len() < 20 {
            self.bad.push(format!(
                "{}: shader {g:e}, Rust {c:e} (scale {scale:e})",
                case()
            ));
        }
    }

    /// Prints each value's worst deviation (seen with --nocapture) and
    /// fails with the first cases that differ.
    pub(super) fn report(self, test: &str, names: &[&str]) {
        use std::io::Write;
        for (n, w) in names.iter().zip(&self.worst) {
            let _ = writeln!(std::io::stderr(), "{test} {n}: worst {w:.2e} of its scale");
        }
        assert!(
            self.bad.is_empty(),
            "{test}: cases differ:\n{}",
            self.bad.join("\n")
        );
    }
}
