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
pub use crate::input::given::{SweepIn, TableIn};
use crate::input::sweep::Sweep;
use crate::params::FrictionTables;
use crate::params::{ParamColumns, Params, Spec};
use crate::progress::{Phase, Show};

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
        table: TableIn,
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

/// Most lanes one run (or one shard) takes: 10^9, an hour or two of a
/// many-core CPU or minutes of a data-centre GPU, and some 500 GB of
/// `lanes.csv`. A larger sweep runs as shards (each checked alone), so no
/// run spends hours checking lanes before it writes anything.
pub const MAX_RUN_LANES: u64 = 1_000_000_000;

impl Source {
    /// The lanes of a run: a sweep file, or a lane table over an optional
    /// sweep file's `[base]` and `[friction_table]`. Every lane is read
    /// and validated here, in one place for both kinds, so bad input is
    /// reported before anything is written.
    pub fn open(sweep: Option<&Path>, lanes: Option<&Path>) -> Result<Source> {
        Source::open_part(sweep, lanes, &|n| (0, n), &Show::default())
    }

    /// [`Source::open`] for a run of part of the lanes: `part` gives the
    /// range of a sweep's lanes that runs (a shard's, from the lane
    /// count), and only those are validated, in parallel, shown by
    /// `show` (a bar on a terminal when the part is large). A
    /// part of more than [`MAX_RUN_LANES`] is refused at once, with the
    /// shards that would fit.
    pub fn open_part(
        sweep: Option<&Path>,
        lanes: Option<&Path>,
        part: &dyn Fn(u64) -> (u64, u64),
        show: &Show,
    ) -> Result<Source> {
        Source::open_from(
            sweep.map(SweepIn::File),
            lanes.map(|l| TableIn::File(l.to_path_buf())),
            part,
            show,
        )
    }

    /// [`Source::open_part`] of a sweep file or text, and a lane table
    /// file or a table in memory.
    pub fn open_from(
        sweep: Option<SweepIn<'_>>,
        lanes: Option<TableIn>,
        part: &dyn Fn(u64) -> (u64, u64),
        show: &Show,
    ) -> Result<Source> {
        if let (Some(s), None) = (sweep, &lanes) {
            let src = Source::sweep_in(s)?;
            src.validate_part(part, show)?;
            return Ok(src);
        }
        let mut src =
            match (sweep, lanes) {
                (None, None) => return Err(Error::Usage(
                    "name a sweep file (tswm run SWEEP.toml) or a lane table (--lanes FILE.csv)"
                        .into(),
                )),
                (Some(s), None) => Source::sweep_in(s)?,
                (s, Some(l)) => Source::table(l, s)?,
            };
        let n = src.validate(show)?;
        if let Source::Table { rows, trace, .. } = &mut src {
            *rows = n;
            if let (Some(t), Some(f)) = (trace.as_ref(), sweep) {
                if let Some(&bad) = t.lanes.iter().find(|&&l| l >= n) {
                    return Err(Error::input(
                        f.name(),
                        None,
                        Some("trace"),
                        format!(
                            "lane {bad} is not in the run; allowed: 0 to {} (the lane table's rows)",
                            n - 1
                        ),
                    ));
                }
            }
        }
        Ok(src)
    }

    /// Lanes of a sweep file (not yet validated lane by lane: see [`Source::open`]).
    pub fn sweep(file: &Path) -> Result<Source> {
        Source::sweep_in(SweepIn::File(file))
    }

    /// Lanes of a sweep file or text (not yet validated lane by lane).
    fn sweep_in(s: SweepIn<'_>) -> Result<Source> {
        Ok(Source::Sweep {
            sweep: Sweep::parse(s.name(), &s.text()?)?,
            file: s.name().to_path_buf(),
        })
    }

