//! The prefiltered environment: the GGX specular chain, the SH irradiance coefficients and
//! the full-resolution source.
//!
//! The chain has [`SPECULAR_LEVELS`] equirect levels; level k holds, for every direction R,
//! `Σ Lenv(L)·NL / Σ NL` over GGX samples with N = V = R and perceptual roughness
//! `r_k = k/(SPECULAR_LEVELS-1)` (Sample Viewer's `ibl_filtering.frag`). Level 0 (r = 0) is
//! the source box-resampled to the base size (at most [`BASE_WIDTH`]×[`BASE_HEIGHT`], the
//! source's own if smaller, aspect kept); level k is the base halved `LEVEL_SHIFT[k]` times:
//! 256, 256, 128, 64, 64, 32, 32 texels wide for a large source, because a rougher lobe needs
//! fewer texels. Samples a texel: 64 at r = 1/6, 128 at r = 1/3, 256 above (`LEVEL_SAMPLES`),
//! from the Hammersley set, one frame per texel (glam's `any_orthonormal_pair`).
//!
//! Filtered importance sampling (Colbert & Křivánek, GPU Gems 3 ch. 20): every sample reads a
//! box-filtered pyramid of the full-resolution source (`resample.rs`) trilinearly at
//! `lod = ½·log2(Ωs/Ωp)`, `Ωs = 1/(n·pdf)`, `pdf = D/4` (N = V), `Ωp = (2π/W)(π/H)·sinθ` the
//! solid angle of a source texel at the sample's latitude, so each sample averages about the
//! solid angle it stands for and a small bright sun spreads instead of making fireflies. No
//! bias is added to the lod (Sample Viewer's cube-map formula omits 4π and is ~1.8 levels
//! blurrier; Babylon.js adds +1).
//!
//! Cost (2 cores, release): a 2048×1024 source prefilters in about 0.15 s (chain ~0.1 s,
//! pyramid, SH projection and content hash the rest); a 512×256 built-in in ~0.1 s.
//! Determinism: every output texel is a fixed sequential sum, rows are independent, so the
//! result is bit-identical for any number of threads.

use std::path::Path;

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::cache::{content_key, Cached, EnvCache};
use super::equirect::{dir_to_uv, dir_to_uv_f64, texel_dir, EnvImage, Plane};
use super::resample::{resample, Pyramid};
use super::{ggx, sh};

/// Levels in the specular chain; level k is for perceptual roughness `k/(SPECULAR_LEVELS-1)`.
pub const SPECULAR_LEVELS: usize = 7;
/// Bumped whenever the prefiltered data would change for the same source (it is part of the
/// cache key and of the disk format).
pub const PREFILTER_VERSION: u32 = 1;
/// Largest level-0 width, in texels.
pub(super) const BASE_WIDTH: usize = 256;
/// Largest level-0 height, in texels.
pub(super) const BASE_HEIGHT: usize = 128;
/// Halvings of the base size per level.
pub(super) const LEVEL_SHIFT: [u32; SPECULAR_LEVELS] = [0, 0, 1, 2, 2, 3, 3];
/// GGX samples per texel per level (level 0 is not sampled).
pub(super) const LEVEL_SAMPLES: [u32; SPECULAR_LEVELS] = [0, 128, 256, 512, 1024, 2048, 2048];

/// The (width, height) of every chain level for a `width×height` source.
pub(super) fn level_dims(width: usize, height: usize) -> [(usize, usize); SPECULAR_LEVELS] {
    let scale = 1f64
        .min(BASE_WIDTH as f64 / width as f64)
        .min(BASE_HEIGHT as f64 / height as f64);
    let side = |s: usize| ((s as f64 * scale).round() as usize).clamp(1, s);
    let (bw, bh) = (side(width), side(height));
    LEVEL_SHIFT.map(|s| ((bw >> s).max(1), (bh >> s).max(1)))
}

/// An environment ready for lighting (module docs). `Send + Sync`; share it in an `Arc`.
#[derive(Clone, PartialEq)]
pub struct Prefiltered {
    name: String,
    key: u64,
    source: Plane,
    levels: Vec<Plane>,
    sh: [Vec3; 9],
}

