//! The glTF 2.0 metallic-roughness BRDF (the specification's Appendix B), generic over
//! [`Num`] so the same source runs in `f32` (vertex stage, pixel probe), `f64` (the
//! references) and on eight lanes (the pixel shaders). Its terms `D` (GGX), `Vis` (Smith,
//! height-correlated) and `F` (Schlick) are written once, in [`crate::microfacet`], which
//! the environment prefilter in `texture` also uses; this module mixes them:
//!
//! - `f = (1 - m) [(1 - max(F_d)) c / π + F_d Vis D] + m F_m Vis D`, the dielectric and
//!   metal lobes mixed by metallic `m`: `F_d` from the dielectric's `F0` and `F90` (0.04 and
//!   1, or what `KHR_materials_ior` and `KHR_materials_specular` make them), `F_m` from the
//!   base colour `c` and 1.
//!
//! The textbook's local illumination model (microfacet reflection with a Fresnel colour,
//! §9.2) is this equation: metal reflects in its own colour and has no diffuse term, so a
//! metal under a single light is dark except in its highlight.
//!
//! α is clamped to at least [`MIN_ALPHA`] (α = 0 is a mirror, whose `D` is a delta: the
//! specification's note asks for a clamp or a separate path). The single-scattering lobe
//! loses energy at high roughness (the white furnace in the README has the figures); the
//! image-based term compensates it ([`ibl_fresnel`]), and so do the punctual lights: each
//! specular lobe is scaled by `1 + F0 (1/E_ss - 1)` (Fdez-Agüera 2019, after Kulla and
//! Conty; three.js does the same since r181), `E_ss` the lobe's directional albedo at `N·V`
//! ([`Pbr::ess`], from the split-sum table read at three.js's table coordinates, so both
//! renderers compensate alike; 1 gives the specification's single-scattering formula).

use super::lighting::SurfaceAt;
pub use crate::microfacet::{alpha, ggx, schlick, schlick_weight, smith_vis, MIN_ALPHA};
use crate::simd::Num;

pub use crate::microfacet::f0_of_ior;

/// The PBR parameters of a surface point (with [`SurfaceAt::kd`] as the base colour).
#[derive(Clone, Copy, Debug)]
pub struct Pbr<T: Num> {
    pub metallic: T,
    /// Perceptual roughness (α = roughness²).
    pub roughness: T,
    /// The dielectric lobe's Fresnel at normal incidence, per channel
    /// (`min(F0_ior · specularColor, 1) · specular`).
    pub f0: T::V,
    /// The dielectric lobe's Fresnel at grazing incidence (`specular`, 1 by default).
    pub f90: T,
    /// The single-scattering lobe's directional albedo `E_ss` at `N·V` and this roughness
    /// (the split-sum table's `A + B` at three.js's table coordinates), which sets the multiple-scattering compensation of
    /// the punctual lights; 1 (the default) turns it off.
    pub ess: T,
}

/// The terms of one light's reflection at a point: what the pixel probe lists.
#[derive(Clone, Copy, Debug)]
pub struct Terms<T: Num> {
    /// Diffuse reflection times `NL` (per unit irradiance).
    pub diffuse: T::V,
    /// Specular reflection times `NL` (per unit irradiance).
    pub specular: T::V,
    /// `D`, `Vis` and the mixed Fresnel `(1 - m) F_d + m F_m` (zero for Phong and Blinn).
    pub d: T,
    pub vis: T,
    pub fresnel: T::V,
}

/// The metallic-roughness BRDF times `NL` for unit normal `n`, light direction `l` and
/// view vector `v`, on the lanes where `lit` (`NL = ndl > 0` there).
#[inline(always)]
#[must_use]
pub fn pbr<T: Num>(
    s: &SurfaceAt<T>,
    p: &Pbr<T>,
    alpha: T,
    n: T::V,
    l: T::V,
    v: T::V,
    ndl: T,
) -> Terms<T> {
    let h = T::normalize_or_zero(l + v);
    let nv = T::dot(n, v).max(T::of(1e-4));
    let nh = T::dot(n, h).max(T::ZERO);
    let vh = T::dot(v, h);
    let d = ggx(nh, alpha);
    let vis = smith_vis(ndl, nv, alpha);
    let w = schlick_weight(vh);
    let fd = schlick::<T>(p.f0, p.f90, w);
    let fm = schlick::<T>(s.kd, T::ONE, w);
    let dielectric = T::ONE - p.metallic;
    let fresnel = fd * dielectric + fm * p.metallic;
    let inv_pi = T::of64(std::f64::consts::FRAC_1_PI);
    let diffuse = s.kd * (dielectric * (T::ONE - T::vmax(fd)) * inv_pi * ndl);
    // The energy lost between microfacets, given back: each lobe times 1 + F0 (1/E_ss - 1)
    // (exactly 1 when E_ss = 1).
    let k = T::ONE / p.ess.max(T::of(1e-3)) - T::ONE;
    let one = T::splat(T::ONE);
    let lobes = fd * (one + p.f0 * k) * dielectric + fm * (one + s.kd * k) * p.metallic;
    let specular = lobes * (vis * d * ndl);
    Terms {
        diffuse,
        specular,
        d,
        vis,
        fresnel,
    }
}

/// The split-sum factors of the specular image-based term with multiple scattering
/// (Fdez-Agüera 2019): for a lobe of Fresnel `f0`, `f90` with the BRDF table's scale and
/// bias `(a, b)` at `NV` and roughness, the single-scattering albedo `FssEss` (which
/// weights the prefiltered radiance) and the multiple-scattering one `FmsEms` (which
/// weights the irradiance over π); the rest of the energy, `1 - FssEss - FmsEms`, is left
/// for a diffuse term. White metal in a white furnace returns exactly 1 (Ess + Ems = 1
/// when F0 = 1).
#[inline(always)]
#[must_use]
pub fn ibl_fresnel<T: Num>(f0: T::V, f90: T, a: T, b: T) -> (T::V, T::V) {
    // Single scattering: F0 A + F90 B.
    let fss_ess = f0 * a + T::splat(f90 * b);
    let ess = a + b;
    let ems = T::ONE - ess;
    // Average Fresnel over the hemisphere for Schlick: F0 + (F90 - F0) / 21.
    let favg = f0 + (T::splat(f90) - f0) * T::of(1.0 / 21.0);
    let [fx, fy, fz] = T::xyz(favg);
    let ms = |f: T| f * ems / (T::ONE - f * ems).max(T::of(1e-6));
    let fms = T::new3(ms(fx), ms(fy), ms(fz));
    (fss_ess, fss_ess * fms)
}
