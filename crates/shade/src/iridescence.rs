//! `KHR_materials_iridescence`'s thin-film Fresnel: the reflectance of a dielectric film
//! (IOR `iridescenceIor`, thickness in nanometres) between the outside (air, IOR 1, or a
//! clear coat) and the base material, in linear Rec. 709 RGB. Interference between the light
//! reflected at the film's top and at its bottom colours the reflection, by thickness and
//! angle (soap bubbles, oil on water, heat-tinted metal).
//!
//! The model is Belcour and Barla 2017 ("A Practical Extension to Microfacet Theory for the
//! Modeling of Varying Iridescence", SIGGRAPH; their §4, "analytic spectral integration")
//! as the extension's implementation notes, the Khronos glTF-Sample-Viewer
//! (`source/Renderer/shaders/iridescence.glsl`, `evalIridescence`) and three.js
//! (`bsdfs`, `evalIridescence`) simplify it; [`fresnel`] follows the sample viewer step by
//! step, with its constants:
//!
//! - the film's IOR `η2` is mixed toward the outside IOR `η1` for very thin films
//!   ([`FADE_NM`]); Snell's law gives the angle in the film, `cos θ2`; none where it is
//!   totally reflected (a film of lower IOR than a clear coat), which reflects 1;
//! - both interfaces reflect by Schlick's approximation with `F90 = 1`, unpolarised: the
//!   top `R12` from `F0 = ((η2 - η1) / (η2 + η1))²` at `cos θ1`, the bottom `R23` at
//!   `cos θ2` from the base's IOR `η3 = (1 + √F0) / (1 - √F0)` (`Fresnel0ToIor`: the base
//!   taken as a dielectric seen from air, metals included, with `F0` clamped to 0.9999);
//! - the phase shifts are 0 or π: `φ21 = π` unless `η2 < η1`, `φ23 = π` where `η3 < η2`;
//! - the Airy series truncated after `m = 2`: `R = C0 + Σ_m 2 C_m S_m` with `T121 = 1 -
//!   R12`, `Rs = T121² R23 / (1 - R12 R23)`, `C0 = R12 + Rs`, `C_m = (Rs - T121) (R12
//!   R23)^(m/2)` (`R12 R23` clamped to [1e-5, 0.9999]); each term's spectrum is integrated
//!   analytically: `S_m` is the Fourier transform of the CIE 1931 sensitivities (Gaussian
//!   fits, `sensitivity` below) at `m` times the optical path difference `OPD = 2 η2 d cos
//!   θ2` and shift `m (φ21 + φ23)`, taken to RGB by [`XYZ_TO_REC709`];
//! - negative (out-of-gamut) channels are clamped to 0.
//!
//! A thickness of 0 (or less) is no film: the base's own Schlick Fresnel `F0 + (1 - F0)(1 -
//! cos θ1)⁵` comes back. The sample viewer has no such case: at 0 it makes `η2 = η1` and
//! still sums the series, whose Schlick `F90 = 1` at the top and clamp leave, for F0 0.04,
//! 0.047 in red at normal incidence and 0.47 at 70° (the base: 0.04 and 0.16). The
//! extension's defaults are [`OUTSIDE_IOR`], [`DEFAULT_IOR`] and the thickness range
//! [`DEFAULT_THICKNESS_MIN`]..[`DEFAULT_THICKNESS_MAX`] ([`thickness`]); the BRDF uses
//! `mix(F_schlick, fresnel(...), iridescence)` as its Fresnel.
//!
//! Against an exact spectral reference (the Airy reflectance of the film, both
//! polarisations, at 1 nm from 380 to 780 nm, integrated against the CIE 1931 observer:
//! the tests, which list the figures) the model is within 0.05 per channel at 0° and 45°
//! for films 200 to 500 nm thick, and up to 0.15 off at 70°: the approximations (Schlick at
//! both interfaces, two terms of the series, the sensitivity fits, the DC term white in RGB
//! where the reference's equal-energy white is not) cost that much. A wrong phase or unit
//! costs several times more.

use crate::microfacet::{schlick, schlick_weight};
use crate::simd::Num;

