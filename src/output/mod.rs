//! Everything a run leaves in its output folder, and how it gets there:
//! the folder and its lock ([`folder`]), files written under temporary
//! names and committed together ([`atomic`]), their SHA-256
//! ([`digest`]), the results table in either format ([`table`]),
//! `sweep.resolved.toml` ([`provenance`]), `traces.csv` ([`traces`]) and
//! the CSV line writer they share ([`csv_lines`]), and short byte
//! copies for the cells ([`short_bytes`]).

pub mod atomic;
pub mod batch;
pub mod csv_lines;
pub mod digest;
pub mod float_text;
pub mod folder;
mod lock;
pub mod provenance;
pub mod short_bytes;
pub mod table;
pub mod traces;

pub use atomic::{commit_together, AtomicFile};
pub use folder::{names, OutDir};
