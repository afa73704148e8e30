//! Image-based lighting data: equirectangular environment images and what a glTF PBR shader
//! reads from them (the CPU half of the split-sum approximation, Karis 2013).
//!
//! This module owns:
//! - [`EnvImage`]: a linear-RGB f32 equirectangular image, loaded from Radiance `.hdr` or
//!   OpenEXR or generated ([`EnvImage::uniform`], [`EnvImage::studio`], [`EnvImage::sky`]);
//! - [`Prefiltered`]: built once from an image and shared in an `Arc`: the specular chain
//!   (one equirect level per perceptual roughness, GGX-filtered with N = V = R; its last
//!   level is also the irradiance), nine spherical-harmonic coefficients, and the
//!   full-resolution source for the background and for the f64 reference renderer;
//! - [`BrdfLut`] ([`brdf_lut`]): the environment-independent (A, B) table of the split sum;
//! - [`EnvView`]: an environment as a scene uses it, turned about +Y and scaled, without
//!   prefiltering again;
//! - [`EnvCache`]: prefiltered environments keyed by content, in memory and on disk.
//!
//! # Conventions
//! Directions are world-space unit vectors, +Y up. The image maps a direction `d` to
//! `u = 0.5 + atan2(d.z, d.x)/(2π)`, `v = acos(d.y)/π` (glTF-Sample-Viewer's `dirToUV` and
//! three.js's `equirectUv`): the top row is +Y, the image centre faces +X, and moving right
//! turns toward +Z. Texel `(x, y)` of a `W×H` image covers `u ∈ [x/W, (x+1)/W)`,
//! `v ∈ [y/H, (y+1)/H)`; sampling is bilinear between texel centres, wrapping in u and clamped
//! in v. Roughness is always the perceptual `r` of glTF (`α = r²`).
//!
//! # Orientation
//! glTF does not say which way an environment faces. Sample Viewer turns its lookups by
//! `environmentRotation` = 90° about +Y, so the image centre lies at world +Z, the side a
//! glTF asset faces; three.js applies no rotation (image centre at +X), and glTF PR #1761
//! (open) proposed +X. [`EnvView::rotation_deg`] is that setting, with Sample Viewer's sense:
//! the lookup direction is turned by the right-handed rotation `R_y(θ)` before it reads the
//! image, so the environment appears turned by `R_y(-θ)` and its centre faces
//! `(cos θ, 0, sin θ)`: +X at 0°, +Z at [`DEFAULT_ROTATION_DEG`] = 90°, -X at 180°.
//! (Seen from above, +Y, increasing θ turns the environment clockwise, from +X toward +Z.)
//!
//! # Designs rejected
//! - Cube maps: the prefiltered chain is stored in the source's own equirect layout, so a
//!   lookup is one `atan2`/`acos` and a bilinear fetch, and level 0 is the source itself
//!   (box-resampled) with no reprojection; the cost is wasted texels near the poles.
//! - Prefiltering by brute force over the source: it costs `O(texels²)`; GGX importance
//!   sampling with filtered importance sampling costs a few hundred fetches a texel and gives
//!   no fireflies from a small sun.
//! - Nine spherical-harmonic coefficients for irradiance (Ramamoorthi & Hanrahan 2001)
//!   as the lookup: they were 6.6 % (studio) and 13.6 % (sky) off at the worst normal, a
//!   small bright source ringing in nine coefficients. Irradiance is read from the chain's
//!   last level instead, which at α = 1 is exactly the cosine-weighted mean (`E/π`) and
//!   costs no extra storage; the coefficients are kept ([`Prefiltered::irradiance_sh`]).

mod builtin;
mod cache;
mod chain;
mod equirect;
mod ggx;
mod lanes;
mod lut;
mod prefilter;
mod resample;
mod sample;
mod sh;
#[cfg(test)]
mod tests;

use std::sync::Arc;

use glam::{DVec3, Vec3};

pub use builtin::BUILTIN_NAMES;
pub use cache::{content_key, default_cache_dir, CacheHit, Cached, EnvCache};
pub use chain::SPECULAR_LEVELS;
pub use equirect::{
    dir_to_uv, dir_to_uv_f64, texel_dir, EnvError, EnvImage, MAX_ENV_SIDE, MAX_ENV_TEXELS,
    MAX_RADIANCE,
};
pub use lut::{brdf_lut, BrdfLut, LUT_SAMPLES, LUT_SIZE};
pub use prefilter::{Prefiltered, PREFILTER_VERSION};
pub use sample::EnvSampler;
pub use sh::{SH_C1, SH_C2, SH_C3, SH_C4, SH_C5};

/// Sample Viewer's default environment rotation, in degrees: the image centre faces world +Z.
/// See the module docs for the sense of the rotation.
pub const DEFAULT_ROTATION_DEG: f32 = 90.0;