impl std::fmt::Debug for Prefiltered {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Prefiltered")
            .field("name", &self.name)
            .field("key", &format_args!("{:016x}", self.key))
            .field("source", &(self.source.width, self.source.height))
            .field("levels", &self.levels.len())
            .finish_non_exhaustive()
    }
}

/// One GGX sample of a level in the frame N = V = +Z.
struct LobeSample {
    l: Vec3,
    nl: f32,
    /// `½·log2(Ωs/Ωp0)`, Ωp0 the source texel's solid angle at the equator.
    lod_bias: f32,
}

/// The samples of roughness `r` (those with NL > 0) and the sum of their NL.
fn lobe(r: f64, n: u32, omega_p0: f64) -> (Vec<LobeSample>, f32) {
    let alpha = ggx::alpha(r);
    let mut samples = Vec::with_capacity(n as usize);
    let mut weight = 0.0;
    for i in 0..n {
        let h = ggx::sample_h(ggx::hammersley(i, n), alpha);
        let l = 2.0 * h.z * h - DVec3::Z;
        if l.z <= 0.0 {
            continue;
        }
        let pdf = ggx::d(h.z, alpha) / 4.0;
        let omega_s = 1.0 / (f64::from(n) * pdf);
        samples.push(LobeSample {
            l: l.as_vec3(),
            nl: l.z as f32,
            lod_bias: (0.5 * (omega_s / omega_p0).log2()) as f32,
        });
        weight += l.z;
    }
    (samples, weight as f32)
}

/// One level of the chain: the lobe of roughness `r` around every texel direction.
///
/// All texels of a row see the same lobe turned about +Y, which only shifts u: the taps
/// (u, v, lod, weight) are computed once a row, for texel 0 in the frame
/// `any_orthonormal_pair` gives its direction, and texel x reads them at `u + x/w`.
fn filter_level(pyramid: &Pyramid, omega_p0: f64, r: f64, n: u32, dims: (usize, usize)) -> Plane {
    let (w, h) = dims;
    let (samples, weight) = lobe(r, n, omega_p0);
    let inv = if weight > 0.0 { 1.0 / weight } else { 0.0 };
    let mut rgb = vec![0.0f32; 3 * w * h];
    rgb.par_chunks_mut(3 * w).enumerate().for_each(|(y, row)| {
        let n0 = texel_dir(0, y, w, h);
        let (t, b) = n0.any_orthonormal_pair();
        let mut taps = Vec::with_capacity(2 * samples.len());
        for s in &samples {
            let l = t * s.l.x + b * s.l.y + n0 * s.l.z;
            // Ωp = Ωp0·sinθ: ½·log2(1/sinθ) = -¼·log2(1 - y²).
            let lod = s.lod_bias - 0.25 * (1.0 - l.y * l.y).max(1e-12).log2();
            pyramid.push_taps(dir_to_uv(l), lod, s.nl * inv, &mut taps);
        }
        for (x, out) in row.chunks_exact_mut(3).enumerate() {
            let sum = Pyramid::sum_taps(&taps, x as f32 / w as f32);
            out.copy_from_slice(&sum.to_array());
        }
    });
    Plane {
        width: w,
        height: h,
        rgb,
    }
}

impl Prefiltered {
    /// Prefilters `image` (no cache; see [`Prefiltered::build_cached`]).
    #[must_use]
    pub fn build(image: EnvImage) -> Self {
        let key = content_key(&image);
        Self::build_keyed(image, key)
    }

    /// Prefilters `image` whose [`content_key`] is `key`.
    pub(super) fn build_keyed(image: EnvImage, key: u64) -> Self {
        let src = &image.plane;
        let dims = level_dims(src.width, src.height);
        let (levels, coeffs) = rayon::join(
            || {
                let pyramid = Pyramid::new(src);
                let omega_p0 = (2.0 * std::f64::consts::PI / src.width as f64)
                    * (std::f64::consts::PI / src.height as f64);
                let last = (SPECULAR_LEVELS - 1) as f64;
                let mut levels = vec![resample(src, dims[0].0, dims[0].1)];
                for k in 1..SPECULAR_LEVELS {
                    let r = k as f64 / last;
                    levels.push(filter_level(
                        &pyramid,
                        omega_p0,
                        r,
                        LEVEL_SAMPLES[k],
                        dims[k],
                    ));
                }
                levels
            },
            || sh::project(src),
        );
        Self::from_parts(image, key, levels, coeffs.map(|c| c.as_vec3()))
    }

