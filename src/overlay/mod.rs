//! 2D drawings with tiny-skia: the CIE chromaticity diagram, HUD and plots.
//!
//! Everything is first described as a [`Canvas`], a display list of fills, strokes, text,
//! raster images and nested clips in pixel units (y down, origin top-left, pixel centres at
//! +0.5), then rendered by one of two backends: tiny-skia (an anti-aliased `Pixmap`, for
//! PNG files and the viewer) or SVG (vector output for papers). One description with two
//! backends keeps the two outputs identical in content; text is drawn as outlines of the
//! embedded DejaVu Sans in both, so it needs no font on the reader's machine and clips
//! like any other shape.
//!
//! | file | owns |
//! |---|---|
//! | `canvas.rs` | [`Canvas`], [`Stroke`], [`RgbaImage`], the tiny-skia backend |
//! | `path.rs` | [`Path2`], [`Color`] |
//! | `text.rs` | the embedded font, text layout and outlines |
//! | `svg.rs` | the SVG backend |
//! | `chroma/` | the chromaticity diagram |

mod canvas;
pub mod chroma;
mod path;
mod svg;
mod text;

pub use canvas::{Canvas, RgbaImage, Stroke};
pub use path::{Color, Path2, Seg};
pub use text::{text_extent, text_path, HAlign, VAlign};

#[cfg(test)]
mod tests;
