//! The report's figures, drawn with plotters into SVG strings that the
//! page inlines. Axes are drawn in index space where a grid may be
//! logarithmic or a list, and labelled with the grid's values.

use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::colors::colormaps::ViridisRGB;

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

/// A value for a tick label: short, and exact for round values.
pub fn tick(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if !(1e-3..1e5).contains(&a) {
        format!("{v:.2e}")
    } else {
        let s = format!("{v:.4}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

/// The colour of a value within [lo, hi] (viridis); grey for no value.
fn colour(v: f64, lo: f64, hi: f64) -> RGBColor {
    if !v.is_finite() {
        return RGBColor(200, 200, 200);
    }
    let (lo, hi) = if hi > lo {
        (lo, hi)
    } else {
        (lo - 0.5, lo + 0.5)
    };
    ViridisRGB.get_color_normalized(v as f32, lo as f32, hi as f32)
}

/// A heat map over a grid: `cells[iy * nx + ix]`, axis labels from `xs`
/// and `ys` (one value per cell column and row), a colour bar, and an
/// optional line (in cell coordinates, centres at i + 0.5).
#[allow(clippy::too_many_arguments)]
pub fn heat_map(
    title: &str,
    x_name: &str,
    xs: &[f64],
    y_name: &str,
    ys: &[f64],
    cells: &[f64],
    value_name: &str,
    line: Option<&[(f64, f64)]>,
) -> Result<String, String> {
    let mut svg = String::new();
    let finite = cells.iter().copied().filter(|v| v.is_finite());
    let lo = finite.clone().fold(f64::INFINITY, f64::min);
    let hi = finite.fold(f64::NEG_INFINITY, f64::max);
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let (map, bar) = root.split_horizontally(SIZE.0 - 110);
        let mut chart = grid_map(&map, title, (x_name, xs), (y_name, ys), |i| {
            colour(cells[i], lo, hi)
        })?;
        // The line is named in the page's text: a legend box would hide
        // cells.
        if let Some(pts) = line {
            if pts.len() >= 2 {
                chart
                    .draw_series(LineSeries::new(pts.iter().copied(), RED.stroke_width(2)))
                    .map_err(err)?;
            }
        }
        colour_bar(&bar, value_name, lo, hi)?;
        root.present().map_err(err)?;
    }
    Ok(inline(svg))
}

/// Chart coordinates of a grid map: cell (ix, iy) spans [ix, ix + 1] x
/// [iy, iy + 1].
type GridChart<'a, 'b> =
    ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// The axes of a map over a grid (labelled with the grid's values, one
/// per cell) and its cells, `cells[iy * nx + ix]` coloured by `colour_of`.
fn grid_map<'a, 'b>(
    area: &'a DrawingArea<SVGBackend<'b>, plotters::coord::Shift>,
    title: &str,
    (x_name, xs): (&str, &[f64]),
    (y_name, ys): (&str, &[f64]),
    colour_of: impl Fn(usize) -> RGBColor,
) -> Result<GridChart<'a, 'b>, String> {
    let (nx, ny) = (xs.len(), ys.len());
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 15))
        .margin(8)
        .x_label_area_size(42)
        .y_label_area_size(62)
        .build_cartesian_2d(0f64..nx as f64, 0f64..ny as f64)
        .map_err(err)?;
    let lab = |v: &[f64], i: f64| {
        v.get(i.floor() as usize)
            .map(|&x| tick(x))
            .unwrap_or_default()
    };
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(x_name)
        .y_desc(y_name)
        .x_labels(nx.min(8))
        .y_labels(ny.min(8))
        .x_label_formatter(&|i| lab(xs, *i))
        .y_label_formatter(&|i| lab(ys, *i))
        .draw()
        .map_err(err)?;
    chart
        .draw_series(
            (0..ny)
                .flat_map(|iy| (0..nx).map(move |ix| (ix, iy)))
                .map(|(ix, iy)| {
                    Rectangle::new(
                        [(ix as f64, iy as f64), (ix as f64 + 1.0, iy as f64 + 1.0)],
                        colour_of(iy * nx + ix).filled(),
                    )
                }),
        )
        .map_err(err)?;
    Ok(chart)
}

