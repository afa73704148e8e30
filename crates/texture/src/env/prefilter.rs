//! The prefiltered environment: the GGX specular chain, the SH irradiance coefficients and
//! the full-resolution source.
//!
//! The chain (`chain.rs`) is read bilinearly in the two levels around `r·(M-1)`, linearly
//! between them (Sample Viewer's mip selection).
//!
//! Cost (release, 2 cores shared with other builds): a 2048×1024 source prefilters in about
//! 250 ms; a 512×256 built-in in about 200 ms (measured by the ignored test
//! `prefilter_timing`).

use std::path::Path;

use glam::{DVec3, Vec3};
use realist_simd::{Level, F8, LANES};

use super::cache::{content_key, Cached, EnvCache};
use super::equirect::{dir_to_uv, dir_to_uv_f64, EnvImage, Plane};
use super::{chain, sh};

/// Bumped whenever the prefiltered data would change for the same source (it is part of the
/// cache key and of the disk format).
pub const PREFILTER_VERSION: u32 = 3;

/// An environment ready for lighting (module docs). `Send + Sync`; share it in an `Arc`.
#[derive(Clone, PartialEq)]
pub struct Prefiltered {
    name: String,
    key: u64,
    source: Plane,
    levels: Vec<Plane>,
    /// The sheen chain (`chain::SHEEN_LEVELS`).
    sheen: Vec<Plane>,
    sh: [Vec3; 9],
    /// Importance sampling of the source, made on first use.
    sampler: Lazy,
}

/// The sampler, built once; two environments compare equal whether or not it was built.
#[derive(Clone, Default)]
struct Lazy(std::sync::OnceLock<super::sample::EnvSampler>);

