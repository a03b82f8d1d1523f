//! The demo's plots with `plotters` (SVG backend only): stacked panels of time series, linear
//! or logarithmic y axis, a legend to the right of each panel.

use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use std::ops::Range;

pub struct Series<'a> {
    pub label: &'a str,
    /// `#rrggbb` or `#rgb`.
    pub colour: &'a str,
    pub dashed: bool,
    pub points: Vec<(f64, f64)>,
}

pub struct Panel<'a> {
    pub title: &'a str,
    pub y_label: &'a str,
    pub log: bool,
    pub series: Vec<Series<'a>>,
}

const WIDTH: u32 = 900;
const PANEL_HEIGHT: u32 = 230;
const LEGEND_WIDTH: u32 = 170;
/// A log axis spans at most this many decades below the largest value.
const LOG_DECADES: f64 = 14.0;
const FONT: &str = "sans-serif";

/// Renders the panels one above the other into an SVG document.
pub fn render(panels: &[Panel]) -> String {
    let mut svg = String::new();
    {
        let height = PANEL_HEIGHT * panels.len().max(1) as u32;
        let root = SVGBackend::with_string(&mut svg, (WIDTH, height)).into_drawing_area();
        // Drawing into a string cannot fail for I/O reasons; an error here is a bug.
        root.fill(&WHITE).expect("SVG background");
        for (area, panel) in root.split_evenly((panels.len().max(1), 1)).iter().zip(panels) {
            draw_panel(area, panel).expect("SVG panel");
        }
        root.present().expect("SVG document");
    }
    svg
}

type DrawResult = Result<(), DrawingAreaErrorKind<std::io::Error>>;

fn draw_panel(area: &DrawingArea<SVGBackend, Shift>, panel: &Panel) -> DrawResult {
    let (plot, legend) = area.split_horizontally(WIDTH - LEGEND_WIDTH);
    let (x, y) = data_ranges(panel);
    if panel.log {
        let axis: LogCoord<f64> = (10f64.powf(y.start)..10f64.powf(y.end)).log_scale().into();
        draw_chart(&plot, panel, x, axis, &|v: &f64| format!("{v:.0e}"))?;
    } else {
        let axis: RangedCoordf64 = y.into();
        draw_chart(&plot, panel, x, axis, &|v: &f64| tick(*v))?;
    }
    draw_legend(&legend, panel)
}

/// The x range of all points (the whole run, even where nothing can be drawn) and the y range
/// of the drawable ones (of log10 y on a log axis) with a margin.
fn data_ranges(panel: &Panel) -> (Range<f64>, Range<f64>) {
    let (mut x_lo, mut x_hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut y_lo, mut y_hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for &(x, y) in panel.series.iter().flat_map(|s| &s.points) {
        if !x.is_finite() {
            continue;
        }
        (x_lo, x_hi) = (x_lo.min(x), x_hi.max(x));
        if let Some(y) = plotted(panel, y) {
            let y = if panel.log { y.log10() } else { y };
            (y_lo, y_hi) = (y_lo.min(y), y_hi.max(y));
        }
    }
    if !x_lo.is_finite() {
        (x_lo, x_hi) = (0.0, 1.0);
    }
    if !y_lo.is_finite() {
        (y_lo, y_hi) = (0.0, 1.0);
    }
    if x_hi - x_lo < 1e-12 {
        x_hi = x_lo + 1.0;
    }
    if panel.log {
        // whole decades, and no more of them than can be read
        (y_lo, y_hi) = (y_lo.floor().max(y_hi.ceil() - LOG_DECADES), y_hi.ceil());
        if y_hi - y_lo < 1.0 {
            y_lo = y_hi - 1.0;
        }
    } else {
        if y_hi - y_lo < 1e-12 {
            (y_lo, y_hi) = (y_lo - 0.5, y_hi + 0.5);
        }
        let pad = 0.05 * (y_hi - y_lo);
        (y_lo, y_hi) = (y_lo - pad, y_hi + pad);
    }
    (x_lo..x_hi, y_lo..y_hi)
}

/// The value to draw, or `None` where the line must break (not finite, or ≤ 0 on a log axis).
fn plotted(panel: &Panel, y: f64) -> Option<f64> {
    (y.is_finite() && (!panel.log || y > 0.0)).then_some(y)
}

fn draw_chart<Y>(
    area: &DrawingArea<SVGBackend, Shift>,
    panel: &Panel,
    x: Range<f64>,
    y: Y,
    y_format: &dyn Fn(&f64) -> String,
) -> DrawResult
where
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let mut chart = ChartBuilder::on(area)
        .caption(panel.title, (FONT, 17).into_font().style(FontStyle::Bold))
        .margin_left(10)
        .margin_right(6)
        .margin_top(6)
        .x_label_area_size(32)
        .y_label_area_size(64)
        .build_cartesian_2d(x, y)?;
    chart
        .configure_mesh()
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(RGBColor(0xdd, 0xdd, 0xdd))
        .axis_style(RGBColor(0x88, 0x88, 0x88))
        .x_desc("t (s)")
        .y_desc(panel.y_label)
        .x_labels(12)
        .y_labels(6)
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(y_format)
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 14))
        .draw()?;
    let (lo, hi) = {
        let range = chart.y_range();
        (range.start, range.end)
    };
    for series in &panel.series {
        let style = colour(series.colour).stroke_width(1);
        // One line per run of drawable points: gaps stay gaps.
        let mut segment: Vec<(f64, f64)> = Vec::new();
        let mut segments = Vec::new();
        for &(t, v) in &series.points {
            match plotted(panel, v).filter(|_| t.is_finite()) {
                Some(v) => segment.push((t, v.clamp(lo, hi))),
                None if !segment.is_empty() => segments.push(std::mem::take(&mut segment)),
                None => {}
            }
        }
        if !segment.is_empty() {
            segments.push(segment);
        }
        for points in segments {
            if series.dashed {
                chart.draw_series(DashedLineSeries::new(points, 5, 4, style))?;
            } else {
                chart.draw_series(LineSeries::new(points, style))?;
            }
        }
    }
    Ok(())
}

fn draw_legend(area: &DrawingArea<SVGBackend, Shift>, panel: &Panel) -> DrawResult {
    for (i, series) in panel.series.iter().enumerate() {
        let y = 40 + 18 * i as i32;
        let style = colour(series.colour).stroke_width(2);
        let line = vec![(6, y), (30, y)];
        if series.dashed {
            area.draw(&DashedPathElement::new(line, 5, 4, style))?;
        } else {
            area.draw(&PathElement::new(line, style))?;
        }
        area.draw(&Text::new(
            series.label,
            (36, y - 6),
            (FONT, 14).into_font().color(&BLACK),
        ))?;
    }
    Ok(())
}

/// A tick label without trailing zeros, in exponent form for very large or small values.
fn tick(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else if v.abs() >= 1e4 || v.abs() < 1e-3 {
        format!("{v:.0e}")
    } else {
        let s = format!("{v:.4}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

fn colour(hex: &str) -> RGBColor {
    let digits = hex.trim_start_matches('#');
    let channel = |i: usize, width: usize| {
        let c = u8::from_str_radix(&digits[i * width..(i + 1) * width], 16).unwrap_or(0);
        if width == 1 {
            c * 17
        } else {
            c
        }
    };
    match digits.len() {
        3 => RGBColor(channel(0, 1), channel(1, 1), channel(2, 1)),
        6 => RGBColor(channel(0, 2), channel(1, 2), channel(2, 2)),
        _ => BLACK,
    }
}
