//! Reading an output folder for the report: `summary.csv` for the shown
//! groups, one pass over the results table into bounded aggregates, and
//! the traced lanes of `traces.csv`, decimated to the plot's resolution.
//!
//! Nothing read is trusted to be well formed: a cell that is not of its
//! column's kind, a word its column does not have, a lane out of order or
//! outside the run, a table shorter or longer than the run it belongs to
//! each stop the report with a one-line error (exit code 2), never a
//! panic and never a page of wrong numbers. Time and memory grow with the
//! folder's rows only linearly and with nothing else.

use std::path::Path;

use crate::columns::{results, Column, Summary};
use crate::error::{Error, Result};
use crate::lanes_file::{columns, Cell, RowReader};
use crate::outdir::names::{SUMMARY, TRACES};
use crate::params::Num;
use crate::sweep::{Axis, Sweep};

pub use super::aggregates::{GroupData, LineData, MapData, RequireData, TraceData};

/// Final contacts as `lanes.csv` spells them, with the words the report
/// uses; the order of the maps' colours.
pub const CONTACT_NAMES: [(&str, &str); 3] = [("stick", "held"), ("aa", "a-a"), ("bb", "b-b")];

/// Most cells along one axis of a map, and points along a line; longer
/// axes are binned.
const MAP_CELLS: u64 = 120;
pub(super) const LINE_POINTS: u64 = 1000;
/// Lanes listed by name among those that could not be finished.
const UNFINISHED_SHOWN: usize = 20;
/// Histogram bins.
const BINS: usize = 40;
/// Traced lanes plotted.
const TRACES_SHOWN: usize = 6;

