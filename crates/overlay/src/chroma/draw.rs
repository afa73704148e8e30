//! Layout and drawing of the chromaticity diagram (see the parent module).

use super::raster::{fill_image, pixel_image};

use super::gamut::locus_polygon;
use super::{ChromaOptions, Plane, PLANCKIAN_LABELS_K};
use crate::color::{self, RgbSpace, SpectralLocus};
use crate::{Canvas, Color, HAlign, Path2, Stroke, VAlign};

/// Colours of successive gamuts (colour-science's cycle).
const CYCLE: [&str; 10] = [
    "#F44336", "#9C27B0", "#3F51B5", "#03A9F4", "#009688", "#8BC34A", "#FFEB3B", "#FF9800",
    "#795548", "#607D8B",
];
const INK: Color = Color {
    r: 0x33,
    g: 0x33,
    b: 0x33,
    a: 255,
};
const GRID: Color = Color {
    r: 0xE4,
    g: 0xE4,
    b: 0xE4,
    a: 255,
};
const PAGE: Color = Color {
    r: 255,
    g: 255,
    b: 255,
    a: 255,
};

fn cycle(i: usize) -> Color {
    Color::hex(CYCLE[i % CYCLE.len()]).unwrap_or(INK)
}

/// Maps plane coordinates to pixels.
pub(super) struct Frame {
    pub(super) left: f32,
    pub(super) top: f32,
    pub(super) side: f32,
    pub(super) bounds: [f64; 4],
    pub(super) plane: Plane,
    /// Scale of every length relative to a 1024 px diagram.
    pub(super) s: f32,
}

impl Frame {
    pub(super) fn px(&self, p: [f64; 2]) -> (f32, f32) {
        let [u0, u1, v0, v1] = self.bounds;
        let fx = (p[0] - u0) / (u1 - u0);
        let fy = (p[1] - v0) / (v1 - v0);
        (
            self.left + fx as f32 * self.side,
            self.top + (1.0 - fy as f32) * self.side,
        )
    }

    pub(super) fn px_xy(&self, xy: [f64; 2]) -> (f32, f32) {
        self.px(self.plane.from_xy(xy))
    }

    /// Plane coordinates of canvas point (x, y).
    pub(super) fn unpx_f(&self, x: f32, y: f32) -> [f64; 2] {
        let [u0, u1, v0, v1] = self.bounds;
        let fx = f64::from((x - self.left) / self.side);
        let fy = 1.0 - f64::from((y - self.top) / self.side);
        [u0 + fx * (u1 - u0), v0 + fy * (v1 - v0)]
    }

    /// Plane coordinates of pixel centre (i, j) of the plot square.
    pub(super) fn unpx(&self, i: u32, j: u32) -> [f64; 2] {
        let [u0, u1, v0, v1] = self.bounds;
        let fx = (f64::from(i) + 0.5) / f64::from(self.side);
        let fy = 1.0 - (f64::from(j) + 0.5) / f64::from(self.side);
        [u0 + fx * (u1 - u0), v0 + fy * (v1 - v0)]
    }
}

/// Builds the diagram described by `opts`.
#[must_use]
pub fn diagram(opts: &ChromaOptions) -> Canvas {
    let size = opts.size.max(64);
    let s = size as f32 / 1024.0;
    let (left, right, top, bottom) = (96.0 * s, 24.0 * s, 92.0 * s, 80.0 * s);
    let side = (size as f32 - left - right)
        .min(size as f32 - top - bottom)
        .floor();
    let frame = Frame {
        left: left.round(),
        top: top.round(),
        side,
        bounds: opts.plane.bounds(),
        plane: opts.plane,
        s,
    };
    let mut c = Canvas::new(size, size);
    c.background(PAGE);

    let plot = Path2::new().rect(frame.left, frame.top, side, side);
    grid(&mut c, &frame);
    c.clip_push(&plot);
    let locus_pts: Vec<(f32, f32)> = locus_polygon(opts.observer, opts.plane)
        .into_iter()
        .map(|p| frame.px(p))
        .collect();
    let locus = Path2::polyline(&locus_pts, true);
    c.clip_push(&locus);
    c.image(frame.left, frame.top, fill_image(opts, &frame));
    c.clip_pop();
    c.stroke(&locus, INK, &Stroke::rounded(1.6 * s));
    wavelength_ticks(&mut c, opts, &frame);
    if opts.planckian {
        planckian(&mut c, opts, &frame, &locus);
    }
    if let Some(px) = &opts.pixels {
        c.image(
            frame.left,
            frame.top,
            pixel_image(px, opts.pixel_style, &frame),
        );
    }
    for (i, g) in opts.gamuts.iter().enumerate() {
        gamut(&mut c, g, cycle(i), &frame);
    }
    for m in &opts.illuminants {
        marker(
            &mut c,
            &frame,
            m.xy,
            &m.label,
            Color::rgb(0xF5, 0xF5, 0xF5),
            INK,
        );
    }
    for m in &opts.points {
        marker(
            &mut c,
            &frame,
            m.xy,
            &m.label,
            Color::rgb(0, 0, 0),
            Color::rgb(255, 255, 255),
        );
    }
    c.clip_pop();
    axes(&mut c, &frame);
    titles(&mut c, opts, &frame);
    legend(&mut c, opts, &frame);
    c
}

