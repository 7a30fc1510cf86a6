//! Where lanes come from: a sweep file, or an explicit lane table
//! (`--lanes FILE.csv`, one lane a row, columns named as in docs/model.md
//! section 9, an empty cell meaning "not set"). Either way lanes are read
//! in order, a chunk at a time, so a sweep of any size runs in bounded
//! memory; a validation pass over every lane comes first, so bad input is
//! reported before anything is written.

use std::path::{Path, PathBuf};

mod check;
mod kept;

pub use kept::RunLanes;

pub use super::reader::LaneReader;
use crate::error::{Error, Result};
pub use crate::input::given::{SweepIn, TableIn};
use crate::input::sweep::Sweep;
use crate::params::FrictionTables;
use crate::params::{ParamColumns, Params, Spec};
use crate::progress::Show;

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
        /// A search over the rows (the sweep file's `[search]`).
        search: Option<crate::input::sweep::search::Search>,
        /// Number of rows (counted by [`Source::open`]).
        rows: u64,
        /// The rows as checked by [`Source::open`], when they are few
        /// enough to keep (`kept`): the run reads them there.
        checked: Option<Box<ParamColumns>>,
    },
}

impl Source {
    /// The lanes of a run: a sweep file, or a lane table over an optional
    /// sweep file's `[base]` and `[friction_table]`. Every lane is read
    /// and validated here, in one place for both kinds, so bad input is
    /// reported before anything is written.
    pub fn open(sweep: Option<&Path>, lanes: Option<&Path>) -> Result<Source> {
        Source::open_part(sweep, lanes, &|n, _| (0, n), &Show::default())
    }

    /// [`Source::open`] for a run of part of the lanes: `part` gives the
    /// range of a sweep's lanes that runs (a shard's, from the lane
    /// count), and only those are validated, in parallel, shown by
    /// `show` (a bar on a terminal when the part is large). A
    /// part of more than [`MAX_RUN_LANES`](super::MAX_RUN_LANES) is refused at once, with the
    /// shards that would fit.
    pub fn open_part(
        sweep: Option<&Path>,
        lanes: Option<&Path>,
        part: &dyn Fn(u64, u64) -> (u64, u64),
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
        part: &dyn Fn(u64, u64) -> (u64, u64),
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
        let (n, kept) = src.validate(show)?;
        if let Source::Table {
            rows,
            checked,
            trace,
            search,
            table,
            ..
        } = &mut src
        {
            *rows = n;
            *checked = kept.map(Box::new);
            if let (Some(s), Some(f)) = (search.as_ref(), sweep) {
                s.check_size(n)
                    .map_err(|m| Error::input(f.name(), None, Some("search"), m))?;
                if table_sets(table, s.param) {
                    return Err(Error::input(
                        table.name(),
                        Some("line 1".into()),
                        Some(s.param.name()),
                        "the sweep's [search] sets this parameter; leave its column out of the \
                         lane table",
                    ));
                }
            }
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
        let (base, tables, report, trace, search) = match sweep {
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
                        "with --lanes the sweep file may hold only [base], friction tables, [trace], \
                         [report] and [search]; the lane table gives the lanes",
                    ));
                }
                (s.base, s.tables, s.report, s.trace, s.search)
            }
            None => (
                Spec::default(),
                FrictionTables::default(),
                Default::default(),
                None,
                None,
            ),
        };
        Ok(Source::Table {
            table,
            base,
            tables,
            report,
            trace,
            search,
            rows: 0,
            checked: None,
        })
    }

    /// The sweep with every lane's source spelled out, as TOML, with the
    /// traces the run writes (`trace`): the sweep file resolved, or for a
    /// lane table the `[base]`, `[friction_table]` and `[report]` under
    /// its cells.
    pub(crate) fn resolved_text(&self, trace: Option<&crate::input::sweep::TraceSpec>) -> String {
        let mut sweep = match self {
            Source::Sweep { sweep, .. } => sweep.clone(),
            Source::Table {
                base,
                tables,
                report,
                search,
                ..
            } => Sweep {
                base: base.clone(),
                axes: Vec::new(),
                study: None,
                tables: tables.clone(),
                trace: None,
                report: report.clone(),
                search: search.clone(),
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
    pub(crate) fn lanes_at(&self, idx: &[u64]) -> Result<Vec<Params>> {
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

    /// The lanes a shard's range is a whole number of: a share search's
    /// groups (a grid point's drives are searched together), else 1.
    pub(crate) fn shard_unit(&self) -> u64 {
        match (self, self.search()) {
            (Source::Sweep { sweep, .. }, Some(s)) if s.at_least.is_some() => {
                sweep.study.as_ref().map_or(1, |st| st.n.max(1))
            }
            _ => 1,
        }
    }

    /// The sweep's search, if it asks for one.
    pub fn search(&self) -> Option<&crate::input::sweep::search::Search> {
        match self {
            Source::Sweep { sweep, .. } => sweep.search.as_ref(),
            Source::Table { search, .. } => search.as_ref(),
        }
    }

    /// The friction tables lanes may refer to.
    pub(crate) fn friction_tables(&self) -> &FrictionTables {
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

/// Whether a lane table has a column of `param` (or of a gear term that
/// gives it).
fn table_sets(table: &TableIn, param: crate::params::Num) -> bool {
    use crate::params::Param;
    table.params().iter().any(|&p| match p {
        Param::Num(n) => n == param || crate::params::gear::gives(n) == Some(param),
        _ => false,
    })
}
