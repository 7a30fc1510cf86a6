//! The report's figures, drawn with plotters into SVG strings that the
//! page inlines. Every axis is an [`Axis`]: numeric (a [`Range`] from
//! `axis`, whose ticks plotters is given) or categorical (grid values at
//! evenly spaced positions, labelled at their centres). So no figure
//! depends on plotters' own tick search or colour normalisation, and any
//! finite value draws.

use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};
use plotters::prelude::*;

use super::axis::{value_labels, Range};

/// Width and height of one figure, px.
pub(crate) const SIZE: (u32, u32) = (560, 400);

/// Plotters' drawing errors carry backend types; the report only needs
/// to say that a figure could not be drawn.
pub(super) type Drawn = Result<(), String>;

pub(super) fn err<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

/// Finishes an SVG for inlining in HTML: the namespace attribute is left
/// out (HTML needs none, and the page then names no address at all).
pub(super) fn inline(svg: String) -> String {
    svg.replace(" xmlns=\"http://www.w3.org/2000/svg\"", "")
}

/// A value for a table cell or a panel's name: short, and exact for
/// round values.
pub fn tick(v: f64) -> String {
    super::axis::number(v, v.abs() * 1e-4)
}

/// The font size of tick labels and axis titles, px: a figure is shown
/// at its own width (two a row), so these are the sizes read, beside the
/// page's 14 to 16 px text.
pub(crate) const LABEL_PX: u32 = 14;

/// Most labelled categories on an axis (the others are drawn unlabelled).
const MAX_LABELS: usize = 8;

/// A figure's axis.
#[derive(Clone, Debug)]
pub enum Axis {
    /// Numbers on a linear scale (values in the range's plotted units).
    Num {
        /// The axis title.
        label: String,
        /// The plotted range.
        range: Range,
    },
    /// Categories at positions 0, 1, ..., labelled with their names, or
    /// at `ticks` (position, label) where given: round values along a
    /// grid range too long to label each value.
    Cat {
        /// The axis title.
        label: String,
        /// The categories' names, at positions 0, 1, ...
        names: Vec<String>,
        /// (position, label) of the ticks shown, where not every name is.
        ticks: Vec<(f64, String)>,
    },
}

impl Axis {
    /// A numeric axis over `values`, padded by 4 % of their span.
    pub(crate) fn numeric(label: &str, values: impl IntoIterator<Item = f64>) -> Axis {
        Axis::Num {
            label: label.to_string(),
            range: Range::of(values, 0.04),
        }
    }

    /// A numeric axis over exactly [lo, hi] (shares, correlations).
    pub fn fixed(label: &str, lo: f64, hi: f64) -> Axis {
        Axis::Num {
            label: label.to_string(),
            range: Range::of([lo, hi], 0.0),
        }
    }

    /// Categories named by grid values (labels that tell them apart);
    /// more values than are labelled one by one, evenly spaced on a
    /// linear or log scale, get ticks at round values between them.
    pub fn grid(label: &str, values: &[f64]) -> Axis {
        // Unevenly spaced values drawn as equal cells are no scale: the
        // axis title says so, and each labelled cell names its value.
        let label = if super::axis::reads_as_scale(values) {
            label.to_string()
        } else {
            format!("{label}; uneven values, one cell each")
        };
        Axis::Cat {
            label,
            names: value_labels(values),
            ticks: if values.len() > MAX_LABELS {
                super::axis::round_ticks(values, MAX_LABELS)
            } else {
                Vec::new()
            },
        }
    }

    /// Categories named by words.
    pub fn words(label: &str, names: Vec<String>) -> Axis {
        Axis::Cat {
            label: label.to_string(),
            names,
            ticks: Vec::new(),
        }
    }

    /// A value in plotted units (a category's index stays as it is).
    pub fn map(&self, v: f64) -> f64 {
        match self {
            Axis::Num { range, .. } => range.map(v),
            Axis::Cat { .. } => v,
        }
    }

