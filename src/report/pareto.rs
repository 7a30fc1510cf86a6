//! The report's trade-offs section (`[report] pareto`): the designs that
//! no other design beats on every objective (the non-dominated front),
//! drawn over the cloud of all designs and listed with their parameters.
//!
//! A design is a grid point (with a tolerance study: the mean of each
//! objective over its drives whose value is a number), or a lane of a run
//! without a study. Design a dominates b when a is at least as good on
//! every objective and better on one. The front is kept as the rows
//! stream past (a design either joins it, removing those it dominates,
//! or is dominated), and the cloud is every k-th design, k doubling as it
//! fills: bounded memory for any number of designs.

use std::path::Path;

use plotters::prelude::*;

use super::charts::PALETTE;
use super::html::Page;
use super::plots::{chart, err, inline, tick, Axis, SIZE};
use crate::columns::LANE;
use crate::error::Result;
use crate::input::sweep::pareto::Objective;
use crate::input::sweep::Sweep;
use crate::output::table::read_batches;
use crate::params::Num;

/// Most designs on a front (more: the section says so, and lists none).
pub(crate) const MAX_FRONT: usize = 5_000;

/// Most designs drawn in the cloud.
const CLOUD: usize = 4_096;

/// Front designs listed in the table at most (all are drawn).
const LISTED: usize = 60;

/// Numeric parameters a lane-table design is listed with at most (those
/// that differ across the front).
const LISTED_PARAMS: usize = 6;

/// A design: its index, its objectives' values, and (a lane of a run
/// without a grid) its numeric parameters.
#[derive(Clone, Debug)]
struct Design {
    id: u64,
    v: Vec<f64>,
    params: Vec<f64>,
}

/// The fronts and cloud as designs stream past.
struct Front {
    objectives: Vec<Objective>,
    front: Vec<Design>,
    overflow: bool,
    cloud: Vec<Design>,
    stride: u64,
    designs: u64,
    /// Designs left out: an objective without a number.
    without: u64,
}

/// Whether `a` dominates `b` (every gain at least, one greater).
fn dominates(o: &[Objective], a: &[f64], b: &[f64]) -> bool {
    let mut better = false;
    for ((o, &x), &y) in o.iter().zip(a).zip(b) {
        let (gx, gy) = (o.gain(x), o.gain(y));
        if gx < gy {
            return false;
        }
        better |= gx > gy;
    }
    better
}

impl Front {
    fn add(&mut self, d: Design) {
        self.designs += 1;
        if d.v.iter().any(|x| !x.is_finite()) {
            self.without += 1;
            return;
        }
        if d.id.is_multiple_of(self.stride) {
            self.cloud.push(d.clone());
            if self.cloud.len() > CLOUD {
                self.stride *= 2;
                let s = self.stride;
                self.cloud.retain(|c| c.id.is_multiple_of(s));
            }
        }
        if self.overflow {
            return;
        }
        let o = &self.objectives;
        if self.front.iter().any(|f| dominates(o, &f.v, &d.v)) {
            return;
        }
        self.front.retain(|f| !dominates(o, &d.v, &f.v));
        self.front.push(d);
        if self.front.len() > MAX_FRONT {
            self.overflow = true;
            self.front.clear();
        }
    }
}