/// The IOR outside the film when nothing covers it (air, as the extension takes it).
pub const OUTSIDE_IOR: f32 = 1.0;
/// `iridescenceIor`'s default.
pub const DEFAULT_IOR: f32 = 1.3;
/// `iridescenceThicknessMinimum`'s default, in nm.
pub const DEFAULT_THICKNESS_MIN: f32 = 100.0;
/// `iridescenceThicknessMaximum`'s default, in nm.
pub const DEFAULT_THICKNESS_MAX: f32 = 400.0;

/// The thickness (nm) over which the film's IOR rises from the outside's to its own:
/// `η2 = mix(η1, iridescenceIor, smoothstep(0, FADE_NM, d))`, the sample viewer's (and
/// three.js's) `smoothstep(0.0, 0.03, thinFilmThickness)` with their thickness in nm, so a
/// step in practice. Belcour and Barla's code, where the line comes from, measures the
/// thickness in micrometres (its `evalSensitivity` scales the path difference by 1e-6, the
/// sample viewer's by 1e-9), so there the fade spans 30 nm. That reading was measured
/// against the spectral reference (tests) and is worse: with `η2` near `η1` the top
/// interface should vanish, but Schlick's `F90 = 1` keeps `(1 - cos θ1)⁵` of it, and at 70°
/// films of 5 to 20 nm came out up to 0.27 off (0.15 with the step).
pub const FADE_NM: f32 = 0.03;

/// XYZ to linear Rec. 709 (sRGB primaries, D65 white), by rows: the sample viewer's
/// `XYZ_TO_REC709` (a GLSL `mat3` is written by columns; these are its rows).
#[allow(clippy::excessive_precision)] // as published
pub const XYZ_TO_REC709: [[f64; 3]; 3] = [
    [3.2404542, -1.5371385, -0.4985314],
    [-0.9692660, 1.8760108, 0.0415560],
    [0.0556434, -0.2040259, 1.0572252],
];

/// The Gaussian fits of the CIE 1931 x̄, ȳ, z̄ in the Fourier domain (Belcour and Barla's
/// supplemental code, the sample viewer's `evalSensitivity`), per XYZ component: amplitude
/// `val`, mean wavenumber `pos` (1/m) and `var` (1/m²); x̄ has a second lobe ([`X_LOBE`]).
const VAL: [f64; 3] = [5.4856e-13, 4.4201e-13, 5.2481e-13];
const POS: [f64; 3] = [1.6810e+06, 1.7953e+06, 2.2084e+06];
const VAR: [f64; 3] = [4.3278e+09, 9.3046e+09, 6.6121e+09];
/// x̄'s second (blue) lobe: `val`, `pos`, `var`.
const X_LOBE: [f64; 3] = [9.7470e-14, 2.2399e+06, 4.5282e+09];
/// The fits' normalisation: each component's transform at 0 is then about 1.
const NORM: f64 = 1.0685e-7;

/// The film's thickness in nm, as the extension sets it: `mix(minimum, maximum, g)` with `g`
/// the `iridescenceThicknessTexture`'s green channel, or `maximum` without the texture.
#[inline(always)]
#[must_use]
pub fn thickness<T: Num>(minimum: T, maximum: T, g: Option<T>) -> T {
    match g {
        Some(g) => minimum + (maximum - minimum) * g,
        None => maximum,
    }
}

/// [`fresnel`] under air in `f32`, out of line: what the shaders' lanes call lane by lane
/// ([`crate::Shade::film`]).
#[inline(never)]
#[must_use]
pub fn film_f32(ior: f32, cos: f32, thickness: f32, f0: glam::Vec3) -> glam::Vec3 {
    fresnel::<f32>(OUTSIDE_IOR, ior, cos, thickness, f0)
}

