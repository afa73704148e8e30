//! Text as vector outlines of the embedded DejaVu Sans (Bitstream Vera licence, see
//! `fonts/LICENSE-DejaVu.txt`): the same shapes in PNG and SVG, clipped like any path, and
//! no font needed on the machine that opens the SVG.
//!
//! Invariants and conventions:
//! - Sizes are the em size in pixels (CSS `font-size`), not ab_glyph's `PxScale` (which is
//!   ascent minus descent); all metrics come from the font's unscaled units.
//! - Text is one line: control characters, line breaks included, are skipped. Kerning
//!   pairs of the font's `kern` table apply between neighbours; there is no shaping, so
//!   scripts that need it (Arabic, Indic) come out as isolated glyphs.
//! - A character the font lacks draws as its `.notdef` box, so a missing glyph is visible.
//! - The font is parsed once, on first use ([`OnceLock`]). DejaVu Sans covers Latin, Greek,
//!   Cyrillic and the symbols plots need (° − ′ ± × µ Δ λ).
//! - [`text_extent`] and [`text_path`] share one layout (same glyphs, kerning and
//!   metrics), so a label placed with the extent is drawn where the extent said.

use std::sync::OnceLock;

use ab_glyph::{Font, FontRef, GlyphId, OutlineCurve};

use super::path::Path2;

static FONT_BYTES: &[u8] = include_bytes!("fonts/DejaVuSans.ttf");

/// Units per em if a font did not say (the TrueType default; DejaVu says 2048).
const DEFAULT_UNITS_PER_EM: f32 = 2048.0;

/// The embedded font, parsed on first use; `None` only if the embedded file were corrupt
/// (then text draws nothing rather than panicking; a test asserts that it parses).
fn font() -> Option<&'static FontRef<'static>> {
    static FONT: OnceLock<Option<FontRef<'static>>> = OnceLock::new();
    FONT.get_or_init(|| FontRef::try_from_slice(FONT_BYTES).ok())
        .as_ref()
}

/// Horizontal placement of text relative to its anchor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HAlign {
    /// The pen starts at the anchor.
    Left,
    /// The advance is centred on the anchor.
    Center,
    /// The pen ends at the anchor.
    Right,
}

/// Vertical placement of text relative to its anchor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VAlign {
    /// The anchor is at the font's ascent line.
    Top,
    /// The anchor is halfway between ascent and descent.
    Middle,
    /// The anchor is on the baseline.
    Baseline,
    /// The anchor is at the font's descent line.
    Bottom,
}

/// Each drawable character's glyph and pen position in font units, and the total advance.
/// Control characters (line breaks included: text is one line) are skipped; kerning
/// applies between neighbouring glyphs.
fn layout(f: &FontRef<'_>, text: &str) -> (Vec<(GlyphId, f32)>, f32) {
    let mut glyphs = Vec::with_capacity(text.len());
    let mut pen = 0.0f32;
    let mut prev = None;
    for c in text.chars().filter(|c| !c.is_control()) {
        let id = f.glyph_id(c);
        if let Some(p) = prev {
            pen += f.kern_unscaled(p, id);
        }
        glyphs.push((id, pen));
        pen += f.h_advance_unscaled(id);
        prev = Some(id);
    }
    (glyphs, pen)
}

/// Pixels per font unit at em size `size_px`.
fn px_per_unit(f: &FontRef<'_>, size_px: f32) -> f32 {
    size_px / f.units_per_em().unwrap_or(DEFAULT_UNITS_PER_EM)
}

/// `(advance width, ascent, descent)` of `text` at em size `size_px`, in pixels: the pen
/// advance including kerning, and the font's ascent and descent lines (descent positive,
/// the same for every string). The ink of any string stays within
/// `ascent + descent` vertically; horizontally it may overhang the advance by a fraction
/// of a pixel (a glyph's side bearing can be negative).
#[must_use]
pub fn text_extent(text: &str, size_px: f32) -> (f32, f32, f32) {
    let Some(f) = font() else {
        return (0.0, 0.0, 0.0);
    };
    let k = px_per_unit(f, size_px);
    let (_, width) = layout(f, text);
    (
        width * k,
        f.ascent_unscaled() * k,
        -f.descent_unscaled() * k,
    )
}