impl PartialEq for Lazy {
    fn eq(&self, _: &Self) -> bool {
        true
    }
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
        let (levels, coeffs) = rayon::join(|| chain::build(src), || sh::project(src));
        Self::from_parts(image, key, levels, coeffs.map(|c| c.as_vec3()))
    }

    /// Assembles a prefiltered environment from every level (the specular chain's, then the
    /// sheen chain's, checked by the caller against `chain::all_dims`).
    pub(super) fn from_parts(
        image: EnvImage,
        key: u64,
        mut levels: Vec<Plane>,
        sh: [Vec3; 9],
    ) -> Self {
        let sheen = levels.split_off(chain::SPECULAR_LEVELS.min(levels.len()));
        Self {
            name: image.name().to_owned(),
            key,
            source: image.plane,
            levels,
            sheen,
            sh,
            sampler: Lazy::default(),
        }
    }

    /// The importance sampler of the full-resolution source (built on first use).
    #[must_use]
    pub fn sampler(&self) -> &super::sample::EnvSampler {
        self.sampler
            .0
            .get_or_init(|| super::sample::EnvSampler::new(&self.source))
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

    /// Levels in the specular chain ([`chain::SPECULAR_LEVELS`]).
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

    /// Every stored level: the specular chain's, then the sheen chain's.
    pub(super) fn level_planes(&self) -> impl Iterator<Item = &Plane> {
        self.levels.iter().chain(&self.sheen)
    }

    /// Bytes held (source plus chain).
    #[must_use]
    pub fn bytes(&self) -> usize {
        self.source.bytes() + self.level_planes().map(Plane::bytes).sum::<usize>()
    }

    /// Prefiltered radiance around `dir` (any length) for perceptual roughness `r` (clamped
    /// to [0, 1]; NaN reads 0): bilinear in levels `⌊r·(M-1)⌋` and the next, linear between.
    #[must_use]
    pub fn specular(&self, dir: Vec3, r: f32) -> Vec3 {
        let (u, v) = dir_to_uv(dir.normalize_or_zero());
        self.specular_uv(u, v, r)
    }

    /// [`Self::specular`] at image coordinates `(u, v)` (for callers that compute them
    /// themselves, eight at a time).
    #[must_use]
    #[inline(always)]
    pub fn specular_uv(&self, u: f32, v: f32, r: f32) -> Vec3 {
        read_chain(&self.levels, u, v, r)
    }

    /// Irradiance `E(n) = ∫ L(ω) max(n·ω, 0) dω` (uniform radiance c gives π·c; never
    /// negative). `n` need not be unit length.
    ///
    /// Read from the chain's last level, π times: at roughness 1 (α = 1) GGX's `D` is the
    /// constant 1/π, so that level's `∫ L·NL·D dω / ∫ NL·D dω` is exactly `E/π`, summed
    /// directly over the image (`chain.rs`). Nine SH coefficients ([`Self::irradiance_sh`])
    /// were 6.6 % (studio) and 13.6 % (sky) off at their worst normal, and made the sphere
    /// grid under a smooth HDR environment 3 % too bright against the f64 reference.
    #[must_use]
    pub fn irradiance(&self, n: Vec3) -> Vec3 {
        let (u, v) = dir_to_uv(n.normalize_or_zero());
        match self.levels.last() {
            Some(level) => level.bilinear(u, v) * std::f32::consts::PI,
            None => sh::irradiance(&self.sh, n),
        }
    }

    /// The radiance averaged over the sheen lobe of roughness `r` around the normal whose
    /// image coordinates are `(u, v)` (the sheen chain, bilinear in the two levels around
    /// `r·(SHEEN_LEVELS-1)`, linear between; NaN reads level 0).
    #[must_use]
    #[inline(always)]
    pub fn sheen_uv(&self, u: f32, v: f32, r: f32) -> Vec3 {
        if self.sheen.is_empty() {
            return self.irradiance_uv(u, v);
        }
        read_chain(&self.sheen, u, v, r)
    }

    /// `E/π` at image coordinates `(u, v)`: [`Self::irradiance`] over π.
    #[must_use]
    #[inline(always)]
    pub fn irradiance_uv(&self, u: f32, v: f32) -> Vec3 {
        match self.levels.last() {
            Some(level) => level.bilinear(u, v),
            None => {
                sh::irradiance(&self.sh, super::equirect::uv_dir(u, v))
                    * std::f32::consts::FRAC_1_PI
            }
        }
    }

    /// [`Self::specular_uv`] at eight points at once (the same values).
    #[must_use]
    #[inline(always)]
    pub fn specular_lanes<L: Level>(&self, u: F8<L>, v: F8<L>, r: F8<L>) -> [F8<L>; 3] {
        super::lanes::chain(&self.levels, u, v, r)
    }

    /// [`Self::irradiance_uv`] at eight points at once (the same values).
    #[must_use]
    #[inline(always)]
    pub fn irradiance_lanes<L: Level>(&self, u: F8<L>, v: F8<L>) -> [F8<L>; 3] {
        match self.levels.last() {
            Some(level) => super::lanes::bilinear([level; LANES], u, v),
            None => {
                let (u, v) = (u.to_array(), v.to_array());
                let mut c = [[0.0; LANES]; 3];
                for i in 0..LANES {
                    let e = self.irradiance_uv(u[i], v[i]);
                    (c[0][i], c[1][i], c[2][i]) = (e.x, e.y, e.z);
                }
                [
                    F8::from_array(c[0]),
                    F8::from_array(c[1]),
                    F8::from_array(c[2]),
                ]
            }
        }
    }

    /// [`Self::sheen_uv`] at eight points at once (the same values).
    #[must_use]
    #[inline(always)]
    pub fn sheen_lanes<L: Level>(&self, u: F8<L>, v: F8<L>, r: F8<L>) -> [F8<L>; 3] {
        if self.sheen.is_empty() {
            return self.irradiance_lanes(u, v);
        }
        super::lanes::chain(&self.sheen, u, v, r)
    }

    /// Irradiance from the nine SH coefficients (Ramamoorthi & Hanrahan 2001): smooth and
    /// cheap to rotate, but a small bright source rings in nine coefficients.
    #[must_use]
    pub fn irradiance_sh(&self, n: Vec3) -> Vec3 {
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

/// A chain of levels (at least one) read at image coordinates `(u, v)` for roughness `r`
/// (clamped to [0, 1]; NaN reads level 0): bilinear in levels `⌊r·(M-1)⌋` and the next,
/// linear between.
#[inline(always)]
fn read_chain(levels: &[Plane], u: f32, v: f32, r: f32) -> Vec3 {
    let last = levels.len() - 1;
    let f = if r.is_nan() {
        0.0
    } else {
        r.clamp(0.0, 1.0) * last as f32
    };
    let k = (f as usize).min(last.saturating_sub(1));
    let t = f - k as f32;
    let a = levels[k].bilinear(u, v);
    if t <= 0.0 || k + 1 > last {
        return a;
    }
    a.lerp(levels[k + 1].bilinear(u, v), t)
}
