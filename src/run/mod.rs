//! Running lanes: the chunk pipeline from a lane source through a backend
//! to a sink ([`pipeline`](mod@pipeline)), a run written to its folder ([`write`](mod@write)) and
//! its summary line ([`summary`]), shards of a run and their manifests
//! ([`shard`]), their merge ([`merge`], verified by [`verify`]), and the
//! CPU against the GPU ([`compare`]), and what a run will cost, from a
//! trial before it ([`estimate`]).

pub mod compare;
mod consumers;
pub mod estimate;
pub mod merge;
mod merge_batches;
pub mod pipeline;
pub mod search;
pub mod shard;
pub mod summary;
pub mod verify;
pub mod write;

pub use pipeline::{pipeline, pipeline_range, Sink};
pub use summary::Summary;
pub use write::{run, Target, Written};