/// The thin-film Fresnel `F_iridescence` in linear Rec. 709, per channel, for a film of IOR
/// `film_ior` and thickness `thickness_nm` under a medium of IOR `outside_ior` (1, or the
/// clear coat's), over a base whose normal-incidence Fresnel is `base_f0`, seen at
/// `cos_theta1` (`V·H` for a light, `N·V` for the environment): the sample viewer's
/// `evalIridescence` (see the module's notes). At least 0 per channel; 1 where the film
/// totally reflects; the base's Schlick Fresnel (`F90 = 1`) for a thickness of 0 or less.
#[inline(always)]
#[must_use]
pub fn fresnel<T: Num>(
    outside_ior: T,
    film_ior: T,
    cos_theta1: T,
    thickness_nm: T,
    base_f0: T::V,
) -> T::V {
    let n1 = outside_ior;
    let n2 = n1 + (film_ior - n1) * smoothstep(T::of(FADE_NM), thickness_nm);
    // Snell: sin²θ2 = (η1/η2)² sin²θ1.
    let ratio = n1 / n2;
    let cos2_sq = T::ONE - ratio * ratio * (T::ONE - cos_theta1 * cos_theta1);
    let tir = T::ZERO.gt(cos2_sq);
    let cos2 = cos2_sq.max(T::ZERO).sqrt();
    // The top interface, and its phase seen from below: φ21 = π (a sign of -1) unless the
    // film's IOR is below the outside's.
    let r12 = schlick1(ior_to_f0(n2, n1), cos_theta1);
    let t121 = T::ONE - r12;
    let s21 = T::select(n1.gt(n2), T::ONE, -T::ONE);
    let [fx, fy, fz] = T::xyz(base_f0);
    let [(rx, sx), (ry, sy), (rz, sz)] = [
        bottom(fx, n2, cos2, s21),
        bottom(fy, n2, cos2, s21),
        bottom(fz, n2, cos2, s21),
    ];
    let opd = T::of(2.0) * n2 * thickness_nm * cos2;
    let [s1, s2] = sensitivity(opd, [sx, sy, sz]);
    let film = T::new3(
        airy(r12, t121, rx, s1[0], s2[0]),
        airy(r12, t121, ry, s1[1], s2[1]),
        airy(r12, t121, rz, s1[2], s2[2]),
    );
    let film = T::vselect(tir, T::splat(T::ONE), film);
    let bare = schlick::<T>(base_f0, T::ONE, schlick_weight(cos_theta1));
    T::vselect(thickness_nm.gt(T::ZERO), film, bare)
}

/// GLSL's `smoothstep(0, edge, x)`: 0 below 0, 1 above `edge`, `t² (3 - 2t)` between.
#[inline(always)]
fn smoothstep<T: Num>(edge: T, x: T) -> T {
    let t = (x / edge).clamp01();
    t * t * (T::of(3.0) - T::of(2.0) * t)
}

/// `IorToFresnel0`: the reflectance at normal incidence from IOR `incident` into
/// `transmitted`, `((t - i) / (t + i))²`.
#[inline(always)]
fn ior_to_f0<T: Num>(transmitted: T, incident: T) -> T {
    let r = (transmitted - incident) / (transmitted + incident);
    r * r
}

/// Schlick's Fresnel with `F90 = 1` at `cos` (the sample viewer's one-argument `F_Schlick`).
#[inline(always)]
fn schlick1<T: Num>(f0: T, cos: T) -> T {
    f0 + (T::ONE - f0) * schlick_weight(cos)
}

/// One channel of the bottom interface, film (IOR `n2`) to base (normal-incidence Fresnel
/// `f0` from air): its reflectance `R23` at `cos2`, and the sign `cos(φ21 + φ23)` of the
/// series' odd terms (`s21` is `cos φ21`; `φ23 = π` where the base's IOR is below the
/// film's).
#[inline(always)]
fn bottom<T: Num>(f0: T, n2: T, cos2: T, s21: T) -> (T, T) {
    // Fresnel0ToIor, guarded against F0 = 1 (an infinite IOR).
    let root = f0.max(T::ZERO).min(T::of(0.9999)).sqrt();
    let n3 = (T::ONE + root) / (T::ONE - root);
    let r23 = schlick1(ior_to_f0(n3, n2), cos2);
    (r23, T::select(n2.gt(n3), -s21, s21))
}

/// One channel of the series: `C0 + 2 C1 S1 + 2 C2 S2`, clamped at 0 (`s1`, `s2` are the
/// channel's sensitivity terms for `m` = 1 and 2, phase signs included).
#[inline(always)]
fn airy<T: Num>(r12: T, t121: T, r23: T, s1: T, s2: T) -> T {
    let r123 = (r12 * r23).max(T::of(1e-5)).min(T::of(0.9999));
    let r = r123.sqrt();
    let rs = t121 * t121 * r23 / (T::ONE - r123);
    let c0 = r12 + rs;
    let c1 = (rs - t121) * r;
    let c2 = c1 * r;
    let two = T::of(2.0);
    (c0 + two * (c1 * s1 + c2 * s2)).max(T::ZERO)
}

