//! Integration tests, built as one binary.

mod accuracy;
mod architecture;
mod bad_input;
mod cli;
mod cluster;
mod common;
mod docs;
mod drive;
mod engineering;
mod fixtures;
mod friction_laws;
mod fuzz;
mod gear;
mod gpu;
mod output;
mod probes;
mod property;
mod reference;
mod report;
mod sensitivity;
mod shader;
mod shards;
mod stats;
mod traces;
mod trust;
mod widths;
