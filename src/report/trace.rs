//! A traced lane decimated to the plot's resolution: per time slice and
//! series the first, lowest, highest and last value, and the slices that
//! hold an event. Memory is fixed and time linear in the rows.

/// Time buckets of a trace plot: about two a pixel of its width.
pub(crate) const TRACE_BUCKETS: usize = 1000;

/// One series of a bucket: the first, lowest, highest and last value
/// with their times, so that the plot of the bucket's points draws what
/// the plot of every row would (jumps at events included).
#[derive(Clone, Copy)]
struct M4 {
    first: (f64, f64),
    min: (f64, f64),
    max: (f64, f64),
    last: (f64, f64),
}

impl M4 {
    fn new(t: f64, v: f64) -> M4 {
        M4 {
            first: (t, v),
            min: (t, v),
            max: (t, v),
            last: (t, v),
        }
    }

    fn add(&mut self, t: f64, v: f64) {
        if v < self.min.1 {
            self.min = (t, v);
        }
        if v > self.max.1 {
            self.max = (t, v);
        }
        self.last = (t, v);
    }

    /// The bucket's points in time order, once each.
    fn points(&self, out: &mut Vec<(f64, f64)>) {
        let mut p = [self.first, self.min, self.max, self.last];
        p.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (i, q) in p.iter().enumerate() {
            if i == 0 || *q != p[i - 1] {
                out.push(*q);
            }
        }
    }
}

/// Series of a trace: v1, S1, S2, psi.
const SERIES: usize = 4;

/// One traced lane, decimated: per time bucket and series, the M4 points
/// (first, min, max, last), and the buckets that hold an event. Memory
/// is fixed and time linear in the rows, whatever their number or that
/// of events.
pub struct TraceData {
    pub lane: u64,
    /// Rows read.
    pub rows: u64,
    /// Events read (rows that repeat the time before them).
    pub events: u64,
    horizon: f64,
    buckets: Vec<[Option<M4>; SERIES]>,
    event_at: Vec<Option<f64>>,
}

impl TraceData {
    /// A lane traced from 0 to `horizon` s.
    pub fn new(lane: u64, horizon: f64) -> TraceData {
        TraceData {
            lane,
            rows: 0,
            events: 0,
            horizon: if horizon > 0.0 { horizon } else { 1.0 },
            buckets: vec![[None; SERIES]; TRACE_BUCKETS],
            event_at: vec![None; TRACE_BUCKETS],
        }
    }

    fn bucket(&self, t: f64) -> usize {
        let b = (t / self.horizon * TRACE_BUCKETS as f64).floor();
        if b.is_finite() {
            b.clamp(0.0, (TRACE_BUCKETS - 1) as f64) as usize
        } else {
            0
        }
    }

    /// Adds a row at time `t` with v1, S1, S2, psi; `event`: it repeats
    /// the row before's time (an event's after-row).
    pub fn add(&mut self, t: f64, vals: [f64; SERIES], event: bool) {
        self.rows += 1;
        if !t.is_finite() {
            return;
        }
        let b = self.bucket(t);
        if event {
            self.events += 1;
            self.event_at[b].get_or_insert(t);
        }
        for (s, v) in self.buckets[b].iter_mut().zip(vals) {
            if v.is_finite() {
                match s {
                    Some(m) => m.add(t, v),
                    None => *s = Some(M4::new(t, v)),
                }
            }
        }
    }

    /// Whether the plot holds fewer points than the lane has rows.
    pub(crate) fn thinned(&self) -> bool {
        let kept: usize = self.buckets.iter().flat_map(|b| b.iter().flatten()).count() * 4;
        self.rows as usize > kept / SERIES
    }

    /// (t, value) points of series `s` (0 v1, 1 S1, 2 S2, 3 psi).
    pub fn series(&self, s: usize) -> Vec<(f64, f64)> {
        let mut out = Vec::new();
        for b in &self.buckets {
            if let Some(m) = &b[s] {
                m.points(&mut out);
            }
        }
        out
    }

    /// Times of the events marked: one per bucket that holds one.
    pub(crate) fn marks(&self) -> Vec<f64> {
        self.event_at.iter().flatten().copied().collect()
    }
}

/// A traced lane's heading: its parameters `params` (the grid's and the
/// sampled, read from `cols` at `row`) and its outcome `word`.
pub(super) fn label(
    params: &[crate::params::Param],
    cols: &[crate::output::batch::Col<'_>],
    row: usize,
    word: &str,
) -> String {
    let mut parts: Vec<String> = params
        .iter()
        .zip(cols)
        .map(|(p, col)| {
            let unit = match p {
                crate::params::Param::Num(n) if !n.def().unit.is_empty() => {
                    format!(" {}", n.def().unit)
                }
                _ => String::new(),
            };
            let v = col.number(row);
            let text = if v.is_finite() {
                super::plots::tick(v)
            } else {
                col.text(row)
            };
            format!("{} = {text}{unit}", p.name())
        })
        .collect();
    parts.push(word.to_string());
    parts.join(", ")
}
