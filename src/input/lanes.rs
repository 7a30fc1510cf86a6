//! Where lanes come from: a sweep file, or an explicit lane table
//! (`--lanes FILE.csv`, one lane a row, columns named as in MODEL.md
//! section 9, an empty cell meaning "not set"). Either way lanes are read
//! in order, a chunk at a time, so a sweep of any size runs in bounded
//! memory; a validation pass over every lane comes first, so bad input is
//! reported before anything is written.

use std::fs::File;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::input::sampling::Uniforms;
use crate::input::sweep::Sweep;
use crate::model::FrictionTable;
use crate::params::{Param, Params, Spec};

/// The lanes of a run.
pub enum Source {
    /// Lanes generated from a sweep file.
    Sweep {
        /// The sweep.
        sweep: Sweep,
        /// Its file, for error messages.
        file: PathBuf,
    },
    /// Lanes read from a lane table; `base` and `table` come from an
    /// optional sweep file given beside it.
    Table {
        /// The lane table.
        path: PathBuf,
        /// Defaults under the table's cells.
        base: Spec,
        /// Friction table for `friction = table` rows.
        table: Option<FrictionTable>,
        /// What the report shows.
        report: crate::input::sweep::ReportSpec,
        /// Rows to trace (the sweep file's `[trace]`).
        trace: Option<crate::input::sweep::TraceSpec>,
        /// Number of rows (counted by [`Source::open`]).
        rows: u64,
    },
}

impl Source {
    /// The lanes of a run: a sweep file, or a lane table over an optional
    /// sweep file's `[base]` and `[friction_table]`. Every lane is read
    /// and validated here, in one place for both kinds, so bad input is
    /// reported before anything is written.
    pub fn open(sweep: Option<&Path>, lanes: Option<&Path>) -> Result<Source> {
        let mut src =
            match (sweep, lanes) {
                (None, None) => return Err(Error::Usage(
                    "name a sweep file (tswm run SWEEP.toml) or a lane table (--lanes FILE.csv)"
                        .into(),
                )),
                (Some(s), None) => Source::sweep(s)?,
                (s, Some(l)) => Source::table(l, s)?,
            };
        let n = src.validate()?;
        if let Source::Table { rows, .. } = &mut src {
            *rows = n;
        }
        Ok(src)
    }

    /// Lanes of a sweep file (not yet validated lane by lane: see [`Source::open`]).
    pub fn sweep(file: &Path) -> Result<Source> {
        Ok(Source::Sweep {
            sweep: Sweep::from_file(file)?,
            file: file.to_path_buf(),
        })
    }

    /// Lanes of a lane table over an optional sweep file's base and table
    /// (rows not yet read: see [`Source::open`]).
    fn table(path: &Path, sweep_file: Option<&Path>) -> Result<Source> {
        let (base, table, report, trace) = match sweep_file {
            Some(f) => {
                let s = Sweep::from_file(f)?;
                if !s.axes.is_empty() || s.study.is_some() {
                    return Err(Error::input(
                        f,
                        None,
                        None,
                        "with --lanes the sweep file may hold only [base], [friction_table], [trace] \
                         and [report]; the lane table gives the lanes",
                    ));
                }
                (s.base, s.table, s.report, s.trace)
            }
            None => (Spec::default(), None, Default::default(), None),
        };
        Ok(Source::Table {
            path: path.to_path_buf(),
            base,
            table,
            report,
            trace,
            rows: 0,
        })
    }

    /// The sweep with every lane's source spelled out, as TOML, with the
    /// traces the run writes (`trace`): the sweep file resolved, or for a
    /// lane table the `[base]`, `[friction_table]` and `[report]` under
    /// its cells.
    pub fn resolved_text(&self, trace: Option<&crate::input::sweep::TraceSpec>) -> String {
        let mut sweep = match self {
            Source::Sweep { sweep, .. } => sweep.clone(),
            Source::Table {
                base,
                table,
                report,
                ..
            } => Sweep {
                base: base.clone(),
                axes: Vec::new(),
                study: None,
                table: *table,
                trace: None,
                report: report.clone(),
            },
        };
        sweep.trace = trace.cloned();
        toml::to_string(&sweep.resolved_toml()).unwrap_or_default()
    }

    /// The traces the source's file asks for (`[trace]`), if any.
    pub fn trace(&self) -> Option<&crate::input::sweep::TraceSpec> {
        match self {
            Source::Sweep { sweep, .. } => sweep.trace.as_ref(),
            Source::Table { trace, .. } => trace.as_ref(),
        }
    }

