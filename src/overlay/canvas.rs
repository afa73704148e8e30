//! [`Canvas`]: a display list of 2D drawing commands, rendered by tiny-skia to a `Pixmap`
//! (anti-aliased) or written as a standalone SVG document.
//!
//! ```
//! use realist::overlay::{Canvas, Color, HAlign, Path2, VAlign};
//! let mut c = Canvas::new(64, 32);
//! c.background(Color::rgb(255, 255, 255));
//! let tri = Path2::new().move_to(4.0, 28.0).line_to(20.0, 4.0).line_to(36.0, 28.0).close();
//! c.fill(&tri, Color::rgb(200, 30, 30));
//! c.text("Hi", 40.0, 16.0, 14.0, Color::rgb(0, 0, 0), HAlign::Left, VAlign::Middle);
//! let pixmap = c.to_pixmap();
//! assert_eq!(pixmap.width(), 64);
//! assert!(c.to_svg().starts_with("<?xml"));
//! ```

use tiny_skia::{FillRule, Mask, Paint, Pixmap, PixmapPaint, Transform};

use super::path::{Color, Path2};
use super::text::{text_path, HAlign, VAlign};

/// How a path's outline is drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct Stroke {
    /// Line width in pixels.
    pub width: f32,
    /// Dash pattern (on, off, ...) in pixels.
    pub dash: Option<Vec<f32>>,
    /// Round caps and joins (else butt caps and miter joins).
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
}

/// A straight-alpha sRGB RGBA8 raster, row-major, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbaImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[u8; 4]>,
}

impl RgbaImage {
    /// As a premultiplied tiny-skia pixmap; `None` if empty or the sizes disagree.
    #[must_use]
    pub fn to_pixmap(&self) -> Option<Pixmap> {
        if self.pixels.len() != self.width as usize * self.height as usize {
            return None;
        }
        let mut pm = Pixmap::new(self.width, self.height)?;
        for (dst, src) in pm.pixels_mut().iter_mut().zip(&self.pixels) {
            let c = tiny_skia::ColorU8::from_rgba(src[0], src[1], src[2], src[3]);
            *dst = c.premultiply();
        }
        Some(pm)
    }
}

/// One drawing command.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Item {
    Fill(Path2, Color),
    Stroke(Path2, Color, Stroke),
    /// Text already turned into outlines; the string is kept for the SVG.
    Text(Path2, Color, String),
    Image(f32, f32, RgbaImage),
    ClipPush(Path2),
    ClipPop,
}

/// A 2D drawing: pixel units, y down, origin at the top-left corner, pixel centres at
/// +0.5. Items are painted in the order they are added; clips nest (their intersection
/// applies) until popped.
#[derive(Clone, Debug, PartialEq)]
pub struct Canvas {
    width: u32,
    height: u32,
    background: Option<Color>,
    pub(crate) items: Vec<Item>,
}

impl Canvas {
    /// An empty, transparent canvas (sizes below 1 become 1).
    #[must_use]
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width: width.max(1),
            height: height.max(1),
            background: None,
            items: Vec::new(),
        }
    }

    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }

    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }

    pub fn background(&mut self, c: Color) {
        self.background = Some(c);
    }

    pub fn fill(&mut self, path: &Path2, color: Color) {
        self.items.push(Item::Fill(path.clone(), color));
    }

    pub fn stroke(&mut self, path: &Path2, color: Color, stroke: &Stroke) {
        self.items
            .push(Item::Stroke(path.clone(), color, stroke.clone()));
    }

    /// Restricts what follows to the inside of `path` (non-zero winding), intersected with
    /// any clip already in force.
    pub fn clip_push(&mut self, path: &Path2) {
        self.items.push(Item::ClipPush(path.clone()));
    }

    /// Ends the innermost clip (no-op without one).
    pub fn clip_pop(&mut self) {
        self.items.push(Item::ClipPop);
    }

    /// Draws `img` 1:1 with its top-left corner at `(x, y)`.
    pub fn image(&mut self, x: f32, y: f32, img: RgbaImage) {
        self.items.push(Item::Image(x, y, img));
    }

    /// Text of em size `size_px` anchored at `(x, y)`.
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

    /// Text rotated by `degrees` (clockwise on screen; -90 reads bottom to top) about its
    /// anchor.
    #[allow(clippy::too_many_arguments)]
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
        self.items.push(Item::Text(path, color, text.to_owned()));
    }

    /// Renders every item, anti-aliased.
    #[must_use]
    pub fn to_pixmap(&self) -> Pixmap {
        // `new` keeps both sizes >= 1, and callers bound them, so this cannot fail.
        let mut pm = Pixmap::new(self.width, self.height).unwrap_or_else(|| unreachable!());
        if let Some(bg) = self.background {
            pm.fill(tiny_skia::Color::from_rgba8(bg.r, bg.g, bg.b, bg.a));
        }
        let mut masks: Vec<Option<Mask>> = Vec::new();
        for item in &self.items {
            let mask = masks.last().and_then(Option::as_ref);
            match item {
                Item::Fill(path, color) | Item::Text(path, color, _) => {
                    if let Some(p) = path.to_skia() {
                        pm.fill_path(
                            &p,
                            &paint(*color),
                            FillRule::Winding,
                            Transform::identity(),
                            mask,
                        );
                    }
                }
                Item::Stroke(path, color, stroke) => {
                    if let Some(p) = path.to_skia() {
                        pm.stroke_path(
                            &p,
                            &paint(*color),
                            &skia_stroke(stroke),
                            Transform::identity(),
                            mask,
                        );
                    }
                }
                Item::Image(x, y, img) => {
                    if let Some(src) = img.to_pixmap() {
                        pm.draw_pixmap(
                            x.round() as i32,
                            y.round() as i32,
                            src.as_ref(),
                            &PixmapPaint::default(),
                            Transform::identity(),
                            mask,
                        );
                    }
                }
                Item::ClipPush(path) => {
                    let next = match (masks.last(), path.to_skia()) {
                        // An empty or degenerate clip hides everything.
                        (_, None) => Mask::new(self.width, self.height),
                        (Some(Some(outer)), Some(p)) => {
                            let mut m = outer.clone();
                            m.intersect_path(&p, FillRule::Winding, true, Transform::identity());
                            Some(m)
                        }
                        (_, Some(p)) => Mask::new(self.width, self.height).map(|mut m| {
                            m.fill_path(&p, FillRule::Winding, true, Transform::identity());
                            m
                        }),
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

    /// PNG bytes of [`Canvas::to_pixmap`].
    pub fn to_png(&self) -> Result<Vec<u8>, String> {
        self.to_pixmap().encode_png().map_err(|e| e.to_string())
    }

    /// A standalone SVG 1.1 document of the same drawing.
    #[must_use]
    pub fn to_svg(&self) -> String {
        super::svg::write(self.width, self.height, self.background, &self.items)
    }
}

fn paint(c: Color) -> Paint<'static> {
    let mut p = Paint::default();
    p.set_color_rgba8(c.r, c.g, c.b, c.a);
    p.anti_alias = true;
    p
}

fn skia_stroke(s: &Stroke) -> tiny_skia::Stroke {
    let mut st = tiny_skia::Stroke {
        width: s.width.max(0.0),
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
