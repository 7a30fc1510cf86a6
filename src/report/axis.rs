//! Value ranges, ticks and colours of the report's figures, computed in
//! one place and robust to any finite values: equal, near-equal (closer
//! than f32 or the eye resolve), and huge (up to ±f64::MAX, whose span
//! overflows). Plotters gets a finite range of positive width and the
//! key points computed here, so its own tick search (which loops on an
//! infinite span) never runs; values too large to plot are shown in a
//! stated power of ten.

use plotters::style::colors::colormaps::ColorMap;
use plotters::style::colors::colormaps::ViridisRGB;
use plotters::style::RGBColor;

/// Values beyond this magnitude, or all below the next, are plotted in
/// units of a power of ten (the label says which), so that spans,
/// paddings and steps stay finite and normal.
const HUGE: f64 = 1e100;
const TINY: f64 = 1e-100;

/// Spans narrower than this share of the values' magnitude are drawn as
/// one value: the eye cannot tell them apart, and ticks could not be told
/// apart either.
const NARROW: f64 = 1e-12;

/// Most ticks on an axis.
const MAX_TICKS: usize = 8;

/// A plotted range of values: its ends (in plotted units), its ticks and
/// their labels, and the power of ten the values are divided by.
#[derive(Clone, Debug, PartialEq)]
pub struct Range {
    /// Lower end, plotted units.
    pub lo: f64,
    /// Upper end, plotted units (> lo).
    pub hi: f64,
    /// Tick positions, plotted units.
    pub ticks: Vec<f64>,
    /// Power of ten the values are divided by (0: none).
    pub exp10: i32,
    /// The values were all (nearly) equal: drawn as one value.
    pub single: bool,
}

impl Range {
    /// The range of the finite values among `values`, padded by `pad` of
    /// its width on each side; (0, 1) when there are none.
    pub fn of(values: impl IntoIterator<Item = f64>, pad: f64) -> Range {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for v in values.into_iter().filter(|v| v.is_finite()) {
            lo = lo.min(v);
            hi = hi.max(v);
        }
        if lo > hi {
            return Range::span(0.0, 1.0, 0, false);
        }
        let big = lo.abs().max(hi.abs());
        let exp10 = if big > HUGE || (big < TINY && big > 0.0) {
            big.log10().floor() as i32
        } else {
            0
        };
        let scale = 10f64.powi(exp10);
        let (lo, hi) = (lo / scale, hi / scale);
        let mag = lo.abs().max(hi.abs());
        if !(hi - lo > NARROW * mag) {
            // One value: a band around it that ticks can name.
            let c = 0.5 * lo + 0.5 * hi;
            let half = if c == 0.0 { 1.0 } else { 0.05 * c.abs() };
            return Range::span(c - half, c + half, exp10, true);
        }
        let p = pad * (hi - lo);
        Range::span(lo - p, hi + p, exp10, false)
    }

    /// A range with ends `lo` < `hi` (plotted units) and ticks on round
    /// values inside it.
    fn span(lo: f64, hi: f64, exp10: i32, single: bool) -> Range {
        Range {
            lo,
            hi,
            ticks: nice_ticks(lo, hi),
            exp10,
            single,
        }
    }

    /// A value in plotted units.
    pub fn map(&self, v: f64) -> f64 {
        if self.exp10 == 0 {
            v
        } else {
            v / 10f64.powi(self.exp10)
        }
    }

    /// The axis label `label` with the power of ten, if any.
    pub fn label(&self, label: &str) -> String {
        if self.exp10 == 0 {
            label.to_string()
        } else {
            format!("{label} / 1e{}", self.exp10)
        }
    }

    /// The label of tick `v` (plotted units), with enough digits to tell
    /// the ticks apart.
    pub(crate) fn tick_label(&self, v: f64) -> String {
        let step = if self.ticks.len() >= 2 {
            self.ticks[1] - self.ticks[0]
        } else {
            (self.hi - self.lo).abs()
        };
        number(v, step)
    }
}

/// Round tick values (1, 2 or 5 times a power of ten apart) inside
/// [lo, hi]: at least two, at most `MAX_TICKS`, computed from integer
/// multiples so that no sum accumulates and no loop can run on.
pub(crate) fn nice_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let width = hi - lo;
    if !(width > 0.0 && width.is_finite()) {
        return vec![lo];
    }
    let raw = width / (MAX_TICKS - 2) as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| width / s <= (MAX_TICKS - 1) as f64)
        .unwrap_or(10.0 * mag);
    let first = (lo / step).ceil();
    let mut ticks = Vec::with_capacity(MAX_TICKS);
    for k in 0..MAX_TICKS {
        let t = (first + k as f64) * step;
        if t > hi {
            break;
        }
        // -0 reads as 0.
        ticks.push(if t == 0.0 { 0.0 } else { t });
    }
    ticks
}

