//! The f64 CPU path: the reference that checks the GPU.

use rayon::prelude::*;

use super::Backend;
use crate::error::{Error, Result};
use crate::integrator::width::{width, Width};
use crate::integrator::{simulate_batch, LaneResult, Settings};
use crate::model::{FrictionTable, Lane};
use crate::params::Params;

/// The f64 reference path: rayon over blocks of lanes, each block
/// interleaved on its thread.
pub struct CpuBackend {
    pool: rayon::ThreadPool,
    /// The vector width each thread runs at.
    width: Width,
    /// Integration settings.
    pub settings: Settings,
}

impl CpuBackend {
    /// A CPU backend on `threads` threads (0: all cores).
    /// Refused when `TSWM_SIMD_WIDTH` asks for a width there is not.
    pub fn new(threads: usize, settings: Settings) -> Result<CpuBackend> {
        let width = width().map_err(Error::Usage)?;
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| Error::Usage(format!("cannot start {threads} threads: {e}")))?;
        Ok(CpuBackend {
            pool,
            width,
            settings,
        })
    }

    /// Threads in the pool.
    pub fn threads(&self) -> usize {
        self.pool.current_num_threads()
    }
}

/// Lanes a thread takes at a time. Within a block a finished lane's slot
/// in the vector takes the block's next lane, so a block much longer
/// than the vector keeps it full; measured on one thread (AVX-512, 8
/// lanes, 20,000 lanes each): 64 gave 34,900 paper-like and 45,400
/// heterogeneous lanes/s, 256 gave 36,500 and 51,700, 1024 gave 34,500
/// and 53,400.
pub const BLOCK_LANES: usize = 256;

/// Runs lanes on the CPU into `out` (cleared first): rayon over blocks of
/// lanes, each block interleaved on its thread (`simulate_batch`).
pub fn run_cpu_lanes(
    pool: &rayon::ThreadPool,
    settings: &Settings,
    lanes: &[Params],
    tables: &[FrictionTable],
    out: &mut Vec<LaneResult>,
) {
    out.clear();
    out.resize(lanes.len(), LaneResult::EMPTY);
    pool.install(|| {
        lanes
            .par_chunks(BLOCK_LANES)
            .zip(out.par_chunks_mut(BLOCK_LANES))
            .for_each(|(p, o)| {
                let mut l = [Lane::new(&p[0], tables); BLOCK_LANES];
                for (d, s) in l.iter_mut().zip(p) {
                    *d = Lane::new(s, tables);
                }
                simulate_batch(&l[..p.len()], tables, settings, o);
            })
    });
}

impl Backend for CpuBackend {
    fn name(&self) -> String {
        format!("cpu ({} threads, {})", self.threads(), self.width.name())
    }
    fn tolerance(&self) -> f64 {
        self.settings.tol
    }
    fn chunk_lanes(&self) -> usize {
        16384
    }
    fn run_chunk(
        &mut self,
        _first: u64,
        lanes: &[Params],
        tables: &[FrictionTable],
        out: &mut Vec<LaneResult>,
    ) -> Result<()> {
        run_cpu_lanes(&self.pool, &self.settings, lanes, tables, out);
        Ok(())
    }
}
