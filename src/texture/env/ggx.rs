//! The GGX pieces the prefilter and the LUT share, in f64: the Hammersley point set, the
//! half-vector sample of the GGX distribution, `D` and the height-correlated Smith `Vis`
//! (glTF spec Appendix B; `gltf-notes.md` §3 and §5).
//!
//! The shading code has its own copies for the renderer; this module cannot import it
//! (`texture` sits below `shade`), and the formulas are the spec's, letter for letter.

use glam::DVec3;

/// Smallest α used (α = r² is singular at 0): r ≈ 0.032.
pub(super) const MIN_ALPHA: f64 = 1e-3;

/// α of perceptual roughness `r`, clamped away from 0.
pub(super) fn alpha(r: f64) -> f64 {
    (r * r).clamp(MIN_ALPHA, 1.0)
}

/// Point `i` of the `n`-point Hammersley set: (i/n, radical inverse of i in base 2).
pub(super) fn hammersley(i: u32, n: u32) -> (f64, f64) {
    (
        f64::from(i) / f64::from(n),
        f64::from(i.reverse_bits()) * (1.0 / 4_294_967_296.0),
    )
}

/// The half vector (N = +Z) for the point (ξ1, ξ2), distributed as `D(h)·NH`:
/// `cosθh = sqrt((1-ξ2)/(1 + (α²-1)ξ2))`, `φ = 2πξ1`.
pub(super) fn sample_h(xi: (f64, f64), alpha: f64) -> DVec3 {
    let a2 = alpha * alpha;
    let cos_t = ((1.0 - xi.1) / (1.0 + (a2 - 1.0) * xi.1))
        .clamp(0.0, 1.0)
        .sqrt();
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let (s, c) = (2.0 * std::f64::consts::PI * xi.0).sin_cos();
    DVec3::new(sin_t * c, sin_t * s, cos_t)
}

/// GGX `D = α²/(π(NH²(α²-1)+1)²)` for NH > 0, else 0.
pub(super) fn d(nh: f64, alpha: f64) -> f64 {
    if nh <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let t = nh * nh * (a2 - 1.0) + 1.0;
    a2 / (std::f64::consts::PI * t * t)
}

/// Height-correlated Smith `Vis = 1/(2(NV·sqrt(α²+(1-α²)NL²) + NL·sqrt(α²+(1-α²)NV²)))`
/// (G over 4·NL·NV), for NL, NV >= 0.
pub(super) fn vis(nl: f64, nv: f64, alpha: f64) -> f64 {
    let a2 = alpha * alpha;
    let gv = nl * (a2 + (1.0 - a2) * nv * nv).sqrt();
    let gl = nv * (a2 + (1.0 - a2) * nl * nl).sqrt();
    let s = gv + gl;
    if s > 0.0 {
        0.5 / s
    } else {
        0.0
    }
}
