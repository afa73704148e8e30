//! Image decoding for textures (PNG and JPEG through the `image` crate) under size limits:
//! at most [`MAX_SIDE`] texels a side, and the decoder may not allocate more than what is
//! left of the load's [`Budget`].

use std::path::Path;

use super::{Budget, LoadError};
use crate::texture::Texture;

/// Largest accepted image width or height, in texels.
pub const MAX_SIDE: u32 = 16384;

/// Why an image could not be decoded.
#[derive(Debug)]
pub(crate) enum DecodeError {
    /// The memory budget would be exceeded: stops the whole load.
    Budget(LoadError),
    /// The image is unusable (unknown format, corrupt, too large a side): the caller decides
    /// whether that is a warning or an error.
    Invalid(String),
}

impl DecodeError {
    /// As a load error about the image file `path`.
    pub(crate) fn into_load_error(self, path: &Path) -> LoadError {
        match self {
            DecodeError::Budget(e) => e,
            DecodeError::Invalid(reason) => LoadError::Image {
                path: path.to_owned(),
                reason,
            },
        }
    }
}

/// Decodes PNG or JPEG bytes into an sRGB RGBA8 texture named `name` with the default
/// sampler, charging the texels to `budget`.
pub(crate) fn decode(bytes: &[u8], name: &str, budget: &Budget) -> Result<Texture, DecodeError> {
    let reader = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| DecodeError::Invalid(e.to_string()))?;
    if reader.format().is_none() {
        return Err(DecodeError::Invalid("not a PNG or JPEG image".into()));
    }
    let (width, height) = reader
        .into_dimensions()
        .map_err(|e| DecodeError::Invalid(e.to_string()))?;
    if width > MAX_SIDE || height > MAX_SIDE {
        return Err(DecodeError::Invalid(format!(
            "{width}x{height} texels, more than {MAX_SIDE} a side"
        )));
    }
    let texel_bytes = u64::from(width) * u64::from(height) * 4;
    budget
        .charge(texel_bytes, || {
            format!("image '{name}' ({width}x{height} texels)")
        })
        .map_err(DecodeError::Budget)?;

    let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| DecodeError::Invalid(e.to_string()))?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_SIDE);
    limits.max_image_height = Some(MAX_SIDE);
    // The decoder's own buffer plus the RGBA copy: bounded by what is left plus the texels
    // just charged (the decoded buffer is dropped before this function returns).
    limits.max_alloc = Some(budget.remaining().saturating_add(texel_bytes));
    reader.limits(limits);
    let rgba = reader
        .decode()
        .map_err(|e| DecodeError::Invalid(e.to_string()))?
        .into_rgba8();
    let (w, h) = rgba.dimensions();
    let texels: Vec<[u8; 4]> = rgba
        .as_raw()
        .chunks_exact(4)
        .map(|c| [c[0], c[1], c[2], c[3]])
        .collect();
    Texture::new(name, w, h, texels, true).map_err(|e| DecodeError::Invalid(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png(width: u32, height: u32) -> Vec<u8> {
        let img = image::RgbaImage::from_pixel(width, height, image::Rgba([10, 20, 30, 255]));
        let mut out = Vec::new();
        img.write_to(&mut std::io::Cursor::new(&mut out), image::ImageFormat::Png)
            .unwrap();
        out
    }

    /// A PNG whose header claims `width` x `height` but which holds 1x1 pixel of data.
    fn lying_png(width: u32, height: u32) -> Vec<u8> {
        let mut bytes = png(1, 1);
        // Signature (8), IHDR length (4), "IHDR" (4), width, height, ..., CRC at 29.
        bytes[16..20].copy_from_slice(&width.to_be_bytes());
        bytes[20..24].copy_from_slice(&height.to_be_bytes());
        let crc = crc32(&bytes[12..29]);
        bytes[29..33].copy_from_slice(&crc.to_be_bytes());
        bytes
    }

    fn crc32(data: &[u8]) -> u32 {
        let mut crc = !0u32;
        for &b in data {
            crc ^= u32::from(b);
            for _ in 0..8 {
                crc = if crc & 1 == 1 {
                    (crc >> 1) ^ 0xEDB8_8320
                } else {
                    crc >> 1
                };
            }
        }
        !crc
    }

    #[test]
    fn header_sizes_are_refused_before_any_texel_is_allocated() {
        let budget = Budget::new(Path::new("t"), 2 << 30);
        match decode(&lying_png(20_000, 16), "wide.png", &budget) {
            Err(DecodeError::Invalid(reason)) => {
                assert_eq!(reason, "20000x16 texels, more than 16384 a side");
            }
            other => panic!("{:?}", other.map(|t| (t.width, t.height))),
        }
        // 16384^2 RGBA is 1 GiB: over a 256 MiB budget, refused from the header alone.
        let small = Budget::new(Path::new("t"), 256 << 20);
        match decode(&lying_png(16384, 16384), "big.png", &small) {
            Err(DecodeError::Budget(e)) => assert!(
                e.to_string()
                    .contains("image 'big.png' (16384x16384 texels) needs 1073741824 bytes"),
                "{e}"
            ),
            other => panic!("{:?}", other.map(|t| (t.width, t.height))),
        }
        // Within the limits the header lie is caught by the decoder: an error, not a panic.
        assert!(matches!(
            decode(&lying_png(64, 64), "short.png", &budget),
            Err(DecodeError::Invalid(_))
        ));
    }

    #[test]
    fn decodes_png_and_enforces_budget() {
        let bytes = png(4, 2);
        let budget = Budget::new(Path::new("t"), 1 << 20);
        let t = decode(&bytes, "t.png", &budget).unwrap();
        assert_eq!((t.width, t.height, t.texels[0]), (4, 2, [10, 20, 30, 255]));
        assert!(t.srgb);
        let small = Budget::new(Path::new("t"), 16);
        assert!(matches!(
            decode(&bytes, "t.png", &small),
            Err(DecodeError::Budget(_))
        ));
        assert!(matches!(
            decode(b"GIF89a....", "x", &budget),
            Err(DecodeError::Invalid(_))
        ));
    }
}
