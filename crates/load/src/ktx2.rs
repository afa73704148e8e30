//! KTX2 images holding Basis Universal data (`KHR_texture_basisu`): ETC1S with BasisLZ, and
//! UASTC, raw or with Zstandard supercompression. Transcoded to RGBA8 by `basisu` (a pure-Rust
//! port of the Basis Universal transcoder, with Zstandard through `ruzstd`); only the base
//! level is used (realist builds its own mipmaps). The texels are the encoded values, so a
//! colour slot reads them as sRGB and a data slot as linear, as for PNG.
//!
//! Before anything is allocated the base level's size is checked against [`MAX_SIDE`] and
//! charged to the load's budget; a transcoder error or a panic inside it is
//! [`DecodeError::Invalid`] (a warning, the texture is dropped, for a glTF image).

use super::images::{DecodeError, MAX_SIDE};
use super::{catch_decoder, Budget};
use crate::texture::{Texels, Texture};

/// The 12-byte KTX 2.0 file identifier.
pub const MAGIC: [u8; 12] = [
    0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A,
];

/// Whether `bytes` start like a KTX2 file.
pub fn is_ktx2(bytes: &[u8]) -> bool {
    bytes.starts_with(&MAGIC)
}

/// Transcodes the base level of a KTX2 Basis Universal image to RGBA8.
pub fn decode(
    bytes: &[u8],
    name: &str,
    budget: &Budget,
    srgb: bool,
) -> Result<Texture, DecodeError> {
    let invalid = DecodeError::Invalid;
    regions_in_file(bytes).map_err(invalid)?;
    let (width, height, rgba) = {
        let transcoder = catch_decoder(|| {
            basisu::Transcoder::new(bytes).map_err(|e| format!("KTX2 (Basis Universal): {e:?}"))
        })
        .map_err(invalid)?;
        let (width, height) = transcoder.base_dimensions();
        if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
            return Err(invalid(format!(
                "KTX2 {width}x{height} texels: each side must be 1 to {MAX_SIDE}"
            )));
        }
        if transcoder.level_count() == 0 || transcoder.is_video() {
            return Err(invalid("KTX2 has no image level, or is a video".into()));
        }
        // A Zstandard level is inflated whole to the length its level index states, before
        // any check of that length (basisu 0.1.0): bound it here (a fuzzed header asked for
        // 3e18 bytes) and charge it.
        let inflated = zstd_level0_length(bytes).unwrap_or(0);
        let most = u64::from(width.div_ceil(4)) * u64::from(height.div_ceil(4)) * 16 * 6 * 64;
        if inflated > most {
            return Err(invalid(format!(
                "KTX2 level 0 claims {inflated} bytes once inflated, more than a {width}x{height} image can hold"
            )));
        }
        // The inflated level, the transcoded RGBA and the texel copy.
        let texel_bytes = u64::from(width) * u64::from(height) * 4;
        budget
            .charge(inflated, || {
                format!("image '{name}' (KTX2 level 0 inflated)")
            })
            .map_err(DecodeError::Budget)?;
        budget
            .charge(texel_bytes * 2, || {
                format!("image '{name}' ({width}x{height} texels, KTX2)")
            })
            .map_err(DecodeError::Budget)?;
        let rgba = catch_decoder(|| {
            transcoder
                .transcode(0, basisu::TargetFormat::Rgba32, basisu::DecodeFlags::NONE)
                .map_err(|e| format!("KTX2 (Basis Universal) transcoding: {e:?}"))
        })
        .map_err(invalid)?;
        (width, height, rgba)
    };
    let texels: Vec<[u8; 4]> = rgba
        .chunks_exact(4)
        .map(|c| [c[0], c[1], c[2], c[3]])
        .collect();
    if texels.len() as u64 != u64::from(width) * u64::from(height) {
        return Err(invalid(format!(
            "KTX2 transcoded to {} texels, expected {width}x{height}",
            texels.len()
        )));
    }
    let texels = if srgb {
        Texels::Srgb8(texels)
    } else {
        Texels::Linear8(texels)
    };
    Texture::from_texels(name, width, height, texels).map_err(|e| invalid(e.to_string()))
}

