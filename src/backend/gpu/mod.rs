//! The GPU path: the shader (`shaders/`, [`shader`]) on wgpu, one lane per
//! invocation.
//!
//! Getting a device ([`Gpu::new`]) is separate from running work on it
//! ([`Gpu::run`]), so tests and benchmarks share one device. A chunk of
//! lanes is uploaded once; its states stay on the GPU while dispatches of
//! at most `budget` step attempts per lane run until every lane is done, so
//! no single dispatch runs long enough to trip a driver watchdog.

mod backend;
pub mod cost;
mod dispatch;
pub mod layout;
#[cfg(test)]
mod mirrored;
pub mod real;
pub mod shader;
pub mod verify;
mod work;

pub use backend::GpuBackend;
pub use real::ShaderReal;
pub use shader::{SHADER, SHADER_F64};
pub use work::{
    max_chunk_lanes, Phase, Span, WorkSize, HW_IN_FLIGHT, HW_LANES_PER_SLOT, HW_RESIDENT,
    SW_IN_FLIGHT, SW_LANES_PER_SLOT, SW_SLOTS_PER_CORE,
};

use std::sync::{Arc, Mutex};
use std::time::Duration;

use crate::error::{Error, Result};

/// Invocations per workgroup (`@workgroup_size` in the shader).
pub const WORKGROUP: u32 = 64;

/// Step attempts per lane per dispatch. A paper-like lane needs about 40
/// f32 steps, so most finish in one dispatch; a dispatch stays well under a
/// second even on a software adapter at the default chunk size.
pub const BUDGET: u32 = 64;

/// Longest wait for one submission before the run is called hung.
const POLL_TIMEOUT: Duration = Duration::from_secs(120);

/// What `tswm devices` shows of an adapter.
#[derive(Clone, Debug)]
pub struct AdapterSummary {
    /// Name, type, backend, driver.
    pub info: wgpu::AdapterInfo,
    /// Its limits.
    pub limits: wgpu::Limits,
    /// Its features (`SHADER_F64`: 64-bit floats in shaders).
    pub features: wgpu::Features,
}

fn instance() -> wgpu::Instance {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    // Compute needs no GL; leaving it out also keeps EGL's probing quiet.
    desc.backends = wgpu::Backends::PRIMARY;
    wgpu::Instance::new(desc)
}

/// Rank for choosing the best adapter: discrete, integrated, virtual, then software.
fn rank(t: wgpu::DeviceType) -> u8 {
    match t {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Cpu => 3,
        wgpu::DeviceType::Other => 4,
    }
}

/// Whether an adapter is real hardware (not a software rasteriser).
pub fn is_hardware(info: &wgpu::AdapterInfo) -> bool {
    rank(info.device_type) <= 2
}

/// Every adapter wgpu finds, best first.
pub fn adapters() -> Vec<AdapterSummary> {
    let mut v: Vec<AdapterSummary> =
        pollster::block_on(instance().enumerate_adapters(wgpu::Backends::PRIMARY))
            .into_iter()
            .map(|a| AdapterSummary {
                info: a.get_info(),
                limits: a.limits(),
                features: a.features(),
            })
            .collect();
    v.sort_by_key(|a| rank(a.info.device_type));
    v
}

/// A device with the TSWM pipeline, ready to run chunks.
pub struct Gpu {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// The adapter it runs on.
    pub info: wgpu::AdapterInfo,
    /// The device's limits.
    pub limits: wgpu::Limits,
    /// The real type its pipeline computes in.
    pub real: ShaderReal,
    /// The adapter's features.
    pub features: wgpu::Features,
    pub(super) pipeline: wgpu::ComputePipeline,
    pub(super) lost: Arc<Mutex<Option<String>>>,
    /// Step attempts per lane per dispatch (default [`BUDGET`]).
    pub budget: u32,
    /// Invocations ("slots") that work through a chunk's lanes, each
    /// taking the next unstarted lane when its own finishes (default:
    /// [`Gpu::default_slots`]).
    pub slots: u32,
}

/// Refuses the f64 shader, in one line naming the adapter, on an adapter
/// whose `features` have no 64-bit floats in shaders.
pub fn refuse_f64(
    name: &str,
    kind: wgpu::DeviceType,
    api: wgpu::Backend,
    features: wgpu::Features,
) -> Result<()> {
    if features.contains(wgpu::Features::SHADER_F64) {
        return Ok(());
    }
    Err(Error::Usage(format!(
        "--precision f64: the adapter {name} ({kind:?}, {api:?}) has no 64-bit floats in \
         shaders (SHADER_F64); use --precision f32 or auto"
    )))
}

pub(super) fn gpu_err(chunk: u64, what: impl std::fmt::Display) -> Error {
    Error::Gpu(format!("chunk {chunk}: {what}"))
}

impl Gpu {
    /// Opens the best adapter (discrete, integrated, virtual, software)
    /// for the f32 shader; with `hardware_only`, software adapters do not
    /// count.
    pub fn new(hardware_only: bool) -> Result<Gpu> {
        Gpu::open(hardware_only, ShaderReal::F32)
    }

