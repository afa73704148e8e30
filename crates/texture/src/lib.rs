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

impl Texture {
    /// A texture from RGBA8 texels (row-major, top row first): RGB sRGB-encoded if `srgb`,
    /// else linear.
    pub fn new(
        name: impl Into<String>,
        width: u32,
        height: u32,
        texels: Vec<[u8; 4]>,
        srgb: bool,
    ) -> Result<Self, TextureError> {
        let texels = if srgb {
            Texels::Srgb8(texels)
        } else {
            Texels::Linear8(texels)
        };
        Self::from_texels(name, width, height, texels)
    }

    /// A texture from texels in any storage.
    pub fn from_texels(
        name: impl Into<String>,
        width: u32,
        height: u32,
        texels: Texels,
    ) -> Result<Self, TextureError> {
        if width == 0 || height == 0 {
            return Err(TextureError::Empty);
        }
        if texels.len() as u64 != u64::from(width) * u64::from(height) {
            return Err(TextureError::Size {
                width,
                height,
                got: texels.len(),
            });
        }
        Ok(Self {
            name: name.into(),
            width,
            height,
            texels,
            mips: MipCache::default(),
        })
    }

    /// The texels as sRGB-encoded RGBA8 (alpha linear): borrowed when they are stored so,
    /// else encoded (float values clamped to [0, 1]).
    #[must_use]
    pub fn to_srgb8(&self) -> std::borrow::Cow<'_, [[u8; 4]]> {
        if let Texels::Srgb8(t) = &self.texels {
            return std::borrow::Cow::Borrowed(t);
        }
        let encode = |c: Vec4| {
            use crate::color::{srgb8, unorm8};
            [srgb8(c.x), srgb8(c.y), srgb8(c.z), unorm8(c.w)]
        };
        let (w, h) = (self.width, self.height);
        std::borrow::Cow::Owned(
            (0..h)
                .flat_map(|y| (0..w).map(move |x| (x, y)))
                .map(|(x, y)| encode(self.fetch(x, y)))
                .collect(),
        )
    }

    /// True if the RGB is 8-bit sRGB-encoded colour.
    #[must_use]
    pub fn is_srgb(&self) -> bool {
        matches!(self.texels, Texels::Srgb8(_))
    }

    /// True if texels may exceed 1 (float storage): such images are never clamped.
    #[must_use]
    pub fn is_hdr(&self) -> bool {
        matches!(self.texels, Texels::Float(_))
    }

    /// The same image stored as a slot of the other colour space needs it: 8-bit texels
    /// re-labelled (sRGB-encoded bytes read as linear data, or the reverse), other storage
    /// converted through the exact transfer function. `srgb` says what the slot wants; the
    /// texels' bytes are taken to be in that encoding (glTF: the slot decides). Returns
    /// `None` if this texture already is what the slot wants.
    #[must_use]
    pub fn as_slot_wants(&self, srgb: bool) -> Option<Texture> {
        let texels = match (&self.texels, srgb) {
            (Texels::Srgb8(_), true) | (Texels::Linear8(_), false) => return None,
            (Texels::Linear16(_) | Texels::Float(_), _) => return None,
            (Texels::Srgb8(t), false) => Texels::Linear8(t.clone()),
            (Texels::Linear8(t), true) => Texels::Srgb8(t.clone()),
        };
        Some(Texture {
            name: self.name.clone(),
            width: self.width,
            height: self.height,
            texels,
            mips: MipCache::default(),
        })
    }

    /// A procedural chequerboard of `n` x `n` squares, `size` texels square (function texture
    /// of the textbook's §9.5). `size` is clamped to 1..=[`MAX_CHECKER`], `n` to 1..=`size`.
    #[must_use]
    pub fn checker(size: u32, n: u32, a: [u8; 4], b: [u8; 4]) -> Self {
        let size = size.clamp(1, MAX_CHECKER);
        let n = u64::from(n.clamp(1, size));
        let s = u64::from(size);
        let texels = (0..s * s)
            .map(|i| {
                let (x, y) = (i % s, i / s);
                if ((x * n / s) + (y * n / s)) % 2 == 0 {
                    a
                } else {
                    b
                }
            })
            .collect();
        Self {
            name: format!("checker{n}"),
            width: size,
            height: size,
            texels: Texels::Srgb8(texels),
            mips: MipCache::default(),
        }
    }

    /// Texel (x, y) in linear light (RGB decoded from sRGB for [`Texels::Srgb8`]; alpha is
    /// linear).
    #[must_use]
    #[inline]
    pub fn fetch(&self, x: u32, y: u32) -> Vec4 {
        let i = (y * self.width + x) as usize;
        match &self.texels {
            Texels::Srgb8(t) => {
                let (t, tab) = (t[i], srgb_table());
                Vec4::new(
                    tab[t[0] as usize],
                    tab[t[1] as usize],
                    tab[t[2] as usize],
                    f32::from(t[3]) / 255.0,
                )
            }
            Texels::Linear8(t) => Vec4::from_array(t[i].map(f32::from)) / 255.0,
            Texels::Linear16(t) => Vec4::from_array(t[i].map(f32::from)) * (1.0 / mip::U16_MAX),
            Texels::Float(t) => Vec4::from_array(t[i]),
        }
    }

    /// Samples at `uv` with the default sampler (repeat; trilinear, which without
    /// derivatives reads the base level as bilinear). Non-finite UVs read texel (0, 0).
    #[must_use]
    pub fn sample(&self, uv: Vec2) -> Vec4 {
        self.sample_with(uv, Sampler::default())
    }

    /// Samples at `uv` (texel centres at half-integers times the texel size).
    /// [`Filter::Trilinear`] reads the base level, as [`Filter::Bilinear`].
    #[must_use]
    pub fn sample_with(&self, uv: Vec2, s: Sampler) -> Vec4 {
        let (w, h) = (self.width, self.height);
        let uv = fold(uv, s);
        match s.filter {
            Filter::Nearest => {
                let x = wrap_index((uv.x * w as f32).floor(), w, s.wrap_u);
                let y = wrap_index((uv.y * h as f32).floor(), h, s.wrap_v);
                self.fetch(x, y)
            }
            Filter::Bilinear | Filter::Trilinear | Filter::Anisotropic(_) => {
                bilinear(uv, w, h, s, |x, y| self.fetch(x, y))
            }
        }
    }

    /// Samples at `uv` with sampler `s`, given the UV's screen-space derivatives (per pixel
    /// along x and along y), which choose the mip level of [`Filter::Trilinear`] and the
    /// taps of [`Filter::Anisotropic`]; the other filters ignore them.
    #[must_use]
    pub fn sample_grad_with(&self, uv: Vec2, duv_dx: Vec2, duv_dy: Vec2, s: Sampler) -> Vec4 {
        match s.filter {
            Filter::Nearest | Filter::Bilinear => self.sample_with(uv, s),
            Filter::Trilinear => self.sample_lod_with(uv, self.lod(duv_dx, duv_dy), s),
            Filter::Anisotropic(max) => {
                let a = self.aniso(duv_dx, duv_dy, max);
                if a.taps <= 1 {
                    return self.sample_lod_with(uv, self.lod(duv_dx, duv_dy), s);
                }
                // Taps at the centres of `taps` equal parts of the major axis, through `uv`.
                let n = a.taps as f32;
                let mut sum = Vec4::ZERO;
                for i in 0..a.taps {
                    let k = (i as f32 + 0.5) / n - 0.5;
                    let at = Vec2::new(uv.x + a.axis.x * k, uv.y + a.axis.y * k);
                    sum += self.sample_lod_with(at, a.lod, s);
                }
                sum * (1.0 / n)
            }
        }
    }

    /// The taps of an anisotropic sample (see [`Filter::Anisotropic`]) for UV derivatives
    /// `duv_dx`, `duv_dy` and largest ratio `max` (clamped to 2..=16).
    ///
    /// The footprint's axes are the two derivative vectors measured in base-level texels;
    /// the major axis is the longer (x on a tie), the minor axis's length is taken as at
    /// least one texel (a footprint thinner than a texel is magnified across, where the
    /// base level is read). Taps = min(ceil(major / minor), max), and 1 when the major axis
    /// is at most one texel (magnified), the derivatives are not finite, or the footprint
    /// is isotropic: then the caller reads the trilinear sample. Otherwise the level of
    /// detail is log2(major / taps), clamped to [0, levels - 1]: each tap covers its share
    /// of the major axis, and the minor axis (major / taps <= minor).
    #[must_use]
    pub fn aniso(&self, duv_dx: Vec2, duv_dy: Vec2, max: u8) -> AnisoTaps {
        let one = AnisoTaps {
            taps: 1,
            lod: 0.0,
            axis: Vec2::ZERO,
        };
        if !(duv_dx.is_finite() && duv_dy.is_finite()) {
            return one;
        }
        let (w, h) = (self.width as f32, self.height as f32);
        let (xu, xv) = (duv_dx.x * w, duv_dx.y * h);
        let (yu, yv) = (duv_dy.x * w, duv_dy.y * h);
        // The same operations as the lane version (no `length`: it may fuse).
        let lx = (xu * xu + xv * xv).sqrt();
        let ly = (yu * yu + yv * yv).sqrt();
        let x_major = lx >= ly;
        let (major, minor) = if x_major { (lx, ly) } else { (ly, lx) };
        let taps = aniso_taps(major, minor, aniso_ratio(max));
        if taps <= 1 {
            return one;
        }
        let top = (self.levels() - 1) as f32;
        let lod = (major / taps as f32).log2().clamp(0.0, top);
        AnisoTaps {
            taps,
            lod,
            axis: if x_major { duv_dx } else { duv_dy },
        }
    }

    /// Trilinear sample at an explicit level of detail `lod` (as GLSL's `textureLod`):
    /// bilinear on levels floor(lod) and floor(lod) + 1, blended by the fraction. `lod` is
    /// clamped to [0, levels - 1]; NaN reads the base level. The filter of `s` is not used.
    #[must_use]
    pub fn sample_lod_with(&self, uv: Vec2, lod: f32, s: Sampler) -> Vec4 {
        let uv = fold(uv, s);
        let top = (self.levels() - 1) as f32;
        if lod.is_nan() || lod <= 0.0 || top == 0.0 {
            return bilinear(uv, self.width, self.height, s, |x, y| self.fetch(x, y));
        }
        let lod = lod.min(top);
        let d = lod.floor();
        let t = lod - d;
        let d = d as usize;
        let a = self.bilinear_level(d, uv, s);
        if t == 0.0 {
            return a;
        }
        a.lerp(self.bilinear_level(d + 1, uv, s), t)
    }

    /// The level of detail λ = log2(ρ) for UV derivatives per pixel along x and y, where ρ
    /// is the longer of the two derivative vectors measured in base-level texels (the
    /// isotropic formula of the OpenGL specification, §8.14.1), clamped to
    /// [0, levels - 1]. Non-finite derivatives give 0 (the base level); derivatives so
    /// large that ρ overflows give the last level.
    #[must_use]
    pub fn lod(&self, duv_dx: Vec2, duv_dy: Vec2) -> f32 {
        if !(duv_dx.is_finite() && duv_dy.is_finite()) {
            return 0.0;
        }
        let size = Vec2::new(self.width as f32, self.height as f32);
        let rho2 = (duv_dx * size)
            .length_squared()
            .max((duv_dy * size).length_squared());
        // log2(ρ) = log2(ρ²) / 2; ρ² = 0 gives -inf and ρ² = inf gives inf, both clamped.
        (0.5 * rho2.log2()).clamp(0.0, (self.levels() - 1) as f32)
    }

    /// Number of mip levels, the base included: floor(log2(max(width, height))) + 1.
    #[must_use]
    pub fn levels(&self) -> usize {
        mip::level_count(self.width, self.height)
    }

    /// Size of mip level `level` (0 = the base): each level halves each side, rounding
    /// down, to no less than 1.
    #[must_use]
    pub fn level_size(&self, level: usize) -> (u32, u32) {
        (0..level).fold((self.width, self.height), |(w, h), _| {
            (mip::half(w), mip::half(h))
        })
    }

    /// Texel (x, y) of mip level `level` (0 = the base, as [`Texture::fetch`]) in linear
    /// light. Builds the chain if needed. Panics if the level or texel does not exist.
    #[must_use]
    pub fn fetch_level(&self, level: usize, x: u32, y: u32) -> Vec4 {
        if level == 0 {
            return self.fetch(x, y);
        }
        let c = self.mips();
        assert!(
            level < c.levels && x < c.size[level].0 && y < c.size[level].1,
            "texel ({x}, {y}) of level {level}"
        );
        c.fetch(level, x, y)
    }

    /// Builds the mip chain now (rows in parallel on the current rayon pool) if it has not
    /// been built yet. Sampling builds it on demand anyway, but serially and while other
    /// threads wait: call this before drawing with a mipmapped texture.
    pub fn prepare_mips(&self) {
        if self.mips.0.get().is_none() && self.levels() > 1 {
            // Built outside the cell: a rayon job must not run inside `get_or_init`, whose
            // thread could steal a job that waits on the same cell. A racing builder's
            // result is simply dropped (both are identical).
            let _ = self.mips.0.set(self.build_mips(true));
        }
    }

    /// Levels 1.., built on first use (serially: see [`Texture::prepare_mips`]).
    fn mips(&self) -> &mip::Chain {
        self.mips.0.get_or_init(|| self.build_mips(false))
    }

    fn build_mips(&self, parallel: bool) -> mip::Chain {
        let row = |y: u32, out: &mut [Vec4]| {
            for (x, o) in out.iter_mut().enumerate() {
                *o = self.fetch(x as u32, y);
            }
        };
        let format = match self.texels {
            Texels::Float(_) => mip::MipFormat::Float,
            Texels::Srgb8(_) | Texels::Linear8(_) | Texels::Linear16(_) => mip::MipFormat::Unorm16,
        };
        mip::Chain::new(self.width, self.height, &row, parallel, format)
    }

    /// Bilinear sample of level `level` at a folded `uv`.
    #[inline]
    fn bilinear_level(&self, level: usize, uv: Vec2, s: Sampler) -> Vec4 {
        if level == 0 {
            bilinear(uv, self.width, self.height, s, |x, y| self.fetch(x, y))
        } else {
            let c = self.mips();
            let (w, h) = c.size[level];
            bilinear(uv, w, h, s, |x, y| c.fetch(level, x, y))
        }
    }
}