    /// Assembles a prefiltered environment (levels checked by the caller against
    /// [`level_dims`]).
    pub(super) fn from_parts(image: EnvImage, key: u64, levels: Vec<Plane>, sh: [Vec3; 9]) -> Self {
        Self {
            name: image.name().to_owned(),
            key,
            source: image.plane,
            levels,
            sh,
        }
    }

    /// Prefilters `image`, or returns the environment already built from the same texels
    /// (the process-wide [`EnvCache::global`], then `disk` if given; see [`EnvCache`]).
    #[must_use]
    pub fn build_cached(image: EnvImage, disk: Option<&Path>) -> Cached {
        EnvCache::global().get_or_build(image, disk)
    }

    /// The name of the image it was built from (the first one, if built from a cache).
    #[must_use]
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The [`content_key`] of the source.
    #[must_use]
    pub fn key(&self) -> u64 {
        self.key
    }

    /// The source's (width, height) in texels.
    #[must_use]
    pub fn source_size(&self) -> (u32, u32) {
        (self.source.width as u32, self.source.height as u32)
    }

    /// Levels in the specular chain ([`SPECULAR_LEVELS`]).
    #[must_use]
    pub fn levels(&self) -> usize {
        self.levels.len()
    }

    /// (width, height) of chain level `k`, if there is one.
    #[must_use]
    pub fn level_size(&self, k: usize) -> Option<(u32, u32)> {
        self.levels
            .get(k)
            .map(|p| (p.width as u32, p.height as u32))
    }

    /// The nine SH radiance coefficients `L_lm` (order: L00, L1-1 (y), L10 (z), L11 (x),
    /// L2-2 (xy), L2-1 (yz), L20 (3z²-1), L21 (xz), L22 (x²-y²); image axes, +Y up).
    #[must_use]
    pub fn sh(&self) -> &[Vec3; 9] {
        &self.sh
    }

    pub(super) fn level_planes(&self) -> &[Plane] {
        &self.levels
    }

    /// Bytes held (source plus chain).
    #[must_use]
    pub fn bytes(&self) -> usize {
        self.source.bytes() + self.levels.iter().map(Plane::bytes).sum::<usize>()
    }

    /// Prefiltered radiance around `dir` (any length) for perceptual roughness `r` (clamped
    /// to [0, 1]; NaN reads 0): bilinear in levels `⌊r·(M-1)⌋` and the next, linear between.
    #[must_use]
    pub fn specular(&self, dir: Vec3, r: f32) -> Vec3 {
        let (u, v) = dir_to_uv(dir.normalize_or_zero());
        let last = self.levels.len() - 1;
        let f = if r.is_nan() {
            0.0
        } else {
            r.clamp(0.0, 1.0) * last as f32
        };
        let k = (f as usize).min(last.saturating_sub(1));
        let t = f - k as f32;
        let a = self.levels[k].bilinear(u, v);
        if t <= 0.0 || k + 1 > last {
            return a;
        }
        a.lerp(self.levels[k + 1].bilinear(u, v), t)
    }

    /// Irradiance `E(n) = ∫ L(ω) max(n·ω, 0) dω` from the SH coefficients (uniform radiance c
    /// gives π·c; never negative). `n` need not be unit length.
    #[must_use]
    pub fn irradiance(&self, n: Vec3) -> Vec3 {
        sh::irradiance(&self.sh, n)
    }

    /// What a camera ray in direction `dir` sees: the full-resolution source (bilinear) at
    /// `blur <= 0` (or NaN), else [`Prefiltered::specular`] at roughness `blur`.
    #[must_use]
    pub fn background(&self, dir: Vec3, blur: f32) -> Vec3 {
        if blur > 0.0 {
            return self.specular(dir, blur);
        }
        let (u, v) = dir_to_uv(dir.normalize_or_zero());
        self.source.bilinear(u, v)
    }

    /// Radiance from `dir` (any length) in f64, bilinear on the full-resolution source.
    #[must_use]
    pub fn radiance_f64(&self, dir: DVec3) -> DVec3 {
        let (u, v) = dir_to_uv_f64(dir.normalize_or_zero());
        self.source.bilinear_f64(u, v)
    }
}
