//! The report's figures, drawn with plotters into SVG strings that the
//! page inlines. Every axis is an [`Axis`]: numeric (a [`Range`] from
//! `axis`, whose ticks plotters is given) or categorical (grid values at
//! evenly spaced positions, labelled at their centres). So no figure
//! depends on plotters' own tick search or colour normalisation, and any
//! finite value draws.

use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};
use plotters::prelude::*;

use super::axis::{colour, value_labels, Range};

/// Width and height of one figure, px.
pub const SIZE: (u32, u32) = (560, 400);

/// Plotters' drawing errors carry backend types; the report only needs
/// to say that a figure could not be drawn.
type Drawn = Result<(), String>;

fn err<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

/// Finishes an SVG for inlining in HTML: the namespace attribute is left
/// out (HTML needs none, and the page then names no address at all).
fn inline(svg: String) -> String {
    svg.replace(" xmlns=\"http://www.w3.org/2000/svg\"", "")
}

/// A value for a table cell or a panel's name: short, and exact for
/// round values.
pub fn tick(v: f64) -> String {
    super::axis::number(v, v.abs() * 1e-4)
}

/// Most labelled categories on an axis (the others are drawn unlabelled).
const MAX_LABELS: usize = 8;

/// A figure's axis.
#[derive(Clone, Debug)]
pub enum Axis {
    /// Numbers on a linear scale (values in the range's plotted units).
    Num { label: String, range: Range },
    /// Categories at positions 0, 1, ..., labelled with their names.
    Cat { label: String, names: Vec<String> },
}