    /// The parameters of the lanes `idx` (ascending), read from the
    /// source (a lane table is read up to the last of them).
    pub fn lanes_at(&self, idx: &[u64]) -> Result<Vec<Params>> {
        let mut out = Vec::with_capacity(idx.len());
        match self {
            Source::Sweep { sweep, file } => {
                let mut u = sweep.uniforms();
                for &i in idx {
                    let p = sweep.lane_spec(i, &mut u).resolve(sweep.table.is_some());
                    out.push(p.map_err(|e| {
                        Error::input(file, Some(format!("lane {i}")), Some(e.param), e.msg)
                    })?);
                }
            }
            Source::Table { .. } => {
                let Some(&last) = idx.last() else {
                    return Ok(out);
                };
                // Streamed a block at a time: memory does not grow with
                // the table.
                let mut r = self.reader_range(0, last + 1)?;
                let (mut buf, mut first, mut want) = (Vec::new(), 0u64, idx.iter().peekable());
                loop {
                    buf.clear();
                    r.fill(4096, &mut buf)?;
                    if buf.is_empty() {
                        break;
                    }
                    let end = first + buf.len() as u64;
                    while let Some(&&i) = want.peek().filter(|&&&i| i < end) {
                        out.push(buf[(i - first) as usize]);
                        want.next();
                    }
                    first = end;
                }
            }
        }
        Ok(out)
    }

    /// The friction table lanes may refer to.
    pub fn friction_table(&self) -> Option<&FrictionTable> {
        match self {
            Source::Sweep { sweep, .. } => sweep.table.as_ref(),
            Source::Table { table, .. } => table.as_ref(),
        }
    }

    /// Number of lanes.
    pub fn lane_count(&self) -> u64 {
        match self {
            Source::Sweep { sweep, .. } => sweep.lane_count(),
            Source::Table { rows, .. } => *rows,
        }
    }

    /// Checks every lane; returns the count. Errors name the lane or row.
    fn validate(&self) -> Result<u64> {
        if let Source::Table { path, .. } = self {
            check_quotes(path)?;
        }
        let mut r = self.reader()?;
        let mut buf = Vec::with_capacity(4096);
        let mut n = 0;
        loop {
            buf.clear();
            r.fill(4096, &mut buf)?;
            if buf.is_empty() {
                break;
            }
            n += buf.len() as u64;
        }
        if n == 0 {
            if let Source::Table { path, .. } = self {
                return Err(Error::input(
                    path,
                    None,
                    None,
                    "the lane table has no rows; give one lane a row",
                ));
            }
        }
        Ok(n)
    }

    /// A reader from the first lane.
    pub fn reader(&self) -> Result<LaneReader<'_>> {
        // Not lane_count(): a table's rows are counted with this reader.
        self.reader_range(0, u64::MAX)
    }

    /// A reader of lanes `start..end` (a shard's); a lane's parameters do
    /// not depend on the range it is read in.
    pub fn reader_range(&self, start: u64, end: u64) -> Result<LaneReader<'_>> {
        match self {
            Source::Sweep { sweep, file } => Ok(LaneReader::Sweep {
                sweep,
                file,
                next: start,
                total: end.min(sweep.lane_count()),
                u: sweep.uniforms(),
            }),
            Source::Table {
                path, base, table, ..
            } => {
                let f = File::open(path).map_err(|e| {
                    Error::input(path, None, None, format!("cannot read the lane table: {e}"))
                })?;
                let mut rd = csv::ReaderBuilder::new()
                    .trim(csv::Trim::All)
                    .from_reader(f);
                let header = rd
                    .headers()
                    .map_err(|e| Error::input(path, Some("line 1".into()), None, e.to_string()))?
                    .clone();
                let mut cols = Vec::with_capacity(header.len());
                for name in header.iter() {
                    let p = Param::from_name(name).ok_or_else(|| {
                        Error::input(
                            path,
                            Some("line 1".into()),
                            Some(name),
                            format!(
                                "unknown column{}; allowed: {}",
                                crate::error::did_you_mean(name, Param::COLUMNS.map(|p| p.name())),
                                Param::all_names()
                            ),
                        )
                    })?;
                    if cols.contains(&p) {
                        return Err(Error::input(
                            path,
                            Some("line 1".into()),
                            Some(name),
                            "column appears twice",
                        ));
                    }
                    cols.push(p);
                }
                let mut rec = csv::StringRecord::new();
                // Rows before the range: read past (they were validated
                // when the source was opened).
                for row in 0..start {
                    if !rd
                        .read_record(&mut rec)
                        .map_err(|e| csv_error(path, row + 1, e))?
                    {
                        break;
                    }
                }
                Ok(LaneReader::Table {
                    path,
                    base,
                    has_table: table.is_some(),
                    cols,
                    rd,
                    rec,
                    row: start,
                    end,
                })
            }
        }
    }
}