fn grid(c: &mut Canvas, f: &Frame) {
    let [u0, u1, v0, v1] = f.bounds;
    let mut path = Path2::new();
    for k in ticks(u0, u1) {
        let (x, _) = f.px([k, v0]);
        path = path.move_to(x, f.top).line_to(x, f.top + f.side);
    }
    for k in ticks(v0, v1) {
        let (_, y) = f.px([u0, k]);
        path = path.move_to(f.left, y).line_to(f.left + f.side, y);
    }
    c.stroke(&path, GRID, &Stroke::solid(1.0 * f.s.max(0.5)));
}

/// Multiples of 0.1 within [a, b].
fn ticks(a: f64, b: f64) -> impl Iterator<Item = f64> {
    let first = (a * 10.0 - 1e-9).ceil() as i32;
    let last = (b * 10.0 + 1e-9).floor() as i32;
    (first..=last).map(|k| f64::from(k) / 10.0)
}

fn wavelength_ticks(c: &mut Canvas, opts: &ChromaOptions, f: &Frame) {
    let locus = SpectralLocus::new(opts.observer);
    let e = f.plane.from_xy([1.0 / 3.0, 1.0 / 3.0]);
    let (ex, ey) = f.px(e);
    let mut ticks = Path2::new();
    let mut dots = Path2::new();
    // colour-science: tick along the normal pointing away from E, 1/50 of a data unit long,
    // label at 1.25 times that.
    let unit = f.side / (f.bounds[1] - f.bounds[0]) as f32;
    let len = unit / 50.0;
    for &nm in f.plane.wavelength_labels() {
        let nmf = f64::from(nm);
        let (x, y) = f.px_xy(locus.xy(nmf));
        let (xa, ya) = f.px_xy(locus.xy(nmf - 0.5));
        let (xb, yb) = f.px_xy(locus.xy(nmf + 0.5));
        let (tx, ty) = (xb - xa, yb - ya);
        let tl = libm::hypotf(tx, ty).max(1e-6);
        let (mut nx, mut ny) = (-ty / tl, tx / tl);
        if nx * (x - ex) + ny * (y - ey) < 0.0 {
            nx = -nx;
            ny = -ny;
        }
        ticks = ticks.move_to(x, y).line_to(x + nx * len, y + ny * len);
        dots = dots.circle(x, y, 3.2 * f.s);
        let (lx, ly) = (x + nx * len * 1.6, y + ny * len * 1.6);
        let h = if nx > 0.35 {
            HAlign::Left
        } else if nx < -0.35 {
            HAlign::Right
        } else {
            HAlign::Center
        };
        let v = if ny > 0.35 {
            VAlign::Top
        } else if ny < -0.35 {
            VAlign::Bottom
        } else {
            VAlign::Middle
        };
        c.text(&nm.to_string(), lx, ly, 13.0 * f.s, INK, h, v);
    }
    c.stroke(&ticks, INK, &Stroke::solid(1.2 * f.s));
    c.fill(&dots, INK);
}