impl Axis {
    /// A numeric axis over `values`, padded by 4 % of their span.
    pub fn numeric(label: &str, values: impl IntoIterator<Item = f64>) -> Axis {
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

    /// Categories named by grid values (labels that tell them apart).
    pub fn grid(label: &str, values: &[f64]) -> Axis {
        Axis::Cat {
            label: label.to_string(),
            names: value_labels(values),
        }
    }

    /// A value in plotted units (a category's index stays as it is).
    pub fn map(&self, v: f64) -> f64 {
        match self {
            Axis::Num { range, .. } => range.map(v),
            Axis::Cat { .. } => v,
        }
    }

    fn ends(&self) -> (f64, f64) {
        match self {
            Axis::Num { range, .. } => (range.lo, range.hi),
            Axis::Cat { names, .. } => (-0.5, names.len().max(1) as f64 - 0.5),
        }
    }

    fn key_points(&self) -> Vec<f64> {
        match self {
            Axis::Num { range, .. } => range.ticks.clone(),
            Axis::Cat { names, .. } => {
                let every = names.len().div_ceil(MAX_LABELS).max(1);
                (0..names.len()).step_by(every).map(|i| i as f64).collect()
            }
        }
    }

    fn label_of(&self, v: f64) -> String {
        match self {
            Axis::Num { range, .. } => range.tick_label(v),
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

    fn desc(&self) -> String {
        match self {
            Axis::Num { label, range } => range.label(label),
            Axis::Cat { label, .. } => label.clone(),
        }
    }

    fn coord(&self) -> Coord {
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
pub struct Coord {
    lo: f64,
    hi: f64,
    keys: Vec<f64>,
}

impl Coord {
    /// [lo, hi] without ticks.
    fn bare(lo: f64, hi: f64) -> Coord {
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
fn chart<'a, 'b>(
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
        .x_label_area_size(42)
        .y_label_area_size(74)
        .build_cartesian_2d(x.coord(), y.coord())
        .map_err(err)?;
    let (fx, fy) = (|v: &f64| x.label_of(*v), |v: &f64| y.label_of(*v));
    let mut m = c.configure_mesh();
    if !mesh {
        m.disable_mesh();
    } else {
        m.light_line_style(WHITE.mix(0.0));
    }
    m.x_desc(x.desc())
        .y_desc(y.desc())
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .draw()
        .map_err(err)?;
    Ok(c)
}

/// A heat map over two grid axes: `cells[iy * nx + ix]`, a colour bar
/// named `value_name`, and an optional line in cell coordinates (cell
/// (ix, iy) centred on (ix, iy)).
pub fn heat_map(
    title: &str,
    x: &Axis,
    y: &Axis,
    cells: &[f64],
    value_name: &str,
    line: Option<&[(f64, f64)]>,
) -> Result<String, String> {
    let range = Range::of(cells.iter().copied(), 0.0);
    let (nx, ny) = (count(x), count(y));
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let (map, bar) = root.split_horizontally(SIZE.0 - 118);
        let mut chart = chart(&map, title, x, y, false)?;
        chart
            .draw_series(
                (0..ny)
                    .flat_map(|iy| (0..nx).map(move |ix| (ix, iy)))
                    .map(|(ix, iy)| {
                        let (cx, cy) = (ix as f64, iy as f64);
                        let v = cells.get(iy * nx + ix).copied().unwrap_or(f64::NAN);
                        Rectangle::new(
                            [(cx - 0.5, cy - 0.5), (cx + 0.5, cy + 0.5)],
                            colour(range.map(v), range.lo, range.hi).filled(),
                        )
                    }),
            )
            .map_err(err)?;
        // The line is named in the page's text: a legend box would hide
        // cells.
        if let Some(pts) = line.filter(|p| p.len() >= 2) {
            chart
                .draw_series(LineSeries::new(pts.iter().copied(), RED.stroke_width(2)))
                .map_err(err)?;
        }
        colour_bar(&bar, value_name, &range)?;
        root.present().map_err(err)?;
    }
    Ok(inline(svg))
}

fn count(a: &Axis) -> usize {
    match a {
        Axis::Cat { names, .. } => names.len(),
        Axis::Num { .. } => 0,
    }
}

fn colour_bar(
    area: &DrawingArea<SVGBackend, plotters::coord::Shift>,
    name: &str,
    range: &Range,
) -> Drawn {
    let y = Axis::Num {
        label: String::new(),
        range: range.clone(),
    };
    let mut c = ChartBuilder::on(area)
        .margin_top(34)
        .margin_bottom(50)
        .margin_right(25)
        .y_label_area_size(55)
        .caption(range.label(name), ("sans-serif", 11))
        .build_cartesian_2d(Coord::bare(0.0, 1.0), y.coord())
        .map_err(err)?;
    let fy = |v: &f64| y.label_of(*v);
    c.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_label_style(("sans-serif", 12))
        .y_label_formatter(&fy)
        .draw()
        .map_err(err)?;
    let steps = 64;
    let (lo, hi) = (range.lo, range.hi);
    c.draw_series((0..steps).map(|i| {
        let f = |k: usize| lo + (0.5 * hi - 0.5 * lo) * 2.0 * k as f64 / steps as f64;
        let (a, b) = (f(i), f(i + 1));
        // From x = 0.4: the tick labels left of the axis keep clear of it.
        Rectangle::new(
            [(0.4, a), (1.0, b)],
            colour(0.5 * a + 0.5 * b, lo, hi).filled(),
        )
    }))
    .map_err(err)?;
    Ok(())
}

/// Colours of the final contacts (held, a-a, b-b) and "no result".
pub const CONTACT_COLOURS: [RGBColor; 4] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(200, 200, 200),
];

/// A map of categories over two grid axes (`cells` hold an index into
/// `names`, or `names.len()` for none) with a legend.
pub fn category_map(
    title: &str,
    x: &Axis,
    y: &Axis,
    cells: &[usize],
    names: &[&str],
) -> Result<String, String> {
    let (nx, ny) = (count(x), count(y));
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let (map, _legend) = root.split_horizontally(SIZE.0 - 118);
        let mut chart = chart(&map, title, x, y, false)?;
        chart
            .draw_series(
                (0..ny)
                    .flat_map(|iy| (0..nx).map(move |ix| (ix, iy)))
                    .map(|(ix, iy)| {
                        let (cx, cy) = (ix as f64, iy as f64);
                        let k = cells.get(iy * nx + ix).copied().unwrap_or(names.len());
                        Rectangle::new(
                            [(cx - 0.5, cy - 0.5), (cx + 0.5, cy + 0.5)],
                            CONTACT_COLOURS[k.min(CONTACT_COLOURS.len() - 1)].filled(),
                        )
                    }),
            )
            .map_err(err)?;
        for (i, name) in names.iter().enumerate() {
            let y = 50 + 22 * i as i32;
            let x = SIZE.0 as i32 - 112;
            root.draw(&Rectangle::new(
                [(x, y), (x + 14, y + 14)],
                CONTACT_COLOURS[i].filled(),
            ))
            .map_err(err)?;
            root.draw(&Text::new(
                name.to_string(),
                (x + 20, y + 1),
                ("sans-serif", 13),
            ))
            .map_err(err)?;
        }
        root.present().map_err(err)?;
    }
    Ok(inline(svg))
}

/// One curve of a line chart: name, points, and an optional band (x,
/// low, high) around it.
pub struct Curve<'a> {
    pub name: &'a str,
    pub points: Vec<(f64, f64)>,
    pub band: Vec<(f64, f64, f64)>,
    /// Its colour (None: the palette's, by position).
    pub colour: Option<RGBColor>,
}

pub(crate) const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
];

/// The x axis of a line chart: numeric over the curves' x values, on a
/// log10 scale when `log` (values <= 0 are left out).
pub fn x_axis(label: &str, curves: &[Curve], marks: &[f64], log: bool) -> Axis {
    let xs = curves
        .iter()
        .flat_map(|c| {
            c.points
                .iter()
                .map(|p| p.0)
                .chain(c.band.iter().map(|b| b.0))
        })
        .chain(marks.iter().copied());
    if log {
        Axis::numeric(
            &format!("{label}, log10"),
            xs.filter(|x| *x > 0.0).map(f64::log10),
        )
    } else {
        Axis::numeric(label, xs)
    }
}

/// A line chart of curves against x (`x` from [`x_axis`]), with vertical
/// marks at `marks` (events), a legend when there is more than one curve.
pub fn line_chart(
    title: &str,
    x: &Axis,
    log: bool,
    y_name: &str,
    curves: &[Curve],
    marks: &[f64],
) -> Result<String, String> {
    let ys = curves.iter().flat_map(|c| {
        c.points
            .iter()
            .map(|p| p.1)
            .chain(c.band.iter().flat_map(|b| [b.1, b.2]))
    });
    let y = Axis::numeric(y_name, ys);
    let px = |v: f64| {
        if log {
            if v > 0.0 {
                x.map(v.log10())
            } else {
                f64::NAN
            }
        } else {
            x.map(v)
        }
    };
    let pt = |(a, b): (f64, f64)| (px(a), y.map(b));
    let fine = |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let mut c = chart(&root, title, x, &y, true)?;
        let (y0, y1) = y.ends();
        for &m in marks {
            let m = px(m);
            if m.is_finite() {
                c.draw_series(LineSeries::new(
                    [(m, y0), (m, y1)],
                    BLACK.mix(0.35).stroke_width(1),
                ))
                .map_err(err)?;
            }
        }
        for (i, cv) in curves.iter().enumerate() {
            let col = cv.colour.unwrap_or(PALETTE[i % PALETTE.len()]);
            if !cv.band.is_empty() {
                let upper = cv.band.iter().map(|b| pt((b.0, b.2)));
                let lower = cv.band.iter().rev().map(|b| pt((b.0, b.1)));
                let poly: Vec<(f64, f64)> = upper.chain(lower).filter(fine).collect();
                c.draw_series(std::iter::once(Polygon::new(poly, col.mix(0.2).filled())))
                    .map_err(err)?;
            }
            let pts: Vec<(f64, f64)> = cv.points.iter().map(|&p| pt(p)).filter(fine).collect();
            c.draw_series(LineSeries::new(pts.iter().copied(), col.stroke_width(2)))
                .map_err(err)?
                .label(cv.name)
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], col.stroke_width(2)));
            // Few points: mark each, so a single one shows too.
            if pts.len() <= 40 {
                c.draw_series(pts.iter().map(|&p| Circle::new(p, 3, col.filled())))
                    .map_err(err)?;
            }
        }
        if curves.len() > 1 || curves.iter().any(|c| !c.band.is_empty()) {
            c.configure_series_labels()
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .draw()
                .map_err(err)?;
        }
        root.present().map_err(err)?;
    }
    Ok(inline(svg))
}

