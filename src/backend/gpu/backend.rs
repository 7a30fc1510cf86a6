//! The GPU as a [`Backend`] of the runner: lanes converted to f32, run
//! chunk by chunk, states converted back through the shared end-state
//! conversion, every row checked (`verify`) and the rows it does not trust
//! recomputed on the f64 path in the same run.

use super::cost::{CostModel, MIN_LEARNT};
use super::layout::{flags, GpuGlobals, GpuLane, GpuState, GPU_TOL_F64};
use super::{verify, Gpu};
use crate::backend::{Backend, CpuBackend};
use crate::error::Result;
use crate::integrator::{LaneResult, Recheck, RowPath, Settings};
use crate::model::{FrictionTable, Lane};
use crate::params::{LaneParams, ParamColumns};

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
    /// Predicts each lane's steps, to order lanes (learnt during the run).
    cost: CostModel,
    keys: Vec<f64>,
    keyed: Vec<(f64, usize)>,
    steps: Vec<u32>,
    states: Vec<GpuState>,
    part_states: Vec<Vec<GpuState>>,
    redo: Vec<(usize, Recheck)>,
    redo_params: ParamColumns,
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
    pub(crate) fn with_cpu(gpu: Gpu, settings: Settings, cpu: CpuBackend) -> GpuBackend {
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
            cost: CostModel::new(),
            keys: Vec::new(),
            keyed: Vec::new(),
            steps: Vec::new(),
            states: Vec::new(),
            part_states: Vec::new(),
            redo: Vec::new(),
            redo_params: ParamColumns::default(),
            redo_out: Vec::new(),
        }
    }

    /// The model that orders lanes by predicted steps.
    pub fn cost_model(&self) -> &CostModel {
        &self.cost
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
        lanes: &ParamColumns,
        tables: &[FrictionTable],
        out: &mut Vec<LaneResult>,
    ) -> Result<()> {
        let chunk = first / self.chunk_lanes() as u64;
        self.lanes64.clear();
        self.lanes64
            .extend((0..lanes.len()).map(|i| Lane::new(&lanes.row(i), tables)));
        out.clear();
        out.resize(lanes.len(), LaneResult::EMPTY);
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
        // Until the cost model has learnt, a pilot of the first lanes runs
        // alone (ordered by t_end) and teaches it, so that the rest of
        // the first chunk is ordered by predicted steps too. The pilot is
        // one lane a slot: a single wave, which leaves the rest of a full
        // chunk a whole number of waves.
        self.states.clear();
        let mut done = 0;
        if !self.cost.trained() {
            let pilot = (self.gpu.slots as usize).max(MIN_LEARNT);
            if self.on_gpu.len() >= 2 * pilot {
                self.run_ordered(chunk, 0..pilot, tables)?;
                done = pilot;
            }
        }
        self.run_ordered(chunk, done..self.on_gpu.len(), tables)?;
        for (&i, st) in self.on_gpu.iter().zip(&self.states) {
            let mut r = st
                .end_state(&self.lanes64[i])
                .result(&self.lanes64[i], tables);
            r.path = RowPath::Gpu;
            let finished = st.flags & flags::DONE != 0;
            let turned = st.flags & flags::FLOW_TURN != 0;
            let why = verify::recheck(&self.lanes64[i], &r, finished)
                .or(turned.then_some(crate::integrator::path::Recheck::FlowTurn));
            match why {
                Some(why) if self.self_check => self.redo.push((i, why)),
                _ => out[i] = r.with_shaft_speeds(&self.lanes64[i], lanes.row(i).radii()),
            }
        }
        self.recompute(first, lanes, tables, out)
    }
}

impl GpuBackend {
    /// Runs the lanes `on_gpu[range]` on the device ordered by predicted
    /// cost, most steps first: lanes of like step count side by side end
    /// together and refill together (see [`CostModel`]), and the last
    /// lanes a part hands out are its shortest, so few slots still run
    /// when it has none left to give. `on_gpu[range]` is left in that
    /// order and their end states are appended to `states`, one for one.
    /// The model then learns from the lanes' step counts.
    fn run_ordered(
        &mut self,
        chunk: u64,
        range: std::ops::Range<usize>,
        tables: &[FrictionTable],
    ) -> Result<()> {
        let which = &mut self.on_gpu[range.clone()];
        self.cost.keys(&self.lanes64, which, &mut self.keys);
        self.keyed.clear();
        self.keyed
            .extend(self.keys.iter().copied().zip(which.iter().copied()));
        self.keyed.sort_by(|a, b| b.0.total_cmp(&a.0));
        for (w, &(_, i)) in which.iter_mut().zip(&self.keyed) {
            *w = i;
        }
        self.lanes32.clear();
        let l64 = &self.lanes64;
        self.lanes32
            .extend(which.iter().map(|&i| GpuLane::from(&l64[i])));
        let globals = GpuGlobals::new(&self.settings, tables);
        // Parts of like cost (the lanes are sorted), in flight together.
        let n_parts = self.lanes32.len().div_ceil(self.part).max(1);
        let size = self.lanes32.len().div_ceil(n_parts).max(1);
        let parts: Vec<&[GpuLane]> = self.lanes32.chunks(size).collect();
        self.part_states.resize_with(parts.len(), Vec::new);
        let outs = &mut self.part_states[..parts.len()];
        self.gpu
            .run_parts(chunk, &parts, globals, outs, self.in_flight, None)?;
        let first = self.states.len();
        for s in outs.iter() {
            self.states.extend_from_slice(s);
        }
        self.steps.clear();
        self.steps
            .extend(self.states[first..].iter().map(|s| s.steps));
        self.cost
            .learn(&self.lanes64, &self.on_gpu[range], &self.steps);
        Ok(())
    }

    /// Recomputes the untrusted rows of a chunk on the f64 path.
    fn recompute(
        &mut self,
        first: u64,
        lanes: &ParamColumns,
        tables: &[FrictionTable],
        out: &mut [LaneResult],
    ) -> Result<()> {
        if self.redo.is_empty() {
            return Ok(());
        }
        self.redo_params = lanes.gather(self.redo.iter().map(|&(i, _)| i));
        self.cpu
            .run_chunk(first, &self.redo_params, tables, &mut self.redo_out)?;
        for (&(i, why), r) in self.redo.iter().zip(&self.redo_out) {
            out[i] = LaneResult {
                path: RowPath::Recomputed(why),
                ..*r
            };
        }
        Ok(())
    }
}
