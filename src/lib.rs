//! `tswm`: batch simulation of the Two-Sided Wedge Mechanism, the dynamic
//! model of a worm drive in `docs/model.md`, over thousands to millions of
//! parameter variants on a CPU (f64, rayon) or a GPU (f32, WGSL via wgpu).
//!
//! The folders follow the path a lane takes (ARCHITECTURE.md): [`cli`]
//! and [`commands`] (the command line), [`input`] (sweep files, lane
//! tables, seeded draws) over [`params`] (the table of parameters),
//! [`model`] (the physics), [`integrator`] (Dormand–Prince with located
//! events and the lane automaton), [`backend`] (the f64 CPU path and the
//! f32 GPU path), [`run`] (the chunk pipeline, shards, merge, CPU against
//! GPU), [`output`] (the folder, its files and the results table, whose
//! columns [`columns`] states), [`stats`] (`summary.csv`), [`report`]
//! (`report.html`), [`error`].

// `!(x > 0.0)` is used on purpose throughout: it also rejects NaN, which
// `x <= 0.0` would let through.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// Every public item says what it is (CI denies warnings).
#![warn(missing_docs)]

pub mod backend;
pub mod cli;
pub mod columns;
pub mod commands;
pub mod error;
pub mod input;
pub mod integrator;
pub mod lanewise;
pub mod model;
pub mod output;
pub mod params;
pub mod progress;
pub mod report;
pub mod run;
pub mod stats;