    /// Opens the best adapter for the shader in `real`: f64 is refused, in
    /// one line naming the adapter, when the adapter has no 64-bit floats
    /// in shaders (wgpu's `SHADER_F64`).
    pub fn open(hardware_only: bool, real: ShaderReal) -> Result<Gpu> {
        let inst = instance();
        let mut list = pollster::block_on(inst.enumerate_adapters(wgpu::Backends::PRIMARY));
        list.sort_by_key(|a| rank(a.get_info().device_type));
        let adapter = list
            .into_iter()
            .find(|a| !hardware_only || is_hardware(&a.get_info()))
            .ok_or_else(|| {
                Error::Gpu(if hardware_only {
                    "no hardware GPU adapter found".into()
                } else {
                    "no GPU adapter found (no Vulkan, Metal, DX12 or GL driver); install one \
                     (on Debian: apt-get install mesa-vulkan-drivers) or use --backend cpu"
                        .into()
                })
            })?;
        let info = adapter.get_info();
        let f64_feature = wgpu::Features::SHADER_F64;
        if real == ShaderReal::F64 {
            refuse_f64(
                &info.name,
                info.device_type,
                info.backend,
                adapter.features(),
            )?;
        }
        let alimits = adapter.limits();
        // Ask for the adapter's own storage limits: chunks are sized from them.
        let limits = wgpu::Limits {
            max_storage_buffer_binding_size: alimits.max_storage_buffer_binding_size,
            max_buffer_size: alimits.max_buffer_size,
            max_compute_workgroups_per_dimension: alimits.max_compute_workgroups_per_dimension,
            ..wgpu::Limits::downlevel_defaults()
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("tswm"),
            required_features: match real {
                ShaderReal::F32 => wgpu::Features::empty(),
                ShaderReal::F64 => f64_feature,
            },
            required_limits: limits.clone(),
            ..Default::default()
        }))
        .map_err(|e| Error::Gpu(format!("{}: cannot open the device: {e}", info.name)))?;
        let lost = Arc::new(Mutex::new(None));
        let l2 = lost.clone();
        device.set_device_lost_callback(move |reason, msg| {
            *l2.lock().unwrap() = Some(format!("device lost ({reason:?}): {msg}"));
        });
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("tswm shader"),
            source: wgpu::ShaderSource::Wgsl(
                match real {
                    ShaderReal::F32 => SHADER.as_str(),
                    ShaderReal::F64 => SHADER_F64.as_str(),
                }
                .into(),
            ),
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("tswm"),
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(Error::Gpu(format!(
                "{}: the shader does not compile: {e}",
                info.name
            )));
        }
        Ok(Gpu {
            device,
            queue,
            info,
            limits,
            real,
            features: adapter.features(),
            pipeline,
            lost,
            budget: BUDGET,
            slots: u32::MAX,
        }
        .with_default_slots())
    }

    fn with_default_slots(mut self) -> Gpu {
        self.slots = self.default_slots();
        self
    }

    /// Slots a chunk gets unless set: [`WorkSize::of`] this device.
    pub fn default_slots(&self) -> u32 {
        WorkSize::of(&self.info, &self.limits).slots
    }

    /// Whether the adapter has 64-bit floats in shaders (wgpu's
    /// `SHADER_F64`), which `--precision f64` needs.
    pub fn has_f64(&self) -> bool {
        self.features.contains(wgpu::Features::SHADER_F64)
    }

    /// Short description: "NAME (type, backend)".
    pub fn describe(&self) -> String {
        format!(
            "{} ({:?}, {:?})",
            self.info.name, self.info.device_type, self.info.backend
        )
    }

    /// Most lanes one chunk may hold on this device: see [`max_chunk_lanes`].
    pub fn max_chunk_lanes(&self) -> usize {
        max_chunk_lanes(&self.limits)
    }

    pub(super) fn check_lost(&self, chunk: u64) -> Result<()> {
        match self.lost.lock().unwrap().take() {
            Some(m) => Err(gpu_err(chunk, m)),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An adapter without 64-bit floats refuses f64 in one line that names
    /// it, as a usage error (exit 2); one with them does not.
    #[test]
    fn f64_is_refused_on_an_adapter_without_it() {
        let refuse = |features| {
            refuse_f64(
                "Example GPU 9000",
                wgpu::DeviceType::DiscreteGpu,
                wgpu::Backend::Metal,
                features,
            )
        };
        let e = refuse(wgpu::Features::empty()).unwrap_err();
        let line = e.to_string();
        assert!(!line.contains('\n'), "{line}");
        assert!(
            line.contains("Example GPU 9000 (DiscreteGpu, Metal)"),
            "{line}"
        );
        assert!(line.contains("--precision f32 or auto"), "{line}");
        assert_eq!(e.exit_code(), 2);
        assert!(refuse(wgpu::Features::SHADER_F64).is_ok());
    }
}