fn planckian(c: &mut Canvas, opts: &ChromaOptions, f: &Frame, locus: &Path2) {
    // 1667 K to 100 000 K, uniformly in mireds (colour-science's range).
    let pts: Vec<(f32, f32)> = (10..=600)
        .rev()
        .map(|mired| f.px_xy(color::planckian_xy(1e6 / f64::from(mired))))
        .collect();
    let curve = Path2::polyline(&pts, false);
    c.stroke(&curve, INK, &Stroke::rounded(1.6 * f.s));
    let inside = locus_polygon(opts.observer, f.plane);
    let within = |px: (f32, f32)| point_in_polygon(&inside, f.unpx_f(px.0, px.1));
    let size = 11.0 * f.s;
    let mut ticks = Path2::new();
    let mut labels = Vec::new();
    for &k in &PLANCKIAN_LABELS_K {
        // The iso-temperature line from Duv -0.05 to +0.05, shortened at the top until its
        // label (centred above the end) fits inside the horseshoe, and at the bottom until
        // it is inside.
        let at = |duv: f64| f.px_xy(color::iso_temperature_xy(k, duv));
        let label = format!("{} K", k.round());
        let (w, ascent, descent) = crate::text_extent(&label, size);
        let fits = |(x, y): (f32, f32)| {
            let (top, bottom) = (y - 2.0 * f.s - ascent - descent, y - 2.0 * f.s);
            [
                (x - w / 2.0, top),
                (x + w / 2.0, top),
                (x - w / 2.0, bottom),
                (x + w / 2.0, bottom),
                (x, y),
            ]
            .into_iter()
            .all(within)
        };
        // The largest |Duv| <= 0.05 on each side that still fits, by bisection (the
        // horseshoe is convex around the locus, so fitting is monotonic in |Duv|).
        let reach = |sign: f64, ok: &dyn Fn((f32, f32)) -> bool| {
            if ok(at(sign * 0.05)) {
                return sign * 0.05;
            }
            let (mut good, mut bad) = (0.0, 0.05);
            for _ in 0..14 {
                let mid = (good + bad) / 2.0;
                if ok(at(sign * mid)) {
                    good = mid;
                } else {
                    bad = mid;
                }
            }
            sign * good
        };
        let hi = reach(1.0, &fits);
        let lo = reach(-1.0, &within);
        if hi <= lo {
            continue;
        }
        let (a, b) = (at(lo), at(hi));
        ticks = ticks.move_to(a.0, a.1).line_to(b.0, b.1);
        labels.push((label, b));
    }
    c.clip_push(locus);
    c.stroke(&ticks, INK, &Stroke::solid(1.2 * f.s));
    c.clip_pop();
    for (label, (x, y)) in labels {
        c.text(
            &label,
            x,
            y - 2.0 * f.s,
            size,
            INK,
            HAlign::Center,
            VAlign::Bottom,
        );
    }
}

/// Even-odd point-in-polygon test.
fn point_in_polygon(poly: &[[f64; 2]], p: [f64; 2]) -> bool {
    let mut inside = false;
    let n = poly.len();
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + n - 1) % n]);
        if (a[1] > p[1]) != (b[1] > p[1])
            && p[0] < (b[0] - a[0]) * (p[1] - a[1]) / (b[1] - a[1]) + a[0]
        {
            inside = !inside;
        }
    }
    inside
}

fn gamut(c: &mut Canvas, g: &RgbSpace, colour: Color, f: &Frame) {
    let pts: Vec<(f32, f32)> = g.primaries.iter().map(|&p| f.px_xy(p)).collect();
    c.stroke(
        &Path2::polyline(&pts, true),
        colour,
        &Stroke::rounded(2.0 * f.s),
    );
    let mut dots = Path2::new();
    for &(x, y) in &pts {
        dots = dots.circle(x, y, 4.5 * f.s);
    }
    let (wx, wy) = f.px_xy(g.white);
    dots = dots.circle(wx, wy, 5.0 * f.s);
    c.fill(&dots, colour);
}

fn marker(c: &mut Canvas, f: &Frame, xy: [f64; 2], label: &str, face: Color, edge: Color) {
    let (x, y) = f.px_xy(xy);
    let dot = Path2::new().circle(x, y, 5.0 * f.s);
    c.fill(&dot, face);
    c.stroke(&dot, edge, &Stroke::rounded(1.5 * f.s));
    if !label.is_empty() {
        c.text(
            label,
            x + 8.0 * f.s,
            y - 4.0 * f.s,
            13.0 * f.s,
            INK,
            HAlign::Left,
            VAlign::Bottom,
        );
    }
}

