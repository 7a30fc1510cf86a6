//! Where lanes come from: sweep files ([`sweep`]), lane tables and the
//! one reader of both ([`lanes`]), a lane table held in memory
//! ([`frame`]) and the forms a run's lanes are given in ([`given`]), the seeded draws of tolerance studies
//! ([`sampling`]), and lane sets of known character for tests and
//! benchmarks ([`testmodels`]).

mod drive_given;
pub mod frame;
pub mod given;
pub mod lanes;
mod reader;
pub mod sampling;
pub mod sobol_seq;
pub mod sweep;
pub mod testmodels;