/// A prefiltered environment as a scene lights with it: turned by `rotation_deg` about +Y
/// and scaled by `intensity`. Both apply at lookup time; changing them never prefilters
/// again.
#[derive(Clone, Debug)]
pub struct EnvView {
    pub env: Arc<Prefiltered>,
    /// Rotation about +Y, in degrees; the image centre faces `(cos θ, 0, sin θ)` (module docs).
    pub rotation_deg: f32,
    /// Multiplies every radiance and irradiance read (1 = as stored).
    pub intensity: f32,
}

impl EnvView {
    /// The environment at Sample Viewer's default rotation ([`DEFAULT_ROTATION_DEG`]) and
    /// intensity 1.
    #[must_use]
    pub fn new(env: Arc<Prefiltered>) -> Self {
        Self {
            env,
            rotation_deg: DEFAULT_ROTATION_DEG,
            intensity: 1.0,
        }
    }

    /// The world direction `d` in the image's frame: `R_y(θ)·d` (right-handed).
    #[inline]
    #[must_use]
    pub fn to_image(&self, d: Vec3) -> Vec3 {
        let (s, c) = libm::sincosf(self.rotation_deg.to_radians());
        Vec3::new(d.x * c + d.z * s, d.y, -d.x * s + d.z * c)
    }

    /// The world direction the image centre (u = v = 0.5) faces: `(cos θ, 0, sin θ)`.
    #[must_use]
    pub fn image_centre(&self) -> Vec3 {
        let (s, c) = libm::sincosf(self.rotation_deg.to_radians());
        Vec3::new(c, 0.0, s)
    }

    /// `(sin θ, cos θ)` of the rotation: a direction `d` is `R_y(θ)·d` in the image, which
    /// eight-lane callers compute themselves ([`Self::to_image`]).
    #[must_use]
    pub fn rotation_sin_cos(&self) -> (f32, f32) {
        libm::sincosf(self.rotation_deg.to_radians())
    }

    /// Prefiltered specular radiance around `dir` for perceptual roughness `r` (the first
    /// factor of the split sum); see [`Prefiltered::specular`].
    #[must_use]
    pub fn specular(&self, dir: Vec3, r: f32) -> Vec3 {
        self.env.specular(self.to_image(dir), r) * self.intensity
    }

    /// Irradiance on a surface with normal `n`; see [`Prefiltered::irradiance`].
    #[must_use]
    pub fn irradiance(&self, n: Vec3) -> Vec3 {
        self.env.irradiance(self.to_image(n)) * self.intensity
    }

    /// The radiance averaged over the sheen lobe of roughness `r` around the normal `n`;
    /// see [`Prefiltered::sheen_uv`].
    #[must_use]
    pub fn sheen(&self, n: Vec3, r: f32) -> Vec3 {
        let (u, v) = equirect::dir_to_uv(self.to_image(n).normalize_or_zero());
        self.env.sheen_uv(u, v, r) * self.intensity
    }

    /// A direction drawn in proportion to the environment's radiance (two uniform numbers
    /// in `[0, 1)`), its radiance (as [`Self::background`] reads it, sharp) and its density
    /// per unit solid angle ([`EnvSampler`]).
    #[must_use]
    pub fn sample(&self, u1: f32, u2: f32) -> (Vec3, Vec3, f32) {
        let (d, pdf) = self.env.sampler().sample(u1, u2);
        // Image frame -> world: the inverse rotation.
        let (s, c) = libm::sincosf(self.rotation_deg.to_radians());
        let w = Vec3::new(d.x * c - d.z * s, d.y, d.x * s + d.z * c);
        (w, self.background(w, 0.0), pdf)
    }

    /// The density [`Self::sample`] gives world direction `dir`.
    #[must_use]
    pub fn pdf(&self, dir: Vec3) -> f32 {
        self.env.sampler().pdf(self.to_image(dir))
    }

    /// What a camera ray in direction `dir` sees; see [`Prefiltered::background`].
    #[must_use]
    pub fn background(&self, dir: Vec3, blur: f32) -> Vec3 {
        self.env.background(self.to_image(dir), blur) * self.intensity
    }

    /// Radiance from `dir` in f64, bilinear on the full-resolution source (for Monte-Carlo
    /// integration in the reference renderer).
    #[must_use]
    pub fn radiance_f64(&self, dir: DVec3) -> DVec3 {
        let (s, c) = libm::sincos(f64::from(self.rotation_deg).to_radians());
        let d = DVec3::new(dir.x * c + dir.z * s, dir.y, -dir.x * s + dir.z * c);
        self.env.radiance_f64(d) * f64::from(self.intensity)
    }
}
