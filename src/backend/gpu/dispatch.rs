//! Running chunks on the device: a chunk's parts uploaded, dispatched in
//! rounds until no slot holds an unfinished lane, and read back, with
//! `in_flight` parts overlapping (one part's upload or read-back while
//! another's dispatches run).

use std::time::Instant;

use wgpu::util::DeviceExt;

use super::layout::GpuControl;
use super::real::Real;
use super::work::{Phase, Span};
use super::{gpu_err, Gpu, POLL_TIMEOUT, WORKGROUP};
use crate::error::Result;

impl Gpu {
    /// Integrates `lanes` to their ends; `out` gets one state per lane.
    /// `chunk` names the chunk in errors.
    pub fn run<R: Real>(
        &self,
        chunk: u64,
        lanes: &[R::Lane],
        globals: R::Globals,
        out: &mut Vec<R::State>,
    ) -> Result<()> {
        let mut outs = [std::mem::take(out)];
        self.run_parts::<R>(chunk, &[lanes], globals, &mut outs, 1, None)?;
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
    /// The device must have been opened for `R` ([`Gpu::real`]).
    pub fn run_parts<R: Real>(
        &self,
        chunk: u64,
        parts: &[&[R::Lane]],
        globals: R::Globals,
        outs: &mut [Vec<R::State>],
        in_flight: usize,
        mut log: Option<&mut Vec<Span>>,
    ) -> Result<()> {
        assert_eq!(parts.len(), outs.len());
        assert_eq!(
            R::SHADER,
            self.real,
            "a device opened for one real type runs only its own"
        );
        let in_flight = in_flight.max(1);
        let mut live: std::collections::VecDeque<Part> = Default::default();
        let mut next = 0;
        while next < parts.len() || !live.is_empty() {
            // Start parts while there is room.
            while next < parts.len() && live.len() < in_flight {
                outs[next].clear();
                if !parts[next].is_empty() {
                    let t0 = Instant::now();
                    let mut p = self.start_part::<R>(chunk, next, parts[next], globals)?;
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
                match bytemuck::try_cast_slice(&bytes) {
                    Ok(states) => outs[p.index].extend_from_slice(states),
                    // A read-back not aligned for the state's type.
                    Err(_) => outs[p.index].extend(
                        bytes
                            .chunks_exact(std::mem::size_of::<R::State>())
                            .map(bytemuck::pod_read_unaligned::<R::State>),
                    ),
                }
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
    fn start_part<R: Real>(
        &self,
        chunk: u64,
        index: usize,
        lanes: &[R::Lane],
        mut globals: R::Globals,
    ) -> Result<Part> {
        let n = lanes.len() as u32;
        let slots = n.min(self.slots.max(1));
        let groups = slots.div_ceil(WORKGROUP);
        let gx = groups.min(self.limits.max_compute_workgroups_per_dimension);
        let gy = groups.div_ceil(gx);
        let sizes = R::sizes(&mut globals);
        sizes.n_lanes = n;
        sizes.n_slots = slots;
        sizes.budget = self.budget;
        sizes.row_lanes = gx * WORKGROUP;
        let max_steps = sizes.max_steps;
        let b = self.chunk_buffers::<R>(chunk, lanes, slots, &globals)?;
        // Enough rounds for every lane of the busiest slot to take
        // max_steps accepted steps plus as many rejections.
        let per_lane = (2 * max_steps as u64).div_ceil(self.budget as u64) + 2;
        let max_dispatches = per_lane * (n as u64).div_ceil(slots as u64);
        Ok(Part {
            index,
            b,
            gx,
            gy,
            rounds: 0,
            max_rounds: max_dispatches,
            reading: false,
            last: None,
            submitted: Instant::now(),
        })
    }

    /// Submits a part's next round: a dispatch (slots refill at its end),
    /// then a copy of its count of active slots, mapped for reading when
    /// the round is done.
    fn submit_round(&self, p: &Part) -> wgpu::SubmissionIndex {
        let mut enc = self.device.create_command_encoder(&Default::default());
        // Only the count of active slots starts again each dispatch; the
        // next-lane counter carries on.
        enc.clear_buffer(&p.b.active, 0, Some(4));
        {
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
    fn chunk_buffers<R: Real>(
        &self,
        chunk: u64,
        lanes: &[R::Lane],
        slots: u32,
        globals: &R::Globals,
    ) -> Result<ChunkBuffers> {
        let state_bytes = (lanes.len() * std::mem::size_of::<R::State>()) as u64;
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
