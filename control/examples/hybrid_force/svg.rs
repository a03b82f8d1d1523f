//! A small SVG writer: stacked panels of time series (polylines), linear or log axes.

use std::fmt::Write as _;

pub struct Series<'a> {
    pub label: &'a str,
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

const W: f64 = 900.0;
const H: f64 = 230.0;
const LEFT: f64 = 80.0;
const RIGHT: f64 = 170.0;
const TOP: f64 = 28.0;
const BOTTOM: f64 = 36.0;

fn nice_ticks(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    let span = (hi - lo).max(1e-300);
    let raw = span / n as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let mut t = (lo / step).ceil() * step;
    let mut v = Vec::new();
    while t <= hi + 1e-9 * step {
        v.push(if t.abs() < 1e-12 * step { 0.0 } else { t });
        t += step;
    }
    v
}

fn fmt_tick(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else if v.abs() >= 1e4 || v.abs() < 1e-3 {
        format!("{v:.0e}")
    } else {
        let s = format!("{v:.4}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

/// Renders the panels one above the other.
pub fn render(panels: &[Panel]) -> String {
    let total_h = H * panels.len() as f64;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{total_h}" viewBox="0 0 {W} {total_h}" font-family="sans-serif" font-size="11">"#
    );
    let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
    for (k, p) in panels.iter().enumerate() {
        let y0 = k as f64 * H;
        let (pw, ph) = (W - LEFT - RIGHT, H - TOP - BOTTOM);
        let tf = |v: f64| if p.log { v.max(1e-300).log10() } else { v };
        let pts = p
            .series
            .iter()
            .flat_map(|s| s.points.iter())
            .filter(|(x, y)| x.is_finite() && y.is_finite() && (!p.log || *y > 0.0));
        let (mut x_lo, mut x_hi, mut y_lo, mut y_hi) =
            (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
        for &(x, y) in pts {
            x_lo = x_lo.min(x);
            x_hi = x_hi.max(x);
            y_lo = y_lo.min(tf(y));
            y_hi = y_hi.max(tf(y));
        }
        if !x_lo.is_finite() {
            (x_lo, x_hi, y_lo, y_hi) = (0.0, 1.0, 0.0, 1.0);
        }
        if p.log {
            y_lo = y_lo.floor().max(y_hi - 14.0);
            y_hi = y_hi.ceil();
        }
        if y_hi - y_lo < 1e-12 {
            y_hi += 0.5;
            y_lo -= 0.5;
        }
        let pad = if p.log { 0.0 } else { 0.05 * (y_hi - y_lo) };
        let (y_lo, y_hi) = (y_lo - pad, y_hi + pad);
        let sx = |x: f64| LEFT + (x - x_lo) / (x_hi - x_lo).max(1e-12) * pw;
        let sy = |y: f64| y0 + TOP + (1.0 - (tf(y).clamp(y_lo, y_hi) - y_lo) / (y_hi - y_lo)) * ph;
        let _ = writeln!(
            s,
            r#"<text x="{LEFT}" y="{}" font-size="13" font-weight="bold">{}</text>"#,
            y0 + 18.0,
            p.title
        );
        let _ = writeln!(
            s,
            r##"<rect x="{LEFT}" y="{}" width="{pw}" height="{ph}" fill="none" stroke="#888"/>"##,
            y0 + TOP
        );
        // y ticks
        let ticks: Vec<f64> = if p.log {
            (y_lo.ceil() as i64..=y_hi.floor() as i64)
                .map(|e| e as f64)
                .collect()
        } else {
            nice_ticks(y_lo, y_hi, 4)
        };
        for t in ticks {
            let v = if p.log { 10f64.powf(t) } else { t };
            let y = sy(v);
            let _ = writeln!(
                s,
                r##"<line x1="{LEFT}" x2="{}" y1="{y:.1}" y2="{y:.1}" stroke="#ddd"/><text x="{}" y="{:.1}" text-anchor="end">{}</text>"##,
                LEFT + pw,
                LEFT - 4.0,
                y + 4.0,
                if p.log {
                    format!("1e{}", t as i64)
                } else {
                    fmt_tick(v)
                }
            );
        }
        for t in nice_ticks(x_lo, x_hi, 10) {
            let x = sx(t);
            let _ = writeln!(
                s,
                r##"<line x1="{x:.1}" x2="{x:.1}" y1="{}" y2="{}" stroke="#eee"/><text x="{x:.1}" y="{}" text-anchor="middle">{}</text>"##,
                y0 + TOP,
                y0 + TOP + ph,
                y0 + TOP + ph + 14.0,
                fmt_tick(t)
            );
        }
        let _ = writeln!(
            s,
            r#"<text x="{}" y="{}" text-anchor="middle">t (s)</text><text x="14" y="{}" transform="rotate(-90 14 {})" text-anchor="middle">{}</text>"#,
            LEFT + pw / 2.0,
            y0 + H - 6.0,
            y0 + TOP + ph / 2.0,
            y0 + TOP + ph / 2.0,
            p.y_label
        );
        for (i, ser) in p.series.iter().enumerate() {
            let mut d = String::new();
            let mut pen_down = false;
            for &(x, y) in &ser.points {
                if !(x.is_finite() && y.is_finite()) || (p.log && y <= 0.0) {
                    pen_down = false;
                    continue;
                }
                let _ = write!(
                    d,
                    "{}{:.1},{:.1} ",
                    if pen_down { "L" } else { "M" },
                    sx(x),
                    sy(y)
                );
                pen_down = true;
            }
            let dash = if ser.dashed {
                r#" stroke-dasharray="5,4""#
            } else {
                ""
            };
            let _ = writeln!(
                s,
                r#"<path d="{d}" fill="none" stroke="{}" stroke-width="1.3"{dash}/>"#,
                ser.colour
            );
            let ly = y0 + TOP + 12.0 + 16.0 * i as f64;
            let lx = LEFT + pw + 10.0;
            let _ = writeln!(
                s,
                r#"<line x1="{lx}" x2="{}" y1="{ly}" y2="{ly}" stroke="{}" stroke-width="2"{dash}/><text x="{}" y="{}">{}</text>"#,
                lx + 22.0,
                ser.colour,
                lx + 27.0,
                ly + 4.0,
                ser.label
            );
        }
    }
    s.push_str("</svg>\n");
    s
}