/// Reads the run's designs from its results table in `dir`.
fn read(dir: &Path, sweep: &Sweep, objectives: &[Objective]) -> Result<Front> {
    let per = sweep.study.as_ref().map_or(1, |s| s.n.max(1));
    let listed: Vec<&str> = if sweep.axes.is_empty() {
        Num::ALL.iter().map(|p| p.name()).collect()
    } else {
        Vec::new()
    };
    let mut names = vec![LANE];
    names.extend(objectives.iter().map(|o| o.column));
    names.extend(&listed);
    let mut f = Front {
        objectives: objectives.to_vec(),
        front: Vec::new(),
        overflow: false,
        cloud: Vec::new(),
        stride: 1,
        designs: 0,
        without: 0,
    };
    let k = objectives.len();
    let mut cur: Option<Summing> = None;
    read_batches(dir, &names, |b| {
        let num = |n: &str| super::cells::numbers(b, n);
        let lanes = super::cells::numbers(b, LANE);
        let cols: Vec<Vec<f64>> = objectives.iter().map(|o| num(o.column)).collect();
        let params: Vec<Vec<f64>> = listed.iter().map(|n| num(n)).collect();
        for r in 0..b.num_rows() {
            let id = lanes[r] as u64 / per;
            if cur.as_ref().is_some_and(|c| c.id != id) {
                f.add(cur.take().expect("a design").mean());
            }
            let c = cur.get_or_insert_with(|| Summing {
                id,
                sums: vec![0.0; k],
                counts: vec![0; k],
                params: params.iter().map(|col| col[r]).collect(),
            });
            for (j, col) in cols.iter().enumerate() {
                if col[r].is_finite() {
                    c.sums[j] += col[r];
                    c.counts[j] += 1;
                }
            }
        }
        Ok(())
    })?;
    if let Some(c) = cur {
        f.add(c.mean());
    }
    Ok(f)
}

/// The design being summed as its rows stream past: the sums and counts
/// of each objective's numbers.
struct Summing {
    id: u64,
    sums: Vec<f64>,
    counts: Vec<u64>,
    params: Vec<f64>,
}

impl Summing {
    /// The design: each objective's mean (NaN for one without a number).
    fn mean(self) -> Design {
        let v = self
            .sums
            .iter()
            .zip(&self.counts)
            .map(|(s, &n)| if n == 0 { f64::NAN } else { s / n as f64 })
            .collect();
        Design {
            id: self.id,
            v,
            params: self.params,
        }
    }
}

/// The trade-offs section of the run in `dir`.
pub fn section(page: &mut Page, dir: &Path, sweep: &Sweep) -> Result<()> {
    let objectives = &sweep.report.pareto;
    if objectives.is_empty() {
        return Ok(());
    }
    let said: Vec<String> = objectives.iter().map(Objective::text).collect();
    page.section(&format!("Trade-offs: {}", said.join(", ")));
    let f = read(dir, sweep, objectives)?;
    let per = match &sweep.study {
        Some(st) => format!(
            "a grid point (each objective the mean over its {} drives)",
            st.n
        ),
        None => "a lane".into(),
    };
    let on = match f.overflow {
        true => format!("more than {MAX_FRONT}"),
        false => f.front.len().to_string(),
    };
    page.note(&format!(
        "A design is {per}. The front holds the designs that no other design beats on every \
         objective (at least as good on each, better on one); {on} of {} designs are on it{}.",
        f.designs,
        match f.without {
            0 => String::new(),
            w => format!(" ({w} left out: an objective without a number, e.g. at rest)"),
        }
    ));
    if f.designs - f.without < 2 {
        page.warning(
            "A front needs designs to compare: give the sweep [[grid]] axes (or a lane table) \
             with at least two designs whose objectives are numbers.",
        );
        return Ok(());
    }
    if f.overflow {
        page.warning(&format!(
            "More than {MAX_FRONT} designs were on the front of the designs read up to some row \
             (those that no design before them beats): too many to keep, so the front is \
             neither drawn nor listed (the objectives hardly conflict, or the grid is very \
             fine); narrow the grid or choose other objectives."
        ));
        return Ok(());
    }
    let mut front = f.front.clone();
    front.sort_by(|a, b| {
        let g = |d: &Design| objectives[0].gain(d.v[0]);
        g(b).total_cmp(&g(a)).then(a.id.cmp(&b.id))
    });
    page.figures(charts(objectives, &f.cloud, &front));
    list(page, sweep, objectives, &front);
    Ok(())
}

/// The front over the cloud: one chart for two objectives, one a pair for
/// three.
fn charts(
    o: &[Objective],
    cloud: &[Design],
    front: &[Design],
) -> Vec<std::result::Result<String, String>> {
    let pairs: &[(usize, usize)] = if o.len() == 2 {
        &[(0, 1)]
    } else {
        &[(0, 1), (0, 2), (1, 2)]
    };
    pairs
        .iter()
        .map(|&(i, j)| pair_chart(o, cloud, front, (i, j)))
        .collect()
}