/// What the report needs from an output folder.
pub struct Folder {
    /// The table's file name (`lanes.csv` or `lanes.parquet`).
    pub table: &'static str,
    pub lanes: u64,
    /// Lanes per status word, in the table's order of words.
    pub by_status: Vec<(&'static str, u64)>,
    pub by_contact: [u64; 3],
    /// Lanes per `hold` word (held, runs_away, coasting).
    pub by_hold: Vec<(&'static str, u64)>,
    /// Lanes whose motor is cut before t_end (those with a `hold`).
    pub hold_lanes: u64,
    /// The largest t_end and t_max among lanes still coasting.
    pub coasting_t_end: f64,
    pub coasting_t_max: f64,
    pub unfinished: Vec<Vec<String>>,
    pub unfinished_total: u64,
    /// Parameters listed for unfinished lanes: the grid's and the sampled.
    pub shown_params: Vec<Num>,
    pub results: Vec<&'static Column>,
    pub study: bool,
    pub map: Option<MapData>,
    pub line: Option<LineData>,
    pub groups: Vec<GroupData>,
    pub groups_total: usize,
    pub traces: Vec<TraceData>,
    pub require: Option<RequireData>,
}

fn open_csv(path: &Path) -> Result<csv::Reader<std::fs::File>> {
    csv::Reader::from_path(path)
        .map_err(|e| Error::input(path, None, None, format!("cannot read it: {e}")))
}

fn bad_row(path: &Path, e: csv::Error) -> Error {
    let line = e.position().map(|p| format!("line {}", p.line()));
    Error::input(path, line, None, format!("not a tswm table: {e}"))
}

fn column(path: &Path, head: &csv::ByteRecord, name: &str) -> Result<usize> {
    head.iter()
        .position(|h| h == name.as_bytes())
        .ok_or_else(|| Error::input(path, Some("line 1".into()), Some(name), "column missing"))
}

/// A number cell of a CSV record: empty is NaN, anything else must be a
/// finite number (else an error naming the line and column).
fn num(path: &Path, rec: &csv::ByteRecord, i: usize, name: &str) -> Result<f64> {
    let t = rec.get(i).unwrap_or(b"");
    if t.is_empty() {
        return Ok(f64::NAN);
    }
    match std::str::from_utf8(t)
        .ok()
        .and_then(|s| s.parse::<f64>().ok())
    {
        Some(v) if v.is_finite() => Ok(v),
        _ => Err(Error::input(
            path,
            rec.position().map(|p| format!("line {}", p.line())),
            Some(name),
            format!(
                "`{}` is not a finite number; not a tswm table",
                crate::error::shown(&String::from_utf8_lossy(t), 40)
            ),
        )),
    }
}

fn text(rec: &csv::ByteRecord, i: usize) -> String {
    String::from_utf8_lossy(rec.get(i).unwrap_or(b"")).into_owned()
}

/// Index `i` of `len` into `bins` bins.
pub(super) fn bin(i: u64, len: u64, bins: u64) -> usize {
    if len <= bins {
        i as usize
    } else {
        (i as u128 * bins as u128 / len as u128) as usize
    }
}

/// The axis value shown for each bin (its first grid value).
pub(super) fn bin_values(a: &Axis, bins: u64) -> Vec<f64> {
    let len = a.len();
    let n = len.min(bins);
    (0..n)
        .map(|b| {
            a.value(if len <= bins {
                b
            } else {
                (b as u128 * len as u128).div_ceil(bins as u128) as u64
            })
        })
        .collect()
}

/// The words of a word column of the results table.
fn words_of(c: &Column) -> Vec<&'static str> {
    match c.summary {
        Summary::Shares(w, _) => w(),
        _ => Vec::new(),
    }
}

/// Where the scan reads a row of the results table.
struct Cols {
    lane: usize,
    status: usize,
    contact: usize,
    hold: usize,
    lock: usize,
    t_end: usize,
    t_max: usize,
    results: Vec<usize>,
    shown: Vec<usize>,
    require: Option<usize>,
    /// Word columns: position and allowed words ("" allowed where noted).
    words: Vec<(usize, &'static str, Vec<&'static str>)>,
}

impl Folder {
    /// Reads the folder `dir` of a run of `sweep`, whose
    /// `sweep.resolved.toml` states `stated` lanes.
    pub fn read(dir: &Path, sweep: &Sweep, stated: u64) -> Result<Folder> {
        let spec = &sweep.report;
        let results: Vec<&'static Column> = spec
            .results()
            .iter()
            .filter_map(|n| crate::columns::result(n))
            .collect();
        let panels = spec.panels();
        let study = sweep.study.is_some();
        let lens: Vec<u64> = sweep.axes.iter().map(|a| a.len()).collect();
        let mut shown_params: Vec<Num> = sweep.axes.iter().map(|a| a.param).collect();
        if let Some(st) = &sweep.study {
            shown_params.extend(st.params.iter().map(|t| t.param));
        }
        let word_counts = |name: &str| -> Vec<(&'static str, u64)> {
            crate::columns::result(name)
                .map(|c| words_of(c).into_iter().map(|w| (w, 0)).collect())
                .unwrap_or_default()
        };
        let mut f = Folder {
            table: crate::lanes_file::Format::of_folder(dir)?.file_name(),
            lanes: 0,
            by_status: word_counts("status"),
            by_contact: [0; 3],
            by_hold: word_counts("hold"),
            hold_lanes: 0,
            coasting_t_end: f64::NAN,
            coasting_t_max: f64::NAN,
            unfinished: Vec::new(),
            unfinished_total: 0,
            shown_params,
            results,
            study,
            map: None,
            line: None,
            groups: Vec::new(),
            groups_total: 0,
            traces: Vec::new(),
            require: spec
                .require
                .as_ref()
                .map(|r| RequireData::new(r.clone(), sweep, panels, LINE_POINTS)),
        };
        if sweep.axes.len() >= 2 {
            f.map = Some(MapData::new(sweep, panels, MAP_CELLS));
        } else if sweep.axes.len() == 1 {
            let a = &sweep.axes[0];
            let xs = bin_values(a, LINE_POINTS);
            let n = xs.len();
            f.line = Some(LineData {
                axis: a.param,
                log: matches!(a.values, crate::sweep::AxisValues::Range { log: true, .. }),
                xs,
                len: a.len(),
                acc: vec![vec![(0.0, 0, f64::INFINITY, f64::NEG_INFINITY); n]; f.results.len()],
                contact: vec![[0; 3]; n],
            });
        }
        if study {
            let groups_total = if sweep.axes.is_empty() {
                1
            } else {
                lens.iter().product::<u64>() as usize
            };
            f.groups_total = groups_total;
            f.read_summary(dir, sweep, groups_total.min(panels))?;
        }
        let traced = f.scan_lanes(dir, sweep, stated)?;
        f.read_traces(dir, &traced)?;
        Ok(f)
    }

