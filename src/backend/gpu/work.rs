//! How a device's work is cut: the lanes a chunk holds, the slots it runs
//! on and the parts in flight, from the adapter and its limits; and the
//! spans the host's work on a part is logged in.

use std::time::Instant;

use super::layout::GpuState;
use super::{is_hardware, WORKGROUP};

/// Most lanes one chunk may hold under `limits`: the state buffer must fit
/// one storage binding and the dispatch the workgroup-count limits.
pub fn max_chunk_lanes(limits: &wgpu::Limits) -> usize {
    let by_binding =
        limits.max_storage_buffer_binding_size / std::mem::size_of::<GpuState>() as u64;
    let by_buffer = limits.max_buffer_size / std::mem::size_of::<GpuState>() as u64;
    let per_dim = limits.max_compute_workgroups_per_dimension as u64;
    let by_dispatch = per_dim * per_dim * WORKGROUP as u64;
    by_binding
        .min(by_buffer)
        .min(by_dispatch)
        .min(u32::MAX as u64) as usize
}

/// Invocations a hardware GPU keeps resident, which wgpu does not report:
/// an H100's 132 SMs x 2,048.
pub const HW_RESIDENT: u64 = 132 * 2048;
/// Slots a core of a software adapter (lavapipe): 8,192 a core, measured
/// on `sweeps/heterogeneous.toml` against a slot a lane and against fewer
/// slots (which cost more in dispatch overhead than they saved;
/// docs/gpu.md, "Slots and refill").
pub const SW_SLOTS_PER_CORE: u64 = 8192;
/// Lanes a chunk holds per slot on a software adapter (65,536 on 2 cores).
pub const SW_LANES_PER_SLOT: u64 = 4;
/// Lanes a chunk holds per slot on a hardware GPU: one slot for each
/// resident invocation, each working through two lanes (about 0.5 M lanes
/// a chunk); not measured on one (none was lent).
pub const HW_LANES_PER_SLOT: u64 = 2;

/// How a device's work is cut: slots (invocations) a chunk runs on and
/// lanes a chunk holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WorkSize {
    /// Slots a chunk runs on.
    pub slots: u32,
    /// Lanes a chunk holds (a part, in [`Gpu::run_parts`](super::Gpu::run_parts): the runner's
    /// chunks hold `in_flight` of them).
    pub chunk_lanes: usize,
    /// Parts in flight at once ([`HW_IN_FLIGHT`], [`SW_IN_FLIGHT`]).
    pub in_flight: usize,
}

impl WorkSize {
    /// The work size for an adapter: on a hardware GPU one slot for each
    /// resident invocation ([`HW_RESIDENT`], as wgpu does not tell) and
    /// [`HW_LANES_PER_SLOT`] lanes a slot; on a software adapter
    /// [`SW_SLOTS_PER_CORE`] slots a core and [`SW_LANES_PER_SLOT`] lanes a
    /// slot; within the adapter's limits ([`max_chunk_lanes`]).
    pub fn of(info: &wgpu::AdapterInfo, limits: &wgpu::Limits) -> WorkSize {
        let (slots, per_slot, in_flight) = if is_hardware(info) {
            (HW_RESIDENT, HW_LANES_PER_SLOT, HW_IN_FLIGHT)
        } else {
            let cores = std::thread::available_parallelism().map_or(1, |c| c.get()) as u64;
            (SW_SLOTS_PER_CORE * cores, SW_LANES_PER_SLOT, SW_IN_FLIGHT)
        };
        let max = max_chunk_lanes(limits).max(1) as u64;
        let slots = slots.clamp(WORKGROUP as u64, max);
        WorkSize {
            slots: slots as u32,
            chunk_lanes: (per_slot * slots).min(max) as usize,
            in_flight,
        }
    }
}

/// Parts of a chunk in flight at once on a hardware GPU (see
/// [`Gpu::run_parts`](super::Gpu::run_parts)): while the host waits for one part or copies out
/// its states, the device runs the other's dispatches.
pub const HW_IN_FLIGHT: usize = 2;
/// The same on a software adapter: 1, because its "device" is the host's
/// own cores, so host work cannot hide behind it; measured on lavapipe
/// (2 cores), two in flight ran 100,000 paper-like lanes 5 % slower and
/// `sweeps/heterogeneous.toml` 3 % slower (`tswm bench --backend gpu`).
pub const SW_IN_FLIGHT: usize = 1;

/// What the host did for a part of a chunk, in a [`Span`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Its buffers made and its lanes written.
    Upload,
    /// A round of its dispatches, from submission to the host seeing it done.
    Compute,
    /// Its states copied to a read-back buffer and out to the host.
    ReadBack,
}

/// One phase of one part, with its start and end on the host's clock.
#[derive(Clone, Copy, Debug)]
pub struct Span {
    /// The part's index.
    pub part: usize,
    /// What was done.
    pub phase: Phase,
    /// When it began.
    pub start: Instant,
    /// When it ended.
    pub end: Instant,
}

impl Span {
    pub(super) fn new(part: usize, phase: Phase, start: Instant) -> Span {
        Span {
            part,
            phase,
            start,
            end: Instant::now(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::backend::gpu::max_chunk_lanes;

    fn adapter(device_type: wgpu::DeviceType) -> wgpu::AdapterInfo {
        wgpu::AdapterInfo {
            name: "test".into(),
            vendor: 0,
            device: 0,
            device_type,
            device_pci_bus_id: String::new(),
            driver: String::new(),
            driver_info: String::new(),
            backend: wgpu::Backend::Vulkan,
            subgroup_min_size: 32,
            subgroup_max_size: 32,
            transient_saves_memory: None,
            limit_bucket: None,
        }
    }

    /// A hardware GPU keeps two parts of a chunk in flight, each a slot for
    /// every resident invocation times HW_LANES_PER_SLOT lanes; a software
    /// adapter one; both within the binding limit.
    #[test]
    fn work_size_follows_the_adapter_and_its_limits() {
        let limits = wgpu::Limits::default();
        let hw = WorkSize::of(&adapter(wgpu::DeviceType::DiscreteGpu), &limits);
        assert_eq!(hw.in_flight, 2);
        assert_eq!(
            hw.slots as u64,
            HW_RESIDENT.min(max_chunk_lanes(&limits) as u64)
        );
        assert!(hw.chunk_lanes <= max_chunk_lanes(&limits));
        let sw = WorkSize::of(&adapter(wgpu::DeviceType::Cpu), &limits);
        assert_eq!(sw.in_flight, 1);
        assert!(sw.chunk_lanes <= max_chunk_lanes(&limits));
        // A binding limit of 1,000 states caps both.
        let small = wgpu::Limits {
            max_storage_buffer_binding_size: 1000 * std::mem::size_of::<GpuState>() as u64,
            ..limits
        };
        let capped = WorkSize::of(&adapter(wgpu::DeviceType::DiscreteGpu), &small);
        assert_eq!(capped.chunk_lanes, 1000);
    }
}