/// Objectives `i` and `j`: the cloud in grey, the front in colour (joined
/// in order of objective `i` where there are only two objectives).
fn pair_chart(
    o: &[Objective],
    cloud: &[Design],
    front: &[Design],
    (i, j): (usize, usize),
) -> std::result::Result<String, String> {
    let label = |k: usize| {
        let c = crate::columns::result(o[k].column).map_or(o[k].column.to_string(), |c| c.label());
        format!(
            "{}, {}",
            c,
            if o[k].max {
                "larger is better"
            } else {
                "smaller is better"
            }
        )
    };
    let all = || cloud.iter().chain(front);
    let x = Axis::numeric(&label(i), all().map(|d| d.v[i]));
    let y = Axis::numeric(&label(j), all().map(|d| d.v[j]));
    let pt = |d: &Design| (x.map(d.v[i]), y.map(d.v[j]));
    let col = PALETTE[1];
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let mut c = chart(&root, "designs and their front", &x, &y, true)?;
        c.draw_series(
            cloud
                .iter()
                .map(|d| Circle::new(pt(d), 2, BLACK.mix(0.25).filled())),
        )
        .map_err(err)?
        .label("every design (a sample where many)")
        .legend(|(x, y)| Circle::new((x + 8, y), 2, BLACK.mix(0.25).filled()));
        if o.len() == 2 {
            let mut line: Vec<(f64, f64)> = front.iter().map(pt).collect();
            line.sort_by(|a, b| a.0.total_cmp(&b.0));
            c.draw_series(LineSeries::new(line, col.stroke_width(1)))
                .map_err(err)?;
        }
        c.draw_series(front.iter().map(|d| Circle::new(pt(d), 4, col.filled())))
            .map_err(err)?
            .label("the front")
            .legend(move |(x, y)| Circle::new((x + 8, y), 4, col.filled()));
        // The legend in the corner beyond the front, where no design is.
        let corner = match (o[i].max, o[j].max) {
            (true, true) => SeriesLabelPosition::UpperRight,
            (true, false) => SeriesLabelPosition::LowerRight,
            (false, true) => SeriesLabelPosition::UpperLeft,
            (false, false) => SeriesLabelPosition::LowerLeft,
        };
        c.configure_series_labels()
            .position(corner)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(err)?;
        root.present().map_err(err)?;
    }
    Ok(inline(svg))
}

/// The front's designs, best first on the first objective: each with its
/// grid values (or its lane and the parameters that differ across the
/// front) and its objectives.
fn list(page: &mut Page, sweep: &Sweep, o: &[Objective], front: &[Design]) {
    let mut head: Vec<String> = vec!["design".into()];
    let varying: Vec<usize> = if sweep.axes.is_empty() {
        (0..Num::ALL.len())
            .filter(|&p| {
                let v = |d: &Design| d.params.get(p).copied().unwrap_or(f64::NAN);
                front
                    .iter()
                    .any(|d| v(d).to_bits() != v(&front[0]).to_bits())
            })
            .take(LISTED_PARAMS)
            .collect()
    } else {
        Vec::new()
    };
    head.extend(sweep.axes.iter().map(|a| a.param.name().to_string()));
    head.extend(varying.iter().map(|&p| Num::ALL[p].name().to_string()));
    head.extend(o.iter().map(Objective::text));
    let rows: Vec<Vec<String>> = front
        .iter()
        .take(LISTED)
        .map(|d| {
            let mut r = vec![match sweep.study {
                Some(_) => format!("grid point {}", d.id),
                None => format!("lane {}", d.id),
            }];
            r.extend(crate::stats::grouping::grid_values(&sweep.axes, d.id));
            r.extend(varying.iter().map(|&p| tick(d.params[p])));
            r.extend(d.v.iter().map(|&v| tick(v)));
            r
        })
        .collect();
    let head: Vec<&str> = head.iter().map(String::as_str).collect();
    page.table(&head, &rows);
    if front.len() > LISTED {
        page.note(&format!(
            "The first {LISTED} of the front's {} designs are listed; all are drawn.",
            front.len()
        ));
    }
}
