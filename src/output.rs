//! The results table `lanes.csv`: each lane's full parameters (MODEL.md
//! section 9 order), then its results; and the provenance file beside it.
//! Both are written under temporary names and committed together
//! (`outdir`), so a `lanes.csv` on disk is always whole and belongs to the
//! `sweep.resolved.toml` beside it.

use std::fmt::Write as _;
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::integrator::LaneResult;
use crate::lanes::Source;
use crate::outdir::AtomicFile;
use crate::params::{Param, Params};

/// Result columns, after the parameter columns.
pub const RESULT_COLUMNS: [&str; 15] = [
    "lane",
    "status",
    "switches",
    "t_first_switch",
    "reversals",
    "sticks",
    "contact_end",
    "x1_end",
    "v1_end",
    "w_motor",
    "w_load",
    "w_friction",
    "eta_end",
    "steps",
    "path",
];

/// Streams rows of `lanes.csv`.
pub struct LanesCsv {
    file: AtomicFile,
    line: String,
    path: PathBuf,
}

/// A float cell: empty for NaN (not applicable, or no such event), else
/// the shortest text that reads back to the same f64.
fn push_f64(s: &mut String, v: f64) {
    if !v.is_nan() {
        let _ = write!(s, "{v:?}");
    }
}

impl LanesCsv {
    /// Starts `path` and writes the header.
    pub fn create(path: &Path) -> Result<LanesCsv> {
        let mut w = LanesCsv {
            file: AtomicFile::create(path)?,
            line: String::with_capacity(512),
            path: path.into(),
        };
        let header: Vec<&str> = Param::COLUMNS
            .iter()
            .map(|p| p.name())
            .chain(RESULT_COLUMNS.iter().copied())
            .collect();
        w.line.push_str(&header.join(","));
        w.line.push('\n');
        w.flush_line()?;
        Ok(w)
    }

    fn flush_line(&mut self) -> Result<()> {
        let r = self.file.writer().write_all(self.line.as_bytes());
        self.line.clear();
        r.map_err(|e| Error::io(&self.path, e))
    }

    /// Appends lane `lane`'s row.
    pub fn write(&mut self, lane: u64, p: &Params, r: &LaneResult) -> Result<()> {
        let s = &mut self.line;
        for c in Param::COLUMNS {
            match c {
                Param::Motor => s.push_str(p.motor.name()),
                Param::Friction => s.push_str(p.friction.name()),
                Param::Num(n) => push_f64(s, p.get(n)),
            }
            s.push(',');
        }
        let _ = write!(s, "{lane},{},{},", r.status.name(), r.switches);
        push_f64(s, r.t_first_switch);
        let _ = write!(s, ",{},{},{},", r.reversals, r.sticks, r.contact_end.name());
        let ok = r.status == crate::integrator::Status::Ok;
        // A lane that could not be finished reports no numbers.
        for v in [
            r.x1_end,
            r.v1_end,
            r.w_motor,
            r.w_load,
            r.w_friction,
            r.eta_end,
        ] {
            push_f64(s, if ok { v } else { f64::NAN });
            s.push(',');
        }
        let _ = writeln!(s, "{},{}", r.steps, r.path.name());
        self.flush_line()
    }

    /// The finished file, to be committed with the run's other files.
    pub fn into_file(self) -> AtomicFile {
        self.file
    }
}

/// The text of `sweep.resolved.toml`: a header naming the tool, backend
/// and tolerance, then the sweep with every lane's source spelled out.
pub fn provenance(source: &Source, backend: &str, tol: f64) -> String {
    let (from, resolved) = match source {
        Source::Sweep { sweep, .. } => (
            "every lane of lanes.csv follows from this file".to_string(),
            toml::to_string(&sweep.resolved_toml()).unwrap_or_default(),
        ),
        Source::Table {
            path, base, table, ..
        } => {
            // The lane table's cells over this [base] and [friction_table].
            let under = crate::sweep::Sweep {
                base: base.clone(),
                axes: Vec::new(),
                study: None,
                table: *table,
            };
            (
                format!(
                    "every lane of lanes.csv follows from the lane table {} ({} rows) \
                     over the [base] and [friction_table] below",
                    path.display(),
                    source.lane_count()
                ),
                toml::to_string(&under.resolved_toml()).unwrap_or_default(),
            )
        }
    };
    format!(
        "# tswm {} resolved sweep: {from}\n\
         # backend: {backend}, tol: {tol:e}, lanes: {}\n{resolved}",
        env!("CARGO_PKG_VERSION"),
        source.lane_count()
    )
}