/// One series of a points chart: a name and, per category, a value with
/// an optional interval (low, high); NaN for none.
pub struct Series<'a> {
    pub name: &'a str,
    pub values: Vec<(f64, f64, f64)>,
    /// Its colour (None: the palette's, by position).
    pub colour: Option<RGBColor>,
}

/// Colours that say "yes", "undecided" and "no".
pub const VERDICT_COLOURS: [RGBColor; 3] = [
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(214, 39, 40),
];

/// Points with whiskers at the categories of `x` (a grid axis with few
/// values: its points are not joined, as a trend would suggest values in
/// between), several series side by side, an optional horizontal line
/// at `level` (with its name).
pub fn points_chart(
    title: &str,
    x: &Axis,
    y: &Axis,
    series: &[Series],
    level: Option<(f64, &str)>,
    legend_at: SeriesLabelPosition,
) -> Result<String, String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let mut c = chart(&root, title, x, y, true)?;
        let n = series.len().max(1) as f64;
        if let Some((v, name)) = level {
            let (x0, x1) = x.ends();
            let v = y.map(v);
            c.draw_series(LineSeries::new([(x0, v), (x1, v)], BLACK.stroke_width(1)))
                .map_err(err)?
                .label(name)
                .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], BLACK.stroke_width(1)));
        }
        for (k, s) in series.iter().enumerate() {
            let col = s.colour.unwrap_or(PALETTE[k % PALETTE.len()]);
            // Side by side within a category.
            let dx = if n > 1.0 {
                (k as f64 - (n - 1.0) / 2.0) * 0.6 / n
            } else {
                0.0
            };
            let at = |i: usize| i as f64 + dx;
            let whiskers: Vec<_> = s
                .values
                .iter()
                .enumerate()
                .filter(|(_, v)| v.1.is_finite() && v.2.is_finite())
                .map(|(i, v)| {
                    PathElement::new(
                        [(at(i), y.map(v.1)), (at(i), y.map(v.2))],
                        col.stroke_width(2),
                    )
                })
                .collect();
            c.draw_series(whiskers).map_err(err)?;
            c.draw_series(
                s.values
                    .iter()
                    .enumerate()
                    .filter(|(_, v)| v.0.is_finite())
                    .map(|(i, v)| Circle::new((at(i), y.map(v.0)), 4, col.filled())),
            )
            .map_err(err)?
            .label(s.name)
            .legend(move |(x, y)| Circle::new((x + 8, y), 4, col.filled()));
        }
        if series.len() > 1 || level.is_some() {
            c.configure_series_labels()
                .position(legend_at)
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .draw()
                .map_err(err)?;
        }
        root.present().map_err(err)?;
    }
    Ok(inline(svg))
}

