//! [`Canvas`]: a display list of 2D drawing commands, rendered by tiny-skia to a `Pixmap`
//! (anti-aliased) or written as a standalone SVG document (`svg.rs`).
//!
//! Invariants, which are what keep the two backends drawing the same picture:
//! - Coordinates are pixels, y down, origin at the top-left corner, pixel centres at +0.5:
//!   a rectangle from (3, 2) to (8, 6) covers exactly the pixels 3..8 x 2..6.
//! - Items paint in the order they were added, source-over, on the background (or on
//!   transparency). Fills and clips use the non-zero winding rule.
//! - Normalisation happens when an item is recorded, never in a backend: an item that would
//!   draw nothing (an empty or non-finite path, a stroke whose width is not positive, a
//!   malformed image) is not recorded at all, and a stroke's dash list is made valid. So
//!   tiny-skia never draws a zero-width stroke as a hairline while SVG draws nothing, and
//!   the SVG never contains a NaN.
//! - Clips nest: [`Canvas::clip_push`] intersects with the clip in force, and
//!   [`Canvas::clip_pop`] restores the previous one. A pop without a push does nothing and
//!   clips still open at the end are closed. A clip path that is empty or not finite hides
//!   everything until popped.
//! - An image is drawn 1:1 at its position rounded to whole pixels, without resampling.
//!
//! Sizes are clamped to `1..=`[`Canvas::MAX_SIDE`], so rendering cannot fail.
//!
//! ```
//! use realist_overlay::{Canvas, Color, HAlign, Path2, VAlign};
//! let mut c = Canvas::new(64, 32);
//! c.background(Color::rgb(255, 255, 255));
//! let tri = Path2::new().move_to(4.0, 28.0).line_to(20.0, 4.0).line_to(36.0, 28.0).close();
//! c.fill(&tri, Color::rgb(200, 30, 30));
//! c.text("Hi", 40.0, 16.0, 14.0, Color::rgb(0, 0, 0), HAlign::Left, VAlign::Middle);
//! let pixmap = c.to_pixmap();
//! assert_eq!((pixmap.width(), pixmap.height()), (64, 32));
//! // The triangle's centre is red, the corner keeps the background.
//! assert_eq!(pixmap.pixel(20, 20).map(|p| p.red()), Some(200));
//! assert_eq!(pixmap.pixel(0, 0).map(|p| p.green()), Some(255));
//! assert!(c.to_svg().contains("aria-label=\"Hi\""));
//! ```

use tiny_skia::{FillRule, Mask, Paint, Pixmap, PixmapPaint, Transform};

use super::path::{Color, Path2};
use super::text::{text_path, HAlign, VAlign};

/// How a path's outline is drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct Stroke {
    /// Line width in pixels; a stroke whose width is not positive and finite is not drawn.
    pub width: f32,
    /// Dash pattern (on, off, ...) in pixels, starting at the path's start. An odd list is
    /// repeated once (SVG's rule); one with a negative or non-finite entry or a zero total
    /// draws a solid line.
    pub dash: Option<Vec<f32>>,
    /// Round caps and joins (else butt caps and miter joins with miter limit 4, the SVG
    /// defaults).
    pub round: bool,
}

impl Stroke {
    /// A solid line of `width` pixels with butt caps.
    #[must_use]
    pub fn solid(width: f32) -> Self {
        Self {
            width,
            dash: None,
            round: false,
        }
    }

    /// A solid line of `width` pixels with round caps and joins.
    #[must_use]
    pub fn rounded(width: f32) -> Self {
        Self {
            round: true,
            ..Self::solid(width)
        }
    }

    /// The stroke as both backends draw it, or `None` if it draws nothing.
    fn normalised(&self) -> Option<Self> {
        if !(self.width > 0.0 && self.width.is_finite()) {
            return None;
        }
        let dash = self.dash.as_ref().and_then(|d| {
            let total: f32 = d.iter().sum();
            let valid = d.iter().all(|v| *v >= 0.0 && v.is_finite()) && total > 0.0;
            let valid = valid && total.is_finite();
            match (valid, d.len() % 2) {
                (false, _) => None,
                (true, 0) => Some(d.clone()),
                (true, _) => Some(d.iter().chain(d).copied().collect()),
            }
        });
        Some(Self {
            width: self.width,
            dash,
            round: self.round,
        })
    }
}

/// A straight-alpha sRGB RGBA8 raster, row-major, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbaImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` pixels, `[r, g, b, a]` each.
    pub pixels: Vec<[u8; 4]>,
}