    /// The shown groups' rows of summary.csv: tables, histogram ranges
    /// and rank correlations.
    fn read_summary(&mut self, dir: &Path, sweep: &Sweep, shown: usize) -> Result<()> {
        let path = dir.join(SUMMARY);
        let mut rd = open_csv(&path)?;
        let head = rd.byte_headers().map_err(|e| bad_row(&path, e))?.clone();
        let c = |n: &str| column(&path, &head, n);
        let (group, kind, name, input, count) = (
            c("group")?,
            c("kind")?,
            c("name")?,
            c("input")?,
            c("count")?,
        );
        let stat_names = [
            "mean",
            "std",
            "min",
            "p1",
            "p5",
            "p50",
            "p95",
            "p99",
            "max",
            "quantiles",
        ];
        let stat_cols: Vec<usize> = stat_names.iter().map(|n| c(n)).collect::<Result<_>>()?;
        let (share, lo, hi, rho) = (c("share")?, c("ci95_low")?, c("ci95_high")?, c("rho")?);
        let (minc, maxc) = (c("min")?, c("max")?);
        let axis_cols: Vec<usize> = sweep
            .axes
            .iter()
            .map(|a| c(a.param.name()))
            .collect::<Result<_>>()?;
        let mut rec = csv::ByteRecord::new();
        while rd
            .read_byte_record(&mut rec)
            .map_err(|e| bad_row(&path, e))?
        {
            let g = num(&path, &rec, group, "group")?;
            if !(g >= 0.0) || g.fract() != 0.0 {
                return Err(Error::input(
                    &path,
                    rec.position().map(|p| format!("line {}", p.line())),
                    Some("group"),
                    "is not a group number; not a tswm summary",
                ));
            }
            if g >= shown as f64 {
                continue;
            }
            let g = g as usize;
            while self.groups.len() <= g {
                self.groups.push(GroupData {
                    label: String::new(),
                    quantile_rows: Vec::new(),
                    contact_rows: Vec::new(),
                    hists: vec![None; self.results.len()],
                    spearman: Vec::new(),
                });
            }
            if self.groups[g].label.is_empty() {
                let mut parts = Vec::new();
                for (a, &i) in sweep.axes.iter().zip(&axis_cols) {
                    let v = num(&path, &rec, i, a.param.name())?;
                    parts.push(format!(
                        "{} = {}",
                        super::param_label(a.param),
                        super::plots::tick(v)
                    ));
                }
                self.groups[g].label = if parts.is_empty() {
                    "all lanes".into()
                } else {
                    format!("grid point {g}: {}", parts.join(", "))
                };
            }
            let nm = text(&rec, name);
            match rec.get(kind).unwrap_or(b"") {
                b"number" => {
                    if let Some(r) = self.results.iter().position(|x| x.name == nm) {
                        let (a, b) = (
                            num(&path, &rec, minc, "min")?,
                            num(&path, &rec, maxc, "max")?,
                        );
                        if a.is_finite() && b.is_finite() {
                            self.groups[g].hists[r] = Some((a, b, vec![0; BINS]));
                        }
                    }
                    let mut row = vec![nm, text(&rec, count)];
                    row.extend(stat_cols.iter().map(|&i| short(&text(&rec, i))));
                    self.groups[g].quantile_rows.push(row);
                }
                b"contact_end" | b"hold" => {
                    let word = CONTACT_NAMES
                        .iter()
                        .find(|c| c.0 == nm)
                        .map_or(nm.clone(), |c| format!("{} ({})", c.0, c.1));
                    let kind = text(&rec, kind);
                    let pct = |x: f64| super::percent(x);
                    let (s, l, h) = (
                        num(&path, &rec, share, "share")?,
                        num(&path, &rec, lo, "ci95_low")?,
                        num(&path, &rec, hi, "ci95_high")?,
                    );
                    self.groups[g].contact_rows.push(vec![
                        format!("{kind} = {word}"),
                        text(&rec, count),
                        pct(s),
                        format!("{} to {}", pct(l), pct(h)),
                    ]);
                }
                b"spearman" => {
                    let r = num(&path, &rec, rho, "rho")?;
                    self.groups[g].spearman.push((nm, text(&rec, input), r));
                }
                _ => {}
            }
        }
        Ok(())
    }

    fn columns_of(&self, path: &Path, head: &csv::ByteRecord) -> Result<Cols> {
        let c = |n: &str| column(path, head, n);
        let word_cols = results()
            .iter()
            .filter(|r| matches!(r.summary, Summary::Shares(..)))
            .map(|r| Ok((c(r.name)?, r.name, words_of(r))))
            .collect::<Result<Vec<_>>>()?;
        Ok(Cols {
            lane: c("lane")?,
            status: c("status")?,
            contact: c("contact_end")?,
            hold: c("hold")?,
            lock: c("lock_margin_deg")?,
            t_end: c(Num::TEnd.name())?,
            t_max: c(Num::TMax.name())?,
            results: self
                .results
                .iter()
                .map(|r| c(r.name))
                .collect::<Result<_>>()?,
            shown: self
                .shown_params
                .iter()
                .map(|n| c(n.name()))
                .collect::<Result<_>>()?,
            require: match &self.require {
                Some(r) => Some(c(r.req.column)?),
                None => None,
            },
            words: word_cols,
        })
    }