fn axes(c: &mut Canvas, f: &Frame) {
    let frame = Path2::new().rect(f.left, f.top, f.side, f.side);
    c.stroke(&frame, INK, &Stroke::solid(1.2 * f.s));
    let [u0, u1, v0, v1] = f.bounds;
    let mut marks = Path2::new();
    let len = 6.0 * f.s;
    let size = 15.0 * f.s;
    for k in ticks(u0, u1) {
        let (x, y) = f.px([k, v0]);
        marks = marks.move_to(x, y).line_to(x, y + len);
        c.text(
            &number(k),
            x,
            y + len + 3.0 * f.s,
            size,
            INK,
            HAlign::Center,
            VAlign::Top,
        );
    }
    for k in ticks(v0, v1) {
        let (x, y) = f.px([u0, k]);
        marks = marks.move_to(x, y).line_to(x - len, y);
        c.text(
            &number(k),
            x - len - 4.0 * f.s,
            y,
            size,
            INK,
            HAlign::Right,
            VAlign::Middle,
        );
    }
    c.stroke(&marks, INK, &Stroke::solid(1.2 * f.s));
    let (xa, ya) = f.plane.axes();
    let label = 18.0 * f.s;
    c.text(
        xa,
        f.left + f.side / 2.0,
        f.top + f.side + 40.0 * f.s,
        label,
        INK,
        HAlign::Center,
        VAlign::Top,
    );
    c.text_rotated(
        ya,
        f.left - 62.0 * f.s,
        f.top + f.side / 2.0,
        label,
        INK,
        HAlign::Center,
        VAlign::Bottom,
        -90.0,
    );
}

/// An axis number: one decimal, with a true minus sign.
fn number(v: f64) -> String {
    let s = format!("{v:.1}");
    if let Some(rest) = s.strip_prefix('-') {
        if rest == "0.0" {
            return "0.0".into();
        }
        return format!("\u{2212}{rest}");
    }
    s
}

fn titles(c: &mut Canvas, opts: &ChromaOptions, f: &Frame) {
    let title = opts.title.clone().unwrap_or_else(|| {
        let names: Vec<&str> = opts.gamuts.iter().map(|g| g.name.as_str()).collect();
        if names.is_empty() {
            opts.plane.title().to_owned()
        } else {
            names.join(", ")
        }
    });
    let sub = format!("{} \u{2014} {}", opts.observer.name(), opts.plane.title());
    let mid = f.left + f.side / 2.0;
    c.text(
        &title,
        mid,
        30.0 * f.s,
        22.0 * f.s,
        INK,
        HAlign::Center,
        VAlign::Middle,
    );
    c.text(
        &sub,
        mid,
        60.0 * f.s,
        17.0 * f.s,
        INK,
        HAlign::Center,
        VAlign::Middle,
    );
}

fn legend(c: &mut Canvas, opts: &ChromaOptions, f: &Frame) {
    let mut rows: Vec<(String, Color)> = opts
        .gamuts
        .iter()
        .enumerate()
        .map(|(i, g)| (format!("{} ({})", g.name, g.white_name), cycle(i)))
        .collect();
    if opts.planckian {
        rows.push(("Planckian locus".into(), INK));
    }
    if let Some(px) = &opts.pixels {
        rows.push((
            format!("pixels of {}", px.name),
            Color::rgb(0x20, 0x20, 0x20),
        ));
    }
    if rows.is_empty() {
        return;
    }
    let size = 15.0 * f.s;
    let row_h = 24.0 * f.s;
    let width = rows
        .iter()
        .map(|(t, _)| crate::text_extent(t, size).0)
        .fold(0.0, f32::max)
        + 56.0 * f.s;
    let height = row_h * rows.len() as f32 + 12.0 * f.s;
    let (x0, y0) = (f.left + f.side - width - 12.0 * f.s, f.top + 12.0 * f.s);
    let bg = Path2::new().rect(x0, y0, width, height);
    c.fill(&bg, Color::rgba(255, 255, 255, 230));
    c.stroke(&bg, Color::rgb(0xCC, 0xCC, 0xCC), &Stroke::solid(1.0 * f.s));
    for (i, (text, colour)) in rows.iter().enumerate() {
        let y = y0 + 6.0 * f.s + row_h * (i as f32 + 0.5);
        let line = Path2::new()
            .move_to(x0 + 10.0 * f.s, y)
            .line_to(x0 + 38.0 * f.s, y);
        c.stroke(&line, *colour, &Stroke::rounded(2.0 * f.s));
        c.fill(&Path2::new().circle(x0 + 24.0 * f.s, y, 4.5 * f.s), *colour);
        c.text(
            text,
            x0 + 46.0 * f.s,
            y,
            size,
            INK,
            HAlign::Left,
            VAlign::Middle,
        );
    }
}