impl RgbaImage {
    /// As a premultiplied tiny-skia pixmap; `None` if empty, too large for tiny-skia, or
    /// the sizes disagree with the pixel count.
    #[must_use]
    pub fn to_pixmap(&self) -> Option<Pixmap> {
        let count = (self.width as usize).checked_mul(self.height as usize)?;
        if self.pixels.len() != count {
            return None;
        }
        let mut pm = Pixmap::new(self.width, self.height)?;
        for (dst, src) in pm.pixels_mut().iter_mut().zip(&self.pixels) {
            *dst = tiny_skia::ColorU8::from_rgba(src[0], src[1], src[2], src[3]).premultiply();
        }
        Some(pm)
    }
}

/// One recorded drawing command, already normalised (see the module doc).
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Item {
    /// A finite path with at least one drawable segment.
    Fill(Path2, Color),
    /// As `Fill`, and the stroke is [`Stroke::normalised`].
    Stroke(Path2, Color, Stroke),
    /// Text already turned into outlines (non-empty); the string is kept for the SVG.
    Text(Path2, Color, String),
    /// Top-left corner in whole pixels, and the image premultiplied (as tiny-skia draws
    /// it; the SVG encodes it back to straight alpha).
    Image(i32, i32, Pixmap),
    /// The clip path, or an empty path to hide everything.
    ClipPush(Path2),
    ClipPop,
}

/// A 2D drawing: pixel units, y down, origin at the top-left corner, pixel centres at
/// +0.5. Items are painted in the order they are added; clips nest (their intersection
/// applies) until popped. See the module doc for the invariants.
#[derive(Clone, Debug, PartialEq)]
pub struct Canvas {
    width: u32,
    height: u32,
    background: Option<Color>,
    pub(crate) items: Vec<Item>,
}

impl Canvas {
    /// The largest width or height, in pixels (a 1 GiB pixmap at most).
    pub const MAX_SIDE: u32 = 16_384;

