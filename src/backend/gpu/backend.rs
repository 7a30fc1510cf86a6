//! The GPU as a [`Backend`] of the runner: lanes converted to f32, run
//! chunk by chunk, states converted back through the shared end-state
//! conversion, every row checked (`verify`) and the rows it does not trust
//! recomputed on the f64 path in the same run.

use super::cost::{CostModel, MIN_LEARNT};
use super::layout::{flags, GPU_TOL_F64};
use super::real::Real;
use super::{verify, Gpu, ShaderReal};
use crate::backend::{Backend, CpuBackend};
use crate::error::Result;
use crate::integrator::accuracy::{needs_refining, ErrorBudget};
use crate::integrator::{EndState, LaneResult, Recheck, RowPath, Settings};
use crate::model::{FrictionTable, Lane};
use crate::params::{LaneParams, ParamColumns};

/// A lane's end on the device: its state, its flag bits and its error
/// estimate (zero in f32, which keeps none).
type End = (EndState, u32, ErrorBudget);

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
    on_gpu: Vec<usize>,
    /// Predicts each lane's steps, to order lanes (learnt during the run).
    cost: CostModel,
    keys: Vec<f64>,
    keyed: Vec<(f64, usize)>,
    steps: Vec<u32>,
    /// The end state, flag bits and error estimate of each lane of
    /// `on_gpu`, one for one.
    ends: Vec<End>,
    f32_bufs: Buffers<f32>,
    f64_bufs: Buffers<f64>,
    /// Rows to compute on the CPU, and the path each will say: a
    /// [`RowPath::Recomputed`] row at the run's settings, a
    /// [`RowPath::Refined`] one at the tighter settings.
    redo: Vec<(usize, RowPath)>,
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
            on_gpu: Vec::new(),
            cost: CostModel::new(),
            keys: Vec::new(),
            keyed: Vec::new(),
            steps: Vec::new(),
            ends: Vec::new(),
            f32_bufs: Buffers::default(),
            f64_bufs: Buffers::default(),
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
        match self.gpu.real {
            ShaderReal::F32 => format!("gpu: {}", self.gpu.describe()),
            ShaderReal::F64 => format!("gpu f64: {}", self.gpu.describe()),
        }
    }
    fn tolerance(&self) -> f64 {
        match self.gpu.real {
            ShaderReal::F32 => GPU_TOL_F64,
            ShaderReal::F64 => super::layout::f64_settings(&self.settings).tol,
        }
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
        let f64 = self.gpu.real == ShaderReal::F64;
        for (i, l) in self.lanes64.iter().enumerate() {
            if !self.self_check || f64 || verify::representable(l) {
                self.on_gpu.push(i);
            } else {
                self.redo.push((i, RowPath::Recomputed(Recheck::F32Range)));
            }
        }
        // Until the cost model has learnt, a pilot of the first lanes runs
        // alone (ordered by t_end) and teaches it, so that the rest of
        // the first chunk is ordered by predicted steps too. The pilot is
        // one lane a slot: a single wave, which leaves the rest of a full
        // chunk a whole number of waves.
        self.ends.clear();
        let mut done = 0;
        if !self.cost.trained() {
            let pilot = (self.gpu.slots as usize).max(MIN_LEARNT);
            if self.on_gpu.len() >= 2 * pilot {
                self.run_ordered(chunk, 0..pilot, tables)?;
                done = pilot;
            }
        }
        self.run_ordered(chunk, done..self.on_gpu.len(), tables)?;
        for (&i, (end, bits, budget)) in self.on_gpu.iter().zip(&self.ends) {
            let mut r = end.result(&self.lanes64[i], tables);
            r.path = if f64 { RowPath::Gpu64 } else { RowPath::Gpu };
            let finished = bits & flags::DONE != 0;
            let turned = bits & flags::FLOW_TURN != 0;
            // f64 resolves a graze as the CPU path does (the same steps).
            let grazed = !f64 && bits & flags::GRAZE != 0;
            let why = if f64 {
                verify::recheck_f64(finished)
            } else {
                verify::recheck(&self.lanes64[i], tables, end, &r, finished)
            }
            .or(turned.then_some(Recheck::FlowTurn))
            .or(grazed.then_some(Recheck::SwitchGraze));
            // An f64 lane whose estimate is over the bound is run again at
            // the tighter settings, as the CPU path runs its own.
            let redo = match why {
                Some(why) => Some(RowPath::Recomputed(why)),
                None if f64 && needs_refining(&self.settings, &r, budget) => Some(RowPath::Refined),
                None => None,
            };
            match redo {
                Some(path) if self.self_check => self.redo.push((i, path)),
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
    /// order and their end states are appended to `ends`, one for one.
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
        let first = self.ends.len();
        let run = Run {
            gpu: &self.gpu,
            chunk,
            which,
            lanes: &self.lanes64,
            settings: &self.settings,
            tables,
            part: self.part,
            in_flight: self.in_flight,
        };
        match self.gpu.real {
            ShaderReal::F32 => run.go(&mut self.f32_bufs, &mut self.ends)?,
            ShaderReal::F64 => run.go(&mut self.f64_bufs, &mut self.ends)?,
        }
        self.steps.clear();
        self.steps
            .extend(self.ends[first..].iter().map(|(e, _, _)| e.steps));
        self.cost
            .learn(&self.lanes64, &self.on_gpu[range], &self.steps);
        Ok(())
    }

    /// Computes the rows of a chunk the GPU's do not stand for on the f64
    /// CPU path: the untrusted ones at the run's settings, the f64 lanes
    /// whose estimate is over the bound at the tighter ones (not refined
    /// again, as on the CPU path).
    fn recompute(
        &mut self,
        first: u64,
        lanes: &ParamColumns,
        tables: &[FrictionTable],
        out: &mut [LaneResult],
    ) -> Result<()> {
        let own = self.cpu.settings;
        let tighter = Settings {
            refine: false,
            ..self.settings.tighter()
        };
        for (refined, set) in [(false, own), (true, tighter)] {
            let which: Vec<(usize, RowPath)> = self
                .redo
                .iter()
                .filter(|(_, p)| (*p == RowPath::Refined) == refined)
                .copied()
                .collect();
            if which.is_empty() {
                continue;
            }
            self.redo_params = lanes.gather(which.iter().map(|&(i, _)| i));
            self.cpu.settings = set;
            let ran = self
                .cpu
                .run_chunk(first, &self.redo_params, tables, &mut self.redo_out);
            self.cpu.settings = own;
            ran?;
            for (&(i, path), r) in which.iter().zip(&self.redo_out) {
                out[i] = LaneResult { path, ..*r };
            }
        }
        Ok(())
    }
}

/// The host's buffers of one real type, kept between chunks.
struct Buffers<R: Real> {
    lanes: Vec<R::Lane>,
    part_states: Vec<Vec<R::State>>,
}

impl<R: Real> Default for Buffers<R> {
    fn default() -> Self {
        Buffers {
            lanes: Vec::new(),
            part_states: Vec::new(),
        }
    }
}

/// One ordered run of lanes on the device, whatever its real type.
struct Run<'a> {
    gpu: &'a Gpu,
    chunk: u64,
    which: &'a [usize],
    lanes: &'a [Lane],
    settings: &'a Settings,
    tables: &'a [FrictionTable],
    part: usize,
    in_flight: usize,
}

