//! Decoded images and their samplers.
//!
//! Texels are stored in the form their slot samples ([`Texels`]): 8-bit colour stays
//! sRGB-encoded as decoded (4 bytes a texel) and is decoded to linear light, exactly, through
//! a 256-entry table at sampling time, so filtering happens in linear light; data (normals,
//! occlusion, heights) is 8- or 16-bit linear; high-dynamic-range images (Radiance `.hdr`,
//! OpenEXR) are 32-bit float. UV convention: glTF's, origin at the top-left texel
//! corner, u to the right, v downwards (OBJ loaders flip v on the way in).
//!
//! Filters ([`Filter`]): nearest, bilinear on the base level, trilinear (mipmapped, the
//! default) and anisotropic (`aniso:N`: up to N trilinear taps along the long axis of the
//! pixel's footprint, as GPUs do it). The mip chain (see `mip.rs` for the box filter and the storage of the levels)
//! is built once per texture, on the first sample that needs a level below the base, or
//! ahead of time by [`Texture::prepare_mips`] (the renderer does this before filling tiles,
//! so no tile waits for it). The level of detail comes from the screen-space UV derivatives
//! ([`Texture::sample_grad`]) with OpenGL's isotropic formula; anisotropic filtering
//! ([`Texture::aniso`]) takes the level from the footprint's length over its number of taps.
//!
//! Shaders that work on eight pixels at once sample with [`Texture::sample_lanes`] and
//! [`Texture::sample_grad_lanes`] (`lanes.rs`): the same results, the coordinate and weight
//! arithmetic done on all lanes at once and only the texel reads per lane.

// The crates below this one, under the module names the code uses (`crate::scene::...`).
use realist_color as color;
use realist_simd as simd;

pub mod env;
mod lanes;
pub mod microfacet;
mod mip;
pub mod noise;
mod procedural;
mod uvgen;

pub use procedural::{
    Baked, Domain, ParseProceduralError, Procedural, ProceduralTexture, SamplePoint, MAX_AMOUNT,
    MAX_BAKE, MAX_CHECKER_SQUARES, MAX_FREQUENCY, MAX_GRID_CELLS, MIN_FREQUENCY, MIN_GRADIENT_STEP,
    PROCEDURAL_NAMES,
};
pub use uvgen::{
    Axis, MappedUv, ParseUvGeneratorError, UvFrame, UvGenerator, MIN_EXTENT_RATIO, SINGULAR_EPS,
};

use std::sync::OnceLock;

use glam::{Vec2, Vec4};

/// How coordinates outside [0, 1] are folded back (glTF sampler wrap modes).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Wrap {
    #[default]
    Repeat,
    MirroredRepeat,
    ClampToEdge,
}

/// Magnification / minification filter.
///
/// The default is [`Filter::Trilinear`]: a viewer is expected to show minified textures
/// without aliasing (glTF leaves the filter of a sampler without `minFilter` to the
/// implementation, and OBJ has none), and trilinear is identical to bilinear wherever the
/// texture is magnified.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Filter {
    /// The texel containing the sample point, on the base level.
    Nearest,
    /// The four nearest texels of the base level, bilinearly weighted (no mipmaps).
    Bilinear,
    /// Mipmapped (GL's `LINEAR_MIPMAP_LINEAR`): bilinear within the two levels around the
    /// level of detail, linear between them; bilinear on the base level when magnified.
    /// Needs derivatives ([`Texture::sample_grad`]); [`Texture::sample`] reads the base level.
    #[default]
    Trilinear,
    /// Anisotropic (as GPUs do it, after `EXT_texture_filter_anisotropic`; no elliptical
    /// weighting): up to `N` trilinear taps spread evenly along the longer axis of the pixel's
    /// footprint, each at the level of detail of the footprint's length over the number of
    /// taps, averaged with equal weights. `N` is the largest ratio, [`MIN_ANISO`] to
    /// [`MAX_ANISO`] (other values are clamped to that range when sampling). Magnified and
    /// isotropic footprints (one tap) read exactly the trilinear sample. Needs derivatives
    /// ([`Texture::sample_grad_with`]); [`Texture::sample`] reads the base level.
    Anisotropic(u8),
}