    /// An empty, transparent canvas; each side is clamped to `1..=MAX_SIDE`.
    #[must_use]
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width: width.clamp(1, Self::MAX_SIDE),
            height: height.clamp(1, Self::MAX_SIDE),
            background: None,
            items: Vec::new(),
        }
    }

    /// Width in pixels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Paints the whole canvas with `c` before any item (the last call wins).
    pub fn background(&mut self, c: Color) {
        self.background = Some(c);
    }

    /// Fills the inside of `path` (non-zero winding).
    pub fn fill(&mut self, path: &Path2, color: Color) {
        if drawable(path) {
            self.items.push(Item::Fill(path.clone(), color));
        }
    }

    /// Strokes the outline of `path`.
    pub fn stroke(&mut self, path: &Path2, color: Color, stroke: &Stroke) {
        if let (true, Some(s)) = (drawable(path), stroke.normalised()) {
            self.items.push(Item::Stroke(path.clone(), color, s));
        }
    }

    /// Restricts what follows to the inside of `path` (non-zero winding), intersected with
    /// any clip already in force, until the matching [`Canvas::clip_pop`].
    pub fn clip_push(&mut self, path: &Path2) {
        let path = if drawable(path) {
            path.clone()
        } else {
            Path2::new()
        };
        self.items.push(Item::ClipPush(path));
    }

    /// Ends the innermost clip (no-op without one).
    pub fn clip_pop(&mut self) {
        self.items.push(Item::ClipPop);
    }

    /// Draws `img` 1:1 with its top-left corner at `(x, y)` rounded to whole pixels. An
    /// image whose pixel count disagrees with its size, or at a non-finite position, is
    /// skipped.
    pub fn image(&mut self, x: f32, y: f32, img: RgbaImage) {
        if let (true, Some(pm)) = (x.is_finite() && y.is_finite(), img.to_pixmap()) {
            // `as` saturates: a position beyond i32 is off the canvas either way.
            self.items
                .push(Item::Image(x.round() as i32, y.round() as i32, pm));
        }
    }

    /// One line of text of em size `size_px` (the CSS `font-size`) anchored at `(x, y)`.
    // The anchor, size, colour and alignment are independent; a struct would only add noise.
    #[allow(clippy::too_many_arguments)]
    pub fn text(
        &mut self,
        text: &str,
        x: f32,
        y: f32,
        size_px: f32,
        color: Color,
        h: HAlign,
        v: VAlign,
    ) {
        self.text_rotated(text, x, y, size_px, color, h, v, 0.0);
    }

    /// As [`Canvas::text`], rotated by `degrees` about the anchor, clockwise on screen (y
    /// points down): -90 reads bottom to top, as a vertical axis label does.
    #[allow(clippy::too_many_arguments)] // as for `text`
    pub fn text_rotated(
        &mut self,
        text: &str,
        x: f32,
        y: f32,
        size_px: f32,
        color: Color,
        h: HAlign,
        v: VAlign,
        degrees: f32,
    ) {
        let path = text_path(text, x, y, size_px, h, v, degrees);
        if drawable(&path) {
            self.items.push(Item::Text(path, color, text.to_owned()));
        }
    }

    /// Renders every item, anti-aliased, on a premultiplied pixmap of the canvas's size.
    #[must_use]
    pub fn to_pixmap(&self) -> Pixmap {
        let mut pm = Pixmap::new(self.width, self.height)
            .expect("Canvas::new keeps both sides in 1..=MAX_SIDE");
        if let Some(bg) = self.background {
            pm.fill(tiny_skia::Color::from_rgba8(bg.r, bg.g, bg.b, bg.a));
        }
        let id = Transform::identity();
        let mut masks: Vec<Mask> = Vec::new();
        for item in &self.items {
            let mask = masks.last();
            match item {
                Item::Fill(path, color) | Item::Text(path, color, _) => {
                    if let Some(p) = path.to_skia() {
                        pm.fill_path(&p, &paint(*color), FillRule::Winding, id, mask);
                    }
                }
                Item::Stroke(path, color, stroke) => {
                    if let Some(p) = path.to_skia() {
                        pm.stroke_path(&p, &paint(*color), &skia_stroke(stroke), id, mask);
                    }
                }
                Item::Image(x, y, src) => {
                    let paint = PixmapPaint::default(); // source-over, nearest: 1:1 copy
                    pm.draw_pixmap(*x, *y, src.as_ref(), &paint, id, mask);
                }
                Item::ClipPush(path) => {
                    let next = match (mask, path.to_skia()) {
                        (Some(outer), Some(p)) => {
                            let mut m = outer.clone();
                            m.intersect_path(&p, FillRule::Winding, true, id);
                            m
                        }
                        (None, Some(p)) => {
                            let mut m = self.empty_mask();
                            m.fill_path(&p, FillRule::Winding, true, id);
                            m
                        }
                        // The recorded empty path: hide everything.
                        (_, None) => self.empty_mask(),
                    };
                    masks.push(next);
                }
                Item::ClipPop => {
                    masks.pop();
                }
            }
        }
        pm
    }

    /// A mask of the canvas's size that lets nothing through.
    fn empty_mask(&self) -> Mask {
        Mask::new(self.width, self.height).expect("Canvas::new keeps both sides in 1..=MAX_SIDE")
    }

    /// [`Canvas::to_pixmap`] as straight-alpha sRGB RGBA8, rows top first.
    #[must_use]
    pub fn to_rgba8(&self) -> Vec<u8> {
        self.to_pixmap()
            .pixels()
            .iter()
            .flat_map(|p| {
                let c = p.demultiply();
                [c.red(), c.green(), c.blue(), c.alpha()]
            })
            .collect()
    }

    /// PNG bytes of the drawing (straight alpha, sRGB), through realist's one PNG writer
    /// ([`crate::color::png::Png`]).
    ///
    /// # Errors
    /// Never for a canvas (its size and bytes agree); the writer's message otherwise.
    pub fn to_png(&self) -> Result<Vec<u8>, String> {
        let rgba = self.to_rgba8();
        crate::color::png::Png::rgba(self.width, self.height, &rgba).encode()
    }

    /// A standalone SVG 1.1 document of the same drawing.
    #[must_use]
    pub fn to_svg(&self) -> String {
        super::svg::write(self.width, self.height, self.background, &self.items)
    }
}

/// Whether `path` has a drawable segment and only finite coordinates.
fn drawable(path: &Path2) -> bool {
    !path.is_empty() && path.is_finite()
}

fn paint(c: Color) -> Paint<'static> {
    let mut p = Paint::default();
    p.set_color_rgba8(c.r, c.g, c.b, c.a);
    p.anti_alias = true;
    p
}

/// The tiny-skia stroke of a [`Stroke::normalised`] stroke.
fn skia_stroke(s: &Stroke) -> tiny_skia::Stroke {
    let mut st = tiny_skia::Stroke {
        width: s.width,
        ..tiny_skia::Stroke::default()
    };
    if s.round {
        st.line_cap = tiny_skia::LineCap::Round;
        st.line_join = tiny_skia::LineJoin::Round;
    }
    st.dash = s
        .dash
        .as_ref()
        .and_then(|d| tiny_skia::StrokeDash::new(d.clone(), 0.0));
    st
}