    /// Lanes of a lane table over an optional sweep's base and table
    /// (rows not yet read: see [`Source::open`]).
    fn table(table: TableIn, sweep: Option<SweepIn<'_>>) -> Result<Source> {
        let (base, tables, report, trace) = match sweep {
            Some(f) => {
                // Its `[trace]` lanes are the table's rows: checked once
                // they are counted (`Source::open`).
                let text = f.text()?;
                let s = Sweep::parse_with_lanes(f.name(), &text, Some(u64::MAX))?;
                if !s.axes.is_empty() || s.study.is_some() {
                    return Err(Error::input(
                        f.name(),
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
            table,
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
                let (mut buf, mut first, mut want) =
                    (ParamColumns::default(), 0u64, idx.iter().peekable());
                loop {
                    buf.clear();
                    r.fill(4096, &mut buf)?;
                    if buf.is_empty() {
                        break;
                    }
                    let end = first + buf.len() as u64;
                    while let Some(&&i) = want.peek().filter(|&&&i| i < end) {
                        out.push(buf.params((i - first) as usize));
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

    /// Checks the lanes of a sweep that run (`part` of them), blocks of
    /// them in parallel; the first bad lane is the one reported.
    fn validate_part(&self, part: &dyn Fn(u64) -> (u64, u64), show: &Show) -> Result<()> {
        use rayon::prelude::*;
        let Source::Sweep { sweep, file } = self else {
            return Ok(());
        };
        let total = sweep
            .lane_count_checked()
            .map_err(|m| Error::input(file, None, None, m))?;
        let (start, end) = part(total);
        let n = end - start;
        if n > MAX_RUN_LANES {
            let shards = n.div_ceil(MAX_RUN_LANES);
            return Err(Error::input(
                file,
                None,
                None,
                // One wording for the command line and Python alike.
                format!(
                    "{n} lanes are more than one run takes (at most {MAX_RUN_LANES:.0e}); run them \
                     as at least {shards} parts of at most {MAX_RUN_LANES:.0e} lanes: from the \
                     command line as {shards} shards (tswm run SWEEP --shard K/{shards}, \
                     docs/cluster.md), or in Python each a tswm.run of its own (split a grid \
                     axis's values, or a lane table's rows: docs/python.md)"
                ),
            ));
        }
        const BLOCK: u64 = 1 << 16;
        let bar = show.bar(Phase::Checking, n >= 10_000_000, n, "checking lanes");
        let blocks = n.div_ceil(BLOCK);
        let bad = (0..blocks)
            .into_par_iter()
            .map(|b| {
                show.check()?;
                let (a, z) = (start + b * BLOCK, (start + (b + 1) * BLOCK).min(end));
                let mut r = self.reader_range(a, z)?;
                let mut buf = ParamColumns::with_capacity(4096);
                loop {
                    buf.clear();
                    r.fill(4096, &mut buf)?;
                    if buf.is_empty() {
                        break;
                    }
                }
                bar.inc(z - a);
                Ok(())
            })
            .find_first(|r: &Result<()>| r.is_err());
        bar.finish_and_clear();
        bad.unwrap_or(Ok(()))
    }

    /// Checks every lane; returns the count. Errors name the lane or row.
    fn validate(&self, show: &Show) -> Result<u64> {
        if let Source::Table {
            table: TableIn::File(path),
            ..
        } = self
        {
            check_quotes(path)?;
        }
        let mut r = self.reader()?;
        let mut buf = ParamColumns::with_capacity(4096);
        let mut n = 0;
        loop {
            show.check()?;
            buf.clear();
            r.fill(4096, &mut buf)?;
            if buf.is_empty() {
                break;
            }
            n += buf.len() as u64;
        }
        if n == 0 {
            if let Source::Table { table, .. } = self {
                return Err(Error::input(
                    table.name(),
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
                spec: Box::default(),
            }),
            Source::Table {
                table: TableIn::File(path),
                base,
                tables,
                ..
            } => LaneReader::table(path, base, &tables.names, start, end),
            Source::Table {
                table: TableIn::Frame(frame),
                base,
                tables,
                ..
            } => Ok(LaneReader::frame(frame, base, &tables.names, start, end)),
        }
    }
}
