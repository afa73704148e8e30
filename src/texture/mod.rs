//! Decoded images and their samplers.
//!
//! Texels are stored as 8-bit RGBA exactly as decoded (4 bytes a texel); colour textures are
//! sRGB-encoded and decoded to linear light through a 256-entry table at sampling time, so
//! filtering happens in linear light. UV convention: glTF's, origin at the top-left texel
//! corner, u to the right, v downwards (OBJ loaders flip v on the way in).

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
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Filter {
    Nearest,
    #[default]
    Bilinear,
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

/// An RGBA8 image.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    pub name: String,
    pub width: u32,
    pub height: u32,
    /// Row-major, top row first.
    pub texels: Vec<[u8; 4]>,
    /// True if RGB is sRGB-encoded (colour data); false for linear data (normals, masks).
    pub srgb: bool,
    pub sampler: Sampler,
}

/// Why an image could not become a [`Texture`].
#[derive(Debug, thiserror::Error)]
pub enum TextureError {
    #[error("image has zero width or height")]
    Empty,
    #[error("texel count {got} does not match {width}x{height}")]
    Size { width: u32, height: u32, got: usize },
}

/// sRGB-encoded byte -> linear light, exact piecewise sRGB transfer.
fn srgb_table() -> &'static [f32; 256] {
    static TABLE: std::sync::OnceLock<[f32; 256]> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| std::array::from_fn(|i| srgb_to_linear(i as f32 / 255.0)))
}

/// Exact sRGB decoding (IEC 61966-2-1).
#[must_use]
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Exact sRGB encoding (IEC 61966-2-1).
#[must_use]
pub fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

impl Texture {
    /// A texture from RGBA8 texels (row-major, top row first).
    pub fn new(
        name: impl Into<String>,
        width: u32,
        height: u32,
        texels: Vec<[u8; 4]>,
        srgb: bool,
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
            srgb,
            sampler: Sampler::default(),
        })
    }

    /// A procedural chequerboard of `n` x `n` squares, `size` texels square (function texture
    /// of seed 000 §9.5). `size` is clamped to 1..=[`MAX_CHECKER`], `n` to 1..=`size`.
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
            texels,
            srgb: true,
            sampler: Sampler::default(),
        }
    }

    /// Texel (x, y) in linear light (RGB decoded from sRGB when `srgb`; alpha is linear).
    #[must_use]
    #[inline]
    pub fn fetch(&self, x: u32, y: u32) -> Vec4 {
        let t = self.texels[(y * self.width + x) as usize];
        if self.srgb {
            let tab = srgb_table();
            Vec4::new(
                tab[t[0] as usize],
                tab[t[1] as usize],
                tab[t[2] as usize],
                f32::from(t[3]) / 255.0,
            )
        } else {
            Vec4::new(
                f32::from(t[0]),
                f32::from(t[1]),
                f32::from(t[2]),
                f32::from(t[3]),
            ) / 255.0
        }
    }

    /// Samples at `uv` with the texture's own sampler. Non-finite UVs read texel (0, 0).
    #[must_use]
    pub fn sample(&self, uv: Vec2) -> Vec4 {
        self.sample_with(uv, self.sampler)
    }

    /// Samples at `uv` (texel centres at half-integers times the texel size).
    #[must_use]
    pub fn sample_with(&self, uv: Vec2, s: Sampler) -> Vec4 {
        let (w, h) = (self.width, self.height);
        let uv = if uv.is_finite() { uv } else { Vec2::ZERO };
        // Fold the coordinates into a small range first: scaling a huge UV by the texture
        // size would overflow to infinity and turn the filter weights into NaN.
        let uv = Vec2::new(reduce(uv.x, s.wrap_u), reduce(uv.y, s.wrap_v));
        match s.filter {
            Filter::Nearest => {
                let x = wrap_index((uv.x * w as f32).floor(), w, s.wrap_u);
                let y = wrap_index((uv.y * h as f32).floor(), h, s.wrap_v);
                self.fetch(x, y)
            }
            Filter::Bilinear => {
                let fx = uv.x * w as f32 - 0.5;
                let fy = uv.y * h as f32 - 0.5;
                let (x0f, y0f) = (fx.floor(), fy.floor());
                let (tx, ty) = (fx - x0f, fy - y0f);
                let x0 = wrap_index(x0f, w, s.wrap_u);
                let x1 = wrap_index(x0f + 1.0, w, s.wrap_u);
                let y0 = wrap_index(y0f, h, s.wrap_v);
                let y1 = wrap_index(y0f + 1.0, h, s.wrap_v);
                let top = self.fetch(x0, y0).lerp(self.fetch(x1, y0), tx);
                let bottom = self.fetch(x0, y1).lerp(self.fetch(x1, y1), tx);
                top.lerp(bottom, ty)
            }
        }
    }
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
}
