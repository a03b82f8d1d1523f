//! A minimal SVG plot: stacked panels of time series (measured against predicted torque).

use std::fmt::Write as _;

/// One panel: a title and named series `(label, colour, values)` over shared times.
pub struct Panel<'a> {
    pub title: String,
    pub series: Vec<(&'a str, &'a str, Vec<f64>)>,
}

/// An SVG of `panels` stacked vertically over `time`.
pub fn svg(title: &str, time: &[f64], panels: &[Panel<'_>]) -> String {
    let (width, panel_height, left, top) = (900.0, 140.0, 60.0, 40.0);
    let height = top + panel_height * panels.len() as f64 + 20.0;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" font-family="sans-serif" font-size="11">"#
    );
    let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(s, r#"<text x="{left}" y="20" font-size="14">{title}</text>"#);
    let (t0, t1) = (
        time.first().copied().unwrap_or(0.0),
        time.last().copied().unwrap_or(1.0),
    );
    let plot_width = width - left - 20.0;
    for (p, panel) in panels.iter().enumerate() {
        let y0 = top + panel_height * p as f64;
        let h = panel_height - 25.0;
        let all = panel.series.iter().flat_map(|(_, _, v)| v.iter().copied());
        let (lo, hi) = all.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
        let (lo, hi) = if hi > lo { (lo, hi) } else { (lo - 1.0, lo + 1.0) };
        let _ = writeln!(
            s,
            r##"<rect x="{left}" y="{y0}" width="{plot_width}" height="{h}" fill="none" stroke="#999"/>"##
        );
        let _ = writeln!(
            s,
            r#"<text x="{}" y="{}">{}</text>"#,
            left + 5.0,
            y0 + 12.0,
            panel.title
        );
        let _ = writeln!(s, r#"<text x="5" y="{}">{hi:.3}</text>"#, y0 + 10.0);
        let _ = writeln!(s, r#"<text x="5" y="{}">{lo:.3}</text>"#, y0 + h);
        for (k, (label, colour, values)) in panel.series.iter().enumerate() {
            let mut points = String::new();
            for (t, v) in time.iter().zip(values) {
                let x = left + plot_width * (t - t0) / (t1 - t0).max(1e-12);
                let y = y0 + h * (hi - v) / (hi - lo);
                let _ = write!(points, "{x:.1},{y:.1} ");
            }
            let _ = writeln!(
                s,
                r#"<polyline fill="none" stroke="{colour}" stroke-width="0.8" points="{points}"/>"#
            );
            let _ = writeln!(
                s,
                r#"<text x="{}" y="{}" fill="{colour}">{label}</text>"#,
                left + plot_width - 160.0 + 80.0 * k as f64,
                y0 + 12.0
            );
        }
    }
    let _ = writeln!(
        s,
        r#"<text x="{left}" y="{}">time (s), {t0:.1} to {t1:.1}</text>"#,
        height - 5.0
    );
    s.push_str("</svg>\n");
    s
}