    /// One pass over the results table. Returns the horizon (t_max or
    /// t_end) of each lane the sweep traces, for the traces' decimation.
    fn scan_lanes(&mut self, dir: &Path, sweep: &Sweep, stated: u64) -> Result<Vec<(u64, f64)>> {
        let mut rd = RowReader::open_folder(dir)?;
        let path = rd.path().to_path_buf();
        let kinds = columns();
        let head = rd.header().clone();
        if head.len() != kinds.len() || head.iter().zip(&kinds).any(|(h, k)| h != k.0.as_bytes()) {
            return Err(Error::input(
                &path,
                Some("line 1".into()),
                None,
                "its columns are not those of this tswm version's table; run it again",
            ));
        }
        let cols = self.columns_of(&path, &head)?;
        let samples = sweep.study.as_ref().map_or(1, |s| s.n);
        let traced_lanes: Vec<u64> = sweep.trace.as_ref().map_or(Vec::new(), |t| t.lanes.clone());
        let mut traced = Vec::new();
        let mut rec = csv::ByteRecord::new();
        let mut cells: Vec<Cell> = Vec::with_capacity(kinds.len());
        let mut vals = vec![0.0; cols.results.len()];
        while rd.read_cells(&mut rec, &kinds, &mut cells)? {
            let row = self.lanes;
            let at = || Some(format!("row {}", row + 1));
            if cells[cols.lane] != Cell::I(row) {
                return Err(Error::input(
                    &path,
                    at(),
                    Some("lane"),
                    format!(
                        "is {}, expected {row}: a table's rows are its lanes 0, 1, 2, ... in order; \
                         not a table tswm wrote",
                        text(&rec, cols.lane)
                    ),
                ));
            }
            if row >= stated {
                return Err(Error::input(
                    &path,
                    at(),
                    Some("lane"),
                    format!(
                        "lane {row} is not in the run: its sweep.resolved.toml states {stated} lanes; \
                         the table belongs to another run"
                    ),
                ));
            }
            for (i, name, words) in &cols.words {
                let w = cells[*i].word();
                if !(words.contains(&w) || (w.is_empty() && *name == "hold")) {
                    return Err(Error::input(
                        &path,
                        at(),
                        Some(name),
                        format!(
                            "`{}` is not one of {}; not a tswm table",
                            crate::error::shown(w, 40),
                            words.join(", ")
                        ),
                    ));
                }
            }
            self.lanes += 1;
            let lane = row;
            let status = cells[cols.status].word();
            let ok = status == "ok";
            if let Some(e) = self.by_status.iter_mut().find(|e| e.0 == status) {
                e.1 += 1;
            }
            let hold = cells[cols.hold].word();
            if !hold.is_empty() {
                self.hold_lanes += 1;
                if let Some(e) = self.by_hold.iter_mut().find(|e| e.0 == hold) {
                    e.1 += 1;
                }
                if hold == "coasting" {
                    let (te, tm) = (cells[cols.t_end].number(), cells[cols.t_max].number());
                    self.coasting_t_end = self.coasting_t_end.max(te);
                    if tm.is_finite() {
                        self.coasting_t_max = self.coasting_t_max.max(tm);
                    }
                }
            }
            if traced_lanes.binary_search(&lane).is_ok() {
                let (te, tm) = (cells[cols.t_end].number(), cells[cols.t_max].number());
                traced.push((lane, if tm.is_finite() { tm.max(te) } else { te }));
            }
            let contact = CONTACT_NAMES
                .iter()
                .position(|c| c.0 == cells[cols.contact].word());
            if !ok {
                self.unfinished_total += 1;
                if self.unfinished.len() < UNFINISHED_SHOWN {
                    let mut r = vec![lane.to_string(), status.to_string()];
                    r.extend(cols.shown.iter().map(|&i| text(&rec, i)));
                    self.unfinished.push(r);
                }
            } else if let Some(k) = contact {
                self.by_contact[k] += 1;
            }
            for (v, &i) in vals.iter_mut().zip(&cols.results) {
                *v = cells[i].number();
            }
            let point = lane / samples;
            let passes = match (&self.require, cols.require) {
                (Some(r), Some(i)) => Some(r.req.passes(&cells[i])),
                _ => None,
            };
            if let (Some(r), Some(p)) = (self.require.as_mut(), passes) {
                r.add(point, p);
            }
            if let Some(m) = self.map.as_mut() {
                let lock = cells[cols.lock].number();
                m.add(point, &vals, if ok { contact } else { None }, lock);
            }
            if let Some(l) = self.line.as_mut() {
                let b = bin(point, l.len, LINE_POINTS).min(l.xs.len().saturating_sub(1));
                for (r, &v) in vals.iter().enumerate() {
                    if v.is_finite() {
                        let a = &mut l.acc[r][b];
                        a.0 += v;
                        a.1 += 1;
                        a.2 = a.2.min(v);
                        a.3 = a.3.max(v);
                    }
                }
                if let (true, Some(k)) = (ok, contact) {
                    l.contact[b][k] += 1;
                }
            }
            if self.study {
                let g = if sweep.axes.is_empty() {
                    0
                } else {
                    point as usize
                };
                if let Some(gd) = self.groups.get_mut(g) {
                    for (r, &v) in vals.iter().enumerate() {
                        if let (Some((lo, hi, counts)), true) =
                            (gd.hists[r].as_mut(), v.is_finite())
                        {
                            // Halves: the span of two finite values cannot overflow.
                            let w = (0.5 * *hi - 0.5 * *lo).max(f64::MIN_POSITIVE);
                            let k = ((0.5 * v - 0.5 * *lo) / w * BINS as f64)
                                .floor()
                                .clamp(0.0, (BINS - 1) as f64);
                            counts[k as usize] += 1;
                        }
                    }
                }
            }
        }
        if self.lanes != stated {
            return Err(Error::input(
                &path,
                None,
                None,
                format!(
                    "has {} rows, but its sweep.resolved.toml states {stated} lanes: the table is \
                     incomplete or belongs to another run; run it again",
                    self.lanes
                ),
            ));
        }
        Ok(traced)
    }

