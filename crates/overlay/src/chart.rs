//! Charts of measurements: the accuracy sweep's time-against-error plot.

use crate::{Canvas, Color, HAlign, Path2, Stroke, VAlign};

/// One point of a chart.
#[derive(Clone, Debug, PartialEq)]
pub struct ChartPoint {
    pub x: f64,
    pub y: f64,
    /// Points of one series share a colour and a legend entry.
    pub series: &'static str,
    /// Written next to the point when it is on the front.
    pub label: String,
}

/// Series colours, in order of first appearance (Material indigo, teal, purple, brown,
/// orange, blue grey).
const PALETTE: [Color; 6] = [
    Color::rgb(0x3F, 0x51, 0xB5),
    Color::rgb(0x00, 0x96, 0x88),
    Color::rgb(0x9C, 0x27, 0xB0),
    Color::rgb(0x79, 0x55, 0x48),
    Color::rgb(0xFF, 0x98, 0x00),
    Color::rgb(0x60, 0x7D, 0x8B),
];

/// A log-log scatter chart of `points`, those on the Pareto front (`front`: indices into
/// `points`, in the order they are joined) joined by a red line and labelled, one colour
/// per series with a legend; `labels` are the x and y axis titles.
#[must_use]
pub fn pareto(points: &[ChartPoint], front: &[usize], title: &str, labels: [&str; 2]) -> Canvas {
    let (w, h) = (1100u32, 760u32);
    let (left, right, top, bottom) = (90.0f32, 30.0f32, 60.0f32, 70.0f32);
    let (pw, ph) = (w as f32 - left - right, h as f32 - top - bottom);
    let mut c = Canvas::new(w, h);
    c.background(Color::rgb(255, 255, 255));
    let ink = Color::rgb(0x33, 0x33, 0x33);
    let positive = |v: f64| v.is_finite() && v > 0.0;
    let xs: Vec<f64> = points
        .iter()
        .map(|r| r.x)
        .filter(|&v| positive(v))
        .collect();
    let ys: Vec<f64> = points
        .iter()
        .map(|r| r.y)
        .filter(|&v| positive(v))
        .collect();
    let range = |v: &[f64]| {
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(0.0, f64::max);
        if lo.is_finite() && hi > 0.0 {
            (
                (libm::log10(lo) - 0.1).floor(),
                (libm::log10(hi) + 0.1).ceil(),
            )
        } else {
            (-1.0, 1.0)
        }
    };
    let ((x0, x1), (y0, y1)) = (range(&xs), range(&ys));
    let px = |ms: f64, de: f64| {
        let fx = (libm::log10(ms.max(1e-12)) - x0) / (x1 - x0);
        let fy = (libm::log10(de.max(1e-12)) - y0) / (y1 - y0);
        (left + fx as f32 * pw, top + (1.0 - fy as f32) * ph)
    };
    // Grid and decade labels.
    let mut grid = Path2::new();
    for d in x0 as i32..=x1 as i32 {
        let (x, _) = px(10f64.powi(d), 1.0);
        grid = grid.move_to(x, top).line_to(x, top + ph);
        c.text(
            &decade(d),
            x,
            top + ph + 8.0,
            14.0,
            ink,
            HAlign::Center,
            VAlign::Top,
        );
    }
    for d in y0 as i32..=y1 as i32 {
        let (_, y) = px(1.0, 10f64.powi(d));
        grid = grid.move_to(left, y).line_to(left + pw, y);
        c.text(
            &decade(d),
            left - 8.0,
            y,
            14.0,
            ink,
            HAlign::Right,
            VAlign::Middle,
        );
    }
    c.stroke(&grid, Color::rgb(0xE4, 0xE4, 0xE4), &Stroke::solid(1.0));
    c.stroke(
        &Path2::new().rect(left, top, pw, ph),
        ink,
        &Stroke::solid(1.2),
    );
    c.text(
        labels[0],
        left + pw / 2.0,
        h as f32 - 24.0,
        16.0,
        ink,
        HAlign::Center,
        VAlign::Middle,
    );
    c.text_rotated(
        labels[1],
        24.0,
        top + ph / 2.0,
        16.0,
        ink,
        HAlign::Center,
        VAlign::Middle,
        -90.0,
    );
    c.text(
        title,
        left + pw / 2.0,
        28.0,
        19.0,
        ink,
        HAlign::Center,
        VAlign::Middle,
    );
    // The series in order of first appearance, each with its colour from PALETTE.
    let mut series: Vec<&str> = Vec::new();
    for p in points {
        if !series.contains(&p.series) {
            series.push(p.series);
        }
    }
    let colour = |series: &[&str], name: &str| {
        let k = series.iter().position(|s| *s == name).unwrap_or(0);
        PALETTE[k % PALETTE.len()]
    };
    let pts: Vec<(f32, f32)> = front
        .iter()
        .map(|&i| px(points[i].x, points[i].y))
        .collect();
    c.stroke(
        &Path2::polyline(&pts, false),
        Color::rgb(0xF4, 0x43, 0x36),
        &Stroke::rounded(2.5),
    );
    for (i, r) in points.iter().enumerate() {
        let (x, y) = px(r.x, r.y);
        let on = front.contains(&i);
        let dot = Path2::new().circle(x, y, if on { 6.0 } else { 4.5 });
        c.fill(&dot, colour(&series, r.series));
        if let Some(k) = front.iter().position(|&f| f == i) {
            c.stroke(&dot, Color::rgb(0xF4, 0x43, 0x36), &Stroke::solid(2.0));
            // Neighbours on the front are often close: labels alternate above and below.
            let (dy, v) = if k % 2 == 0 {
                (-4.0, VAlign::Bottom)
            } else {
                (5.0, VAlign::Top)
            };
            c.text(&r.label, x + 9.0, y + dy, 12.0, ink, HAlign::Left, v);
        }
    }
    for (k, knob) in series.iter().enumerate() {
        let y = top + 20.0 + 22.0 * k as f32;
        c.fill(
            &Path2::new().circle(left + pw - 150.0, y, 5.0),
            colour(&series, knob),
        );
        c.text(
            knob,
            left + pw - 138.0,
            y,
            14.0,
            ink,
            HAlign::Left,
            VAlign::Middle,
        );
    }
    c
}

fn decade(d: i32) -> String {
    match d {
        0 => "1".into(),
        1 => "10".into(),
        2 => "100".into(),
        3 => "1000".into(),
        -1 => "0.1".into(),
        -2 => "0.01".into(),
        -3 => "0.001".into(),
        _ => format!("1e{d}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(x: f64, y: f64, series: &'static str) -> ChartPoint {
        ChartPoint {
            x,
            y,
            series,
            label: format!("{x} ms"),
        }
    }

    #[test]
    fn the_chart_draws_every_point_in_its_series_colour_and_labels_the_front() {
        let points = [
            point(1.0, 1.0, "a"),
            point(10.0, 0.1, "a"),
            point(5.0, 2.0, "b"),
            point(f64::NAN, 0.0, "b"),
        ];
        let png = pareto(&points, &[0, 1], "title", ["x", "y"]).to_pixmap();
        let (w, h) = (png.width(), png.height());
        let at = |c: Color| {
            png.pixels()
                .iter()
                .filter(|p| (p.red(), p.green(), p.blue()) == (c.r, c.g, c.b))
                .count()
        };
        assert_eq!((w, h), (1100, 760));
        assert!(at(PALETTE[0]) > 50, "series a drawn");
        assert!(at(PALETTE[1]) > 50, "series b drawn");
        assert!(at(Color::rgb(0xF4, 0x43, 0x36)) > 50, "the front joined");
    }
}