impl Run<'_> {
    /// Converts the lanes `which` to `R`, runs them in parts of like cost
    /// (the lanes are sorted), in flight together, and appends each
    /// lane's end state, flag bits and error estimate to `ends`.
    fn go<R: Real>(&self, bufs: &mut Buffers<R>, ends: &mut Vec<End>) -> Result<()> {
        bufs.lanes.clear();
        bufs.lanes
            .extend(self.which.iter().map(|&i| R::Lane::from(&self.lanes[i])));
        let globals = R::globals(self.settings, self.tables);
        let n_parts = bufs.lanes.len().div_ceil(self.part).max(1);
        let size = bufs.lanes.len().div_ceil(n_parts).max(1);
        let parts: Vec<&[R::Lane]> = bufs.lanes.chunks(size).collect();
        bufs.part_states.resize_with(parts.len(), Vec::new);
        let outs = &mut bufs.part_states[..parts.len()];
        self.gpu
            .run_parts::<R>(self.chunk, &parts, globals, outs, self.in_flight, None)?;
        let states = outs.iter().flatten();
        ends.extend(
            self.which
                .iter()
                .zip(states)
                .map(|(&i, s)| (R::end_state(s, &self.lanes[i]), R::flags(s), R::budget(s))),
        );
        Ok(())
    }
}
