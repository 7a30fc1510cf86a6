//! Where lanes come from: sweep files ([`sweep`]), lane tables and the
//! one reader of both ([`lanes`]), a lane table held in memory
//! ([`frame`]) and the forms a run's lanes are given in ([`given`]), the seeded draws of tolerance studies
//! ([`sampling`]), and lane sets of known character for tests and
//! benchmarks ([`testmodels`]).

/// Most lanes one run (or one shard) takes: 10^9, an hour or two of a
/// many-core CPU or minutes of a data-centre GPU, and some 500 GB of
/// `lanes.csv`. A larger sweep runs as shards (each checked alone), so no
/// run spends hours checking lanes before it writes anything.
pub const MAX_RUN_LANES: u64 = 1_000_000_000;

mod drive_given;
pub mod frame;
pub mod given;
pub mod lanes;
mod reader;
pub mod sampling;
pub mod sobol_seq;
pub mod sweep;
pub mod testmodels;
