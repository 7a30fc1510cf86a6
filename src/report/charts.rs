//! Charts of values against a numeric or categorical axis: lines with
//! bands, points with whiskers, histograms and tornados (maps are in
//! [`super::plots`], with the axes they all share).

use plotters::prelude::*;

use super::plots::{chart, err, inline, Axis, Coord, LABEL_PX, SIZE};

/// One curve of a line chart: name, points, and an optional band (x,
/// low, high) around it.
pub(crate) struct Curve<'a> {
    /// Its name in the legend.
    pub name: &'a str,
    /// (x, y) points, joined in order.
    pub points: Vec<(f64, f64)>,
    /// (x, low, high): a shaded band around the curve; empty for none.
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
pub(crate) fn x_axis(label: &str, curves: &[Curve], marks: &[f64], log: bool) -> Axis {
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
pub(crate) fn line_chart(
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
    /// Its name in the legend.
    pub name: &'a str,
    /// Per category: (value, low, high); NaN for none.
    pub values: Vec<(f64, f64, f64)>,
    /// Its colour (None: the palette's, by position).
    pub colour: Option<RGBColor>,
}

/// Colours that say "yes", "undecided" and "no".
pub(crate) const VERDICT_COLOURS: [RGBColor; 3] = [
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
        // Series side by side within a category only where two of them
        // have a point there; exclusive series (met, not met) sit on
        // their ticks.
        let len = series.iter().map(|s| s.values.len()).max().unwrap_or(0);
        let overlap = (0..len).any(|i| {
            series
                .iter()
                .filter(|s| s.values.get(i).is_some_and(|v| v.0.is_finite()))
                .count()
                > 1
        });
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
            let dx = if n > 1.0 && overlap {
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
pub(crate) fn histogram(
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
            .x_label_area_size(50)
            .y_label_area_size(70)
            .right_y_label_area_size(60)
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
            .label_style(("sans-serif", LABEL_PX))
            .axis_desc_style(("sans-serif", LABEL_PX))
            .x_desc(x.desc())
            .y_desc("lanes")
            .x_label_formatter(&fx)
            .y_label_formatter(&fy)
            .draw()
            .map_err(err)?;
        c.configure_secondary_axes()
            .label_style(("sans-serif", LABEL_PX))
            .axis_desc_style(("sans-serif", LABEL_PX))
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
pub(crate) fn tornado(title: &str, bars: &[(String, f64)]) -> Result<String, String> {
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
            .x_label_area_size(50)
            .y_label_area_size(110)
            .build_cartesian_2d(x.coord(), Coord::bare(0.0, n as f64))
            .map_err(err)?;
        let fx = |v: &f64| x.label_of(*v);
        c.configure_mesh()
            .disable_y_mesh()
            .label_style(("sans-serif", LABEL_PX))
            .axis_desc_style(("sans-serif", LABEL_PX))
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
