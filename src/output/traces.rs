//! `traces.csv`: traced lanes through time (docs/model.md section 11), a row
//! at a time.

use std::fmt::Write as _;
use std::path::Path;

use super::atomic::AtomicFile;
use super::csv_lines::{push_f64, CsvLines};
use crate::error::Result;

/// Streams rows of `traces.csv` (docs/model.md section 11).
pub struct TracesCsv(CsvLines);

/// The columns of `traces.csv`.
pub const TRACE_COLUMNS: &str = "lane,t,x1,v1,a1,f1,s1,s2,psi,phi,contact";

impl TracesCsv {
    /// Starts `path` and writes the header; `hashed` as for
    /// [`CsvLines::start`].
    pub fn create(path: &Path, hashed: bool) -> Result<TracesCsv> {
        CsvLines::start(path, TRACE_COLUMNS, hashed).map(TracesCsv)
    }

    /// Appends one row of lane `lane`.
    pub fn write(&mut self, lane: u64, r: &crate::integrator::trace::TraceRow) -> Result<()> {
        let s = self.0.line();
        let _ = write!(s, "{lane}");
        for v in [r.t, r.x1, r.v1, r.a1, r.f1, r.s1, r.s2, r.psi, r.phi] {
            s.push(',');
            push_f64(s, v);
        }
        let _ = write!(s, ",{}", r.contact.name());
        self.0.end_line()
    }

    /// The finished file, to be committed with the run's other files.
    pub fn into_file(self) -> AtomicFile {
        self.0.into_file()
    }
}
