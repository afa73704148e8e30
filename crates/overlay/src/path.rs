//! [`Path2`]: a backend-neutral vector path in pixel coordinates, and [`Color`].
//!
//! A `Path2` is plain data, a list of [`Seg`]s in canvas pixels (y down), so the same
//! geometry feeds both backends: [`Path2::to_skia`] for the raster and
//! [`Path2::to_svg_data`] for SVG. Filled paths use the non-zero winding rule everywhere.
//! Nothing here validates coordinates; [`Canvas`](super::Canvas) drops non-finite paths
//! when they are recorded, so neither backend ever sees a NaN.

/// A straight (non-premultiplied) sRGB colour, 8 bits per channel; `a = 255` is opaque.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Color {
    pub r: u8,
    pub g: u8,
    pub b: u8,
    pub a: u8,
}

impl Color {
    /// An opaque colour.
    #[must_use]
    pub const fn rgb(r: u8, g: u8, b: u8) -> Self {
        Self { r, g, b, a: 255 }
    }

    /// A colour with straight alpha `a`.
    #[must_use]
    pub const fn rgba(r: u8, g: u8, b: u8, a: u8) -> Self {
        Self { r, g, b, a }
    }

    /// `#rrggbb` or `#rrggbbaa` (either case); `None` if malformed.
    #[must_use]
    pub fn hex(s: &str) -> Option<Self> {
        let h = s.strip_prefix('#')?;
        // `from_str_radix` alone would accept a sign, as in "#+1+2+3".
        if !(h.len() == 6 || h.len() == 8) || !h.bytes().all(|b| b.is_ascii_hexdigit()) {
            return None;
        }
        let byte = |i: usize| u8::from_str_radix(h.get(i..i + 2)?, 16).ok();
        let a = if h.len() == 8 { byte(6)? } else { 255 };
        Some(Self {
            r: byte(0)?,
            g: byte(2)?,
            b: byte(4)?,
            a,
        })
    }

    /// The same colour with alpha `a`.
    #[must_use]
    pub const fn with_alpha(self, a: u8) -> Self {
        Self { a, ..self }
    }
}

/// One segment of a [`Path2`]; points are in pixels, y down.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Seg {
    /// Starts a sub-path at a point.
    Move(f32, f32),
    /// A straight line to a point.
    Line(f32, f32),
    /// Control point, end point.
    Quad(f32, f32, f32, f32),
    /// Two control points, end point.
    Cubic(f32, f32, f32, f32, f32, f32),
    /// A straight line back to the sub-path's start.
    Close,
}

impl Seg {
    /// The points of the segment, control points included.
    fn points(&self) -> impl Iterator<Item = (f32, f32)> {
        let (pts, n) = match *self {
            Seg::Move(x, y) | Seg::Line(x, y) => ([(x, y); 3], 1),
            Seg::Quad(a, b, x, y) => ([(a, b), (x, y), (x, y)], 2),
            Seg::Cubic(a, b, c, d, x, y) => ([(a, b), (c, d), (x, y)], 3),
            Seg::Close => ([(0.0, 0.0); 3], 0),
        };
        pts.into_iter().take(n)
    }
}

/// A path of sub-paths (non-zero winding when filled). Built by chaining:
/// `Path2::new().move_to(0.0, 0.0).line_to(10.0, 0.0).line_to(0.0, 10.0).close()`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Path2 {
    /// The segments in drawing order.
    pub segs: Vec<Seg>,
}

impl Path2 {
    /// An empty path.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Starts a new sub-path at `(x, y)`.
    #[must_use]
    pub fn move_to(mut self, x: f32, y: f32) -> Self {
        self.segs.push(Seg::Move(x, y));
        self
    }

    /// A straight line to `(x, y)`.
    #[must_use]
    pub fn line_to(mut self, x: f32, y: f32) -> Self {
        self.segs.push(Seg::Line(x, y));
        self
    }

    /// A quadratic Bézier with control point `(cx, cy)` to `(x, y)`.
    #[must_use]
    pub fn quad_to(mut self, cx: f32, cy: f32, x: f32, y: f32) -> Self {
        self.segs.push(Seg::Quad(cx, cy, x, y));
        self
    }

    /// A cubic Bézier with control points `(c1x, c1y)`, `(c2x, c2y)` to `(x, y)`.
    #[must_use]
    pub fn cubic_to(mut self, c1x: f32, c1y: f32, c2x: f32, c2y: f32, x: f32, y: f32) -> Self {
        self.segs.push(Seg::Cubic(c1x, c1y, c2x, c2y, x, y));
        self
    }

    /// Closes the current sub-path.
    #[must_use]
    pub fn close(mut self) -> Self {
        self.segs.push(Seg::Close);
        self
    }

    /// Appends an axis-aligned rectangle as a closed sub-path.
    #[must_use]
    pub fn rect(self, x: f32, y: f32, w: f32, h: f32) -> Self {
        self.move_to(x, y)
            .line_to(x + w, y)
            .line_to(x + w, y + h)
            .line_to(x, y + h)
            .close()
    }

    /// Appends a circle as a closed sub-path of four cubic arcs, clockwise on screen
    /// (radial error < 0.03%).
    #[must_use]
    pub fn circle(self, cx: f32, cy: f32, r: f32) -> Self {
        const K: f32 = 0.552_284_8; // 4/3 (sqrt(2) - 1)
        let k = K * r;
        self.move_to(cx + r, cy)
            .cubic_to(cx + r, cy + k, cx + k, cy + r, cx, cy + r)
            .cubic_to(cx - k, cy + r, cx - r, cy + k, cx - r, cy)
            .cubic_to(cx - r, cy - k, cx - k, cy - r, cx, cy - r)
            .cubic_to(cx + k, cy - r, cx + r, cy - k, cx + r, cy)
            .close()
    }