/// Where an anisotropic sample reads ([`Texture::aniso`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnisoTaps {
    /// Number of trilinear taps, 1..=16 (1: the plain trilinear sample).
    pub taps: u32,
    /// Level of detail of every tap (unused with one tap).
    pub lod: f32,
    /// The major axis in UV units: tap i of n is at `uv + axis * ((i + 0.5) / n - 0.5)`.
    pub axis: Vec2,
}

/// Number of anisotropic taps for footprint axes `major` >= `minor` (texels) and largest
/// ratio `max`: 1 if `major` <= 1 (or NaN), else min(ceil(major / max(minor, 1)), max). An
/// infinite or NaN ratio takes `max`.
#[inline(always)]
fn aniso_taps(major: f32, minor: f32, max: u8) -> u32 {
    // `major <= 1.0` would let NaN through.
    if major.is_nan() || major <= 1.0 {
        return 1;
    }
    let r = major / minor.max(1.0);
    let maxf = f32::from(max);
    if r < maxf {
        // 1 < r < 16 here, or r <= 1 (isotropic): ceil as an integer.
        let n = r as u32;
        if (n as f32) < r {
            n + 1
        } else {
            n
        }
    } else {
        u32::from(max)
    }
}

/// A UV made safe to scale: non-finite -> (0, 0), then whole periods removed ([`reduce`]).
#[inline]
fn fold(uv: Vec2, s: Sampler) -> Vec2 {
    let uv = if uv.is_finite() { uv } else { Vec2::ZERO };
    // Fold the coordinates into a small range first: scaling a huge UV by the texture
    // size would overflow to infinity and turn the filter weights into NaN.
    Vec2::new(reduce(uv.x, s.wrap_u), reduce(uv.y, s.wrap_v))
}