/// Reads lanes in order, validated.
pub enum LaneReader<'a> {
    /// From a sweep.
    Sweep {
        /// The sweep.
        sweep: &'a Sweep,
        /// Its file.
        file: &'a Path,
        /// Next lane index.
        next: u64,
        /// Lane count.
        total: u64,
        /// The study's uniforms.
        u: Uniforms,
    },
    /// From a lane table.
    Table {
        /// The table's file.
        path: &'a Path,
        /// Defaults under the cells.
        base: &'a Spec,
        /// Whether a friction table exists.
        has_table: bool,
        /// The column of each cell.
        cols: Vec<Param>,
        /// The CSV reader.
        rd: csv::Reader<File>,
        /// Reused record.
        rec: csv::StringRecord,
        /// Rows read so far.
        row: u64,
        /// One past the last row to read.
        end: u64,
    },
}

impl LaneReader<'_> {
    /// Appends up to `max` lanes to `out` (none at the end).
    pub fn fill(&mut self, max: usize, out: &mut Vec<Params>) -> Result<()> {
        match self {
            LaneReader::Sweep {
                sweep,
                file,
                next,
                total,
                u,
            } => {
                let has_table = sweep.table.is_some();
                while out.len() < max && *next < *total {
                    let spec = sweep.lane_spec(*next, u);
                    let p = spec.resolve(has_table).map_err(|e| {
                        Error::input(file, Some(format!("lane {}", *next)), Some(e.param), e.msg)
                    })?;
                    out.push(p);
                    *next += 1;
                }
            }
            LaneReader::Table {
                path,
                base,
                has_table,
                cols,
                rd,
                rec,
                row,
                end,
            } => {
                while out.len() < max && *row < *end {
                    let more = rd
                        .read_record(rec)
                        .map_err(|e| csv_error(path, *row + 1, e))?;
                    if !more {
                        break;
                    }
                    *row += 1;
                    let line = rec.position().map_or(0, |p| p.line());
                    let at = || Some(format!("row {} (line {line})", *row));
                    let mut spec = (*base).clone();
                    for (p, cell) in cols.iter().zip(rec.iter()) {
                        spec.set_text(*p, cell)
                            .map_err(|m| Error::input(path, at(), Some(p.name()), m))?;
                    }
                    let p = spec
                        .resolve(*has_table)
                        .map_err(|e| Error::input(path, at(), Some(e.param), e.msg))?;
                    out.push(p);
                }
            }
        }
        Ok(())
    }
}

/// A CSV reader's error as a one-line error naming the row.
fn csv_error(path: &Path, row: u64, e: csv::Error) -> Error {
    let line = e.position().map_or(0, |p| p.line());
    let at = Some(format!("row {row} (line {line})"));
    match e.kind() {
        csv::ErrorKind::UnequalLengths {
            expected_len, len, ..
        } => Error::input(
            path,
            at,
            None,
            format!(
                "has {len} cells but the header has {expected_len}; give one cell per column \
                 (an empty cell means \"not set\")"
            ),
        ),
        csv::ErrorKind::Utf8 { .. } => Error::input(path, at, None, "is not valid UTF-8 text"),
        _ => Error::input(path, at, None, e.to_string()),
    }
}

/// Refuses a quote that is opened and never closed: the CSV reader would
/// take the rest of the file as one cell (`"100` as 100). Quotes of a
/// well-formed table pair up (`""` inside a quoted cell is one quote), so
/// their count is even; the last one opened names the line.
fn check_quotes(path: &Path) -> Result<()> {
    use std::io::Read;
    let mut f = File::open(path)
        .map_err(|e| Error::input(path, None, None, format!("cannot read the lane table: {e}")))?;
    let mut buf = vec![0u8; 1 << 16];
    let (mut quotes, mut line, mut last_line) = (0u64, 1u64, 0u64);
    loop {
        let n = f.read(&mut buf).map_err(|e| Error::io(path, e))?;
        if n == 0 {
            break;
        }
        for &b in &buf[..n] {
            match b {
                b'"' => {
                    quotes += 1;
                    last_line = line;
                }
                b'\n' => line += 1,
                _ => {}
            }
        }
    }
    if quotes % 2 == 1 {
        return Err(Error::input(
            path,
            Some(format!("line {last_line}")),
            None,
            "a quote (\") is opened and never closed; close it or remove it",
        ));
    }
    Ok(())
}
