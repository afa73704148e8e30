//! Image decoding for textures (PNG, JPEG, WebP, Radiance HDR and OpenEXR through the `image`
//! crate, KTX2 with Basis Universal data through [`super::ktx2`]) under size limits: at most [`MAX_SIDE`] texels a side, and the decoder may not
//! allocate more than what is left of the load's [`Budget`].
//!
//! The storage follows the image and the slot that reads it ([`Texels`]): 8-bit images stay
//! 8-bit (sRGB-encoded for colour slots, linear for data); 16-bit images become 16-bit
//! linear (a colour slot's sRGB decoded through the exact transfer function, data as
//! stored); float images (HDR, EXR) stay float. PNG and JPEG colour metadata (gamma, ICC) is
//! ignored, as glTF requires.

use std::path::Path;

use super::{Budget, LoadError};
use crate::texture::{srgb_to_linear, Texels, Texture};

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

/// Decodes PNG, JPEG, WebP, KTX2 (Basis Universal), HDR or EXR bytes into a texture named `name` for a slot whose RGB is
/// sRGB-encoded colour (`srgb`) or linear data, charging the texels to `budget`.
pub(crate) fn decode(
    bytes: &[u8],
    name: &str,
    budget: &Budget,
    srgb: bool,
) -> Result<Texture, DecodeError> {
    if super::ktx2::is_ktx2(bytes) {
        return super::ktx2::decode(bytes, name, budget, srgb);
    }
    let reader = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| DecodeError::Invalid(e.to_string()))?;
    if reader.format().is_none() {
        return Err(DecodeError::Invalid(
            "not a PNG, JPEG, WebP, KTX2, Radiance HDR or OpenEXR image".into(),
        ));
    }
    let (width, height, per_texel) = {
        use image::ImageDecoder as _;
        let decoder = reader
            .into_decoder()
            .map_err(|e| DecodeError::Invalid(e.to_string()))?;
        let (w, h) = decoder.dimensions();
        (w, h, storage_bytes(decoder.color_type()))
    };
    if width > MAX_SIDE || height > MAX_SIDE {
        return Err(DecodeError::Invalid(format!(
            "{width}x{height} texels, more than {MAX_SIDE} a side"
        )));
    }
    let texel_bytes = u64::from(width) * u64::from(height) * per_texel;
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
    let decoded = reader
        .decode()
        .map_err(|e| DecodeError::Invalid(e.to_string()))?;
    let (w, h) = (decoded.width(), decoded.height());
    let texels = texels_of(decoded, srgb);
    Texture::from_texels(name, w, h, texels).map_err(|e| DecodeError::Invalid(e.to_string()))
}

/// Bytes a texel of an image of colour type `c` takes in its [`Texels`] storage.
fn storage_bytes(c: image::ColorType) -> u64 {
    use image::ColorType as C;
    match c {
        C::Rgb32F | C::Rgba32F => 16,
        C::L16 | C::La16 | C::Rgb16 | C::Rgba16 => 8,
        _ => 4,
    }
}

/// The storage for a decoded image read by a slot of colour space `srgb` (see the module
/// docs).
fn texels_of(img: image::DynamicImage, srgb: bool) -> Texels {
    use image::DynamicImage as D;
    match img {
        D::ImageRgb32F(_) | D::ImageRgba32F(_) => Texels::Float(
            img.into_rgba32f()
                .as_raw()
                .chunks_exact(4)
                .map(|c| [c[0], c[1], c[2], c[3]])
                .collect(),
        ),
        D::ImageLuma16(_) | D::ImageLumaA16(_) | D::ImageRgb16(_) | D::ImageRgba16(_) => {
            let linear = |c: u16| -> u16 {
                let v = srgb_to_linear(f32::from(c) / 65535.0);
                (v.clamp(0.0, 1.0) * 65535.0 + 0.5) as u16
            };
            Texels::Linear16(
                img.into_rgba16()
                    .as_raw()
                    .chunks_exact(4)
                    .map(|c| match srgb {
                        true => [linear(c[0]), linear(c[1]), linear(c[2]), c[3]],
                        false => [c[0], c[1], c[2], c[3]],
                    })
                    .collect(),
            )
        }
        _ => {
            let bytes: Vec<[u8; 4]> = img
                .into_rgba8()
                .as_raw()
                .chunks_exact(4)
                .map(|c| [c[0], c[1], c[2], c[3]])
                .collect();
            if srgb {
                Texels::Srgb8(bytes)
            } else {
                Texels::Linear8(bytes)
            }
        }
    }
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
        match decode(&lying_png(20_000, 16), "wide.png", &budget, true) {
            Err(DecodeError::Invalid(reason)) => {
                assert_eq!(reason, "20000x16 texels, more than 16384 a side");
            }
            other => panic!("{:?}", other.map(|t| (t.width, t.height))),
        }
        // 16384^2 RGBA is 1 GiB: over a 256 MiB budget, refused from the header alone.
        let small = Budget::new(Path::new("t"), 256 << 20);
        match decode(&lying_png(16384, 16384), "big.png", &small, true) {
            Err(DecodeError::Budget(e)) => assert!(
                e.to_string()
                    .contains("image 'big.png' (16384x16384 texels) needs 1073741824 bytes"),
                "{e}"
            ),
            other => panic!("{:?}", other.map(|t| (t.width, t.height))),
        }
        // Within the limits the header lie is caught by the decoder: an error, not a panic.
        assert!(matches!(
            decode(&lying_png(64, 64), "short.png", &budget, true),
            Err(DecodeError::Invalid(_))
        ));
    }

    #[test]
    fn decodes_png_and_enforces_budget() {
        let bytes = png(4, 2);
        let budget = Budget::new(Path::new("t"), 1 << 20);
        let t = decode(&bytes, "t.png", &budget, true).unwrap();
        assert_eq!((t.width, t.height), (4, 2));
        assert_eq!(t.texels, Texels::Srgb8(vec![[10, 20, 30, 255]; 8]));
        let small = Budget::new(Path::new("t"), 16);
        assert!(matches!(
            decode(&bytes, "t.png", &small, true),
            Err(DecodeError::Budget(_))
        ));
        assert!(matches!(
            decode(b"GIF89a....", "x", &budget, true),
            Err(DecodeError::Invalid(_))
        ));
    }
}