/// Bilinear filter of a `w` x `h` image read by `fetch`, at a folded `uv`.
#[inline(always)]
fn bilinear(uv: Vec2, w: u32, h: u32, s: Sampler, fetch: impl Fn(u32, u32) -> Vec4) -> Vec4 {
    let fx = uv.x * w as f32 - 0.5;
    let fy = uv.y * h as f32 - 0.5;
    let (x0f, y0f) = (fx.floor(), fy.floor());
    let (tx, ty) = (fx - x0f, fy - y0f);
    let x0 = wrap_index(x0f, w, s.wrap_u);
    let x1 = wrap_index(x0f + 1.0, w, s.wrap_u);
    let y0 = wrap_index(y0f, h, s.wrap_v);
    let y1 = wrap_index(y0f + 1.0, h, s.wrap_v);
    let top = fetch(x0, y0).lerp(fetch(x1, y0), tx);
    let bottom = fetch(x0, y1).lerp(fetch(x1, y1), tx);
    top.lerp(bottom, ty)
}

/// Folds a texture coordinate into [-1, 2) without changing what any wrap mode samples:
/// whole periods (1 for repeat, 2 for mirrored repeat) are removed; clamping only needs a
/// margin around [0, 1].
#[inline]
fn reduce(t: f32, wrap: Wrap) -> f32 {
    match wrap {
        Wrap::Repeat => t - t.floor(),
        Wrap::MirroredRepeat => t.rem_euclid(2.0),
        Wrap::ClampToEdge => t.clamp(-1.0, 2.0),
    }
}