/// The outline of `text` at em size `size_px`, anchored at `(x, y)` with the given
/// alignment and rotated by `degrees` about the anchor, clockwise on screen (y points
/// down). Empty if the font is missing or a number is not usable (non-positive size,
/// non-finite anchor).
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
    let k = px_per_unit(f, size_px);
    let (glyphs, width) = layout(f, text);
    let (ascent, descent) = (f.ascent_unscaled() * k, -f.descent_unscaled() * k);
    let dx = match h {
        HAlign::Left => 0.0,
        HAlign::Center => -width * k / 2.0,
        HAlign::Right => -width * k,
    };
    let dy = match v {
        VAlign::Top => ascent,
        VAlign::Middle => (ascent - descent) / 2.0,
        VAlign::Baseline => 0.0,
        VAlign::Bottom => -descent,
    };
    let (sin, cos) = libm::sincosf(degrees.to_radians());
    for (id, pen) in glyphs {
        if let Some(outline) = f.outline(id) {
            // Font units (y up, origin at the pen on the baseline) -> aligned text
            // coordinates (y down) -> rotated about the anchor.
            let place = |p: ab_glyph::Point| {
                let (tx, ty) = ((pen + p.x) * k + dx, -p.y * k + dy);
                (x + tx * cos - ty * sin, y + tx * sin + ty * cos)
            };
            path = append_outline(path, &outline.curves, place);
        }
    }
    path
}

/// Appends a glyph's curves to `path`, starting a closed sub-path wherever a curve does
/// not start at the previous one's end (ab_glyph's outlines are a flat list of curves,
/// each contour closed by a final line back to its start).
fn append_outline(
    mut path: Path2,
    curves: &[OutlineCurve],
    place: impl Fn(ab_glyph::Point) -> (f32, f32),
) -> Path2 {
    let mut last: Option<ab_glyph::Point> = None;
    for curve in curves {
        let (start, end) = match *curve {
            OutlineCurve::Line(a, b) | OutlineCurve::Quad(a, _, b) => (a, b),
            OutlineCurve::Cubic(a, _, _, b) => (a, b),
        };
        if last != Some(start) {
            if last.is_some() {
                path = path.close();
            }
            let (sx, sy) = place(start);
            path = path.move_to(sx, sy);
        }
        let (bx, by) = place(end);
        path = match *curve {
            OutlineCurve::Line(..) => path.line_to(bx, by),
            OutlineCurve::Quad(_, c, _) => {
                let (cx, cy) = place(c);
                path.quad_to(cx, cy, bx, by)
            }
            OutlineCurve::Cubic(_, c1, c2, _) => {
                let ((ax, ay), (cx, cy)) = (place(c1), place(c2));
                path.cubic_to(ax, ay, cx, cy, bx, by)
            }
        };
        last = Some(end);
    }
    if last.is_some() {
        path = path.close();
    }
    path
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn font_parses_and_covers_plot_symbols() {
        let f = font().expect("the embedded font parses");
        assert_eq!(f.units_per_em(), Some(DEFAULT_UNITS_PER_EM));
        for c in "°−′″±×µΔλσΩαβγ‰".chars() {
            assert_ne!(f.glyph_id(c), GlyphId(0), "{c:?} falls back to .notdef");
        }
        // A character DejaVu Sans lacks (a CJK ideograph) still draws: the .notdef box.
        let missing = '\u{4e00}';
        assert_eq!(f.glyph_id(missing), GlyphId(0));
        let notdef = text_path(
            "\u{4e00}",
            0.0,
            0.0,
            20.0,
            HAlign::Left,
            VAlign::Baseline,
            0.0,
        );
        assert!(!notdef.is_empty());
    }

    #[test]
    fn kerning_and_control_characters() {
        let f = font().expect("the embedded font parses");
        let (a, v) = (f.glyph_id('A'), f.glyph_id('V'));
        assert!(f.kern_unscaled(a, v) < 0.0, "DejaVu kerns AV");
        let (av, ..) = text_extent("AV", 100.0);
        let (a_alone, ..) = text_extent("A", 100.0);
        let (v_alone, ..) = text_extent("V", 100.0);
        assert!(
            av < a_alone + v_alone - 1.0,
            "{av} vs {a_alone} + {v_alone}"
        );
        // Line breaks and other control characters take no room and draw nothing.
        assert_eq!(text_extent("a\nb\t", 20.0).0, text_extent("ab", 20.0).0);
        let p = |s| text_path(s, 5.0, 9.0, 20.0, HAlign::Center, VAlign::Middle, 30.0);
        assert_eq!(p("a\r\nb"), p("ab"));
        assert!(p("").is_empty() && p(" ").is_empty());
    }

    #[test]
    fn extent_scales_with_size_and_metrics_are_the_fonts() {
        let (w10, a10, d10) = text_extent("Hg", 10.0);
        let (w20, a20, d20) = text_extent("Hg", 20.0);
        assert!((w20 - 2.0 * w10).abs() < 1e-4 && (a20 - 2.0 * a10).abs() < 1e-4);
        assert!((d20 - 2.0 * d10).abs() < 1e-4);
        // DejaVu Sans: ascent 1901, descent 483 units of 2048.
        assert!((a20 - 20.0 * 1901.0 / 2048.0).abs() < 1e-3, "{a20}");
        assert!((d20 - 20.0 * 483.0 / 2048.0).abs() < 1e-3, "{d20}");
        assert_eq!(text_extent("", 20.0).0, 0.0);
        assert!(text_path("x", 0.0, 0.0, 0.0, HAlign::Left, VAlign::Top, 0.0).is_empty());
    }
}
