//! The GPU as a [`Backend`] of the runner: lanes converted to f32, run
//! chunk by chunk, states converted back through the shared end-state
//! conversion.

use super::layout::{GpuGlobals, GpuLane, GpuState, GPU_TOL_F64};
use super::Gpu;
use crate::backend::Backend;
use crate::error::Result;
use crate::integrator::{LaneResult, Settings};
use crate::model::{FrictionTable, Lane};
use crate::params::Params;

/// The GPU as a [`Backend`] of the runner.
pub struct GpuBackend {
    gpu: Gpu,
    settings: Settings,
    chunk: usize,
    lanes64: Vec<Lane>,
    lanes32: Vec<GpuLane>,
    states: Vec<GpuState>,
}

/// Default lanes per chunk (capped by the device's limits).
pub const CHUNK_LANES: usize = 1 << 16;

impl GpuBackend {
    /// A backend on an opened device.
    pub fn new(gpu: Gpu, settings: Settings) -> GpuBackend {
        let chunk = CHUNK_LANES.min(gpu.max_chunk_lanes()).max(1);
        GpuBackend {
            gpu,
            settings,
            chunk,
            lanes64: Vec::new(),
            lanes32: Vec::new(),
            states: Vec::new(),
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
        self.chunk
    }
    fn run_chunk(
        &mut self,
        first: u64,
        lanes: &[Params],
        table: Option<&FrictionTable>,
        out: &mut Vec<LaneResult>,
    ) -> Result<()> {
        let chunk = first / self.chunk as u64;
        self.lanes64.clear();
        self.lanes64
            .extend(lanes.iter().map(|p| Lane::new(p, table)));
        self.lanes32.clear();
        self.lanes32.extend(self.lanes64.iter().map(GpuLane::from));
        let globals = GpuGlobals::new(&self.settings, table);
        self.gpu
            .run(chunk, &self.lanes32, globals, &mut self.states)?;
        out.clear();
        out.extend(
            self.states
                .iter()
                .zip(&self.lanes64)
                .map(|(s, l)| s.end_state().result(l, table)),
        );
        Ok(())
    }
}
