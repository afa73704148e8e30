//! Reading a texture: texel fetch, wrapping, bilinear and trilinear filtering through the mip chain, anisotropic taps along the footprint's major axis.

use super::*;

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
        let lod = libm::log2f(major / taps as f32).clamp(0.0, top);
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
        (0.5 * libm::log2f(rho2)).clamp(0.0, (self.levels() - 1) as f32)
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
    pub(super) fn mips(&self) -> &mip::Chain {
        self.mips.0.get_or_init(|| self.build_mips(false))
    }

    pub(super) fn build_mips(&self, parallel: bool) -> mip::Chain {
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
    pub(super) fn bilinear_level(&self, level: usize, uv: Vec2, s: Sampler) -> Vec4 {
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
pub(super) fn aniso_taps(major: f32, minor: f32, max: u8) -> u32 {
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
pub(super) fn fold(uv: Vec2, s: Sampler) -> Vec2 {
    let uv = if uv.is_finite() { uv } else { Vec2::ZERO };
    // Fold the coordinates into a small range first: scaling a huge UV by the texture
    // size would overflow to infinity and turn the filter weights into NaN.
    Vec2::new(reduce(uv.x, s.wrap_u), reduce(uv.y, s.wrap_v))
}

/// Bilinear filter of a `w` x `h` image read by `fetch`, at a folded `uv`.
#[inline(always)]
pub(super) fn bilinear(
    uv: Vec2,
    w: u32,
    h: u32,
    s: Sampler,
    fetch: impl Fn(u32, u32) -> Vec4,
) -> Vec4 {
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
pub(super) fn reduce(t: f32, wrap: Wrap) -> f32 {
    match wrap {
        Wrap::Repeat => t - t.floor(),
        Wrap::MirroredRepeat => t.rem_euclid(2.0),
        Wrap::ClampToEdge => t.clamp(-1.0, 2.0),
    }
}

/// Folds an integer texel coordinate (given as a float, possibly huge) into 0..n.
#[inline]
pub(super) fn wrap_index(i: f32, n: u32, wrap: Wrap) -> u32 {
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
