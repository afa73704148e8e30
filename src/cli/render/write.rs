//! The image `realist render` writes: a PNG naming its model and settings, or the format
//! another extension names.

use std::path::Path;

use anyhow::{Context, Result};

use realist::render::Settings;

/// What a written image says about its settings (the PNG's `Description`).
pub(super) fn describe(s: &Settings) -> String {
    let shading = s.shading.map_or("per instance", |m| m.name());
    let mut d = format!(
        "shading {shading}, exposure {} EV, tone {}, {} sample(s) per side, msaa {}",
        s.exposure,
        s.tone.name(),
        s.samples,
        s.msaa
    );
    for p in &s.sections.planes {
        d += &format!(", section {},{},{},{}", p.x, p.y, p.z, p.w);
    }
    d
}

/// Writes 8-bit sRGB RGB: a PNG through realist's one writer (naming the model it shows and
/// the settings) for a `.png` name, else the format the extension names.
pub(super) fn write_image(
    path: &Path,
    w: u32,
    h: u32,
    rgb: &[u8],
    source: &str,
    description: &str,
) -> Result<()> {
    let png = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if !png {
        let img =
            image::RgbImage::from_raw(w, h, rgb.to_vec()).context("framebuffer size mismatch")?;
        return Ok(img.save(path)?);
    }
    realist::color::png::Png::rgb(w, h, rgb)
        .with_text("Source", source)
        .with_text("Description", description)
        .write(path)
        .map_err(anyhow::Error::msg)
}
