//! The microfacet terms of the glTF 2.0 BRDF (the specification's Appendix B), the one place
//! they are written, generic over [`Num`] (f32, f64 and eight lanes):
//!
//! - `D = α² / (π (NH² (α² - 1) + 1)²)`, GGX / Trowbridge-Reitz, `α = roughness²`;
//! - `Vis = 1 / (2 (NL sqrt(NV² (1 - α²) + α²) + NV sqrt(NL² (1 - α²) + α²)))`, Smith's
//!   height-correlated masking-shadowing divided by `4 NL NV`;
//! - `F = F0 + (F90 - F0) (1 - VH)⁵`, Schlick.
//!
//! It sits at the bottom of the crate, beside `simd`, because two layers need the same
//! formulas: `shade::brdf` lights surfaces with them, and `texture::env` prefilters
//! environments and builds the split-sum table with them (`texture` sits below `shade`
//! and cannot import it).

use glam::DVec3;

use crate::simd::Num;

/// Smallest α = roughness² used: a roughness of about 0.032.
pub const MIN_ALPHA: f32 = 1e-3;

/// α of perceptual roughness `r`: `r²`, clamped to `[MIN_ALPHA, 1]`.
#[inline(always)]
#[must_use]
pub fn alpha<T: Num>(r: T) -> T {
    (r * r).max(T::of(MIN_ALPHA)).min(T::ONE)
}

/// GGX normal distribution `D` at `NH` for α.
#[inline(always)]
#[must_use]
pub fn ggx<T: Num>(nh: T, alpha: T) -> T {
    let a2 = alpha * alpha;
    let k = T::mul_add(nh * nh, a2 - T::ONE, T::ONE);
    a2 / (T::of64(std::f64::consts::PI) * k * k)
}

/// Smith height-correlated visibility `G / (4 NL NV)` for α (`NL`, `NV` positive).
#[inline(always)]
#[must_use]
pub fn smith_vis<T: Num>(nl: T, nv: T, alpha: T) -> T {
    let a2 = alpha * alpha;
    let one_a2 = T::ONE - a2;
    let gv = nl * T::mul_add(nv * nv, one_a2, a2).sqrt();
    let gl = nv * T::mul_add(nl * nl, one_a2, a2).sqrt();
    let den = gv + gl;
    T::select(den.gt(T::ZERO), T::of(0.5) / den, T::ZERO)
}

/// Schlick's weight `(1 - VH)⁵` (`VH` clamped to [0, 1]).
#[inline(always)]
#[must_use]
pub fn schlick_weight<T: Num>(vh: T) -> T {
    let x = T::ONE - vh.clamp01();
    let x2 = x * x;
    x2 * x2 * x
}

/// Schlick's Fresnel `F0 + (F90 - F0) w` per channel.
#[inline(always)]
#[must_use]
pub fn schlick<T: Num>(f0: T::V, f90: T, w: T) -> T::V {
    f0 + (T::splat(f90) - f0) * w
}

/// Point `i` of the `n`-point Hammersley set: (i/n, radical inverse of i in base 2).
pub fn hammersley(i: u32, n: u32) -> (f64, f64) {
    (
        f64::from(i) / f64::from(n),
        f64::from(i.reverse_bits()) * (1.0 / 4_294_967_296.0),
    )
}

/// The half vector (N = +Z) for the point (ξ1, ξ2), distributed as `D(h)·NH`:
/// `cosθh = sqrt((1-ξ2)/(1 + (α²-1)ξ2))`, `φ = 2πξ1`.
pub fn sample_h(xi: (f64, f64), alpha: f64) -> DVec3 {
    let a2 = alpha * alpha;
    let cos_t = ((1.0 - xi.1) / (1.0 + (a2 - 1.0) * xi.1))
        .clamp(0.0, 1.0)
        .sqrt();
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let (s, c) = (2.0 * std::f64::consts::PI * xi.0).sin_cos();
    DVec3::new(sin_t * c, sin_t * s, cos_t)
}

/// The dielectric `F0` of index of refraction `ior`: `((ior - 1) / (ior + 1))²` (0.04 at
/// 1.5); `ior = 0` is `KHR_materials_ior`'s "infinite" (F0 = 1).
#[must_use]
pub fn f0_of_ior(ior: f32) -> f32 {
    if ior == 0.0 || !ior.is_finite() {
        return 1.0;
    }
    let r = (ior - 1.0) / (ior + 1.0);
    r * r
}
