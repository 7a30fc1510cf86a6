//! `tswm`: batch simulation of the Two-Sided Wedge Mechanism, the dynamic
//! model of a worm drive in `docs/model.md`, over thousands to millions of
//! parameter variants on a CPU (f64, rayon) or a GPU (f32, WGSL via wgpu).
//!
//! Modules: [`params`] (the parameter table, specs, validation), [`model`]
//! (physics), [`integrator`] (DP5 with located events, the lane
//! automaton), [`sweep`], [`sampling`] and [`lanes`] (where lanes come
//! from), [`backend`] (CPU path, choosing a backend) and [`gpu`] (the
//! WGSL path), [`runner`] and [`output`] (chunked runs streamed to
//! `lanes.csv`), [`lanes_file`] (the table as CSV or Parquet), [`stats`]
//! (`summary.csv`), [`report`] (`report.html`), [`shard`] and [`merge`]
//! (runs split across machines, joined again), [`check`] (CPU against
//! GPU), [`cli`].

// `!(x > 0.0)` is used on purpose throughout: it also rejects NaN, which
// `x <= 0.0` would let through.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod backend;
pub mod cli;
pub mod columns;
pub mod commands;
pub mod error;
pub mod input;
pub mod integrator;
pub mod model;
pub mod output;
pub mod params;
pub mod report;
pub mod run;
pub mod stats;
