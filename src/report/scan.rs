//! Reading an output folder for the report: `summary.csv` for the shown
//! groups, one pass over `lanes.csv` into bounded aggregates, and the
//! traced lanes of `traces.csv` (thinned past a cap).

use std::collections::BTreeMap;
use std::path::Path;

use crate::error::{Error, Result};
use crate::params::Num;
use crate::sweep::{Axis, Sweep};

pub use super::aggregates::{GroupData, LineData, MapData, Panel, TraceData, TraceRow};

/// Final contacts as `lanes.csv` spells them, with the words the report
/// uses; the order of the maps' colours.
pub const CONTACT_NAMES: [(&str, &str); 3] = [("stick", "held"), ("aa", "a-a"), ("bb", "b-b")];

/// Most cells along one axis of a map, and points along a line; longer
/// axes are binned.
const MAP_CELLS: u64 = 120;
const LINE_POINTS: u64 = 1000;
/// Lanes listed by name among those that could not be finished.
const UNFINISHED_SHOWN: usize = 20;
/// Histogram bins.
const BINS: usize = 40;
/// Traced lanes plotted, and rows kept per lane before thinning.
const TRACES_SHOWN: usize = 6;
const TRACE_ROWS: usize = 8000;

/// What the report needs from an output folder.
pub struct Folder {
    /// The table's file name (`lanes.csv` or `lanes.parquet`).
    pub table: &'static str,
    pub lanes: u64,
    pub by_status: BTreeMap<String, u64>,
    pub by_contact: [u64; 3],
    pub unfinished: Vec<Vec<String>>,
    pub unfinished_total: u64,
    /// Parameters listed for unfinished lanes: the grid's and the sampled.
    pub shown_params: Vec<Num>,
    pub results: Vec<String>,
    pub study: bool,
    pub map: Option<MapData>,
    pub line: Option<LineData>,
    pub groups: Vec<GroupData>,
    pub groups_total: usize,
    pub traces: Vec<TraceData>,
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

fn num(rec: &csv::ByteRecord, i: usize) -> f64 {
    std::str::from_utf8(&rec[i])
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(f64::NAN)
}

fn text(rec: &csv::ByteRecord, i: usize) -> String {
    String::from_utf8_lossy(&rec[i]).into_owned()
}

/// Index `i` of `len` into `bins` bins.
fn bin(i: u64, len: u64, bins: u64) -> usize {
    if len <= bins {
        i as usize
    } else {
        (i as u128 * bins as u128 / len as u128) as usize
    }
}

/// The axis value shown for each bin (its first grid value).
fn bin_values(a: &Axis, bins: u64) -> Vec<f64> {
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

impl Folder {
    /// Reads the folder `dir` of a run of `sweep`.
    pub fn read(dir: &Path, sweep: &Sweep) -> Result<Folder> {
        let spec = &sweep.report;
        let results = spec.results();
        let panels = spec.panels();
        let study = sweep.study.is_some();
        let samples = sweep.study.as_ref().map_or(1, |s| s.n);
        let lens: Vec<u64> = sweep.axes.iter().map(|a| a.len()).collect();
        let mut shown_params: Vec<Num> = sweep.axes.iter().map(|a| a.param).collect();
        if let Some(st) = &sweep.study {
            shown_params.extend(st.params.iter().map(|t| t.param));
        }
        let mut f = Folder {
            table: crate::lanes_file::Format::of_folder(dir)?.file_name(),
            lanes: 0,
            by_status: BTreeMap::new(),
            by_contact: [0; 3],
            unfinished: Vec::new(),
            unfinished_total: 0,
            shown_params,
            results: results.clone(),
            study,
            map: None,
            line: None,
            groups: Vec::new(),
            groups_total: 0,
            traces: Vec::new(),
        };
        if sweep.axes.len() >= 2 {
            let pick = |k: usize| {
                spec.axes
                    .get(k)
                    .and_then(|n| sweep.axes.iter().position(|a| a.param == *n))
                    .unwrap_or(
                        if spec.axes.first().is_some_and(|n| sweep.axes[0].param == *n) {
                            1
                        } else {
                            k
                        },
                    )
            };
            let (ix, iy) = (pick(0), pick(1));
            let (ax, ay) = (&sweep.axes[ix], &sweep.axes[iy]);
            let others: u64 = lens
                .iter()
                .enumerate()
                .filter(|(i, _)| *i != ix && *i != iy)
                .map(|(_, l)| l)
                .product();
            let (xs, ys) = (bin_values(ax, MAP_CELLS), bin_values(ay, MAP_CELLS));
            let cells = xs.len() * ys.len();
            let shown = (others as usize).min(panels);
            let mut list = Vec::new();
            for p in 0..shown {
                // The other axes' values of panel p (mixed radix, slowest first).
                let mut rest = p as u64;
                let mut label = Vec::new();
                for (i, a) in sweep.axes.iter().enumerate().rev() {
                    if i == ix || i == iy {
                        continue;
                    }
                    label.push(format!(
                        "{} = {}",
                        param_label_short(a.param),
                        plots_tick(a.value(rest % lens[i]))
                    ));
                    rest /= lens[i];
                }
                label.reverse();
                list.push(Panel {
                    label: if label.is_empty() {
                        "all lanes".into()
                    } else {
                        label.join(", ")
                    },
                    nx: xs.len(),
                    ny: ys.len(),
                    sums: vec![vec![0.0; cells]; results.len()],
                    counts: vec![vec![0; cells]; results.len()],
                    contact: vec![[0; 3]; cells],
                    lock: vec![(0.0, 0); cells],
                });
            }
            f.map = Some(MapData {
                x: ax.param,
                y: ay.param,
                binned: ax.len() > MAP_CELLS || ay.len() > MAP_CELLS,
                xs,
                ys,
                panels: list,
                panel_total: others as usize,
                ix,
                iy,
                lens: lens.clone(),
            });
        } else if sweep.axes.len() == 1 {
            let a = &sweep.axes[0];
            let xs = bin_values(a, LINE_POINTS);
            let n = xs.len();
            f.line = Some(LineData {
                axis: a.param,
                log: matches!(a.values, crate::sweep::AxisValues::Range { log: true, .. }),
                xs,
                len: a.len(),
                acc: vec![vec![(0.0, 0, f64::INFINITY, f64::NEG_INFINITY); n]; results.len()],
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
        f.scan_lanes(dir, sweep, samples)?;
        f.read_traces(dir)?;
        Ok(f)
    }

    /// The shown groups' rows of summary.csv: tables, histogram ranges
    /// and rank correlations.
    fn read_summary(&mut self, dir: &Path, sweep: &Sweep, shown: usize) -> Result<()> {
        let path = dir.join("summary.csv");
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
        let stat_cols: Vec<usize> = [
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
        ]
        .iter()
        .map(|n| c(n))
        .collect::<Result<_>>()?;
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
            let g = num(&rec, group) as usize;
            if g >= shown {
                continue;
            }
            while self.groups.len() <= g {
                self.groups.push(GroupData {
                    label: String::new(),
                    quantile_rows: Vec::new(),
                    contact_rows: Vec::new(),
                    hists: vec![None; self.results.len()],
                    spearman: Vec::new(),
                });
            }
            let gd = &mut self.groups[g];
            if gd.label.is_empty() {
                let parts: Vec<String> = sweep
                    .axes
                    .iter()
                    .zip(&axis_cols)
                    .map(|(a, &i)| {
                        format!(
                            "{} = {}",
                            param_label_short(a.param),
                            plots_tick(num(&rec, i))
                        )
                    })
                    .collect();
                gd.label = if parts.is_empty() {
                    "all lanes".into()
                } else {
                    format!("grid point {g}: {}", parts.join(", "))
                };
            }
            let nm = text(&rec, name);
            match &rec[kind] {
                b"number" => {
                    if let Some(r) = self.results.iter().position(|x| *x == nm) {
                        let (a, b) = (num(&rec, minc), num(&rec, maxc));
                        if a.is_finite() && b.is_finite() {
                            gd.hists[r] = Some((a, b, vec![0; BINS]));
                        }
                    }
                    let mut row = vec![nm, text(&rec, count)];
                    row.extend(stat_cols.iter().map(|&i| short(&text(&rec, i))));
                    gd.quantile_rows.push(row);
                }
                b"contact_end" => {
                    let word = CONTACT_NAMES
                        .iter()
                        .find(|c| c.0 == nm)
                        .map_or(nm.clone(), |c| format!("{} ({})", c.0, c.1));
                    let pct = |i: usize| super::percent(num(&rec, i));
                    gd.contact_rows.push(vec![
                        word,
                        text(&rec, count),
                        pct(share),
                        format!("{} to {}", pct(lo), pct(hi)),
                    ]);
                }
                b"spearman" => gd.spearman.push((nm, text(&rec, input), num(&rec, rho))),
                _ => {}
            }
        }
        Ok(())
    }

    fn scan_lanes(&mut self, dir: &Path, sweep: &Sweep, samples: u64) -> Result<()> {
        // lanes.csv or lanes.parquet, read alike as text records.
        let mut rd = crate::lanes_file::RowReader::open_folder(dir)?;
        let path = rd.path().to_path_buf();
        let head = rd.header().clone();
        let c = |n: &str| column(&path, &head, n);
        let (lane_c, status_c, contact_c, lock_c) = (
            c("lane")?,
            c("status")?,
            c("contact_end")?,
            c("lock_margin_deg")?,
        );
        let res_c: Vec<usize> = self.results.iter().map(|n| c(n)).collect::<Result<_>>()?;
        let shown_c: Vec<usize> = self
            .shown_params
            .iter()
            .map(|n| c(n.name()))
            .collect::<Result<_>>()?;
        let grouped = !sweep.axes.is_empty();
        let mut rec = csv::ByteRecord::new();
        let mut idx = vec![0u64; sweep.axes.len()];
        let mut vals = vec![0.0; res_c.len()];
        while rd.read(&mut rec)? {
            self.lanes += 1;
            let lane = num(&rec, lane_c) as u64;
            let status = &rec[status_c];
            let ok = status == b"ok";
            if let Some(n) = self
                .by_status
                .get_mut(std::str::from_utf8(status).unwrap_or("?"))
            {
                *n += 1;
            } else {
                self.by_status.insert(text(&rec, status_c), 1);
            }
            let contact = CONTACT_NAMES
                .iter()
                .position(|c| c.0.as_bytes() == &rec[contact_c]);
            if !ok {
                self.unfinished_total += 1;
                if self.unfinished.len() < UNFINISHED_SHOWN {
                    let mut row = vec![lane.to_string(), text(&rec, status_c)];
                    row.extend(shown_c.iter().map(|&i| text(&rec, i)));
                    self.unfinished.push(row);
                }
            } else if let Some(k) = contact {
                self.by_contact[k] += 1;
            }
            for (v, &i) in vals.iter_mut().zip(&res_c) {
                *v = num(&rec, i);
            }
            // The grid point and its axis indices (last axis fastest).
            let point = lane / samples;
            let mut rest = point;
            for (i, &len) in self
                .map
                .as_ref()
                .map_or(&Vec::new(), |m| &m.lens)
                .iter()
                .enumerate()
                .rev()
            {
                idx[i] = rest % len;
                rest /= len;
            }
            if let Some(m) = self.map.as_mut() {
                let mut p = 0u64;
                for (i, &len) in m.lens.iter().enumerate() {
                    if i != m.ix && i != m.iy {
                        p = p * len + idx[i];
                    }
                }
                if let Some(panel) = m.panels.get_mut(p as usize) {
                    let cx = bin(idx[m.ix], m.lens[m.ix], MAP_CELLS);
                    let cy = bin(idx[m.iy], m.lens[m.iy], MAP_CELLS);
                    let cell = cy * panel.nx + cx;
                    for (r, v) in vals.iter().enumerate() {
                        if v.is_finite() {
                            panel.sums[r][cell] += v;
                            panel.counts[r][cell] += 1;
                        }
                    }
                    if let (true, Some(k)) = (ok, contact) {
                        panel.contact[cell][k] += 1;
                    }
                    let lm = num(&rec, lock_c);
                    if lm.is_finite() {
                        panel.lock[cell].0 += lm;
                        panel.lock[cell].1 += 1;
                    }
                }
            }
            if let Some(l) = self.line.as_mut() {
                let b = bin(point, l.len, LINE_POINTS);
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
                let g = if grouped { point as usize } else { 0 };
                if let Some(gd) = self.groups.get_mut(g) {
                    for (r, &v) in vals.iter().enumerate() {
                        if let (Some((lo, hi, counts)), true) =
                            (gd.hists[r].as_mut(), v.is_finite())
                        {
                            let w = (*hi - *lo).max(f64::MIN_POSITIVE);
                            let k = (((v - *lo) / w) * BINS as f64)
                                .floor()
                                .clamp(0.0, (BINS - 1) as f64);
                            counts[k as usize] += 1;
                        }
                    }
                }
            }
        }
        Ok(())
    }

    fn read_traces(&mut self, dir: &Path) -> Result<()> {
        let path = dir.join("traces.csv");
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
            let lane = num(&rec, lane_c) as u64;
            if self.traces.last().is_none_or(|t| t.lane != lane) {
                if self.traces.len() == TRACES_SHOWN {
                    break;
                }
                self.traces.push(TraceData {
                    lane,
                    thinned: false,
                    rows: Vec::new(),
                    stride: 1,
                    seen: 0,
                    events: Vec::new(),
                });
                last_t = f64::NAN;
            }
            let tr = self.traces.last_mut().expect("pushed");
            let row = TraceRow {
                t: num(&rec, t_c),
                v1: num(&rec, v_c),
                s1: num(&rec, s1_c),
                s2: num(&rec, s2_c),
                psi: num(&rec, psi_c),
            };
            // Two rows with one t are an event's before and after: always kept.
            let event = row.t == last_t;
            last_t = row.t;
            if event && tr.events.last() != Some(&row.t) {
                tr.events.push(row.t);
            }
            tr.seen += 1;
            if event || tr.seen.is_multiple_of(tr.stride) {
                tr.rows.push(row);
            }
            if tr.rows.len() >= TRACE_ROWS {
                // Thin: keep every other row (events stay), sample half as often.
                let mut keep = false;
                let evs = tr.events.clone();
                tr.rows.retain(|r| {
                    keep = !keep;
                    keep || evs.contains(&r.t)
                });
                tr.stride *= 2;
                tr.thinned = true;
            }
        }
        Ok(())
    }
}

fn param_label_short(n: Num) -> String {
    let u = n.def().unit;
    if u.is_empty() {
        n.name().to_string()
    } else {
        format!("{} ({u})", n.name())
    }
}

fn plots_tick(v: f64) -> String {
    super::plots::tick(v)
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