    /// A new path: one polyline through `points`, closed if `closed` (empty if `points` is).
    #[must_use]
    pub fn polyline(points: &[(f32, f32)], closed: bool) -> Self {
        let mut p = Self::new();
        for (i, &(x, y)) in points.iter().enumerate() {
            p = if i == 0 {
                p.move_to(x, y)
            } else {
                p.line_to(x, y)
            };
        }
        if closed && !points.is_empty() {
            p = p.close();
        }
        p
    }

    /// Appends every segment of `other`.
    #[must_use]
    pub fn append(mut self, other: &Path2) -> Self {
        self.segs.extend_from_slice(&other.segs);
        self
    }

    /// Whether the path has no drawable segment.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        !self
            .segs
            .iter()
            .any(|s| !matches!(s, Seg::Move(..) | Seg::Close))
    }

    /// Whether every coordinate is finite.
    #[must_use]
    pub fn is_finite(&self) -> bool {
        self.segs
            .iter()
            .flat_map(Seg::points)
            .all(|(x, y)| x.is_finite() && y.is_finite())
    }

    /// Bounds of every point, control points included (so they may exceed the curve's
    /// own bounds): `(min_x, min_y, max_x, max_y)`, `None` without points.
    #[must_use]
    pub fn bounds(&self) -> Option<(f32, f32, f32, f32)> {
        let mut it = self.segs.iter().flat_map(Seg::points);
        let first = it.next()?;
        Some(it.fold(
            (first.0, first.1, first.0, first.1),
            |(a, b, c, d), (x, y)| (a.min(x), b.min(y), c.max(x), d.max(y)),
        ))
    }

    /// The tiny-skia path, or `None` if it has no drawable segment or is not finite.
    #[must_use]
    pub fn to_skia(&self) -> Option<tiny_skia::Path> {
        let mut pb = tiny_skia::PathBuilder::new();
        for s in &self.segs {
            match *s {
                Seg::Move(x, y) => pb.move_to(x, y),
                Seg::Line(x, y) => pb.line_to(x, y),
                Seg::Quad(a, b, x, y) => pb.quad_to(a, b, x, y),
                Seg::Cubic(a, b, c, d, x, y) => pb.cubic_to(a, b, c, d, x, y),
                Seg::Close => pb.close(),
            }
        }
        pb.finish()
    }

    /// SVG path data (`d` attribute), coordinates rounded to 0.01 px (`SVG_DECIMALS`).
    #[must_use]
    pub fn to_svg_data(&self) -> String {
        use std::fmt::Write as _;
        let mut d = String::new();
        for s in &self.segs {
            let (cmd, n) = match *s {
                Seg::Move(..) => ('M', 1),
                Seg::Line(..) => ('L', 1),
                Seg::Quad(..) => ('Q', 2),
                Seg::Cubic(..) => ('C', 3),
                Seg::Close => ('Z', 0),
            };
            d.push(cmd);
            for (i, (x, y)) in s.points().take(n).enumerate() {
                let sep = if i == 0 { "" } else { " " };
                let _ = write!(d, "{sep}{} {}", svg_number(x), svg_number(y));
            }
        }
        d
    }
}

/// Decimal places of SVG coordinates: 0.01 px is far below what anti-aliasing can show.
pub(crate) const SVG_DECIMALS: usize = 2;

/// `v` with [`SVG_DECIMALS`] places, trailing zeros and a negative zero removed.
pub(crate) fn svg_number(v: f32) -> String {
    let s = format!("{v:.SVG_DECIMALS$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        &s
    };
    if s == "-0" {
        "0".to_owned()
    } else {
        s.to_owned()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hex_parses_only_well_formed_colours() {
        assert_eq!(Color::hex("#F44336"), Some(Color::rgb(0xf4, 0x43, 0x36)));
        assert_eq!(
            Color::hex("#f4433680"),
            Some(Color::rgba(0xf4, 0x43, 0x36, 0x80))
        );
        for bad in [
            "F44336", "#F4433", "#F443361", "#+1+2+3", "#12345g", "#ééé", "",
        ] {
            assert_eq!(Color::hex(bad), None, "{bad:?}");
        }
        assert_eq!(Color::rgb(1, 2, 3).with_alpha(4), Color::rgba(1, 2, 3, 4));
    }

    #[test]
    fn builders_bounds_and_svg_data() {
        let p = Path2::polyline(&[(1.0, 2.0), (5.0, -1.0), (3.0, 7.5)], true);
        assert_eq!(p.bounds(), Some((1.0, -1.0, 5.0, 7.5)));
        assert_eq!(p.to_svg_data(), "M1 2L5 -1L3 7.5Z");
        assert!(Path2::polyline(&[], true).is_empty());
        assert_eq!(Path2::new().bounds(), None);
        let c = Path2::new().circle(10.0, 10.0, 4.0);
        assert_eq!(c.bounds(), Some((6.0, 6.0, 14.0, 14.0)));
        assert_eq!(
            Path2::new().quad_to(0.004, -0.004, 1.25, 2.0).to_svg_data(),
            "Q0 0 1.25 2"
        );
        assert_eq!(svg_number(-0.001), "0");
        assert_eq!(svg_number(120.0), "120");
        assert!(!Path2::new()
            .move_to(f32::NAN, 0.0)
            .line_to(1.0, 1.0)
            .is_finite());
        assert!(Path2::new().rect(0.0, 0.0, 1.0, 1.0).is_finite());
        assert!(Path2::new().move_to(3.0, 3.0).close().is_empty());
        assert!(Path2::new().to_skia().is_none());
    }
}
