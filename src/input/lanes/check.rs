//! Checking a source's lanes before a run: every lane read once, in
//! parallel blocks for a sweep, so a bad lane is refused before anything
//! is written.

use super::kept::KEEP_BYTES;
use super::{Source, TableIn};
use crate::error::{Error, Result};
use crate::input::reader::check_quotes;
use crate::input::MAX_RUN_LANES;
use crate::params::ParamColumns;
use crate::progress::{Phase, Show};

impl Source {
    /// Checks the lanes of a sweep that run (`part` of them), blocks of
    /// them in parallel; the first bad lane is the one reported.
    pub(super) fn validate_part(
        &self,
        part: &dyn Fn(u64, u64) -> (u64, u64),
        show: &Show,
    ) -> Result<()> {
        use rayon::prelude::*;
        let Source::Sweep { sweep, file } = self else {
            return Ok(());
        };
        let total = sweep
            .lane_count_checked()
            .map_err(|m| Error::input(file, None, None, m))?;
        let (start, end) = part(total, self.shard_unit());
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

    /// Checks every lane; returns the count, and for a lane table of at
    /// most [`KEEP_BYTES`] of parameters its lanes as checked (the run
    /// reads them there: `Source::run_lanes`). Errors name the lane or row.
    pub(super) fn validate(&self, show: &Show) -> Result<(u64, Option<ParamColumns>)> {
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
        // A search reads its drives again itself (`reader_range`): nothing
        // to keep for it.
        let keep = matches!(self, Source::Table { .. }) && self.search().is_none();
        let mut kept = keep.then(ParamColumns::default);
        loop {
            show.check()?;
            buf.clear();
            r.fill(4096, &mut buf)?;
            if buf.is_empty() {
                break;
            }
            n += buf.len() as u64;
            if let Some(k) = &mut kept {
                if (k.len() + buf.len()) * ParamColumns::LANE_BYTES <= KEEP_BYTES {
                    k.extend_from(&buf, 0..buf.len());
                } else {
                    kept = None;
                }
            }
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
        Ok((n, kept))
    }
}
