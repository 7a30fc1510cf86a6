//! The GPU path: `shaders/tswm.wgsl` on wgpu, one lane per invocation.
//!
//! Getting a device ([`Gpu::new`]) is separate from running work on it
//! ([`Gpu::run`]), so tests and benchmarks share one device. A chunk of
//! lanes is uploaded once; its states stay on the GPU while dispatches of
//! at most `budget` step attempts per lane run until every lane is done, so
//! no single dispatch runs long enough to trip a driver watchdog.

mod backend;
pub mod cost;
pub mod layout;
pub mod verify;

pub use backend::GpuBackend;

use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use wgpu::util::DeviceExt;

use crate::error::{Error, Result};
use layout::{GpuControl, GpuGlobals, GpuLane, GpuState};

/// The shader source.
pub const SHADER: &str = include_str!("../../../shaders/tswm.wgsl");

/// Invocations per workgroup (`@workgroup_size` in the shader).
pub const WORKGROUP: u32 = 64;

/// Step attempts per lane per dispatch. A paper-like lane needs about 40
/// f32 steps, so most finish in one dispatch; a dispatch stays well under a
/// second even on a software adapter at the default chunk size.
pub const BUDGET: u32 = 64;
/// Dispatches a round trip to the host (see [`Gpu::dispatches_per_sync`]).
pub const DISPATCHES_PER_SYNC: u32 = 1;

/// Longest wait for one submission before the run is called hung.
const POLL_TIMEOUT: Duration = Duration::from_secs(120);

/// What `tswm devices` shows of an adapter.
#[derive(Clone, Debug)]
pub struct AdapterSummary {
    /// Name, type, backend, driver.
    pub info: wgpu::AdapterInfo,
    /// Its limits.
    pub limits: wgpu::Limits,
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
    pipeline: wgpu::ComputePipeline,
    lost: Arc<Mutex<Option<String>>>,
    /// Step attempts per lane per dispatch (default [`BUDGET`]).
    pub budget: u32,
    /// Dispatches recorded before the host reads back whether any slot
    /// is still active (default [`DISPATCHES_PER_SYNC`]).
    pub dispatches_per_sync: u32,
    /// Invocations ("slots") that work through a chunk's lanes, each
    /// taking the next unstarted lane when its own finishes (default:
    /// [`Gpu::default_slots`]).
    pub slots: u32,
}

fn gpu_err(chunk: u64, what: impl std::fmt::Display) -> Error {
    Error::Gpu(format!("chunk {chunk}: {what}"))
}

