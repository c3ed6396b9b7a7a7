//! SVG charts of the report (plotters): series of points on log–log or linear axes.

use plotters::coord::combinators::IntoLogRange;
use plotters::prelude::*;
use std::path::Path;

/// One named series of `(x, y)` points, drawn as a line with markers.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// The legend's label.
    pub name: String,
    /// The points (non-positive values are left out on a log axis).
    pub points: Vec<(f64, f64)>,
    /// A short label written next to each point (may be empty).
    pub labels: Vec<String>,
}

/// A chart's text.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Labels<'a> {
    /// The title.
    pub title: &'a str,
    /// The x axis.
    pub x: &'a str,
    /// The y axis.
    pub y: &'a str,
}

const COLORS: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
];

fn log_bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
    if lo > hi {
        return (0.1, 10.0);
    }
    // whole decades around the data
    (
        10f64.powf(lo.log10().floor()),
        10f64.powf((hi.log10() + 1e-9).ceil().max(lo.log10().floor() + 1.0)),
    )
}

/// The label of a log axis's key point: `1e-3` at each power of ten, nothing between (the grid lines there stay).
fn decade_label(v: &f64) -> String {
    let e = v.log10();
    if (e - e.round()).abs() < 1e-9 {
        format!("1e{}", e.round() as i64)
    } else {
        String::new()
    }
}

/// Draws `series` on log–log axes into the SVG file `path` (800 × 520).
pub fn loglog_svg(path: &Path, labels: Labels, series: &[Series]) -> anyhow::Result<()> {
    let err = |e: &dyn std::fmt::Display| anyhow::anyhow!("{}: {e}", path.display());
    let pts = |f: fn(&(f64, f64)) -> f64| {
        series
            .iter()
            .flat_map(|s| s.points.iter().map(f))
            .collect::<Vec<_>>()
    };
    // Both axes span whole decades around the data, so that each axis has at least two labelled decades.
    let (x0, x1) = log_bounds(pts(|p| p.0).into_iter());
    let (y0, y1) = log_bounds(pts(|p| p.1).into_iter());
    // a free decade on top for the legend
    let y1 = y1 * 10.0;
    let root = SVGBackend::new(path, (800, 520)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(labels.title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(70)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .x_desc(labels.x)
        .y_desc(labels.y)
        .x_labels(24)
        .y_labels(24)
        .light_line_style(BLACK.mix(0.05))
        .x_label_formatter(&decade_label)
        .y_label_formatter(&decade_label)
        .draw()
        .map_err(|e| err(&e))?;
    for (i, s) in series.iter().enumerate() {
        let color = COLORS[i % COLORS.len()];
        let keep = |&(x, y): &(f64, f64)| x > 0.0 && y > 0.0 && x.is_finite() && y.is_finite();
        let p: Vec<(f64, f64)> = s.points.iter().copied().filter(keep).collect();
        chart
            .draw_series(LineSeries::new(p.clone(), color.stroke_width(2)))
            .map_err(|e| err(&e))?
            .label(s.name.as_str())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2))
            });
        chart
            .draw_series(p.iter().map(|&q| Circle::new(q, 4, color.filled())))
            .map_err(|e| err(&e))?;
        let texts = s
            .points
            .iter()
            .zip(&s.labels)
            .filter(|(q, _)| keep(q))
            .map(|(&q, l)| {
                EmptyElement::at(q)
                    + Text::new(
                        l.clone(),
                        (6, -15),
                        ("sans-serif", 11).into_font().color(&color),
                    )
            });
        chart.draw_series(texts).map_err(|e| err(&e))?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(|e| err(&e))?;
    root.present().map_err(|e| err(&e))?;
    Ok(())
}
