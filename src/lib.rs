//! `tswm`: batch simulation of the Two-Sided Wedge Mechanism, the dynamic
//! model of a worm drive in `MODEL.md`, over thousands to millions of
//! parameter variants on a CPU (f64, rayon) or a GPU (f32, WGSL via wgpu).

pub mod integrator;
pub mod model;
pub mod params;
pub mod sampling;
pub mod testmodels;
