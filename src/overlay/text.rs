//! Text as vector outlines of the embedded DejaVu Sans (Bitstream Vera licence, see
//! `fonts/LICENSE-DejaVu.txt`): the same shapes in PNG and SVG, clipped like any path, and
//! no font needed on the machine that opens the SVG.
//!
//! Sizes are the em size in pixels. Kerning pairs from the font's `kern` table are applied.
//! A character the font lacks draws as its `.notdef` box.

use std::sync::OnceLock;

use ab_glyph::{Font, FontRef, OutlineCurve};

use super::path::Path2;

static FONT_BYTES: &[u8] = include_bytes!("fonts/DejaVuSans.ttf");

fn font() -> Option<&'static FontRef<'static>> {
    static FONT: OnceLock<Option<FontRef<'static>>> = OnceLock::new();
    FONT.get_or_init(|| FontRef::try_from_slice(FONT_BYTES).ok())
        .as_ref()
}

/// Horizontal placement of text relative to its anchor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HAlign {
    Left,
    Center,
    Right,
}

/// Vertical placement of text relative to its anchor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VAlign {
    /// The anchor is at the font's ascent line.
    Top,
    /// The anchor is halfway between ascent and descent.
    Middle,
    Baseline,
    /// The anchor is at the font's descent line.
    Bottom,
}

/// `(advance width, ascent, descent)` of `text` at `size_px`, in pixels (descent positive).
#[must_use]
pub fn text_extent(text: &str, size_px: f32) -> (f32, f32, f32) {
    let Some(f) = font() else {
        return (0.0, 0.0, 0.0);
    };
    let scale = size_px / f.units_per_em().unwrap_or(2048.0);
    let mut width = 0.0;
    let mut prev = None;
    for c in text.chars() {
        let id = f.glyph_id(c);
        if let Some(p) = prev {
            width += f.kern_unscaled(p, id);
        }
        width += f.h_advance_unscaled(id);
        prev = Some(id);
    }
    (
        width * scale,
        f.ascent_unscaled() * scale,
        -f.descent_unscaled() * scale,
    )
}

/// The outline of `text` at `size_px`, anchored at `(x, y)` with the given alignment and
/// rotated by `degrees` (clockwise on screen, as y points down) about the anchor.
#[must_use]
pub fn text_path(
    text: &str,
    x: f32,
    y: f32,
    size_px: f32,
    h: HAlign,
    v: VAlign,
    degrees: f32,
) -> Path2 {
    let mut path = Path2::new();
    let Some(f) = font() else {
        return path;
    };
    if !(size_px > 0.0 && size_px.is_finite() && x.is_finite() && y.is_finite()) {
        return path;
    }
    let scale = size_px / f.units_per_em().unwrap_or(2048.0);
    let (width, ascent, descent) = text_extent(text, size_px);
    let dx = match h {
        HAlign::Left => 0.0,
        HAlign::Center => -width / 2.0,
        HAlign::Right => -width,
    };
    let dy = match v {
        VAlign::Top => ascent,
        VAlign::Middle => (ascent - descent) / 2.0,
        VAlign::Baseline => 0.0,
        VAlign::Bottom => -descent,
    };
    let (sin, cos) = degrees.to_radians().sin_cos();
    // Local text coordinates (pen at 0, baseline at 0, y down) -> canvas.
    let place = |lx: f32, ly: f32| {
        let (px, py) = (lx + dx, ly + dy);
        (x + px * cos - py * sin, y + px * sin + py * cos)
    };
    let mut pen = 0.0f32;
    let mut prev = None;
    for c in text.chars() {
        let id = f.glyph_id(c);
        if let Some(p) = prev {
            pen += f.kern_unscaled(p, id) * scale;
        }
        prev = Some(id);
        if let Some(outline) = f.outline(id) {
            // Font units are y up.
            let pt = |p: ab_glyph::Point| place(pen + p.x * scale, -p.y * scale);
            let mut last: Option<ab_glyph::Point> = None;
            for curve in &outline.curves {
                let start = match *curve {
                    OutlineCurve::Line(a, _)
                    | OutlineCurve::Quad(a, _, _)
                    | OutlineCurve::Cubic(a, _, _, _) => a,
                };
                if last != Some(start) {
                    if last.is_some() {
                        path = path.close();
                    }
                    let (sx, sy) = pt(start);
                    path = path.move_to(sx, sy);
                }
                last = Some(match *curve {
                    OutlineCurve::Line(_, b) => {
                        let (bx, by) = pt(b);
                        path = path.line_to(bx, by);
                        b
                    }
                    OutlineCurve::Quad(_, c1, b) => {
                        let ((cx, cy), (bx, by)) = (pt(c1), pt(b));
                        path = path.quad_to(cx, cy, bx, by);
                        b
                    }
                    OutlineCurve::Cubic(_, c1, c2, b) => {
                        let ((ax, ay), (cx, cy), (bx, by)) = (pt(c1), pt(c2), pt(b));
                        path = path.cubic_to(ax, ay, cx, cy, bx, by);
                        b
                    }
                });
            }
            if last.is_some() {
                path = path.close();
            }
        }
        pen += f.h_advance_unscaled(id) * scale;
    }
    path
}
