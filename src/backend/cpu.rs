//! The f64 CPU path: the reference that checks the GPU.

use rayon::prelude::*;

use super::Backend;
use crate::error::{Error, Result};
use crate::integrator::width::{width, Width};
use crate::integrator::{first_pass, own_width, refine_pass, LaneResult, Settings};
use crate::model::{FrictionTable, Lane};
use crate::params::{LaneParams, ParamColumns};

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

/// Most lanes a thread takes at a time. Within a block a finished lane's
/// slot in the vector takes the block's next lane, and lanes refined take
/// a second pass together, so a block much longer than the vector keeps it
/// full. Measured on one thread at AVX-512 x16, 20,000 lanes each (the
/// paper's design, f2 from -1.2 to 10.8 kN; `heterogeneous.toml`):
/// blocks of 256 gave 41,200 and 58,700 lanes/s, 512 gave 44,300 and
/// 61,500, 1024 gave 45,300 and 64,000.
pub const BLOCK_LANES: usize = 1024;

/// Fewest lanes in a block, when a chunk is cut finer so that every
/// thread has work.
const MIN_BLOCK_LANES: usize = 64;

/// The block size for `n` lanes on `threads` threads: at least 4 blocks a
/// thread (rayon balances them), each as long as that allows up to
/// [`BLOCK_LANES`]. A row does not depend on it (`tests/it/widths.rs`).
fn block_lanes(n: usize, threads: usize) -> usize {
    (n / (4 * threads.max(1))).clamp(MIN_BLOCK_LANES, BLOCK_LANES)
}

/// Runs lanes on the CPU into `out` (cleared first): rayon over blocks of
/// lanes, each block stepped in lockstep on its thread (`first_pass`);
/// then the lanes any block found to need a second, tighter run, gathered
/// from all blocks and shared out again (`refine_pass`), so that they fill
/// the vectors and every thread rather than trailing each block a few
/// lanes at a time.
pub fn run_cpu_lanes(
    pool: &rayon::ThreadPool,
    settings: &Settings,
    lanes: &ParamColumns,
    tables: &[FrictionTable],
    out: &mut Vec<LaneResult>,
) {
    out.clear();
    out.resize(lanes.len(), LaneResult::EMPTY);
    let w = own_width();
    let threads = pool.current_num_threads();
    let block = block_lanes(lanes.len(), threads);
    let redo: Vec<usize> = pool.install(|| {
        out.par_chunks_mut(block)
            .enumerate()
            .flat_map_iter(|(b, o)| {
                let at = b * block;
                let l: Vec<Lane> = (at..at + o.len())
                    .map(|i| Lane::new(&lanes.row(i), tables))
                    .collect();
                let redo = first_pass(w, &l, tables, settings, o);
                for (k, r) in o.iter_mut().enumerate() {
                    *r = r.with_shaft_speeds(&l[k], lanes.row(at + k).radii());
                }
                redo.into_iter().map(move |i| b * block + i)
            })
            .collect()
    });
    if redo.is_empty() {
        return;
    }
    // Each thread a share, in whole vectors.
    let share = redo.len().div_ceil(threads).next_multiple_of(w.lanes);
    let mut rows = vec![LaneResult::EMPTY; redo.len()];
    pool.install(|| {
        redo.par_chunks(share)
            .zip(rows.par_chunks_mut(share))
            .for_each(|(which, r)| {
                let l: Vec<Lane> = which
                    .iter()
                    .map(|&i| Lane::new(&lanes.row(i), tables))
                    .collect();
                refine_pass(w, &l, tables, settings, r);
                for ((r, l), &i) in r.iter_mut().zip(&l).zip(which) {
                    *r = r.with_shaft_speeds(l, lanes.row(i).radii());
                }
            })
    });
    for (i, r) in redo.into_iter().zip(rows) {
        out[i] = r;
    }
}

impl Backend for CpuBackend {
    fn name(&self) -> String {
        let n = self.threads();
        format!(
            "cpu ({n} thread{}, {})",
            if n == 1 { "" } else { "s" },
            self.width.name()
        )
    }
    fn tolerance(&self) -> f64 {
        self.settings.tol
    }
    fn chunk_lanes(&self) -> usize {
        // Enough for 4 full blocks a thread.
        (4 * BLOCK_LANES * self.threads()).max(16384)
    }
    fn batch_lanes(&self) -> usize {
        // A full block a thread: a round's lane columns built for it
        // (some 300 bytes a lane, 600 kB for two threads) are still in
        // cache when the threads read them.
        BLOCK_LANES * self.threads()
    }
    fn run_chunk(
        &mut self,
        _first: u64,
        lanes: &ParamColumns,
        tables: &[FrictionTable],
        out: &mut Vec<LaneResult>,
    ) -> Result<()> {
        run_cpu_lanes(&self.pool, &self.settings, lanes, tables, out);
        Ok(())
    }
}