    /// The first traced lanes of `traces.csv`, decimated: `traced` gives
    /// each lane the sweep traces with its horizon.
    fn read_traces(&mut self, dir: &Path, traced: &[(u64, f64)]) -> Result<()> {
        let path = dir.join(TRACES);
        if !path.exists() {
            return Ok(());
        }
        let mut rd = open_csv(&path)?;
        let head = rd.byte_headers().map_err(|e| bad_row(&path, e))?.clone();
        let c = |n: &str| column(&path, &head, n);
        let (lane_c, t_c, v_c, s1_c, s2_c, psi_c) =
            (c("lane")?, c("t")?, c("v1")?, c("s1")?, c("s2")?, c("psi")?);
        let mut rec = csv::ByteRecord::new();
        let mut last_t = f64::NAN;
        while rd
            .read_byte_record(&mut rec)
            .map_err(|e| bad_row(&path, e))?
        {
            let at = || rec.position().map(|p| format!("line {}", p.line()));
            let lane = num(&path, &rec, lane_c, "lane")?;
            let horizon = traced
                .iter()
                .find(|(l, _)| *l as f64 == lane)
                .map(|x| x.1)
                .ok_or_else(|| {
                    Error::input(
                        &path,
                        at(),
                        Some("lane"),
                        format!("lane {lane} is not a traced lane of the run; not its traces.csv"),
                    )
                })?;
            let lane = lane as u64;
            if self.traces.last().is_none_or(|t| t.lane != lane) {
                if self.traces.iter().any(|t| t.lane == lane) {
                    return Err(Error::input(
                        &path,
                        at(),
                        Some("lane"),
                        format!("the rows of lane {lane} are not together; not a tswm traces.csv"),
                    ));
                }
                if self.traces.len() == TRACES_SHOWN {
                    break;
                }
                self.traces.push(TraceData::new(lane, horizon));
                last_t = f64::NAN;
            }
            let t = num(&path, &rec, t_c, "t")?;
            let vals = [
                num(&path, &rec, v_c, "v1")?,
                num(&path, &rec, s1_c, "s1")?,
                num(&path, &rec, s2_c, "s2")?,
                num(&path, &rec, psi_c, "psi")?,
            ];
            // Two rows with one t are an event's before and after.
            let event = t == last_t;
            last_t = t;
            self.traces.last_mut().expect("pushed").add(t, vals, event);
        }
        Ok(())
    }
}

/// A long number cell shortened for a table (6 significant digits).
fn short(s: &str) -> String {
    match s.parse::<f64>() {
        Ok(v) if v != 0.0 && v.is_finite() => {
            let a = v.abs();
            if (1e-3..1e6).contains(&a) {
                let digits = (5 - a.log10().floor() as i32).max(0) as usize;
                format!("{v:.digits$}")
            } else {
                format!("{v:.5e}")
            }
        }
        _ => s.to_string(),
    }
}