/// A histogram of counts over equal bins from `lo` to `hi`, with the
/// empirical CDF (right axis in shares) drawn over it.
pub fn histogram(
    title: &str,
    x_name: &str,
    lo: f64,
    hi: f64,
    counts: &[u64],
) -> Result<String, String> {
    let n = counts.len().max(1);
    let x = Axis::numeric(x_name, [lo, hi]);
    let (x0, x1) = x.ends();
    let (a, b) = (x.map(lo), x.map(hi));
    let (a, b) = if b > a { (a, b) } else { (x0, x1) };
    let w = (0.5 * b - 0.5 * a) * 2.0 / n as f64;
    let top = counts.iter().copied().max().unwrap_or(1).max(1) as f64;
    let y = Axis::fixed("lanes", 0.0, top * 1.05);
    let total: u64 = counts.iter().sum();
    let cdf = Axis::fixed("empirical CDF", 0.0, 1.0);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let mut c = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 15))
            .margin(10)
            .x_label_area_size(42)
            .y_label_area_size(60)
            .right_y_label_area_size(50)
            .build_cartesian_2d(x.coord(), y.coord())
            .map_err(err)?
            .set_secondary_coord(x.coord(), cdf.coord());
        let (fx, fy, fc) = (
            |v: &f64| x.label_of(*v),
            |v: &f64| y.label_of(*v),
            |v: &f64| cdf.label_of(*v),
        );
        c.configure_mesh()
            .disable_mesh()
            .x_desc(x.desc())
            .y_desc("lanes")
            .x_label_formatter(&fx)
            .y_label_formatter(&fy)
            .draw()
            .map_err(err)?;
        c.configure_secondary_axes()
            .y_desc("empirical CDF")
            .y_label_formatter(&fc)
            .draw()
            .map_err(err)?;
        c.draw_series(counts.iter().enumerate().map(|(i, &k)| {
            let left = a + w * i as f64;
            Rectangle::new(
                [(left, 0.0), (left + w, k as f64)],
                PALETTE[0].mix(0.6).filled(),
            )
        }))
        .map_err(err)?;
        let mut cum = 0u64;
        let mut steps = vec![(a, 0.0)];
        for (i, &k) in counts.iter().enumerate() {
            cum += k;
            let right = a + w * (i + 1) as f64;
            let share = cum as f64 / total.max(1) as f64;
            steps.push((right - w, share));
            steps.push((right, share));
        }
        c.draw_secondary_series(LineSeries::new(steps, PALETTE[1].stroke_width(2)))
            .map_err(err)?;
        root.present().map_err(err)?;
    }
    Ok(inline(svg))
}