fn colour_bar(
    area: &DrawingArea<SVGBackend, plotters::coord::Shift>,
    name: &str,
    lo: f64,
    hi: f64,
) -> Drawn {
    if !(lo.is_finite() && hi.is_finite()) {
        return Ok(());
    }
    let (lo2, hi2) = if hi > lo {
        (lo, hi)
    } else {
        (lo - 0.5, lo + 0.5)
    };
    let mut c = ChartBuilder::on(area)
        .margin_top(34)
        .margin_bottom(50)
        .margin_right(25)
        .y_label_area_size(45)
        .caption(name, ("sans-serif", 12))
        .build_cartesian_2d(0f64..1f64, lo2..hi2)
        .map_err(err)?;
    c.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_labels(6)
        .y_label_style(("sans-serif", 12))
        .y_label_formatter(&|v| tick(*v))
        .draw()
        .map_err(err)?;
    let steps = 64;
    c.draw_series((0..steps).map(|i| {
        let a = lo2 + (hi2 - lo2) * i as f64 / steps as f64;
        let b = lo2 + (hi2 - lo2) * (i + 1) as f64 / steps as f64;
        // From x = 0.4: the tick labels left of the axis keep clear of it.
        Rectangle::new([(0.4, a), (1.0, b)], colour(0.5 * (a + b), lo, hi).filled())
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

/// A map of categories (`cells` hold an index into `names`, or
/// `names.len()` for none) with a legend.
pub fn category_map(
    title: &str,
    x_name: &str,
    xs: &[f64],
    y_name: &str,
    ys: &[f64],
    cells: &[usize],
    names: &[&str],
) -> Result<String, String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let (map, _legend) = root.split_horizontally(SIZE.0 - 110);
        grid_map(&map, title, (x_name, xs), (y_name, ys), |i| {
            CONTACT_COLOURS[cells[i].min(CONTACT_COLOURS.len() - 1)]
        })?;
        // Legend: one swatch per category, right of the map.
        for (i, name) in names.iter().enumerate() {
            let y = 50 + 22 * i as i32;
            let x = SIZE.0 as i32 - 110;
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

/// One curve of a line chart: name, points, and an optional band (low,
/// high) around it.
pub struct Curve<'a> {
    pub name: &'a str,
    pub points: Vec<(f64, f64)>,
    pub band: Vec<(f64, f64, f64)>,
}

const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
];

/// A line chart of curves against x, with vertical marks at `marks`
/// (e.g. events), a legend when there is more than one curve.
pub fn line_chart(
    title: &str,
    x_name: &str,
    y_name: &str,
    curves: &[Curve],
    marks: &[f64],
    log_x: bool,
) -> Result<String, String> {
    let pts = curves.iter().flat_map(|c| c.points.iter().chain([].iter()));
    let bands = curves
        .iter()
        .flat_map(|c| c.band.iter().flat_map(|b| [(b.0, b.1), (b.0, b.2)]));
    let all: Vec<(f64, f64)> = pts
        .copied()
        .chain(bands)
        .filter(|p| p.0.is_finite() && p.1.is_finite())
        .collect();
    let range = |f: fn(&(f64, f64)) -> f64| {
        let lo = all.iter().map(f).fold(f64::INFINITY, f64::min);
        let hi = all.iter().map(f).fold(f64::NEG_INFINITY, f64::max);
        if !lo.is_finite() {
            (0.0, 1.0)
        } else if hi > lo {
            let pad = 0.04 * (hi - lo);
            (lo - pad, hi + pad)
        } else {
            (lo - 0.5, lo + 0.5)
        }
    };
    let (x0, x1) = {
        let (a, b) = range(|p| p.0);
        if log_x {
            (a.max(f64::MIN_POSITIVE), b)
        } else {
            (a, b)
        }
    };
    let (y0, y1) = range(|p| p.1);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let mut b = ChartBuilder::on(&root);
        b.caption(title, ("sans-serif", 15))
            .margin(10)
            .x_label_area_size(42)
            .y_label_area_size(70);
        macro_rules! draw {
            ($chart:expr) => {{
                let mut chart = $chart;
                chart
                    .configure_mesh()
                    .x_desc(x_name)
                    .y_desc(y_name)
                    .x_label_formatter(&|v| tick(*v))
                    .y_label_formatter(&|v| tick(*v))
                    .light_line_style(WHITE.mix(0.0))
                    .draw()
                    .map_err(err)?;
                for &m in marks {
                    chart
                        .draw_series(LineSeries::new(
                            [(m, y0), (m, y1)],
                            BLACK.mix(0.35).stroke_width(1),
                        ))
                        .map_err(err)?;
                }
                for (i, c) in curves.iter().enumerate() {
                    let col = PALETTE[i % PALETTE.len()];
                    if !c.band.is_empty() {
                        let upper = c.band.iter().map(|b| (b.0, b.2));
                        let lower = c.band.iter().rev().map(|b| (b.0, b.1));
                        chart
                            .draw_series(std::iter::once(Polygon::new(
                                upper.chain(lower).collect::<Vec<_>>(),
                                col.mix(0.2).filled(),
                            )))
                            .map_err(err)?;
                    }
                    chart
                        .draw_series(LineSeries::new(
                            c.points.iter().copied().filter(|p| p.1.is_finite()),
                            col.stroke_width(2),
                        ))
                        .map_err(err)?
                        .label(c.name)
                        .legend(move |(x, y)| {
                            PathElement::new([(x, y), (x + 16, y)], col.stroke_width(2))
                        });
                    // Few points: mark each, so a single one shows too.
                    if c.points.len() <= 40 {
                        chart
                            .draw_series(
                                c.points
                                    .iter()
                                    .filter(|p| p.1.is_finite())
                                    .map(|&p| Circle::new(p, 3, col.filled())),
                            )
                            .map_err(err)?;
                    }
                }
                if curves.len() > 1 || curves.iter().any(|c| !c.band.is_empty()) {
                    chart
                        .configure_series_labels()
                        .background_style(WHITE.mix(0.85))
                        .border_style(BLACK)
                        .draw()
                        .map_err(err)?;
                }
            }};
        }
        if log_x {
            draw!(b
                .build_cartesian_2d((x0..x1).log_scale(), y0..y1)
                .map_err(err)?);
        } else {
            draw!(b.build_cartesian_2d(x0..x1, y0..y1).map_err(err)?);
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
    let (lo, hi) = if hi > lo {
        (lo, hi)
    } else {
        (lo - 0.5, lo + 0.5)
    };
    let w = (hi - lo) / n as f64;
    let top = counts.iter().copied().max().unwrap_or(1).max(1) as f64 * 1.05;
    let total: u64 = counts.iter().sum();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 15))
            .margin(10)
            .x_label_area_size(42)
            .y_label_area_size(60)
            .right_y_label_area_size(50)
            .build_cartesian_2d(lo..hi, 0f64..top)
            .map_err(err)?
            .set_secondary_coord(lo..hi, 0f64..1.0);
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(x_name)
            .y_desc("lanes")
            .x_label_formatter(&|v| tick(*v))
            .y_label_formatter(&|v| tick(*v))
            .draw()
            .map_err(err)?;
        chart
            .configure_secondary_axes()
            .y_desc("empirical CDF")
            .y_label_formatter(&|v| tick(*v))
            .draw()
            .map_err(err)?;
        chart
            .draw_series(counts.iter().enumerate().map(|(i, &c)| {
                let a = lo + w * i as f64;
                Rectangle::new([(a, 0.0), (a + w, c as f64)], PALETTE[0].mix(0.6).filled())
            }))
            .map_err(err)?;
        let mut cum = 0u64;
        let mut steps = vec![(lo, 0.0)];
        for (i, &c) in counts.iter().enumerate() {
            cum += c;
            let x = lo + w * (i + 1) as f64;
            steps.push((x - w, cum as f64 / total.max(1) as f64));
            steps.push((x, cum as f64 / total.max(1) as f64));
        }
        chart
            .draw_secondary_series(LineSeries::new(steps, PALETTE[1].stroke_width(2)))
            .map_err(err)?;
        root.present().map_err(err)?;
    }
    Ok(inline(svg))
}

/// A tornado chart: one horizontal bar per input, longest first.
pub fn tornado(title: &str, bars: &[(String, f64)]) -> Result<String, String> {
    let n = bars.len().max(1);
    let h = (80 + 34 * n as u32).max(200);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (SIZE.0, h)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let names: Vec<String> = bars.iter().map(|b| b.0.clone()).collect();
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 15))
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(110)
            .build_cartesian_2d(-1f64..1f64, 0f64..n as f64)
            .map_err(err)?;
        chart
            .configure_mesh()
            .disable_y_mesh()
            .x_desc("Spearman rank correlation")
            .y_label_formatter(&|_| String::new())
            .x_label_formatter(&|v| tick(*v))
            .draw()
            .map_err(err)?;
        chart
            .draw_series(bars.iter().enumerate().map(|(i, (_, r))| {
                let y = (n - 1 - i) as f64;
                let col = if *r >= 0.0 { PALETTE[0] } else { PALETTE[1] };
                Rectangle::new([(0.0, y + 0.15), (*r, y + 0.85)], col.filled())
            }))
            .map_err(err)?;
        // The inputs' names left of the plot, level with their bars.
        for (i, name) in names.iter().enumerate() {
            let (_, py) = chart.backend_coord(&(-1.0, (n - 1 - i) as f64 + 0.5));
            root.draw(&Text::new(name.clone(), (12, py - 7), ("sans-serif", 13)))
                .map_err(err)?;
        }
        root.present().map_err(err)?;
    }
    Ok(inline(svg))
}
