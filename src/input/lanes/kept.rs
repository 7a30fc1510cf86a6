//! The lanes a run reads: a lane table's as its check kept them, or read
//! again a chunk at a time.
//!
//! A run reads every lane twice: once to check them all before anything
//! is written, once to run them. For a lane table the second reading
//! parsed and checked every row again, a third of a run's work on one
//! core for cheap lanes (docs/performance.md). A table of at most
//! [`KEEP_BYTES`] of parameters (about 400,000 lanes) is kept as the
//! check read it, and the run copies its chunks from there; a larger one
//! is read again, so memory stays bounded whatever the table's size.

use super::{LaneReader, Source};
use crate::error::Result;
use crate::params::ParamColumns;

/// The most parameter bytes of a lane table kept from its check.
pub(crate) const KEEP_BYTES: usize = 128 << 20;

/// Where a run's lanes come from ([`Source::run_lanes`]).
pub enum RunLanes<'a> {
    /// Read (a sweep's lanes generated, a table's rows parsed and checked).
    Read(Box<LaneReader<'a>>),
    /// Copied from the lanes the check kept.
    Kept {
        /// The kept lanes.
        cols: &'a ParamColumns,
        /// The next lane.
        next: usize,
        /// One past the last lane to read.
        end: usize,
    },
}

impl RunLanes<'_> {
    /// Appends up to `max` lanes to `out` (none at the end), as
    /// [`LaneReader::fill`] does.
    pub fn fill(&mut self, max: usize, out: &mut ParamColumns) -> Result<()> {
        match self {
            RunLanes::Read(r) => r.fill(max, out),
            RunLanes::Kept { cols, next, end } => {
                let to = (*next + max.saturating_sub(out.len())).min(*end);
                out.extend_from(cols, *next..to);
                *next = to;
                Ok(())
            }
        }
    }
}

impl Source {
    /// The lanes `start..end` of a run: from the lanes the check kept
    /// when it kept them, else from [`Source::reader_range`].
    pub fn run_lanes(&self, start: u64, end: u64) -> Result<RunLanes<'_>> {
        if let Source::Table {
            checked: Some(cols),
            ..
        } = self
        {
            let len = cols.len() as u64;
            return Ok(RunLanes::Kept {
                cols,
                next: start.min(len) as usize,
                end: end.min(len) as usize,
            });
        }
        self.reader_range(start, end)
            .map(|r| RunLanes::Read(Box::new(r)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::sampling::Uniforms;

    /// A run reads from the kept lanes exactly what it would read from the
    /// table, for any range (a shard's) and chunk size.
    #[test]
    fn kept_lanes_are_the_lanes_read_again() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("lanes.csv");
        let mut u = Uniforms::new(5);
        let mut text = String::from("gamma_deg,f2,friction,mu,motor,f1,t_end\n");
        for i in 0..9000 {
            let (law, mu) = if i % 3 == 0 {
                ("coulomb", format!("{}", 0.02 + 0.1 * u.next()))
            } else {
                ("paper", String::new())
            };
            let (motor, f1) = if i % 4 == 0 {
                ("constant", format!("{}", 2000.0 * u.next()))
            } else {
                ("", String::new())
            };
            text += &format!(
                "{},{},{law},{mu},{motor},{f1},{}\n",
                2.0 + 20.0 * u.next(),
                -5000.0 + 10000.0 * u.next(),
                0.5 + u.next()
            );
        }
        std::fs::write(&path, text).unwrap();
        let src = Source::open(None, Some(&path)).unwrap();
        assert!(matches!(
            src,
            Source::Table {
                checked: Some(_),
                ..
            }
        ));
        for (a, b, chunk) in [
            (0, 9000, 4096),
            (0, u64::MAX, 1000),
            (17, 5000, 333),
            (8999, 9000, 7),
        ] {
            let (mut kept, mut read) = (
                src.run_lanes(a, b).unwrap(),
                src.reader_range(a, b).unwrap(),
            );
            assert!(matches!(kept, RunLanes::Kept { .. }));
            let (mut x, mut y) = (ParamColumns::default(), ParamColumns::default());
            loop {
                x.clear();
                y.clear();
                kept.fill(chunk, &mut x).unwrap();
                read.fill(chunk, &mut y).unwrap();
                // Compared as text: unset values are NaN, never == NaN.
                assert_eq!(
                    format!("{x:?}"),
                    format!("{y:?}"),
                    "range {a}..{b}, chunk {chunk}"
                );
                if x.is_empty() {
                    break;
                }
            }
        }
    }
}