/// Checks that every region the KTX2 header points at (data format descriptor, key/value
/// data, supercompression global data, each level) lies inside the file. basisu 0.1.0 adds
/// the header's offsets to lengths unchecked: a fuzzed supercompression offset near 2^64
/// wrapped its bounds check and indexed out of the file (a panic, caught, but a useless
/// message).
fn regions_in_file(bytes: &[u8]) -> Result<(), String> {
    let len = bytes.len() as u64;
    let short = || format!("KTX2 header truncated ({len} bytes)");
    let inside = |what: &str, offset: u64, length: u64| {
        if length == 0 || offset.checked_add(length).is_some_and(|end| end <= len) {
            Ok(())
        } else {
            Err(format!(
                "KTX2 {what} (offset {offset}, {length} bytes) lies outside the file ({len} bytes)"
            ))
        }
    };
    let field = |at: usize| u32_at(bytes, at).map(u64::from).ok_or_else(short);
    let field64 = |at: usize| u64_at(bytes, at).ok_or_else(short);
    inside("data format descriptor", field(48)?, field(52)?)?;
    inside("key/value data", field(56)?, field(60)?)?;
    inside("supercompression global data", field64(64)?, field64(72)?)?;
    // The level index: three u64 per level from byte 80 (levelCount 0 means one level).
    let levels = field(40)?.max(1);
    if 80 + 24 * levels > len {
        return Err(format!(
            "KTX2 level index of {levels} levels lies outside the file ({len} bytes)"
        ));
    }
    for level in 0..levels as usize {
        let at = 80 + 24 * level;
        inside(&format!("level {level}"), field64(at)?, field64(at + 8)?)?;
    }
    Ok(())
}

/// The inflated length of level 0 in a Zstandard-supercompressed KTX2 file (its level
/// index's `uncompressedByteLength`), or `None` if the file is not one.
fn zstd_level0_length(bytes: &[u8]) -> Option<u64> {
    // Header: supercompressionScheme at 44; the level index from byte 80, three u64 per level.
    (u32_at(bytes, 44)? == 2).then_some(())?;
    u64_at(bytes, 80 + 16)
}

/// The little-endian u32 at byte `at` of a KTX2 file (its header is little-endian).
fn u32_at(bytes: &[u8], at: usize) -> Option<u32> {
    Some(u32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?))
}

/// The little-endian u64 at byte `at`.
fn u64_at(bytes: &[u8], at: usize) -> Option<u64> {
    Some(u64::from_le_bytes(bytes.get(at..at + 8)?.try_into().ok()?))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn garbage_and_truncation_are_errors() {
        let budget = Budget::new(Path::new("t"), 1 << 24);
        let mut bytes = MAGIC.to_vec();
        assert!(matches!(
            decode(&bytes, "x", &budget, true),
            Err(DecodeError::Invalid(_))
        ));
        bytes.extend_from_slice(&[0xff; 200]);
        assert!(matches!(
            decode(&bytes, "x", &budget, true),
            Err(DecodeError::Invalid(_))
        ));
    }

    /// A header region pointing past the end of the file (or wrapping around 2^64) is
    /// refused with a message naming it, before the transcoder reads it.
    #[test]
    fn header_regions_outside_the_file_are_named() {
        let mut bytes = MAGIC.to_vec();
        bytes.resize(80 + 24, 0);
        bytes[40..44].copy_from_slice(&1u32.to_le_bytes());
        assert_eq!(regions_in_file(&bytes), Ok(()));
        // Supercompression global data at offset 2^64 - 1, 20 bytes long.
        bytes[64..72].copy_from_slice(&u64::MAX.to_le_bytes());
        bytes[72..80].copy_from_slice(&20u64.to_le_bytes());
        let e = regions_in_file(&bytes).expect_err("wrapping offset");
        assert!(e.contains("supercompression global data"), "{e}");
        bytes[64..80].fill(0);
        // Level 0 past the end.
        bytes[80..88].copy_from_slice(&100u64.to_le_bytes());
        bytes[88..96].copy_from_slice(&8u64.to_le_bytes());
        let e = regions_in_file(&bytes).expect_err("level past the end");
        assert!(e.contains("level 0") && e.contains("104 bytes"), "{e}");
        // More levels than the index holds.
        bytes[80..96].fill(0);
        bytes[40..44].copy_from_slice(&9u32.to_le_bytes());
        assert!(regions_in_file(&bytes).is_err());
    }
}
