//! Integration tests, built as one binary.

mod accuracy;
mod bad_input;
mod cli;
mod common;
mod fixtures;
mod fuzz;
mod gpu;
mod output;
mod shader;