/// `evalSensitivity(m OPD, m φ)` for `m` = 1 and 2, in Rec. 709: per XYZ component,
/// `val √(2π var) cos(m pos p + m φ) exp(-m² p² var) / NORM` with `p = 2π OPD 1e-9` (OPD in
/// nm), x̄'s second lobe added. The shifts are whole multiples of π, so the cosine is
/// `cos(m pos p)` times `sign^m` (`sign = cos φ`, per component as the sample viewer pairs
/// them: the shift of RGB channel `k` goes to XYZ component `k`); `cos 2a = 2 cos²a - 1` and
/// `exp(-4x) = exp(-x)⁴` give `m = 2` from `m = 1`.
#[inline(always)]
fn sensitivity<T: Num>(opd_nm: T, sign: [T; 3]) -> [[T; 3]; 2] {
    let p = T::of64(2.0 * std::f64::consts::PI * 1e-9) * opd_nm;
    let p2 = p * p;
    let mut xyz = [[T::ZERO; 3]; 2];
    for k in 0..3 {
        let [a, b] = lobe(p, p2, [VAL[k], POS[k], VAR[k]]);
        xyz[0][k] = sign[k] * a;
        xyz[1][k] = b;
    }
    let [a, b] = lobe(p, p2, X_LOBE);
    xyz[0][0] = xyz[0][0] + sign[0] * a;
    xyz[1][0] = xyz[1][0] + b;
    [rec709(xyz[0]), rec709(xyz[1])]
}

/// One Gaussian lobe `[val, pos, var]` of the sensitivity at phase `p` (`p2 = p²`), for
/// `m` = 1 and 2 without the phase shift: `A cos(pos p) exp(-p² var)` and
/// `A cos(2 pos p) exp(-4 p² var)`, `A = val √(2π var) / NORM`.
#[inline(always)]
fn lobe<T: Num>(p: T, p2: T, [val, pos, var]: [f64; 3]) -> [T; 2] {
    let amp = T::of64(val * (2.0 * std::f64::consts::PI * var).sqrt() / NORM);
    let c = (T::of64(pos) * p).cos();
    let e = (-(p2 * T::of64(var))).exp();
    let e2 = e * e;
    [amp * c * e, amp * (T::of(2.0) * c * c - T::ONE) * (e2 * e2)]
}

/// `XYZ_TO_REC709 xyz`.
#[inline(always)]
fn rec709<T: Num>(xyz: [T; 3]) -> [T; 3] {
    let m = XYZ_TO_REC709;
    [row(m[0], xyz), row(m[1], xyz), row(m[2], xyz)]
}

/// One row of a matrix times `v`.
#[inline(always)]
fn row<T: Num>(r: [f64; 3], v: [T; 3]) -> T {
    T::of64(r[0]) * v[0] + T::of64(r[1]) * v[1] + T::of64(r[2]) * v[2]
}

#[cfg(test)]
mod tests {
    use glam::{DVec3, Vec3};

    use super::*;
    use crate::simd::kernel::__private::Portable;
    use crate::simd::F8;

    type P = F8<Portable>;

    /// The spectral reference in linear Rec. 709 (`realist_color::thin_film`: the exact
    /// Airy reflectance against the CIE 1931 observer).
    fn reference(n2: f64, f0: f64, d: f64, cos1: f64) -> DVec3 {
        DVec3::from(realist_color::thin_film::rec709(n2, f0, d, cos1))
    }

    fn model(n2: f64, f0: f64, d: f64, cos1: f64) -> DVec3 {
        fresnel::<f64>(1.0, n2, cos1, d, DVec3::splat(f0))
    }

