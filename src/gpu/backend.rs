//! The GPU as a [`Backend`] of the runner: lanes converted to f32, run
//! chunk by chunk, states converted back through the shared end-state
//! conversion, every row checked (`verify`) and the rows it does not trust
//! recomputed on the f64 path in the same run.

use super::layout::{flags, GpuGlobals, GpuLane, GpuState, GPU_TOL_F64};
use super::{verify, Gpu};
use crate::backend::{Backend, CpuBackend, PLACEHOLDER};
use crate::error::Result;
use crate::integrator::{LaneResult, Recheck, RowPath, Settings};
use crate::model::{FrictionTable, Lane};
use crate::params::Params;

/// The GPU as a [`Backend`] of the runner.
pub struct GpuBackend {
    gpu: Gpu,
    settings: Settings,
    /// Lanes of a part of a chunk (a chunk holds `in_flight` parts; from
    /// [`super::WorkSize`], settable for tests and measurements).
    pub part: usize,
    /// Parts in flight at once (likewise).
    pub in_flight: usize,
    /// The f64 path for rows the check does not trust.
    cpu: CpuBackend,
    /// Check every row and recompute the untrusted ones (on by default;
    /// off only to measure the raw f32 kernel).
    pub self_check: bool,
    lanes64: Vec<Lane>,
    lanes32: Vec<GpuLane>,
    on_gpu: Vec<usize>,
    states: Vec<GpuState>,
    part_states: Vec<Vec<GpuState>>,
    redo: Vec<(usize, Recheck)>,
    redo_params: Vec<Params>,
    redo_out: Vec<LaneResult>,
}

impl GpuBackend {
    /// A backend on an opened device; rows it does not trust are
    /// recomputed on all cores.
    pub fn new(gpu: Gpu, settings: Settings) -> GpuBackend {
        let cpu = CpuBackend::new(0, settings).expect("a thread pool on all cores");
        GpuBackend::with_cpu(gpu, settings, cpu)
    }

    /// A backend whose recomputed rows run on `cpu`.
    pub fn with_cpu(gpu: Gpu, settings: Settings, cpu: CpuBackend) -> GpuBackend {
        // Each part of a chunk is the work size the device is tuned for;
        // `in_flight` of them overlap (`Gpu::run_parts`).
        let work = super::WorkSize::of(&gpu.info, &gpu.limits);
        GpuBackend {
            gpu,
            settings,
            part: work.chunk_lanes,
            in_flight: work.in_flight,
            cpu,
            self_check: true,
            lanes64: Vec::new(),
            lanes32: Vec::new(),
            on_gpu: Vec::new(),
            states: Vec::new(),
            part_states: Vec::new(),
            redo: Vec::new(),
            redo_params: Vec::new(),
            redo_out: Vec::new(),
        }
    }
}

impl Backend for GpuBackend {
    fn name(&self) -> String {
        format!("gpu: {}", self.gpu.describe())
    }
    fn tolerance(&self) -> f64 {
        GPU_TOL_F64
    }
    fn chunk_lanes(&self) -> usize {
        self.in_flight * self.part
    }
    fn run_chunk(
        &mut self,
        first: u64,
        lanes: &[Params],
        table: Option<&FrictionTable>,
        out: &mut Vec<LaneResult>,
    ) -> Result<()> {
        let chunk = first / self.chunk_lanes() as u64;
        self.lanes64.clear();
        self.lanes64
            .extend(lanes.iter().map(|p| Lane::new(p, table)));
        out.clear();
        out.resize(lanes.len(), PLACEHOLDER);
        self.redo.clear();
        // Lanes f32 cannot represent never go to the GPU.
        self.on_gpu.clear();
        for (i, l) in self.lanes64.iter().enumerate() {
            if !self.self_check || verify::representable(l) {
                self.on_gpu.push(i);
            } else {
                self.redo.push((i, Recheck::F32Range));
            }
        }
        // Lanes of like length side by side: neighbouring invocations
        // step in lockstep, and a lane's result does not depend on where
        // it runs (each goes back to its own row through `on_gpu`).
        let l64 = &self.lanes64;
        self.on_gpu
            .sort_by(|&a, &b| l64[a].t_end.total_cmp(&l64[b].t_end));
        self.lanes32.clear();
        let l64 = &self.lanes64;
        self.lanes32
            .extend(self.on_gpu.iter().map(|&i| GpuLane::from(&l64[i])));
        let globals = GpuGlobals::new(&self.settings, table);
        // Parts of like length (the lanes are sorted), in flight together.
        let n_parts = self.lanes32.len().div_ceil(self.part).max(1);
        let size = self.lanes32.len().div_ceil(n_parts).max(1);
        let parts: Vec<&[GpuLane]> = self.lanes32.chunks(size).collect();
        self.part_states.resize_with(parts.len(), Vec::new);
        let outs = &mut self.part_states[..parts.len()];
        self.gpu
            .run_parts(chunk, &parts, globals, outs, self.in_flight, None)?;
        self.states.clear();
        for s in outs.iter() {
            self.states.extend_from_slice(s);
        }
        for (&i, st) in self.on_gpu.iter().zip(&self.states) {
            let mut r = st.end_state().result(&self.lanes64[i], table);
            r.path = RowPath::Gpu;
            let finished = st.flags & flags::DONE != 0;
            match verify::recheck(&self.lanes64[i], &r, finished) {
                Some(why) if self.self_check => self.redo.push((i, why)),
                _ => out[i] = r,
            }
        }
        self.recompute(first, lanes, table, out)
    }
}

impl GpuBackend {
    /// Recomputes the untrusted rows of a chunk on the f64 path.
    fn recompute(
        &mut self,
        first: u64,
        lanes: &[Params],
        table: Option<&FrictionTable>,
        out: &mut [LaneResult],
    ) -> Result<()> {
        if self.redo.is_empty() {
            return Ok(());
        }
        self.redo_params.clear();
        self.redo_params
            .extend(self.redo.iter().map(|&(i, _)| lanes[i]));
        self.cpu
            .run_chunk(first, &self.redo_params, table, &mut self.redo_out)?;
        for (&(i, why), r) in self.redo.iter().zip(&self.redo_out) {
            out[i] = LaneResult {
                path: RowPath::Recomputed(why),
                ..*r
            };
        }
        Ok(())
    }
}