/// A tornado chart: one horizontal bar per input, longest first.
pub fn tornado(title: &str, bars: &[(String, f64)]) -> Result<String, String> {
    let n = bars.len().max(1);
    let h = (80 + 34 * n as u32).max(200);
    let x = Axis::fixed("Spearman rank correlation", -1.0, 1.0);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (SIZE.0, h)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let mut c = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 15))
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(110)
            .build_cartesian_2d(x.coord(), Coord::bare(0.0, n as f64))
            .map_err(err)?;
        let fx = |v: &f64| x.label_of(*v);
        c.configure_mesh()
            .disable_y_mesh()
            .x_desc(x.desc())
            .y_label_formatter(&|_| String::new())
            .x_label_formatter(&fx)
            .draw()
            .map_err(err)?;
        c.draw_series(bars.iter().enumerate().map(|(i, (_, r))| {
            let y = (n - 1 - i) as f64;
            let col = if *r >= 0.0 { PALETTE[0] } else { PALETTE[1] };
            Rectangle::new(
                [(0.0, y + 0.15), (r.clamp(-1.0, 1.0), y + 0.85)],
                col.filled(),
            )
        }))
        .map_err(err)?;
        // The inputs' names left of the plot, level with their bars.
        for (i, (name, _)) in bars.iter().enumerate() {
            let (_, py) = c.backend_coord(&(-1.0, (n - 1 - i) as f64 + 0.5));
            root.draw(&Text::new(name.clone(), (12, py - 7), ("sans-serif", 13)))
                .map_err(err)?;
        }
        root.present().map_err(err)?;
    }
    Ok(inline(svg))
}