    /// The model against the spectral reference, over bases of F0 0.04 (IOR 1.5) and 0.25
    /// (IOR 3), films of IOR 1.3, 1.5 and 2, at 0° and 45°, 200 to 500 nm thick. The
    /// largest channel differences measured (f64; `cargo test -p realist-shade
    /// iridescence -- --nocapture` prints them):
    ///
    /// | F0   | film | 0°     | 45°    |
    /// |------|------|--------|--------|
    /// | 0.04 | 1.3  | 0.0046 | 0.0118 |
    /// | 0.04 | 1.5  | 0.0184 | 0.0244 |
    /// | 0.04 | 2.0  | 0.0266 | 0.0469 |
    /// | 0.25 | 1.3  | 0.0349 | 0.0495 |
    /// | 0.25 | 1.5  | 0.0230 | 0.0441 |
    /// | 0.25 | 2.0  | 0.0501 | 0.0337 |
    ///
    /// They are the model's, not noise: its DC term is white in RGB where the reference's
    /// flat spectrum (equal energy) is (1.20, 0.95, 0.91) in Rec. 709, which alone is 0.2 F0
    /// in red; Schlick replaces both interfaces' Fresnel; the series stops at m = 2; and
    /// `R12 R23` is clamped to at least 1e-5, which leaves a ±0.007 ripple where the film
    /// matches the base (1.5 on 1.5, where the reference is flat; there `η3 = η2` up to
    /// rounding, and `φ23` with it: F0 0.04 ± 1e-9 gave 0.0187 and 0.0215). At 70° they
    /// reach 0.04 (F0 0.04, film 1.3) to 0.15 (F0 0.25, film 1.3), mostly Schlick's error
    /// at grazing angles: not tested. The tolerances sit a little above the measurements: 0.03
    /// where the film contrasts little with air and base (F0 0.04, films 1.3 and 1.5: the
    /// interference swings by under ±0.02) and 0.055 for the rest, where it swings by ±0.1
    /// to ±0.2. Each of these errors, made on purpose, failed this test (the largest
    /// difference over the cases in brackets): `φ21` or `φ23` off by π (0.35), the thickness
    /// read as micrometres (1e-6 for 1e-9 in the phase: 0.20), the path difference without
    /// its factor 2 (0.31) or with `cos θ1` for `cos θ2` (0.25), the matrix transposed
    /// (0.093), x̄'s second lobe left out (0.092), the phase sign applied to `m = 2` too
    /// (0.065).
    #[test]
    fn matches_the_spectral_reference() {
        let mut worst = Vec::new();
        for (f0, n2, tol) in [
            (0.04, 1.3, 0.03),
            (0.04, 1.5, 0.03),
            (0.04, 2.0, 0.055),
            (0.25, 1.3, 0.055),
            (0.25, 1.5, 0.055),
            (0.25, 2.0, 0.055),
        ] {
            for deg in [0.0f64, 45.0] {
                let c = libm::cos(deg.to_radians());
                let mut max: f64 = 0.0;
                for d in [200.0, 300.0, 400.0, 500.0] {
                    let (m, r) = (model(n2, f0, d, c), reference(n2, f0, d, c));
                    let diff = (m - r).abs().max_element();
                    assert!(diff < tol, "F0 {f0}, film {n2}, {deg}°, {d} nm: {m} vs {r}");
                    max = max.max(diff);
                }
                worst.push(format!("F0 {f0} film {n2} {deg}°: {max:.4}"));
            }
        }
        println!(
            "largest differences from the spectral reference:\n{}",
            worst.join("\n")
        );
    }

    /// The model's base Fresnel: Schlick with F90 = 1.
    fn schlick_f(f0: f64, c: f64) -> f64 {
        f0 + (1.0 - f0) * (1.0 - c).powi(5)
    }

    #[test]
    fn no_film_is_the_base_fresnel() {
        let f0 = DVec3::new(0.04, 0.5, 0.95);
        for c in [1.0, 0.8, 0.5, 0.2, 0.0] {
            let want = DVec3::new(schlick_f(f0.x, c), schlick_f(f0.y, c), schlick_f(f0.z, c));
            for d in [0.0, -5.0] {
                for n2 in [1.3, 2.0] {
                    let got = fresnel::<f64>(1.0, n2, c, d, f0);
                    assert!((got - want).abs().max_element() < 1e-12, "{c} {d}: {got}");
                    let got = fresnel::<f32>(1.0, n2 as f32, c as f32, d as f32, f0.as_vec3());
                    assert!((got.as_dvec3() - want).abs().max_element() < 1e-6, "{got}");
                }
            }
        }
        // Whereas a film, even a thin one, changes it.
        let thin = fresnel::<f64>(1.0, 2.0, 1.0, 20.0, DVec3::splat(0.04));
        assert!(
            (thin - DVec3::splat(0.04)).abs().min_element() > 0.01,
            "{thin}"
        );
    }

