//! The results table `lanes.csv`: each lane's full parameters (MODEL.md
//! section 9 order), then its results. Written under a temporary name and
//! renamed only when complete, so a `lanes.csv` on disk is always whole.

use std::fmt::Write as _;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::integrator::LaneResult;
use crate::lanes::Source;
use crate::params::{Param, Params};

/// Result columns, after the parameter columns.
pub const RESULT_COLUMNS: [&str; 14] = [
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
];

/// A file written under `NAME.partial` and renamed to `NAME` by `commit`;
/// dropped uncommitted, the partial file is removed.
pub struct AtomicFile {
    tmp: PathBuf,
    dest: PathBuf,
    w: Option<BufWriter<File>>,
}

impl AtomicFile {
    /// Starts `dest`.
    pub fn create(dest: &Path) -> Result<AtomicFile> {
        let name = dest
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let tmp = dest.with_file_name(format!(".{name}.partial"));
        let f = File::create(&tmp).map_err(|e| Error::io(&tmp, e))?;
        Ok(AtomicFile {
            tmp,
            dest: dest.to_path_buf(),
            w: Some(BufWriter::with_capacity(1 << 20, f)),
        })
    }

    /// The writer.
    pub fn writer(&mut self) -> &mut BufWriter<File> {
        self.w.as_mut().expect("writer used after commit")
    }

    /// Flushes, syncs and renames to the final name.
    pub fn commit(mut self) -> Result<()> {
        let w = self.w.take().expect("committed twice");
        let f = w
            .into_inner()
            .map_err(|e| Error::io(&self.tmp, e.into_error()))?;
        f.sync_all().map_err(|e| Error::io(&self.tmp, e))?;
        std::fs::rename(&self.tmp, &self.dest).map_err(|e| Error::io(&self.dest, e))
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.w.is_some() {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// Writes a whole small file atomically.
pub fn write_atomic(dest: &Path, bytes: &[u8]) -> Result<()> {
    let mut f = AtomicFile::create(dest)?;
    f.writer()
        .write_all(bytes)
        .map_err(|e| Error::io(dest, e))?;
    f.commit()
}

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
        let _ = writeln!(s, "{}", r.steps);
        self.flush_line()
    }

    /// Completes the file under its final name.
    pub fn commit(self) -> Result<()> {
        self.file.commit()
    }
}

/// The text of `sweep.resolved.toml`: a header naming the tool, backend
/// and tolerance, then the sweep with every lane's source spelled out.
pub fn provenance(source: &Source, backend: &str, tol: f64) -> String {
    let resolved = match source {
        Source::Sweep { sweep, .. } => toml::to_string(&sweep.resolved_toml()).unwrap_or_default(),
        Source::Table { path, .. } => format!("# lanes from {}\n", path.display()),
    };
    format!(
        "# tswm {} resolved sweep: every lane of lanes.csv follows from this file\n\
         # backend: {backend}, tol: {tol:e}, lanes: {}\n{resolved}",
        env!("CARGO_PKG_VERSION"),
        source.lane_count()
    )
}