/// A number for a label, with digits enough for steps of `step` (and at
/// least four significant ones): fixed notation for 1e-3 <= |v| < 1e6,
/// else scientific.
pub fn number(v: f64, step: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    if !v.is_finite() {
        return format!("{v}");
    }
    let a = v.abs();
    let step = if step > 0.0 && step.is_finite() {
        step.abs()
    } else {
        a
    };
    if (1e-3..1e6).contains(&a) {
        let decimals = (-(step.log10().floor()) as i32 + 1)
            .max(3 - a.log10().floor() as i32)
            .clamp(0, 15) as usize;
        let s = format!("{v:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        let digits = ((a.log10().floor() - step.log10().floor()) as i32 + 1).clamp(3, 15) as usize;
        let s = format!("{v:.digits$e}");
        // 1.500e3 reads better as 1.5e3.
        match s.split_once('e') {
            Some((m, e)) if m.contains('.') => {
                format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.'))
            }
            _ => s,
        }
    }
}

/// Labels for the values of a grid axis (cells, categories): each with
/// the fewest significant digits (at least four) that tell neighbours
/// apart.
pub(crate) fn value_labels(values: &[f64]) -> Vec<String> {
    for digits in 4..=17 {
        let labels: Vec<String> = values.iter().map(|&v| significant(v, digits)).collect();
        if labels.windows(2).all(|w| w[0] != w[1]) {
            return labels;
        }
    }
    values.iter().map(|v| format!("{v:?}")).collect()
}

/// `v` with `digits` significant digits, trailing zeros dropped.
fn significant(v: f64, digits: usize) -> String {
    if v == 0.0 || !v.is_finite() {
        return number(v, 1.0);
    }
    let a = v.abs();
    if (1e-3..1e6).contains(&a) {
        let decimals = (digits as i32 - 1 - a.log10().floor() as i32).clamp(0, 17) as usize;
        let s = format!("{v:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        let s = format!("{v:.*e}", digits.saturating_sub(1));
        match s.split_once('e') {
            Some((m, e)) if m.contains('.') => {
                format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.'))
            }
            _ => s,
        }
    }
}

/// Whether `values` (at least two) are evenly spaced after `f` (the
/// identity for a linear scale, ln for a log one).
fn evenly_spaced(values: &[f64], f: &dyn Fn(f64) -> f64) -> bool {
    let n = values.len();
    if n < 2 {
        return false;
    }
    let (a, b) = (f(values[0]), f(values[n - 1]));
    let step = (b - a) / (n - 1) as f64;
    let tol = 1e-9 * a.abs().max(b.abs()).max(step.abs());
    step != 0.0
        && values
            .iter()
            .enumerate()
            .all(|(i, &v)| (f(v) - (a + i as f64 * step)).abs() <= tol)
}

/// Whether grid values drawn as equal cells read as a scale: at most two
/// values, or evenly spaced on a linear or a log scale. Others (`values =
/// [1, 2, 5, 10, 30]`) are drawn one cell each, and their axis says so.
pub(crate) fn reads_as_scale(values: &[f64]) -> bool {
    values.len() <= 2
        || values.iter().any(|v| !v.is_finite())
        || evenly_spaced(values, &|v| v)
        || (values.iter().all(|&v| v > 0.0) && evenly_spaced(values, &|v: f64| v.ln()))
}

/// Round ticks along grid values evenly spaced on a linear or a log
/// scale, at their fractional positions (value i at position i): the
/// values a person reads off an axis, not the grid's 0.1019. Empty for
/// other values (lists), which are labelled as they are.
pub(crate) fn round_ticks(values: &[f64], max_labels: usize) -> Vec<(f64, String)> {
    let n = values.len();
    if n < 3 || values.iter().any(|v| !v.is_finite()) {
        return Vec::new();
    }
    let (v0, vn) = (values[0], values[n - 1]);
    let even = |f: &dyn Fn(f64) -> f64| evenly_spaced(values, f);
    let (lo, hi) = (v0.min(vn), v0.max(vn));
    let mut ticks: Vec<(f64, f64)> = Vec::new();
    if even(&|v| v) {
        let step = (vn - v0) / (n - 1) as f64;
        let t = nice_ticks(lo, hi);
        let d = if t.len() >= 2 { t[1] - t[0] } else { hi - lo };
        return t
            .into_iter()
            .map(|t| ((t - v0) / step, number(t, d)))
            .collect();
    } else if lo > 0.0 && even(&|v: f64| v.ln()) {
        let lstep = (vn.ln() - v0.ln()) / (n - 1) as f64;
        let (k0, k1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
        for mults in [&[1.0, 2.0, 5.0][..], &[1.0][..]] {
            ticks.clear();
            for k in k0..=k1 {
                for &m in mults {
                    let t = m * 10f64.powi(k);
                    if t >= lo * (1.0 - 1e-9) && t <= hi * (1.0 + 1e-9) {
                        ticks.push((t, (t.ln() - v0.ln()) / lstep));
                    }
                }
            }
            if ticks.len() <= max_labels {
                break;
            }
        }
    }
    if ticks.len() < 2 {
        return Vec::new();
    }
    ticks.into_iter().map(|(t, p)| (p, number(t, t))).collect()
}

/// The colour of `v` on a viridis scale over [lo, hi] (plotted units);
/// grey for no value. Normalised in f64 before plotters sees it: its
/// colour map divides in f32, where a narrow or huge span is 0 or
/// infinite.
pub fn colour(v: f64, lo: f64, hi: f64) -> RGBColor {
    if !v.is_finite() {
        return RGBColor(200, 200, 200);
    }
    // Halves: the difference of two finite values cannot overflow.
    let w = 0.5 * hi - 0.5 * lo;
    let t = if w > 0.0 {
        ((0.5 * v - 0.5 * lo) / w).clamp(0.0, 1.0)
    } else {
        0.5
    };
    ViridisRGB.get_color_normalized(t as f32, 0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_are_finite_and_wide_for_any_values() {
        let cases: Vec<Vec<f64>> = vec![
            vec![],
            vec![f64::NAN],
            vec![4774.0],
            vec![4774.0, 4774.0 + 1e-9],
            vec![0.0, 0.0],
            vec![1e40, 2e40],
            vec![1.7e308, -1.7e308],
            vec![f64::MAX, f64::MIN],
            vec![f64::MIN_POSITIVE, 2.0 * f64::MIN_POSITIVE],
            vec![-1e-300, 1e-300],
            vec![0.8254001, 0.8254002],
        ];
        for v in cases {
            let r = Range::of(v.iter().copied(), 0.04);
            assert!(
                r.lo.is_finite() && r.hi.is_finite() && r.hi > r.lo,
                "{v:?}: {r:?}"
            );
            assert!(
                !r.ticks.is_empty() && r.ticks.len() <= MAX_TICKS,
                "{v:?}: {r:?}"
            );
            for t in &r.ticks {
                assert!(*t >= r.lo && *t <= r.hi, "{v:?}: {r:?}");
            }
            let labels: Vec<String> = r.ticks.iter().map(|&t| r.tick_label(t)).collect();
            assert!(labels.windows(2).all(|w| w[0] != w[1]), "{v:?}: {labels:?}");
            for x in &v {
                if x.is_finite() {
                    let m = r.map(*x);
                    assert!(m >= r.lo && m <= r.hi, "{x} in {r:?}");
                }
            }
        }
    }

    #[test]
    fn one_value_is_named_by_a_tick_near_it() {
        let r = Range::of([4774.0], 0.04);
        assert!(r.single);
        assert!(r
            .ticks
            .iter()
            .any(|&t| t == 4774.0 || (t - 4774.0).abs() < 100.0));
    }

    #[test]
    fn colours_never_panic() {
        for (v, lo, hi) in [
            (1.0, 1.0, 1.0),
            (4774.0 + 5e-10, 4774.0, 4774.0 + 1e-9),
            (1e40, 1e40, 2e40),
            (f64::MAX, f64::MIN, f64::MAX),
            (f64::NAN, 0.0, 1.0),
        ] {
            let _ = colour(v, lo, hi);
        }
    }

    #[test]
    fn labels_tell_neighbours_apart() {
        let l = value_labels(&[5.710593137499643, 5.7106, 6.0]);
        assert_eq!(l.len(), 3);
        assert!(l[0] != l[1] && l[1] != l[2], "{l:?}");
        assert_eq!(value_labels(&[2.0, 2.25, 2.5]), ["2", "2.25", "2.5"]);
        assert_eq!(number(4774.0, 10.0), "4774");
        assert_eq!(number(0.2, 0.1), "0.2");
    }
}