    #[test]
    fn total_reflection_under_a_coat_reflects_everything() {
        // From IOR 1.5 into a film of 1.3 beyond the critical angle (sin θ1 > 1.3/1.5).
        let got = fresnel::<f64>(1.5, 1.3, 0.3, 300.0, DVec3::splat(0.04));
        assert_eq!(got, DVec3::ONE);
        let got = fresnel::<f64>(1.5, 1.3, 0.6, 300.0, DVec3::splat(0.04));
        assert!(got.max_element() < 0.5, "{got}");
    }

    #[test]
    fn thickness_follows_the_extension() {
        assert_eq!(
            thickness(DEFAULT_THICKNESS_MIN, DEFAULT_THICKNESS_MAX, None),
            400.0
        );
        assert_eq!(thickness(100.0f32, 400.0, Some(0.0)), 100.0);
        assert_eq!(thickness(100.0f32, 400.0, Some(0.5)), 250.0);
    }

    /// Inputs over the parameters' ranges: outside IOR (air, coat), film IOR, `cos θ1`,
    /// thickness (nm, 0 and below the fade included), base F0 (dielectric, coloured
    /// metals, one channel at 1).
    fn inputs() -> Vec<(f32, f32, f32, f32, Vec3)> {
        let mut v = Vec::new();
        let bases = [
            Vec3::splat(0.05),
            Vec3::new(1.0, 0.78, 0.34),
            Vec3::new(0.95, 0.64, 0.54),
            Vec3::ZERO,
        ];
        for n1 in [1.0f32, 1.5] {
            for n2 in [1.0f32, 1.3, 1.5, 2.0, 2.5] {
                for c in [1.0f32, 0.9, 0.7, 0.5, 0.3, 0.1, 0.0] {
                    for d in [0.0f32, 0.01, 20.0, 100.0, 250.0, 400.0, 800.0, 1200.0] {
                        for f0 in bases {
                            v.push((n1, n2, c, d, f0));
                        }
                    }
                }
            }
        }
        v
    }

    #[test]
    fn f32_and_f64_agree() {
        let mut worst: f64 = 0.0;
        for (n1, n2, c, d, f0) in inputs() {
            let a = fresnel::<f32>(n1, n2, c, d, f0).as_dvec3();
            let b = fresnel::<f64>(n1.into(), n2.into(), c.into(), d.into(), f0.as_dvec3());
            let e = (a - b).abs().max_element();
            if e > 1e-4 {
                println!("BAD {n1} {n2} {c} {d} {f0}: {a} {b}");
            }
            worst = worst.max(e);
        }
        // f32's rounding of the phase (up to about 80 radians at 1200 nm) dominates.
        assert!(worst < 1e-5, "f32 and f64 differ by {worst}");
    }

    #[test]
    fn lanes_agree_with_f32() {
        let mut worst: f32 = 0.0;
        for chunk in inputs().chunks(8) {
            if chunk.len() < 8 {
                continue;
            }
            let lane = |f: fn(&(f32, f32, f32, f32, Vec3)) -> f32| {
                P::from_array(std::array::from_fn(|i| f(&chunk[i])))
            };
            let f0 = crate::simd::V3::new(lane(|x| x.4.x), lane(|x| x.4.y), lane(|x| x.4.z));
            let got = fresnel::<P>(
                lane(|x| x.0),
                lane(|x| x.1),
                lane(|x| x.2),
                lane(|x| x.3),
                f0,
            );
            for (i, &(n1, n2, c, d, f0)) in chunk.iter().enumerate() {
                let want = fresnel::<f32>(n1, n2, c, d, f0);
                let g = Vec3::new(got.x.lane(i), got.y.lane(i), got.z.lane(i));
                worst = worst.max((g - want).abs().max_element());
            }
        }
        // The lanes' cos and exp are polynomials (absolute error about 1e-7, times the
        // series' amplitudes), the scalars' the standard library's.
        assert!(worst < 1e-6, "lanes and f32 differ by {worst}");
    }
}