/// Folds an integer texel coordinate (given as a float, possibly huge) into 0..n.
#[inline]
fn wrap_index(i: f32, n: u32, wrap: Wrap) -> u32 {
    let nf = n as f32;
    match wrap {
        Wrap::ClampToEdge => i.clamp(0.0, nf - 1.0) as u32,
        Wrap::Repeat => (i.rem_euclid(nf) as u32).min(n - 1),
        Wrap::MirroredRepeat => {
            let m = i.rem_euclid(2.0 * nf);
            let m = if m >= nf { 2.0 * nf - 1.0 - m } else { m };
            (m.max(0.0) as u32).min(n - 1)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trip() {
        for i in 0..=255 {
            let c = i as f32 / 255.0;
            assert!((linear_to_srgb(srgb_to_linear(c)) - c).abs() < 1e-5);
        }
    }

    #[test]
    fn wrap_modes() {
        assert_eq!(wrap_index(-1.0, 4, Wrap::Repeat), 3);
        assert_eq!(wrap_index(5.0, 4, Wrap::Repeat), 1);
        assert_eq!(wrap_index(-1.0, 4, Wrap::ClampToEdge), 0);
        assert_eq!(wrap_index(4.0, 4, Wrap::MirroredRepeat), 3);
        assert_eq!(wrap_index(-1.0, 4, Wrap::MirroredRepeat), 0);
        assert_eq!(wrap_index(1e30, 4, Wrap::Repeat), 0);
    }

    #[test]
    fn huge_uvs_sample_finite_colours() {
        let t = Texture::checker(256, 8, [255, 0, 0, 255], [0, 0, 255, 255]);
        for wrap in [Wrap::Repeat, Wrap::MirroredRepeat, Wrap::ClampToEdge] {
            for filter in [Filter::Nearest, Filter::Bilinear] {
                let s = Sampler {
                    wrap_u: wrap,
                    wrap_v: wrap,
                    filter,
                };
                for uv in [
                    Vec2::new(1.0, -1.7e38),
                    Vec2::new(3e38, 0.5),
                    Vec2::new(-1e20, 1e20),
                    Vec2::new(f32::NAN, 0.0),
                ] {
                    assert!(t.sample_with(uv, s).is_finite(), "{wrap:?} {filter:?} {uv}");
                }
            }
        }
        // Reduction keeps what a wrap mode samples.
        let s = Sampler {
            wrap_u: Wrap::Repeat,
            wrap_v: Wrap::Repeat,
            filter: Filter::Nearest,
        };
        assert_eq!(
            t.sample_with(Vec2::new(0.3, 0.7), s),
            t.sample_with(Vec2::new(5.3, -2.3), s)
        );
    }

    #[test]
    fn uvs_near_1e5_keep_their_texel() {
        // f32 spacing at 1e5 is 1/128, so a UV there is known to 1/256; a texel centre of a
        // 100-texel map (texels 1/100 wide) is still resolved. Nearest sampling at
        // u = 1e5 + centre must give the texel of the centre itself: folding the UV before
        // scaling keeps it (scaling first puts u * 100 = 1e7 where f32 spacing is 1).
        let n = 100;
        let texels: Vec<[u8; 4]> = (0..n * n)
            .map(|i| [(i % n) as u8, (i / n) as u8, 0, 255])
            .collect();
        let t = Texture::new("ramp", n, n, texels, false).unwrap();
        let mut tried = 0;
        for wrap in [Wrap::Repeat, Wrap::MirroredRepeat] {
            let s = Sampler {
                wrap_u: wrap,
                wrap_v: wrap,
                filter: Filter::Nearest,
            };
            for k in 0..n {
                let f = (k as f32 + 0.5) / n as f32;
                let near = t.sample_with(Vec2::new(f, f), s);
                // 1e5 is even, so mirrored repeat also maps it back onto [0, 1).
                let far = t.sample_with(Vec2::new(1e5 + f, 1e5 + f), s);
                assert_eq!(near, far, "{wrap:?} texel {k}");
                tried += 1;
            }
        }
        assert_eq!(tried, 200);
    }

    #[test]
    fn bilinear_between_texels() {
        let t = Texture::new("t", 2, 1, vec![[0, 0, 0, 255], [255, 255, 255, 255]], false).unwrap();
        let s = Sampler {
            wrap_u: Wrap::ClampToEdge,
            wrap_v: Wrap::ClampToEdge,
            filter: Filter::Bilinear,
        };
        let mid = t.sample_with(Vec2::new(0.5, 0.5), s);
        assert!((mid.x - 0.5).abs() < 1e-6, "{mid}");
    }

    /// Deterministic pseudo-random texels (splitmix64).
    fn noise(name: &str, w: u32, h: u32, srgb: bool, seed: u64) -> Texture {
        let mut state = seed;
        let mut next = move || {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            (z ^ (z >> 31)) as u8
        };
        let texels = (0..w * h)
            .map(|_| [next(), next(), next(), next()])
            .collect();
        Texture::new(name, w, h, texels, srgb).unwrap()
    }

    fn level_mean(t: &Texture, level: usize) -> glam::DVec4 {
        let (w, h) = t.level_size(level);
        let mut sum = glam::DVec4::ZERO;
        for y in 0..h {
            for x in 0..w {
                sum += t.fetch_level(level, x, y).as_dvec4();
            }
        }
        sum / f64::from(w * h)
    }

    #[test]
    fn every_mip_level_keeps_the_mean_in_linear_light() {
        let mut checked = 0;
        for (w, h) in [
            (64, 64),
            (37, 20),
            (20, 37),
            (1, 37),
            (37, 1),
            (5, 3),
            (2, 1),
        ] {
            for srgb in [true, false] {
                let t = noise("noise", w, h, srgb, u64::from(w * 1000 + h));
                let base = level_mean(&t, 0);
                let (mut lw, mut lh) = (w, h);
                for level in 1..t.levels() {
                    (lw, lh) = ((lw / 2).max(1), (lh / 2).max(1));
                    assert_eq!(t.level_size(level), (lw, lh), "{w}x{h} level {level}");
                    let m = level_mean(&t, level);
                    // 16-bit levels: a rounding of at most 2^-17 per level.
                    let err = (m - base).abs().max_element();
                    assert!(
                        err < 2e-5,
                        "{w}x{h} srgb {srgb} level {level}: {m} vs {base}"
                    );
                    checked += 1;
                }
                assert_eq!(t.level_size(t.levels() - 1), (1, 1), "{w}x{h}");
            }
        }
        assert_eq!(checked, 2 * (6 + 5 + 5 + 5 + 5 + 2 + 1));
    }

    #[test]
    fn odd_sizes_weigh_every_texel_by_its_area() {
        // 3 -> 1: the mean of the three texels (a 2-tap filter would drop one).
        let t = Texture::new(
            "t",
            3,
            1,
            vec![[0, 0, 0, 0], [30, 60, 90, 120], [255, 255, 255, 255]],
            false,
        )
        .unwrap();
        let want = Vec4::new(285.0, 315.0, 345.0, 375.0) / (3.0 * 255.0);
        let got = t.fetch_level(1, 0, 0);
        assert!((got - want).abs().max_element() < 1e-4, "{got} vs {want}");
        // 5 -> 2: weights (2, 2, 1) / 5 and (1, 2, 2) / 5.
        let v = [0u8, 50, 100, 150, 250];
        let t = Texture::new(
            "t",
            5,
            1,
            v.iter().map(|&c| [c, c, c, 255]).collect(),
            false,
        )
        .unwrap();
        let l = |x| t.fetch_level(1, x, 0).x * 255.0;
        assert!((l(0) - 40.0).abs() < 0.01, "{}", l(0));
        assert!((l(1) - 180.0).abs() < 0.01, "{}", l(1));
    }

    #[test]
    fn levels_are_filtered_in_linear_light() {
        // Black and white sRGB texels average to 0.5 in linear light (sRGB 188, not 128).
        let t = Texture::checker(2, 2, [0, 0, 0, 255], [255, 255, 255, 255]);
        let m = t.fetch_level(1, 0, 0);
        assert!(
            (m - Vec4::new(0.5, 0.5, 0.5, 1.0)).abs().max_element() < 1e-4,
            "{m}"
        );
        // sRGB 0 and 128: linear 0 and 0.2158, mean 0.1079 (averaging the codes would give
        // 0.0513 decoded, or 0.251 taken as linear).
        let t = Texture::checker(2, 2, [0, 0, 0, 255], [128, 128, 128, 255]);
        let want = srgb_to_linear(128.0 / 255.0) / 2.0;
        let m = t.fetch_level(1, 0, 0);
        assert!(
            (m.x - want).abs() < 1e-4 && (want - 0.1079).abs() < 1e-4,
            "{m}"
        );
        // Linear data is averaged as stored.
        let t = t.as_slot_wants(false).expect("re-labelled as linear"); // without a chain
        assert!((t.fetch_level(1, 0, 0).x - 64.0 / 255.0).abs() < 1e-4);
    }

    #[test]
    fn lod_is_log2_of_the_longer_derivative_in_texels() {
        let t = Texture::checker(64, 8, [0; 4], [255; 4]); // 7 levels
        let texel = 1.0 / 64.0;
        let lod = |dx: Vec2, dy: Vec2| t.lod(dx, dy);
        assert_eq!(
            lod(Vec2::new(2.0 * texel, 0.0), Vec2::new(0.0, 2.0 * texel)),
            1.0
        );
        assert_eq!(
            lod(Vec2::new(0.5 * texel, 0.0), Vec2::new(0.0, 4.0 * texel)),
            2.0
        );
        assert!((lod(Vec2::new(3.0 * texel, 4.0 * texel), Vec2::ZERO) - 5f32.log2()).abs() < 1e-6);
        // Magnification and zero derivatives: the base level; far minification: the last.
        assert_eq!(lod(Vec2::new(0.25 * texel, 0.0), Vec2::ZERO), 0.0);
        assert_eq!(lod(Vec2::ZERO, Vec2::ZERO), 0.0);
        assert_eq!(lod(Vec2::new(1e3, 0.0), Vec2::ZERO), 6.0);
        assert_eq!(lod(Vec2::new(f32::MAX, f32::MAX), Vec2::ZERO), 6.0);
        // Non-finite derivatives: the base level.
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            assert_eq!(lod(Vec2::new(bad, 0.0), Vec2::new(1.0, 1.0)), 0.0);
            assert_eq!(lod(Vec2::ZERO, Vec2::new(0.0, bad)), 0.0);
        }
        // Non-square: texels are counted per axis.
        let t = noise("wide", 256, 4, true, 1);
        assert_eq!(
            t.lod(Vec2::new(4.0 / 256.0, 0.0), Vec2::new(0.0, 1.0 / 4.0)),
            2.0
        );
    }

    #[test]
    fn integer_lod_reads_that_level_and_fractions_blend() {
        let t = noise("n", 40, 24, true, 7);
        let s = Sampler {
            wrap_u: Wrap::Repeat,
            wrap_v: Wrap::Repeat,
            filter: Filter::Trilinear,
        };
        for level in 0..t.levels() {
            let (w, h) = t.level_size(level);
            for (x, y) in [(0, 0), (w - 1, h - 1), (w / 2, h / 3)] {
                let uv = Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
                let got = t.sample_lod_with(uv, level as f32, s);
                let want = t.fetch_level(level, x, y);
                assert!(
                    (got - want).abs().max_element() < 1e-5,
                    "level {level} ({x}, {y})"
                );
            }
        }
        let uv = Vec2::new(0.3, 0.6);
        let (a, b) = (t.sample_lod_with(uv, 1.0, s), t.sample_lod_with(uv, 2.0, s));
        let mid = t.sample_lod_with(uv, 1.25, s);
        assert!((mid - a.lerp(b, 0.25)).abs().max_element() < 1e-6);
    }

    #[test]
    fn derivatives_change_only_trilinear() {
        let t = noise("n", 32, 32, true, 3);
        let (dx, dy) = (Vec2::new(0.3, 0.0), Vec2::new(0.0, 0.2));
        for filter in [Filter::Nearest, Filter::Bilinear] {
            let s = Sampler {
                filter,
                ..Sampler::default()
            };
            for uv in [Vec2::new(0.1, 0.7), Vec2::new(-3.3, 2.1)] {
                // Bit-identical to sampling without derivatives.
                assert_eq!(t.sample_grad_with(uv, dx, dy, s), t.sample_with(uv, s));
            }
        }
        let tri = Sampler::default();
        let bi = Sampler {
            filter: Filter::Bilinear,
            ..tri
        };
        assert_eq!(tri.filter, Filter::Trilinear, "the default");
        let uv = Vec2::new(0.37, 0.61);
        // Magnified: exactly the bilinear sample.
        let small = Vec2::new(0.5 / 32.0, 0.0);
        assert_eq!(
            t.sample_grad_with(uv, small, small.perp(), tri),
            t.sample_with(uv, bi)
        );
        assert_eq!(t.sample_with(uv, tri), t.sample_with(uv, bi));
        // Minified: not the bilinear sample of the noise.
        assert_ne!(t.sample_grad_with(uv, dx, dy, tri), t.sample_with(uv, bi));
    }

    #[test]
    fn no_nan_from_degenerate_derivatives_or_uvs() {
        let specials = [
            0.0,
            -0.0,
            1e-30,
            1.0,
            -7.5,
            1e30,
            -1e30,
            f32::MAX,
            f32::MIN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
        ];
        let mut tried = 0;
        for (w, h) in [(1, 1), (1, 9), (9, 1), (16, 16)] {
            let t = noise("n", w, h, true, 11);
            for wrap in [Wrap::Repeat, Wrap::MirroredRepeat, Wrap::ClampToEdge] {
                let s = Sampler {
                    wrap_u: wrap,
                    wrap_v: wrap,
                    filter: Filter::Trilinear,
                };
                for &a in &specials {
                    for &b in &specials {
                        let d = Vec2::new(a, b);
                        for uv in [Vec2::new(0.4, 0.6), Vec2::new(b, a), Vec2::new(a, 0.5)] {
                            let c = t.sample_grad_with(uv, d, d.perp(), s);
                            assert!(c.is_finite(), "{w}x{h} {wrap:?} uv {uv} d {d}: {c}");
                            for n in [2, 16] {
                                let an = Sampler {
                                    filter: Filter::Anisotropic(n),
                                    ..s
                                };
                                for e in [d.perp(), Vec2::new(b, 0.01)] {
                                    let c = t.sample_grad_with(uv, d, e, an);
                                    assert!(c.is_finite(), "aniso {n} uv {uv} d {d} {e}: {c}");
                                    let taps = t.aniso(d, e, n).taps;
                                    assert!((1..=u32::from(n)).contains(&taps));
                                }
                            }
                            let lod = t.lod(d, Vec2::new(b, 0.1));
                            assert!((0.0..=(t.levels() - 1) as f32).contains(&lod));
                            tried += 1;
                        }
                    }
                }
                for lod in specials {
                    assert!(t.sample_lod_with(Vec2::new(0.2, 0.9), lod, s).is_finite());
                }
            }
        }
        assert_eq!(tried, 4 * 3 * 12 * 12 * 3);
    }

    #[test]
    fn filter_names_parse_and_round_trip() {
        for f in Filter::COMMON {
            assert_eq!(f.name().parse::<Filter>(), Ok(f));
            assert_eq!(f.to_string(), f.name());
        }
        for n in MIN_ANISO..=MAX_ANISO {
            let f = Filter::Anisotropic(n);
            assert_eq!(f.name(), format!("aniso:{n}"));
            assert_eq!(f.name().parse::<Filter>(), Ok(f));
        }
        assert_eq!(" Aniso:08 ".parse::<Filter>(), Ok(Filter::Anisotropic(8)));
        assert_eq!("TRILINEAR".parse::<Filter>(), Ok(Filter::Trilinear));
        // Out-of-range ratios are named (and sampled) clamped.
        assert_eq!(Filter::Anisotropic(0).name(), "aniso:2");
        assert_eq!(Filter::Anisotropic(200).name(), "aniso:16");
        for bad in [
            "",
            "aniso",
            "aniso:",
            "aniso:1",
            "aniso:17",
            "aniso:+4",
            "aniso:-4",
            "aniso:4x",
            "aniso:256",
            "aniso:999",
            "aniso4",
            "linear",
            "tri",
            "aniso:٣",
        ] {
            let e = bad.parse::<Filter>().expect_err(bad).to_string();
            for form in ["nearest", "bilinear", "trilinear", "aniso:N", "2", "16"] {
                assert!(e.contains(form), "{bad}: {e}");
            }
        }
    }

    fn aniso_sampler(n: u8) -> Sampler {
        Sampler {
            filter: Filter::Anisotropic(n),
            ..Sampler::default()
        }
    }

    #[test]
    fn aniso_taps_follow_the_footprint() {
        let t = noise("n", 64, 64, true, 9); // 7 levels
        let texel = 1.0 / 64.0;
        let taps = |dx: Vec2, dy: Vec2, max| {
            let a = t.aniso(dx * texel, dy * texel, max);
            (a.taps, a.lod)
        };
        // 8 x 1 texels: 8 taps at the base level; along y, the same.
        assert_eq!(taps(Vec2::new(8.0, 0.0), Vec2::new(0.0, 1.0), 16), (8, 0.0));
        assert_eq!(taps(Vec2::new(0.0, 1.0), Vec2::new(0.0, 8.0), 16), (8, 0.0));
        // 64 x 2: ratio 32 capped at 16 taps, each covering 4 texels: lod 2.
        assert_eq!(
            taps(Vec2::new(64.0, 0.0), Vec2::new(0.0, 2.0), 16),
            (16, 2.0)
        );
        assert_eq!(taps(Vec2::new(64.0, 0.0), Vec2::new(0.0, 2.0), 4), (4, 4.0));
        // Ratio 2.5 -> 3 taps; lod log2(10 / 3).
        let (n, lod) = taps(Vec2::new(0.0, 4.0), Vec2::new(10.0, 0.0), 16);
        assert_eq!(n, 3);
        assert!((lod - (10f32 / 3.0).log2()).abs() < 1e-6);
        // A thinner-than-a-texel minor axis counts as one texel.
        assert_eq!(
            taps(Vec2::new(6.0, 0.0), Vec2::ZERO, 16),
            (6, (6f32 / 6.0).log2())
        );
        // Out-of-range ratios clamp: 0 and 1 mean 2, 200 means 16.
        assert_eq!(taps(Vec2::new(64.0, 0.0), Vec2::ZERO, 0).0, 2);
        assert_eq!(taps(Vec2::new(64.0, 0.0), Vec2::ZERO, 1).0, 2);
        assert_eq!(taps(Vec2::new(64.0, 0.0), Vec2::ZERO, 200).0, 16);
        // Isotropic, magnified, zero or non-finite: one tap.
        for (dx, dy) in [
            (Vec2::new(4.0, 0.0), Vec2::new(0.0, 4.0)),
            (Vec2::new(3.0, 4.0), Vec2::new(-4.0, 3.0)),
            (Vec2::new(0.9, 0.0), Vec2::ZERO),
            (Vec2::ZERO, Vec2::ZERO),
            (Vec2::new(f32::NAN, 0.0), Vec2::new(0.0, 1e3)),
            (Vec2::new(f32::INFINITY, 0.0), Vec2::ZERO),
        ] {
            assert_eq!(taps(dx, dy, 16).0, 1, "{dx} {dy}");
        }
        // Derivatives whose length overflows: 16 taps on the last level.
        let a = t.aniso(Vec2::new(f32::MAX, f32::MAX), Vec2::ZERO, 16);
        assert_eq!((a.taps, a.lod), (16, 6.0));
        let a = t.aniso(Vec2::splat(f32::MAX), Vec2::splat(-f32::MAX), 16);
        assert_eq!((a.taps, a.lod), (16, 6.0));
    }

    #[test]
    fn one_tap_aniso_is_exactly_trilinear() {
        let t = noise("n", 40, 24, true, 4);
        let texel = Vec2::new(1.0 / 40.0, 1.0 / 24.0);
        let mut checked = 0;
        for wrap in [Wrap::Repeat, Wrap::MirroredRepeat, Wrap::ClampToEdge] {
            for (dx, dy) in [
                (Vec2::new(0.5, 0.0), Vec2::new(0.0, 0.3)),
                (Vec2::new(3.0, 0.0), Vec2::new(0.0, 3.0)),
                (Vec2::new(5.0, 1.0), Vec2::new(-1.0, 5.0)),
                (Vec2::ZERO, Vec2::ZERO),
                (Vec2::new(f32::NAN, 1.0), Vec2::new(1.0, 0.0)),
            ] {
                let (dx, dy) = (dx * texel, dy * texel);
                for uv in [Vec2::new(0.31, 0.77), Vec2::new(-2.2, 5.01)] {
                    let tri = Sampler {
                        wrap_u: wrap,
                        wrap_v: wrap,
                        filter: Filter::Trilinear,
                    };
                    for n in [2, 16] {
                        let an = Sampler {
                            filter: Filter::Anisotropic(n),
                            ..tri
                        };
                        assert_eq!(
                            t.sample_grad_with(uv, dx, dy, an),
                            t.sample_grad_with(uv, dx, dy, tri),
                            "{wrap:?} {dx} {dy} {uv}"
                        );
                        checked += 1;
                    }
                }
                // Without derivatives: the base level, as trilinear.
                let uv = Vec2::new(0.4, 0.1);
                assert_eq!(
                    t.sample_with(uv, aniso_sampler(8)),
                    t.sample_with(uv, Sampler::default())
                );
            }
        }
        assert_eq!(checked, 3 * 5 * 2 * 2);
    }

    #[test]
    fn aniso_averages_along_the_long_axis_and_keeps_the_short_one_sharp() {
        // Linear texels: green alternates per column (mean 0.5), red is a ramp down the
        // rows (smooth along v). A footprint 8 texels along u and 1 along v: anisotropic
        // filtering averages green to its mean and reads red as sharp as bilinear does;
        // trilinear (level 3) blurs red across 8 rows.
        let (w, h) = (64u32, 64u32);
        let texels = (0..w * h)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                let g = if x % 2 == 0 { 0 } else { 255 };
                let r = ((y % 32) * 8) as u8;
                [r, g, 0, 255]
            })
            .collect();
        let t = Texture::new("stripes", w, h, texels, false).unwrap();
        let (dx, dy) = (Vec2::new(8.0 / 64.0, 0.0), Vec2::new(0.0, 1.0 / 64.0));
        let bi = Sampler {
            filter: Filter::Bilinear,
            ..Sampler::default()
        };
        let (mut tri_err, mut checked) = (0f32, 0);
        for k in 0..32 {
            // Rows 4..28 of the ramp (away from its wrap from 248 to 0).
            let uv = Vec2::new(0.37 + 0.011 * k as f32, (4.5 + 0.77 * k as f32) / 64.0);
            let a = t.sample_grad_with(uv, dx, dy, aniso_sampler(16));
            let sharp = t.sample_with(uv, bi);
            assert!((a.y - 0.5).abs() < 1e-5, "{uv}: green {a}");
            assert!((a.x - sharp.x).abs() < 1e-5, "{uv}: red {a} vs {sharp}");
            let tri = t.sample_grad_with(uv, dx, dy, Sampler::default());
            assert!((tri.y - 0.5).abs() < 1e-3, "{uv}: trilinear green {tri}");
            tri_err = tri_err.max((tri.x - sharp.x).abs());
            checked += 1;
        }
        assert_eq!(checked, 32);
        // Level 3 averages 8 rows of the ramp: off by at least a step somewhere.
        assert!(tri_err > 0.02, "{tri_err}");
    }

    #[test]
    fn clones_rebuild_and_prepared_chains_match_lazy_ones() {
        let t = noise("n", 37, 20, true, 5);
        let lazy = t.fetch_level(2, 3, 1);
        let u = t.clone();
        assert_eq!(u, t, "the chain takes no part in equality");
        assert!(format!("{u:?}").contains("MipCache(not built)"));
        u.prepare_mips();
        assert_eq!(
            u.fetch_level(2, 3, 1),
            lazy,
            "parallel and serial builds agree"
        );
        for level in 1..t.levels() {
            let (w, h) = t.level_size(level);
            for y in 0..h {
                for x in 0..w {
                    assert_eq!(u.fetch_level(level, x, y), t.fetch_level(level, x, y));
                }
            }
        }
    }
}
