//! The report's maps: heat maps of a result and maps of categories over
//! two grid axes, each a grid of cells on categorical [`Axis`]es.

use plotters::prelude::*;

use super::axis::{colour, Range};
use super::plots::{chart, err, inline, Axis, Coord, Drawn, SIZE};

/// What a heat map draws besides its colours.
#[derive(Clone, Copy, Default)]
pub(crate) struct HeatMarks<'a> {
    /// A line in cell coordinates (cell (ix, iy) centred on (ix, iy)).
    pub line: Option<&'a [(f64, f64)]>,
    /// Cells struck through (a diagonal), with the legend's word for them.
    pub struck: Option<(&'a [bool], &'a str)>,
    /// Cells <= 0 drawn in one colour of their own, with the legend's
    /// word for them, and left out of the colour scale (a self-locking
    /// drive's inverse efficiency is no point on the scale of the others).
    pub at_most_zero: Option<&'a str>,
}

/// The colour of the cells a heat map shows as <= 0.
pub(crate) const AT_MOST_ZERO: RGBColor = RGBColor(70, 70, 70);

/// A heat map over two grid axes: `cells[iy * nx + ix]`, a colour bar
/// named `value_name`, and what `marks` adds.
pub(crate) fn heat_map(
    title: &str,
    x: &Axis,
    y: &Axis,
    cells: &[f64],
    value_name: &str,
    marks: HeatMarks,
) -> Result<String, String> {
    let floor = marks.at_most_zero.is_some();
    let low = |v: f64| floor && v <= 0.0;
    let range = Range::of(cells.iter().copied().filter(|&v| !low(v)), 0.0);
    let (nx, ny) = (count(x), count(y));
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let (map, bar) = root.split_horizontally(SIZE.0 - 118);
        let mut chart = chart(&map, title, x, y, false)?;
        fill_cells(&mut chart, nx, ny, |i| {
            let v = cells.get(i).copied().unwrap_or(f64::NAN);
            if low(v) {
                AT_MOST_ZERO
            } else {
                colour(range.map(v), range.lo, range.hi)
            }
        })?;
        if let Some((struck, _)) = marks.struck {
            chart
                .draw_series(
                    (0..ny)
                        .flat_map(|iy| (0..nx).map(move |ix| (ix, iy)))
                        .filter(|&(ix, iy)| struck.get(iy * nx + ix).copied().unwrap_or(false))
                        .map(|(ix, iy)| {
                            let (cx, cy) = (ix as f64, iy as f64);
                            PathElement::new(
                                vec![(cx - 0.5, cy - 0.5), (cx + 0.5, cy + 0.5)],
                                BLACK.stroke_width(1),
                            )
                        }),
                )
                .map_err(err)?;
        }
        // The line is named in the page's text: a legend box would hide
        // cells.
        if let Some(pts) = marks.line.filter(|p| p.len() >= 2) {
            chart
                .draw_series(LineSeries::new(pts.iter().copied(), RED.stroke_width(2)))
                .map_err(err)?;
        }
        colour_bar(&bar, value_name, &range)?;
        legend(&root, &marks)?;
        root.present().map_err(err)?;
    }
    Ok(inline(svg))
}

/// Fills the nx × ny cells of a map (cell (ix, iy) centred on (ix, iy))
/// with the colour of cell `iy * nx + ix`.
fn fill_cells(
    chart: &mut ChartContext<SVGBackend, Cartesian2d<Coord, Coord>>,
    nx: usize,
    ny: usize,
    colour_of: impl Fn(usize) -> RGBColor,
) -> Drawn {
    chart
        .draw_series(
            (0..ny)
                .flat_map(|iy| (0..nx).map(move |ix| (ix, iy)))
                .map(|(ix, iy)| {
                    let (cx, cy) = (ix as f64, iy as f64);
                    Rectangle::new(
                        [(cx - 0.5, cy - 0.5), (cx + 0.5, cy + 0.5)],
                        colour_of(iy * nx + ix).filled(),
                    )
                }),
        )
        .map_err(err)?;
    Ok(())
}

/// What the cells outside the colour scale mean, below the colour bar.
fn legend(root: &DrawingArea<SVGBackend, plotters::coord::Shift>, marks: &HeatMarks) -> Drawn {
    let x0 = SIZE.0 as i32 - 112;
    let mut y0 = SIZE.1 as i32 - 40;
    if let Some(word) = marks.at_most_zero {
        root.draw(&Rectangle::new(
            [(x0, y0), (x0 + 12, y0 + 12)],
            AT_MOST_ZERO.filled(),
        ))
        .map_err(err)?;
        root.draw(&Text::new(
            format!("<= 0: {word}"),
            (x0 + 16, y0),
            ("sans-serif", 13),
        ))
        .map_err(err)?;
        y0 += 18;
    }
    if let Some((_, word)) = marks.struck.filter(|s| s.0.iter().any(|&b| b)) {
        root.draw(&PathElement::new(
            vec![(x0, y0), (x0 + 12, y0 + 12)],
            BLACK.stroke_width(1),
        ))
        .map_err(err)?;
        root.draw(&Text::new(
            word.to_string(),
            (x0 + 16, y0),
            ("sans-serif", 13),
        ))
        .map_err(err)?;
    }
    Ok(())
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
        .caption(range.label(name), ("sans-serif", 13))
        .build_cartesian_2d(Coord::bare(0.0, 1.0), y.coord())
        .map_err(err)?;
    let fy = |v: &f64| y.label_of(*v);
    c.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_label_style(("sans-serif", 13))
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

/// A map of categories over two grid axes (`cells` hold an index into
/// `names`, or `names.len()` for none, drawn in `none`) with a legend of
/// the categories in `shown` (those that occur).
pub(crate) fn category_map(
    title: &str,
    x: &Axis,
    y: &Axis,
    cells: &[usize],
    names: &[(&str, RGBColor)],
    none: RGBColor,
    shown: &[usize],
) -> Result<String, String> {
    let (nx, ny) = (count(x), count(y));
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let (map, _legend) = root.split_horizontally(SIZE.0 - 118);
        let mut chart = chart(&map, title, x, y, false)?;
        fill_cells(&mut chart, nx, ny, |i| {
            let k = cells.get(i).copied().unwrap_or(names.len());
            names.get(k).map_or(none, |n| n.1)
        })?;
        for (i, &k) in shown.iter().enumerate() {
            let Some((name, colour)) = names.get(k) else {
                continue;
            };
            let y = 50 + 22 * i as i32;
            let x = SIZE.0 as i32 - 112;
            root.draw(&Rectangle::new([(x, y), (x + 14, y + 14)], colour.filled()))
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