    pub(super) fn ends(&self) -> (f64, f64) {
        match self {
            Axis::Num { range, .. } => (range.lo, range.hi),
            Axis::Cat { names, .. } => (-0.5, names.len().max(1) as f64 - 0.5),
        }
    }

    pub(super) fn key_points(&self) -> Vec<f64> {
        match self {
            Axis::Num { range, .. } => range.ticks.clone(),
            Axis::Cat { ticks, .. } if !ticks.is_empty() => ticks.iter().map(|t| t.0).collect(),
            Axis::Cat { names, .. } => {
                let every = names.len().div_ceil(MAX_LABELS).max(1);
                (0..names.len()).step_by(every).map(|i| i as f64).collect()
            }
        }
    }

    pub(super) fn label_of(&self, v: f64) -> String {
        match self {
            Axis::Num { range, .. } => range.tick_label(v),
            Axis::Cat { ticks, .. } if !ticks.is_empty() => ticks
                .iter()
                .find(|t| (t.0 - v).abs() < 1e-9)
                .map(|t| t.1.clone())
                .unwrap_or_default(),
            Axis::Cat { names, .. } => {
                let i = v.round();
                if i >= 0.0 && (i - v).abs() < 1e-9 {
                    names.get(i as usize).cloned().unwrap_or_default()
                } else {
                    String::new()
                }
            }
        }
    }

    /// The labelled ticks: (position, label).
    pub fn ticks(&self) -> Vec<(f64, String)> {
        self.key_points()
            .into_iter()
            .map(|p| (p, self.label_of(p)))
            .collect()
    }

    pub(super) fn desc(&self) -> String {
        match self {
            Axis::Num { label, range } => range.label(label),
            Axis::Cat { label, .. } => label.clone(),
        }
    }

    pub(super) fn coord(&self) -> Coord {
        let (lo, hi) = self.ends();
        Coord {
            lo,
            hi,
            keys: self.key_points(),
        }
    }
}

/// A linear f64 coordinate whose ticks are given (plotters' own f64
/// coordinate computes them itself, and loops on an infinite span).
#[derive(Clone, Debug)]
pub(crate) struct Coord {
    lo: f64,
    hi: f64,
    keys: Vec<f64>,
}

impl Coord {
    /// [lo, hi] without ticks.
    pub(super) fn bare(lo: f64, hi: f64) -> Coord {
        Coord {
            lo,
            hi,
            keys: Vec::new(),
        }
    }
}

impl Ranged for Coord {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, v: &f64, limit: (i32, i32)) -> i32 {
        let t = (v - self.lo) / (self.hi - self.lo);
        let p = limit.0 as f64 + t * (limit.1 - limit.0) as f64;
        // Far outside (or NaN, which `as` makes 0) stays a finite pixel.
        p.clamp(-1e6, 1e6).round() as i32
    }

    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            Vec::new()
        } else {
            self.keys.clone()
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.lo..self.hi
    }
}

type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<Coord, Coord>>;

/// The chart of a figure: caption, axes with their ticks and labels.
pub(super) fn chart<'a, 'b>(
    area: &'a DrawingArea<SVGBackend<'b>, plotters::coord::Shift>,
    title: &str,
    x: &Axis,
    y: &Axis,
    mesh: bool,
) -> Result<Chart<'a, 'b>, String> {
    let mut c = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 15))
        .margin(10)
        .margin_right(18)
        .x_label_area_size(50)
        .y_label_area_size(84)
        .build_cartesian_2d(x.coord(), y.coord())
        .map_err(err)?;
    let (fx, fy) = (|v: &f64| x.label_of(*v), |v: &f64| y.label_of(*v));
    let mut m = c.configure_mesh();
    if !mesh {
        m.disable_mesh();
    } else {
        m.light_line_style(WHITE.mix(0.0));
    }
    m.label_style(("sans-serif", LABEL_PX))
        .axis_desc_style(("sans-serif", LABEL_PX))
        .x_desc(x.desc())
        .y_desc(y.desc())
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .draw()
        .map_err(err)?;
    Ok(c)
}