impl Gpu {
    /// Opens the best adapter (discrete, integrated, virtual, software);
    /// with `hardware_only`, software adapters do not count.
    pub fn new(hardware_only: bool) -> Result<Gpu> {
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
            required_features: wgpu::Features::empty(),
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
            label: Some("tswm.wgsl"),
            source: wgpu::ShaderSource::Wgsl(SHADER.into()),
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
            pipeline,
            lost,
            budget: BUDGET,
            dispatches_per_sync: DISPATCHES_PER_SYNC,
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

    fn check_lost(&self, chunk: u64) -> Result<()> {
        match self.lost.lock().unwrap().take() {
            Some(m) => Err(gpu_err(chunk, m)),
            None => Ok(()),
        }
    }

    /// Integrates `lanes` to their ends; `out` gets one state per lane.
    /// `chunk` names the chunk in errors.
    pub fn run(
        &self,
        chunk: u64,
        lanes: &[GpuLane],
        globals: GpuGlobals,
        out: &mut Vec<GpuState>,
    ) -> Result<()> {
        let mut outs = [std::mem::take(out)];
        self.run_parts(chunk, &[lanes], globals, &mut outs, 1, None)?;
        let [o] = outs;
        *out = o;
        Ok(())
    }

    /// Integrates the parts of a chunk, up to `in_flight` of them on the
    /// device at once (at least 1), each on all slots: while the host waits for one
    /// part's count of active slots or copies out its states, the other's
    /// dispatches run, and a part that ends makes room for the next one's
    /// upload. `outs[i]` gets part i's states; `log`, when given, gets the
    /// span of every upload, round of dispatches and read-back.
    pub fn run_parts(
        &self,
        chunk: u64,
        parts: &[&[GpuLane]],
        globals: GpuGlobals,
        outs: &mut [Vec<GpuState>],
        in_flight: usize,
        mut log: Option<&mut Vec<Span>>,
    ) -> Result<()> {
        assert_eq!(parts.len(), outs.len());
        let in_flight = in_flight.max(1);
        let mut live: std::collections::VecDeque<Part> = Default::default();
        let mut next = 0;
        while next < parts.len() || !live.is_empty() {
            // Start parts while there is room.
            while next < parts.len() && live.len() < in_flight {
                outs[next].clear();
                if !parts[next].is_empty() {
                    let t0 = Instant::now();
                    let mut p = self.start_part(chunk, next, parts[next], globals)?;
                    if let Some(l) = log.as_deref_mut() {
                        l.push(Span::new(next, Phase::Upload, t0));
                    }
                    p.submitted = Instant::now();
                    p.last = Some(self.submit_round(&p));
                    live.push_back(p);
                }
                next += 1;
            }
            let Some(mut p) = live.pop_front() else {
                continue;
            };
            // Only this part's work: the other part's may still run.
            self.wait_for(chunk, p.last.take())?;
            if p.reading {
                let mut bytes = Vec::new();
                self.copy_mapped(chunk, &p.b.states_read, &mut bytes)?;
                outs[p.index].extend_from_slice(bytemuck::cast_slice(&bytes));
                if let Some(l) = log.as_deref_mut() {
                    l.push(Span::new(p.index, Phase::ReadBack, p.submitted));
                }
                continue;
            }
            let mut bytes = Vec::new();
            self.copy_mapped(chunk, &p.b.active_read, &mut bytes)?;
            if let Some(l) = log.as_deref_mut() {
                l.push(Span::new(p.index, Phase::Compute, p.submitted));
            }
            p.rounds += 1;
            let active = u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]);
            p.submitted = Instant::now();
            if active == 0 || p.rounds >= p.max_rounds {
                let mut enc = self.device.create_command_encoder(&Default::default());
                enc.copy_buffer_to_buffer(&p.b.states, 0, &p.b.states_read, 0, p.b.states.size());
                let idx = self.queue.submit([enc.finish()]);
                p.b.states_read
                    .slice(..)
                    .map_async(wgpu::MapMode::Read, |_| {});
                p.last = Some(idx);
                p.reading = true;
            } else {
                p.last = Some(self.submit_round(&p));
            }
            live.push_back(p);
        }
        Ok(())
    }

    /// Uploads a part and sizes its dispatches.
    fn start_part(
        &self,
        chunk: u64,
        index: usize,
        lanes: &[GpuLane],
        mut globals: GpuGlobals,
    ) -> Result<Part> {
        let n = lanes.len() as u32;
        let slots = n.min(self.slots.max(1));
        let groups = slots.div_ceil(WORKGROUP);
        let gx = groups.min(self.limits.max_compute_workgroups_per_dimension);
        let gy = groups.div_ceil(gx);
        globals.n_lanes = n;
        globals.n_slots = slots;
        globals.budget = self.budget;
        globals.row_lanes = gx * WORKGROUP;
        let b = self.chunk_buffers(chunk, lanes, slots, &globals)?;
        // Enough rounds for every lane of the busiest slot to take
        // max_steps accepted steps plus as many rejections.
        let per_lane = (2 * globals.max_steps as u64).div_ceil(self.budget as u64) + 2;
        let max_dispatches = per_lane * (n as u64).div_ceil(slots as u64);
        let per_sync = self.dispatches_per_sync.max(1) as u64;
        Ok(Part {
            index,
            b,
            gx,
            gy,
            rounds: 0,
            max_rounds: max_dispatches.div_ceil(per_sync),
            reading: false,
            last: None,
            submitted: Instant::now(),
        })
    }

    /// Submits a part's next round: several dispatches (slots refill at
    /// every one), then a copy of its count of active slots, mapped for
    /// reading when the round is done.
    fn submit_round(&self, p: &Part) -> wgpu::SubmissionIndex {
        let mut enc = self.device.create_command_encoder(&Default::default());
        for _ in 0..self.dispatches_per_sync.max(1) {
            // Only the count of active slots starts again each dispatch;
            // the next-lane counter carries on.
            enc.clear_buffer(&p.b.active, 0, Some(4));
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("advance"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &p.b.bind, &[]);
            pass.dispatch_workgroups(p.gx, p.gy, 1);
        }
        enc.copy_buffer_to_buffer(&p.b.active, 0, &p.b.active_read, 0, 4);
        let idx = self.queue.submit([enc.finish()]);
        p.b.active_read
            .slice(..)
            .map_async(wgpu::MapMode::Read, |_| {});
        idx
    }

    /// Waits for one submission (all, when `None`).
    fn wait_for(&self, chunk: u64, idx: Option<wgpu::SubmissionIndex>) -> Result<()> {
        self.device
            .poll(wgpu::PollType::Wait {
                submission_index: idx,
                timeout: Some(POLL_TIMEOUT),
            })
            .map_err(|e| gpu_err(chunk, format!("the GPU did not finish ({e})")))?;
        self.check_lost(chunk)
    }

    /// Copies out a buffer whose mapping was asked for and whose last
    /// submission is done, and unmaps it.
    fn copy_mapped(&self, chunk: u64, buf: &wgpu::Buffer, out: &mut Vec<u8>) -> Result<()> {
        out.clear();
        {
            let view = buf
                .slice(..)
                .get_mapped_range()
                .map_err(|e| gpu_err(chunk, format!("read-back failed: {e:?}")))?;
            out.extend_from_slice(&view);
        }
        buf.unmap();
        Ok(())
    }

    /// The buffers of one chunk and their bind group; out-of-memory and
    /// validation errors name the chunk.
    fn chunk_buffers(
        &self,
        chunk: u64,
        lanes: &[GpuLane],
        slots: u32,
        globals: &GpuGlobals,
    ) -> Result<ChunkBuffers> {
        let state_bytes = (lanes.len() * std::mem::size_of::<GpuState>()) as u64;
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let vscope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let dev = &self.device;
        let init = |label, contents: &[u8], usage| {
            dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
        };
        let plain = |label, size, usage| {
            dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        use wgpu::BufferUsages as U;
        let globals_buf = init("globals", bytemuck::bytes_of(globals), U::UNIFORM);
        let lanes_buf = init("lanes", bytemuck::cast_slice(lanes), U::STORAGE);
        // New buffers are zeroed: every lane starts "not started".
        let states = plain("states", state_bytes, U::STORAGE | U::COPY_SRC);
        // Slot s starts on lane s; the next lane to take is the first
        // after them.
        let control = GpuControl {
            n_active: 0,
            next_lane: slots,
        };
        let active = init(
            "control",
            bytemuck::bytes_of(&control),
            U::STORAGE | U::COPY_SRC | U::COPY_DST,
        );
        let first: Vec<u32> = (0..slots).collect();
        let slot_lane = init("slot lanes", bytemuck::cast_slice(&first), U::STORAGE);
        let active_read = plain("active read-back", 4, U::MAP_READ | U::COPY_DST);
        let states_read = plain("states read-back", state_bytes, U::MAP_READ | U::COPY_DST);
        let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("tswm"),
            layout: &self.pipeline.get_bind_group_layout(0),
            entries: &[
                bind_entry(0, &globals_buf),
                bind_entry(1, &lanes_buf),
                bind_entry(2, &states),
                bind_entry(3, &active),
                bind_entry(4, &slot_lane),
            ],
        });
        if let Some(e) = pollster::block_on(vscope.pop()) {
            return Err(gpu_err(chunk, format!("invalid GPU work: {e}")));
        }
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(gpu_err(
                chunk,
                format!("out of GPU memory for {} lanes ({e})", lanes.len()),
            ));
        }
        Ok(ChunkBuffers {
            states,
            active,
            active_read,
            states_read,
            bind,
        })
    }
}

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
/// Slots a core of a software adapter (lavapipe): measured on
/// `sweeps/heterogeneous.toml`, 2,048 a core (4,096 on 2 cores) ran its
/// lanes 7 % faster than a slot a lane, and fewer slots a dispatch cost
/// more in dispatch overhead than they saved (README, "GPU path").
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
    /// Lanes a chunk holds (a part, in [`Gpu::run_parts`]: the runner's
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
/// [`Gpu::run_parts`]): while the host waits for one part or copies out
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
    fn new(part: usize, phase: Phase, start: Instant) -> Span {
        Span {
            part,
            phase,
            start,
            end: Instant::now(),
        }
    }
}

/// A part of a chunk in flight.
struct Part {
    index: usize,
    b: ChunkBuffers,
    gx: u32,
    gy: u32,
    rounds: u64,
    max_rounds: u64,
    /// Its states are being copied out (its last round is done).
    reading: bool,
    /// Its last submission, not yet waited for.
    last: Option<wgpu::SubmissionIndex>,
    /// When its current work was submitted.
    submitted: Instant,
}

fn bind_entry(binding: u32, buf: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: buf.as_entire_binding(),
    }
}

/// A chunk's buffers on the device (the globals and lanes buffers live on
/// through the bind group).
struct ChunkBuffers {
    states: wgpu::Buffer,
    active: wgpu::Buffer,
    active_read: wgpu::Buffer,
    states_read: wgpu::Buffer,
    bind: wgpu::BindGroup,
}

#[cfg(test)]
mod tests {
    use super::*;

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
