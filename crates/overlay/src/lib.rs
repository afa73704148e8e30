//! 2D drawings with tiny-skia: the CIE chromaticity diagram, HUD and plots.
//!
//! This module owns the 2D drawing layer: a [`Canvas`] is a display list of fills,
//! strokes, text, raster images and nested clips, which one of two backends renders:
//! tiny-skia (an anti-aliased `Pixmap`, for PNG files and the viewer) or SVG (a standalone
//! vector document, for papers). One description with two backends keeps the outputs
//! identical in content, and lets callers such as the chromaticity diagram draw once for
//! both.
//!
//! Conventions shared by everything here:
//! - Coordinates are `f32` pixels, y down, origin at the top-left corner of the canvas,
//!   pixel centres at +0.5: an integer-aligned rectangle covers whole pixels exactly.
//! - Colours are straight (non-premultiplied) sRGB with 8-bit alpha ([`Color`]); images are
//!   straight-alpha RGBA8 ([`RgbaImage`]). Premultiplication happens inside the raster
//!   backend only.
//! - Fills and clips use the non-zero winding rule; nested clips intersect.
//! - Input is normalised when recorded, not when rendered: items that would draw nothing
//!   are dropped and dash lists made valid, so the backends cannot disagree on edge cases.
//! - Text is drawn as outlines of the embedded DejaVu Sans in both backends, so the SVG
//!   needs no font on the reader's machine and text clips like any other shape.
//!
//! | file | owns |
//! |---|---|
//! | `canvas.rs` | [`Canvas`], [`Stroke`], [`RgbaImage`], recording, the tiny-skia backend |
//! | `path.rs` | [`Path2`] and its [`Seg`]s, [`Color`] |
//! | `text.rs` | the embedded font, one-line layout ([`text_extent`]) and outlines |
//! | `svg.rs` | the SVG backend |
//! | `tests.rs` | raster coverage tests of the canvas |
//! | `chroma/` | the chromaticity diagram |
//! | `chart.rs` | charts of measurements (the accuracy sweep's time against error) |

// The crates below this one, under the module names the code uses (`crate::scene::...`).
use realist_color as color;
use realist_geom as geom;
use realist_texture as texture;

mod canvas;
pub mod chart;
pub mod chroma;
mod path;
mod svg;
mod text;

pub use canvas::{Canvas, RgbaImage, Stroke};
pub use path::{Color, Path2, Seg};
pub use text::{text_extent, text_path, HAlign, VAlign};

#[cfg(test)]
mod tests;
