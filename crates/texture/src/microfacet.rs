//! The microfacet terms of the glTF 2.0 BRDF (the specification's Appendix B), the one place
//! they are written, generic over [`Num`] (f32, f64 and eight lanes):
//!
//! - `D = α² / (π (NH² (α² - 1) + 1)²)`, GGX / Trowbridge-Reitz, `α = roughness²`;
//! - `Vis = 1 / (2 (NL sqrt(NV² (1 - α²) + α²) + NV sqrt(NL² (1 - α²) + α²)))`, Smith's
//!   height-correlated masking-shadowing divided by `4 NL NV`;
//! - `F = F0 + (F90 - F0) (1 - VH)⁵`, Schlick;
//! - `KHR_materials_sheen`'s "Charlie" distribution and visibility ([`charlie_d`],
//!   [`charlie_v`]; Estevez and Kulla 2017).
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
    let (s, c) = libm::sincos(2.0 * std::f64::consts::PI * xi.0);
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

/// The smallest sheen roughness used (α = 0.0049): at 0 the Charlie distribution is a delta
/// at grazing half vectors.
pub const MIN_SHEEN_ROUGHNESS: f32 = 0.07;

/// α of sheen roughness `r` (clamped to [`MIN_SHEEN_ROUGHNESS`]..1 first).
#[inline(always)]
#[must_use]
pub fn sheen_alpha<T: Num>(r: T) -> T {
    let r = r.max(T::of(MIN_SHEEN_ROUGHNESS)).min(T::ONE);
    r * r
}

/// `(1 - α)²`-interpolated coefficients of the visibility's `l(x)` (Estevez and Kulla's
/// fits at α = 0 and 1).
#[inline(always)]
fn sheen_coefficients<T: Num>(alpha: T) -> [T; 5] {
    let t = (T::ONE - alpha) * (T::ONE - alpha);
    [
        sheen_lerp(21.5473, 25.3245, t),
        sheen_lerp(3.82987, 3.32435, t),
        sheen_lerp(0.19823, 0.16801, t),
        sheen_lerp(-1.97760, -1.27393, t),
        sheen_lerp(-4.32054, -4.85967, t),
    ]
}

/// `a + (b - a) t` (a function, not a closure, so lane code stays inside each kernel).
#[inline(always)]
fn sheen_lerp<T: Num>(a: f64, b: f64, t: T) -> T {
    T::of64(a) + T::of64(b - a) * t
}

#[inline(always)]
fn sheen_l<T: Num>(x: T, k: &[T; 5]) -> T {
    k[0] / (T::ONE + k[1] * x.powf(k[2])) + k[3] * x + k[4]
}

/// `e^y` (through [`Num::powf`], which every number type has).
#[inline(always)]
fn exp<T: Num>(y: T) -> T {
    T::of64(std::f64::consts::E).powf(y)
}

/// The visibility's `Λ(c)`: `exp(l(c))` below c = 0.5, `exp(2 l(0.5) - l(1 - c))` above.
#[inline(always)]
fn sheen_lambda<T: Num>(c: T, k: &[T; 5]) -> T {
    let low = exp(sheen_l(c, k));
    let half = sheen_l(T::of(0.5), k);
    let high = exp(half + half - sheen_l(T::ONE - c, k));
    T::select(c.lt(T::of(0.5)), low, high)
}

/// The sheen distribution `D = (2 + 1/α) sin(θ_h)^(1/α) / (2π)` at `N·H` for α.
#[inline(always)]
#[must_use]
pub fn charlie_d<T: Num>(nh: T, alpha: T) -> T {
    let inv = alpha.recip();
    let sin2 = (T::ONE - nh * nh).max(T::ZERO);
    (T::of(2.0) + inv) * sin2.powf(inv * T::of(0.5)) * T::of64(0.5 * std::f64::consts::FRAC_1_PI)
}

/// The sheen visibility `V = 1 / ((1 + Λ(N·V) + Λ(N·L)) 4 (N·V)(N·L))` at `N·L` and `N·V`
/// (both positive) for α, at most 1 (as the Khronos sample viewer clamps it: unclamped, a
/// smooth sheen seen at grazing angles reflects up to three times the light it receives).
#[inline(always)]
#[must_use]
pub fn charlie_v<T: Num>(nl: T, nv: T, alpha: T) -> T {
    let k = sheen_coefficients(alpha);
    let denom = (T::ONE + sheen_lambda(nv, &k) + sheen_lambda(nl, &k)) * T::of(4.0) * nv * nl;
    denom.max(T::ONE).recip()
}
