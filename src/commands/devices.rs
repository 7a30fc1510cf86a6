//! `tswm devices`: the CPU path's threads and vector width, and the GPU
//! adapters wgpu finds, their limits and the work sizes a run gets from
//! them.

use crate::error::Result;

/// What a run can use: the CPU path and the GPU adapters.
#[derive(Clone, Debug)]
pub struct Devices {
    /// CPU threads.
    pub threads: usize,
    /// Lanes one thread steps together.
    pub lanes: usize,
    /// The CPU path's width, named ("avx512 x16").
    pub width: String,
    /// The GPU adapters, in wgpu's order.
    pub adapters: Vec<Adapter>,
}

/// One GPU adapter and the work a run gets from it.
#[derive(Clone, Debug)]
pub struct Adapter {
    /// Its name.
    pub name: String,
    /// Discrete, integrated, virtual GPU or CPU (software).
    pub device_type: String,
    /// The graphics API (Vulkan, Metal, DX12).
    pub api: String,
    /// Its driver and the driver's own version text.
    pub driver: String,
    /// Whether it is a hardware GPU (not a software rasteriser).
    pub hardware: bool,
    /// Whether its shaders have 64-bit floats (wgpu's `SHADER_F64`;
    /// Vulkan only): whether `--precision f64` runs on it.
    pub shader_f64: bool,
    /// The limits a run's work is sized by: largest storage buffer
    /// binding and buffer (bytes), workgroups a dimension, invocations a
    /// workgroup.
    pub limits: [u64; 4],
    /// Lanes a chunk, lanes a part, parts in flight, slots a part.
    pub work: [u64; 4],
    /// Most lanes a part by the limits.
    pub max_part_lanes: u64,
}

/// The CPU path's width and the GPU adapters of this machine.
pub fn list() -> Result<Devices> {
    let w = crate::integrator::width::width().map_err(crate::error::Error::Usage)?;
    let adapters = crate::backend::gpu::adapters()
        .into_iter()
        .map(|a| {
            let l = &a.limits;
            let w = crate::backend::gpu::WorkSize::of(&a.info, l);
            Adapter {
                name: a.info.name.clone(),
                device_type: format!("{:?}", a.info.device_type),
                api: format!("{:?}", a.info.backend),
                driver: format!("{} {}", a.info.driver, a.info.driver_info),
                hardware: crate::backend::gpu::is_hardware(&a.info),
                shader_f64: a.features.contains(wgpu::Features::SHADER_F64),
                limits: [
                    l.max_storage_buffer_binding_size,
                    l.max_buffer_size,
                    u64::from(l.max_compute_workgroups_per_dimension),
                    u64::from(l.max_compute_invocations_per_workgroup),
                ],
                work: [
                    (w.in_flight * w.chunk_lanes) as u64,
                    w.chunk_lanes as u64,
                    w.in_flight as u64,
                    u64::from(w.slots),
                ],
                max_part_lanes: crate::backend::gpu::max_chunk_lanes(l) as u64,
            }
        })
        .collect();
    Ok(Devices {
        threads: std::thread::available_parallelism().map_or(1, |n| n.get()),
        lanes: w.lanes,
        width: w.name(),
        adapters,
    })
}

/// Runs `tswm devices`.
pub fn run() -> Result<()> {
    let d = list()?;
    sayln!(
        "cpu: {} threads, each stepping {} lanes in lockstep ({}; {} forces a width, see the guide)",
        d.threads,
        d.lanes,
        d.width,
        crate::integrator::width::WIDTH_VAR,
    );
    if d.adapters.is_empty() {
        sayln!("no GPU adapters found (install a Vulkan driver, e.g. mesa-vulkan-drivers)");
    }
    for a in d.adapters {
        let [binding, buffer, groups, invocations] = a.limits;
        let [chunk, part, in_flight, slots] = a.work;
        sayln!(
            "{} ({}, {}, driver {})\n  max_storage_buffer_binding_size {binding} B, max_buffer_size {buffer} B, \
             max_compute_workgroups_per_dimension {groups}, max_compute_invocations_per_workgroup {invocations}\n  \
             chunks: {chunk} lanes, cut into parts of {part} lanes, {in_flight} in flight at once, each on {slots} slots \
             ({}; at most {} lanes a part by the limits)\n  \
             64-bit floats in shaders (SHADER_F64): {}",
            a.name,
            a.device_type,
            a.api,
            a.driver,
            if a.hardware {
                format!(
                    "hardware: a slot for each invocation an H100 keeps resident, {} lanes a slot",
                    crate::backend::gpu::HW_LANES_PER_SLOT
                )
            } else {
                format!(
                    "software: {} slots a core, {} lanes a slot",
                    crate::backend::gpu::SW_SLOTS_PER_CORE,
                    crate::backend::gpu::SW_LANES_PER_SLOT
                )
            },
            a.max_part_lanes,
            if a.shader_f64 {
                "yes (--precision f64 runs here)"
            } else {
                "no (--precision f64 is refused here; f32 runs)"
            },
        );
    }
    Ok(())
}
