//! Where lanes come from: a sweep file, or an explicit lane table
//! (`--lanes FILE.csv`, one lane a row, columns named as in docs/model.md
//! section 9, an empty cell meaning "not set"). Either way lanes are read
//! in order, a chunk at a time, so a sweep of any size runs in bounded
//! memory; a validation pass over every lane comes first, so bad input is
//! reported before anything is written.

use std::path::{Path, PathBuf};

use super::reader::check_quotes;
pub use super::reader::LaneReader;
use crate::error::{Error, Result};
use crate::input::sweep::Sweep;
use crate::model::FrictionTables;
use crate::params::{Params, Spec};

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
        /// Friction tables for `friction = table` rows.
        tables: FrictionTables,
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
        let (base, tables, report, trace) = match sweep_file {
            Some(f) => {
                let s = Sweep::from_file(f)?;
                if !s.axes.is_empty() || s.study.is_some() {
                    return Err(Error::input(
                        f,
                        None,
                        None,
                        "with --lanes the sweep file may hold only [base], friction tables, [trace] \
                         and [report]; the lane table gives the lanes",
                    ));
                }
                (s.base, s.tables, s.report, s.trace)
            }
            None => (
                Spec::default(),
                FrictionTables::default(),
                Default::default(),
                None,
            ),
        };
        Ok(Source::Table {
            path: path.to_path_buf(),
            base,
            tables,
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
                tables,
                report,
                ..
            } => Sweep {
                base: base.clone(),
                axes: Vec::new(),
                study: None,
                tables: tables.clone(),
                trace: None,
                report: report.clone(),
                key_lines: Vec::new(),
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
                    let p = sweep.lane_spec(i, &mut u).resolve(&sweep.tables.names);
                    out.push(p.map_err(|e| {
                        Error::input(file, Some(sweep.lane_at(i, e.param)), Some(e.param), e.msg)
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

    /// The friction tables lanes may refer to.
    pub fn friction_tables(&self) -> &FrictionTables {
        match self {
            Source::Sweep { sweep, .. } => &sweep.tables,
            Source::Table { tables, .. } => tables,
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
                path, base, tables, ..
            } => LaneReader::table(path, base, &tables.names, start, end),
        }
    }
}
