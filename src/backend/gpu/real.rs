//! The shader's `real` on the host: which type a shader computes in
//! ([`ShaderReal`]) and, for each, the structs it shares with the host
//! ([`Real`], implemented for f32 and f64 in `layout`), so that the
//! dispatch is written once for both.

use bytemuck::{Pod, Zeroable};

use crate::integrator::accuracy::ErrorBudget;
use crate::integrator::{EndState, Settings};
use crate::model::{FrictionTable, Lane};

/// The real type a shader is built with (its `real`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShaderReal {
    /// f32, on every adapter.
    F32,
    /// f64, on adapters with `SHADER_F64`.
    F64,
}

/// The words that head [`GpuGlobals`](super::layout::GpuGlobals) and
/// [`GpuGlobals64`](super::layout::GpuGlobals64) alike, which
/// the dispatch sets per part.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct Sizes {
    /// Lanes in the part.
    pub n_lanes: u32,
    /// Step attempts per lane per dispatch.
    pub budget: u32,
    /// A lane's step limit.
    pub max_steps: u32,
    /// A lane's event limit.
    pub max_events: u32,
    /// Number of friction tables.
    pub n_tables: u32,
    /// Invocations per row of a 2-D dispatch.
    pub row_lanes: u32,
    /// Slots working through the part's lanes.
    pub n_slots: u32,
}

/// The shader's `real` on the host: f32 or f64, with its structs.
pub trait Real: Pod + Send + Sync {
    /// A lane's constants.
    type Lane: Pod + Send + Sync + for<'a> From<&'a Lane>;
    /// A lane's state between dispatches.
    type State: Pod + Send + Sync;
    /// The run's values.
    type Globals: Pod + Send + Sync;
    /// Which shader runs these structs.
    const SHADER: ShaderReal;
    /// The run's values for `settings` and friction tables `tables`.
    fn globals(settings: &Settings, tables: &[FrictionTable]) -> Self::Globals;
    /// The words of `g` the dispatch sets.
    fn sizes(g: &mut Self::Globals) -> &mut Sizes;
    /// Where the lane `lane` stopped, in f64.
    fn end_state(s: &Self::State, lane: &Lane) -> EndState;
    /// The state's flag bits ([`flags`](super::layout::flags)).
    fn flags(s: &Self::State) -> u32;
    /// The lane's error estimate (kept by the f64 shader only).
    fn budget(s: &Self::State) -> ErrorBudget;
}
