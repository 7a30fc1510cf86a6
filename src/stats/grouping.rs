//! How the lanes of a run fall into groups (grid points of a sampled
//! sweep), which inputs are sampled, and a sensitivity design's shape.

use super::sensitivity::Design;
use super::sobol::Bootstrap;
use crate::input::lanes::Source;
use crate::input::sweep::Axis;
use crate::params::Num;

/// How lanes fall into groups, and which inputs are sampled.
#[derive(Clone, Debug, Default)]
pub struct Grouping {
    /// Lanes per group (0: the whole run is one group).
    pub per_group: u64,
    /// Lanes of the run.
    pub lanes: u64,
    /// The grid's axes, whose values name a group.
    pub axes: Vec<Axis>,
    /// The sampled inputs, for rank correlations.
    pub inputs: Vec<Num>,
    /// A sensitivity design, for `sensitivity.csv`.
    pub sensitivity: Option<Design>,
    /// Whether the lanes are sampled (a `[sampling]` study), so that a
    /// share has a Wilson interval; a grid or a lane table samples
    /// nothing, and a sensitivity design's lanes are not independent.
    pub sampled: bool,
    /// A search (`[search]`): each row is a drive, with the search's
    /// columns; with `at_least`, each group's share boundary.
    pub search: Option<crate::input::sweep::search::Search>,
}

impl Grouping {
    /// A sampled sweep with a grid: one group per grid point; otherwise the
    /// whole run.
    pub fn of(source: &Source) -> Grouping {
        Grouping {
            lanes: source.lane_count(),
            search: source.search().cloned(),
            ..Grouping::groups_of(source)
        }
    }

    /// [`Grouping::of`] but for the run's size.
    fn groups_of(source: &Source) -> Grouping {
        match source {
            Source::Sweep { sweep, .. } => {
                let inputs: Vec<Num> = sweep
                    .study
                    .as_ref()
                    .map(|s| s.params.iter().map(|t| t.param).collect())
                    .unwrap_or_default();
                let sensitivity = sweep.study.as_ref().and_then(|st| {
                    st.sensitivity.as_ref().map(|sn| Design {
                        inputs: inputs.clone(),
                        base: sn.base,
                        boot: Bootstrap {
                            resamples: sn.bootstrap,
                            confidence: sn.confidence,
                            seed: st.seed,
                        },
                    })
                });
                match &sweep.study {
                    Some(st) if !sweep.axes.is_empty() => Grouping {
                        per_group: st.n,
                        axes: sweep.axes.clone(),
                        inputs,
                        sampled: sensitivity.is_none(),
                        sensitivity,
                        lanes: 0,
                        search: None,
                    },
                    Some(_) => Grouping {
                        inputs,
                        sampled: sensitivity.is_none(),
                        sensitivity,
                        ..Grouping::default()
                    },
                    None => Grouping::default(),
                }
            }
            Source::Table { .. } => Grouping::default(),
        }
    }

    pub(super) fn group_of(&self, lane: u64) -> u64 {
        lane.checked_div(self.per_group).unwrap_or(0)
    }

    /// Lanes of a group: its grid point's samples, or the whole run's.
    pub(super) fn group_lanes(&self) -> u64 {
        match self.per_group {
            0 => self.lanes,
            n => n,
        }
    }
}

/// The grid values of grid point `point` (the last axis runs fastest, as
/// in `Sweep::lane_spec`); the lanes' own values may differ, when a
/// tolerance scatters an axis parameter. As text: a number as lanes.csv
/// writes it, or the word of an axis over laws or tables.
pub(crate) fn grid_values(axes: &[Axis], point: u64) -> Vec<String> {
    let mut rest = point;
    let mut v: Vec<String> = axes
        .iter()
        .rev()
        .map(|a| {
            let x = a.text(rest % a.len());
            rest /= a.len();
            x
        })
        .collect();
    v.reverse();
    v
}