/// Smallest and largest ratio of [`Filter::Anisotropic`].
pub const MIN_ANISO: u8 = 2;
/// See [`MIN_ANISO`].
pub const MAX_ANISO: u8 = 16;

/// The names `aniso:2` .. `aniso:16` (index = ratio - [`MIN_ANISO`]).
const ANISO_NAMES: [&str; (MAX_ANISO - MIN_ANISO + 1) as usize] = [
    "aniso:2", "aniso:3", "aniso:4", "aniso:5", "aniso:6", "aniso:7", "aniso:8", "aniso:9",
    "aniso:10", "aniso:11", "aniso:12", "aniso:13", "aniso:14", "aniso:15", "aniso:16",
];

impl Filter {
    /// Every filter a user can name, with the anisotropic ratios most often compared (the
    /// viewer's and the sweep's list): nearest, bilinear, trilinear, aniso:2/4/8/16.
    pub const COMMON: [Filter; 7] = [
        Filter::Nearest,
        Filter::Bilinear,
        Filter::Trilinear,
        Filter::Anisotropic(2),
        Filter::Anisotropic(4),
        Filter::Anisotropic(8),
        Filter::Anisotropic(16),
    ];

    /// The name the command line and scene files use: `nearest`, `bilinear`, `trilinear` or
    /// `aniso:N` (N clamped to [`MIN_ANISO`]..=[`MAX_ANISO`], as sampling clamps it).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Filter::Nearest => "nearest",
            Filter::Bilinear => "bilinear",
            Filter::Trilinear => "trilinear",
            Filter::Anisotropic(n) => ANISO_NAMES[usize::from(aniso_ratio(n) - MIN_ANISO)],
        }
    }

    /// True if the filter reads the mip chain (trilinear and anisotropic): a renderer should
    /// call [`Texture::prepare_mips`] before drawing with it.
    #[must_use]
    pub fn mipmapped(self) -> bool {
        matches!(self, Filter::Trilinear | Filter::Anisotropic(_))
    }
}

/// The largest anisotropic ratio actually used for a requested `n`.
#[inline]
fn aniso_ratio(n: u8) -> u8 {
    n.clamp(MIN_ANISO, MAX_ANISO)
}

impl std::fmt::Display for Filter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Why a filter name was not understood.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "unknown filter '{0}' (expected nearest, bilinear, trilinear or aniso:N with N from {MIN_ANISO} to {MAX_ANISO})"
)]
pub struct ParseFilterError(pub String);

impl std::str::FromStr for Filter {
    type Err = ParseFilterError;

    /// `nearest`, `bilinear`, `trilinear` or `aniso:N` (N = 2..=16), case-insensitive,
    /// surrounding spaces ignored.
    fn from_str(s: &str) -> Result<Self, ParseFilterError> {
        let t = s.trim().to_ascii_lowercase();
        let bad = || ParseFilterError(s.to_owned());
        match t.as_str() {
            "nearest" => Ok(Filter::Nearest),
            "bilinear" => Ok(Filter::Bilinear),
            "trilinear" => Ok(Filter::Trilinear),
            _ => {
                let n = t.strip_prefix("aniso:").ok_or_else(bad)?.trim();
                // Digits only: `u8::from_str` would also take a leading '+'.
                if n.is_empty() || n.len() > 2 || !n.bytes().all(|b| b.is_ascii_digit()) {
                    return Err(bad());
                }
                let n: u8 = n.parse().map_err(|_| bad())?;
                if (MIN_ANISO..=MAX_ANISO).contains(&n) {
                    Ok(Filter::Anisotropic(n))
                } else {
                    Err(bad())
                }
            }
        }
    }
}

