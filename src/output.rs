//! The results table `lanes.csv`: each lane's full parameters (MODEL.md
//! section 9 order), then its results; and the provenance file beside it.
//! Both are written under temporary names and committed together
//! (`outdir`), so a `lanes.csv` on disk is always whole and belongs to the
//! `sweep.resolved.toml` beside it.

use std::fmt::Write as _;
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::lanes::Source;
use crate::outdir::AtomicFile;

/// A CSV file written line by line under a temporary name (the files of
/// one run are committed together, `outdir::commit_together`).
pub struct CsvLines {
    file: AtomicFile,
    line: String,
    path: PathBuf,
}

impl CsvLines {
    /// Starts `path` with the header line `header`.
    pub fn create(path: &Path, header: &str) -> Result<CsvLines> {
        CsvLines::start(path, header, false)
    }

    /// Starts `path` with the header line `header`, hashing it when
    /// `hashed` (see [`AtomicFile::create_hashed`]).
    pub fn start(path: &Path, header: &str, hashed: bool) -> Result<CsvLines> {
        let mut w = CsvLines {
            file: if hashed {
                AtomicFile::create_hashed(path)?
            } else {
                AtomicFile::create(path)?
            },
            line: String::with_capacity(512),
            path: path.into(),
        };
        w.line.push_str(header);
        w.end_line()?;
        Ok(w)
    }

    /// The line being built (empty after each `end_line`).
    pub fn line(&mut self) -> &mut String {
        &mut self.line
    }

    /// Ends the line and writes it.
    pub fn end_line(&mut self) -> Result<()> {
        self.line.push('\n');
        let r = self.file.writer().write_all(self.line.as_bytes());
        self.line.clear();
        r.map_err(|e| Error::io(&self.path, e))
    }

    /// Writes whole lines, already formatted.
    pub fn write_raw(&mut self, lines: &[u8]) -> Result<()> {
        self.file
            .writer()
            .write_all(lines)
            .map_err(|e| Error::io(&self.path, e))
    }

    /// The finished file, to be committed with the run's other files.
    pub fn into_file(self) -> AtomicFile {
        self.file
    }
}

/// A float cell: empty for NaN (not applicable, or no such event), else
/// the shortest text that reads back to the same f64.
pub(crate) fn push_f64(s: &mut String, v: f64) {
    if !v.is_nan() {
        let _ = write!(s, "{v:?}");
    }
}

/// A string as a one-line TOML basic string (quoted, every control
/// character, quote and backslash escaped; the serializer would choose a
/// multi-line string for text with a line break), so no file name or
/// device name can break a line of `sweep.resolved.toml`.
pub fn toml_string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if c.is_control() => out.push_str(&format!("\\u{:04X}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// The text of `sweep.resolved.toml`: header lines naming the tool, the
/// lanes' source, backend, tolerance, lane count, run time
/// (`seconds`) and, for a shard, its lanes; then the sweep with every
/// lane's source spelled out and the traces the run writes (`trace`).
/// Every string in the header is a TOML string (escaped); the body is
/// written by the TOML serializer.
pub fn provenance(
    source: &Source,
    trace: Option<&crate::sweep::TraceSpec>,
    backend: &str,
    tol: f64,
    seconds: f64,
    shard: Option<(crate::shard::Shard, (u64, u64))>,
) -> String {
    let from = match source {
        Source::Sweep { .. } => "# every lane follows from this file\n".to_string(),
        Source::Table { path, .. } => format!(
            "# every lane follows from the lane table {} ({} rows) over the [base] and \
             [friction_table] below\n",
            toml_string(&path.display().to_string()),
            source.lane_count()
        ),
    };
    let resolved = source.resolved_text(trace);
    let (shard_line, run) = match shard {
        Some((s, (a, b))) => (
            format!(
                "{SHARD_LINE}{}/{} (lanes {a} to {}, {} lanes)\n",
                s.k,
                s.n,
                b.max(1) - 1,
                b - a
            ),
            b - a,
        ),
        None => (String::new(), source.lane_count()),
    };
    format!(
        "# tswm {} resolved sweep\n{from}\
         # backend: {}, tol: {tol:e}\n\
         {LANES_LINE}{}\n\
         {shard_line}{}{resolved}",
        env!("CARGO_PKG_VERSION"),
        toml_string(backend),
        source.lane_count(),
        time_line(seconds, run),
    )
}

/// How `sweep.resolved.toml` begins its line of the run's lane count.
pub const LANES_LINE: &str = "# lanes: ";

/// The lane count the header of a `sweep.resolved.toml` states.
pub fn stated_lanes(text: &str) -> Option<u64> {
    text.lines()
        .take_while(|l| l.starts_with('#'))
        .find_map(|l| l.strip_prefix(LANES_LINE))
        .and_then(|n| n.trim().parse().ok())
}

/// How a shard's `sweep.resolved.toml` names the shard (a merge drops
/// the line).
pub const SHARD_LINE: &str = "# shard: ";
/// How `sweep.resolved.toml` begins its line of the run time.
pub const TIME_LINE: &str = "# time: ";

/// The line of the run time of `lanes` lanes in `seconds`.
pub fn time_line(seconds: f64, lanes: u64) -> String {
    format!(
        "{TIME_LINE}{seconds:.3} s ({:.0} lanes/s)\n",
        lanes as f64 / seconds.max(1e-9)
    )
}

/// Streams rows of `traces.csv` (MODEL.md section 11).
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn toml_strings_stay_on_one_line_and_read_back() {
        for s in ["a\nb.csv", "q\"uo\\te", "tab\tand\u{1}", "plain"] {
            let t = toml_string(s);
            assert_eq!(t.lines().count(), 1, "{t}");
            let v: toml::Table = toml::from_str(&format!("x = {t}")).unwrap();
            assert_eq!(v["x"].as_str(), Some(s));
        }
    }
}
