//! `tswm devices`: the CPU path's threads and vector width, and the GPU
//! adapters wgpu finds, their limits and the work sizes a run gets from
//! them.

use crate::error::Result;

/// Runs `tswm devices`.
pub fn run() -> Result<()> {
    let w = crate::integrator::width::width().map_err(crate::error::Error::Usage)?;
    sayln!(
        "cpu: {} threads, each stepping {} lanes in lockstep ({}; {} forces a width, see the guide)",
        std::thread::available_parallelism().map_or(1, |n| n.get()),
        w.lanes,
        w.name(),
        crate::integrator::width::WIDTH_VAR,
    );
    let list = crate::backend::gpu::adapters();
    if list.is_empty() {
        sayln!("no GPU adapters found (install a Vulkan driver, e.g. mesa-vulkan-drivers)");
    }
    for a in list {
        let l = &a.limits;
        let w = crate::backend::gpu::WorkSize::of(&a.info, l);
        sayln!(
            "{} ({:?}, {:?}, driver {} {})\n  max_storage_buffer_binding_size {} B, max_buffer_size {} B, \
             max_compute_workgroups_per_dimension {}, max_compute_invocations_per_workgroup {}\n  \
             chunks: {} lanes, cut into parts of {} lanes, {} in flight at once, each on {} slots \
             ({}; at most {} lanes a part by the limits)",
            a.info.name,
            a.info.device_type,
            a.info.backend,
            a.info.driver,
            a.info.driver_info,
            l.max_storage_buffer_binding_size,
            l.max_buffer_size,
            l.max_compute_workgroups_per_dimension,
            l.max_compute_invocations_per_workgroup,
            w.in_flight * w.chunk_lanes,
            w.chunk_lanes,
            w.in_flight,
            w.slots,
            if crate::backend::gpu::is_hardware(&a.info) {
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
            crate::backend::gpu::max_chunk_lanes(l),
        );
    }
    Ok(())
}