/// How a texture is read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Sampler {
    pub wrap_u: Wrap,
    pub wrap_v: Wrap,
    pub filter: Filter,
}

/// Largest procedural chequerboard edge, in texels.
pub const MAX_CHECKER: u32 = 8192;

/// How a texture's texels are stored (row-major, top row first, RGBA).
#[derive(Clone, Debug, PartialEq)]
pub enum Texels {
    /// 8-bit RGB sRGB-encoded, alpha linear (colour slots), decoded exactly by table.
    Srgb8(Vec<[u8; 4]>),
    /// 8-bit linear RGBA (data slots: normals, occlusion, metallic-roughness, heights).
    Linear8(Vec<[u8; 4]>),
    /// 16-bit linear RGBA (16-bit images: data as stored, colour decoded from sRGB).
    Linear16(Vec<[u16; 4]>),
    /// 32-bit float linear RGBA (high dynamic range: values may exceed 1).
    Float(Vec<[f32; 4]>),
}

impl Texels {
    /// Number of texels.
    #[must_use]
    pub fn len(&self) -> usize {
        match self {
            Texels::Srgb8(t) | Texels::Linear8(t) => t.len(),
            Texels::Linear16(t) => t.len(),
            Texels::Float(t) => t.len(),
        }
    }

    /// True if there are no texels.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Bytes of storage.
    #[must_use]
    pub fn bytes(&self) -> u64 {
        let per = match self {
            Texels::Srgb8(_) | Texels::Linear8(_) => 4,
            Texels::Linear16(_) => 8,
            Texels::Float(_) => 16,
        };
        self.len() as u64 * per
    }

    /// The storage's name in reports ("sRGB8", "linear8", "linear16", "float32").
    #[must_use]
    pub fn format_name(&self) -> &'static str {
        match self {
            Texels::Srgb8(_) => "sRGB8",
            Texels::Linear8(_) => "linear8",
            Texels::Linear16(_) => "linear16",
            Texels::Float(_) => "float32",
        }
    }
}

/// A decoded image and (built on demand) its mip chain. How it is sampled (filters, wrap
/// modes) belongs to the slot that reads it ([`crate::scene::TextureSlot`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    pub name: String,
    pub width: u32,
    pub height: u32,
    /// The mip chain is built from these the first time it is needed: change them only on
    /// a texture that was never sampled with [`Filter::Trilinear`], or on a clone (a clone
    /// starts without a chain).
    pub texels: Texels,
    /// Levels 1.. (built lazily).
    mips: MipCache,
}

/// The lazily built mip chain of a texture. Derived data: it takes no part in equality, and
/// a clone starts empty (the clone's texels may be changed before it is sampled).
#[derive(Default)]
struct MipCache(OnceLock<mip::Chain>);

impl Clone for MipCache {
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl PartialEq for MipCache {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl std::fmt::Debug for MipCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.0.get() {
            Some(c) => write!(f, "MipCache({} levels below the base)", c.levels - 1),
            None => f.write_str("MipCache(not built)"),
        }
    }
}

/// Why an image could not become a [`Texture`].
#[derive(Debug, thiserror::Error)]
pub enum TextureError {
    #[error("image has zero width or height")]
    Empty,
    #[error("texel count {got} does not match {width}x{height}")]
    Size { width: u32, height: u32, got: usize },
}

/// Linear byte -> [0, 1]: `c / 255` (the same division as [`Texture::fetch`]).
fn linear_table() -> &'static [f32; 256] {
    static TABLE: std::sync::OnceLock<[f32; 256]> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| std::array::from_fn(|i| i as f32 / 255.0))
}

/// sRGB-encoded byte -> linear light, exact piecewise sRGB transfer.
fn srgb_table() -> &'static [f32; 256] {
    crate::color::srgb8_decode_table()
}

pub use crate::color::{linear_to_srgb, srgb_to_linear};

mod sample;
pub use sample::*;

#[cfg(test)]
mod tests;
