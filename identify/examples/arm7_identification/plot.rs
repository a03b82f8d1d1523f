//! The validation plot with `plotters` (SVG backend only): one panel per joint, measured
//! torque against the torque the identified description predicts.

use plotters::prelude::*;

/// One panel: a title and its series `(label, colour, values)` over the shared times.
pub struct Panel<'a> {
    pub title: String,
    pub series: Vec<(&'a str, RGBColor, Vec<f64>)>,
}

const WIDTH: u32 = 900;
const PANEL_HEIGHT: u32 = 160;
const FONT: &str = "sans-serif";

/// The panels stacked vertically over `time`, under `title`, as an SVG document.
pub fn svg(title: &str, time: &[f64], panels: &[Panel<'_>]) -> String {
    let mut svg = String::new();
    {
        let height = 40 + PANEL_HEIGHT * panels.len().max(1) as u32;
        let root = SVGBackend::with_string(&mut svg, (WIDTH, height)).into_drawing_area();
        // Drawing into a string cannot fail for I/O reasons; an error here is a bug.
        root.fill(&WHITE).expect("SVG background");
        let root = root.titled(title, (FONT, 16)).expect("SVG title");
        for (area, panel) in root.split_evenly((panels.len().max(1), 1)).iter().zip(panels) {
            draw_panel(area, time, panel).expect("SVG panel");
        }
        root.present().expect("SVG document");
    }
    svg
}

fn draw_panel(
    area: &DrawingArea<SVGBackend, plotters::coord::Shift>,
    time: &[f64],
    panel: &Panel<'_>,
) -> Result<(), DrawingAreaErrorKind<std::io::Error>> {
    let values = panel.series.iter().flat_map(|(_, _, v)| v.iter().copied());
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    let pad = 0.05 * (hi - lo).max(1e-9);
    let (t0, t1) = (
        time.first().copied().unwrap_or(0.0),
        time.last().copied().unwrap_or(1.0),
    );
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, (FONT, 13))
        .margin(6)
        .x_label_area_size(22)
        .y_label_area_size(50)
        .build_cartesian_2d(t0..t1.max(t0 + 1e-9), (lo - pad)..(hi + pad))?;
    chart
        .configure_mesh()
        .disable_mesh()
        .label_style((FONT, 10))
        .draw()?;
    for (label, colour, values) in &panel.series {
        let colour = *colour;
        chart
            .draw_series(LineSeries::new(
                time.iter().copied().zip(values.iter().copied()),
                colour,
            ))?
            .label(*label)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], colour));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font((FONT, 10))
        .draw()
}
