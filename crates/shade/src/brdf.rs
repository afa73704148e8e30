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

use super::lighting::{Shade, SurfaceAt};
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
    /// The clear coat and the sheen over the base, if the material has either.
    pub layers: Option<Layers<T>>,
    /// The thin film on the base (`KHR_materials_iridescence`), if the material has one.
    pub iridescence: Option<Iridescence<T>>,
    /// The base's anisotropy (`KHR_materials_anisotropy`) at the point, where the material
    /// has it and the point a tangent frame ([`Anisotropy::at`]).
    pub anisotropy: Option<Anisotropy<T>>,
    /// The base's diffuse transmission (`KHR_materials_diffuse_transmission`), if any.
    pub translucency: Option<Translucency<T>>,
    /// The base's specular transmission (`KHR_materials_transmission`), if any: its
    /// diffuse terms are scaled by `1 - factor`, and the light through it is added by the
    /// shader's `transmit` stage.
    pub transmission: Option<Transmission<T>>,
}

/// Specular transmission (`KHR_materials_transmission`, `KHR_materials_volume`): the
/// dielectric base's `mix(diffuse, specular_btdf x baseColor, factor)`.
#[derive(Clone, Copy, Debug)]
pub struct Transmission<T: Num> {
    pub factor: T,
    /// The volume's thickness under the surface (mesh units; 0: thin-walled).
    pub thickness: T,
}

/// Diffuse transmission (`KHR_materials_diffuse_transmission`): the dielectric base's
/// diffuse term becomes `mix(diffuse_brdf(baseColor), diffuse_btdf(color), factor)`, the
/// BTDF Lambert's `color / π` for light from the other side ([`translucent`]); Fresnel
/// and the specular lobe are unchanged.
#[derive(Clone, Copy, Debug)]
pub struct Translucency<T: Num> {
    pub factor: T,
    pub color: T::V,
}

/// What light `l` arriving from behind (`ndl = N·L < 0`) gives through a translucent base,
/// per unit irradiance: `factor color / π (1 - metallic) (1 - max F) (-N·L)`, with the
/// dielectric's Fresnel `F` at the light mirrored to the front (as the Khronos sample
/// viewer takes it).
#[inline(always)]
#[must_use]
pub fn translucent<T: Num>(
    p: &Pbr<T>,
    tr: &Translucency<T>,
    n: T::V,
    l: T::V,
    v: T::V,
    ndl: T,
) -> T::V {
    let mirrored = l - n * (ndl + ndl);
    let vh = T::dot(v, T::normalize_or_zero(mirrored + v)).max(T::ZERO);
    let fd = schlick::<T>(p.f0, p.f90, schlick_weight(vh));
    let k = tr.factor
        * (T::ONE - p.metallic)
        * (T::ONE - T::vmax(fd))
        * T::of64(std::f64::consts::FRAC_1_PI)
        * (-ndl).max(T::ZERO);
    tr.color * k
}

/// An anisotropic base (`KHR_materials_anisotropy`): GGX with the roughness `α_t =
/// mix(α, 1, strength²)` along the direction `t` and `α_b = α` across it (the
/// specification's `D` and `V`); under the environment, the prefiltered light is read about
/// a normal bent towards the direction (Filament's, which three.js uses).
#[derive(Clone, Copy, Debug)]
pub struct Anisotropy<T: Num> {
    pub strength: T,
    /// The unit direction the highlight stretches along, and `N × t`.
    pub t: T::V,
    pub b: T::V,
}

impl<T: Num> Anisotropy<T> {
    /// The frame at a point of unit shading normal `n` and interpolated tangent `tangent`
    /// (its handedness `w`): the direction `dir` in the tangent frame (the texture's RG
    /// mapped to [-1, 1], else +x), turned by `anisotropyRotation` (`rotation`: its cosine
    /// and sine), and `strength` (`anisotropyStrength` times the texture's B).
    #[inline(always)]
    #[must_use]
    pub fn at(n: T::V, tangent: T::V, w: T, dir: [T; 2], rotation: [f32; 2], strength: T) -> Self {
        let t = T::normalize_or_zero(tangent - n * T::dot(n, tangent));
        let b = T::cross(n, t) * T::select(T::ZERO.gt(w), -T::ONE, T::ONE);
        let (c, s) = (T::of(rotation[0]), T::of(rotation[1]));
        let (x, y) = (c * dir[0] - s * dir[1], s * dir[0] + c * dir[1]);
        let t = T::normalize_or_zero(t * x + b * y);
        Self {
            strength: strength.clamp01(),
            t,
            b: T::cross(n, t),
        }
    }

    /// `α_t` and `α_b` for the isotropic α.
    #[inline(always)]
    #[must_use]
    pub fn alphas(&self, alpha: T) -> (T, T) {
        let s2 = self.strength * self.strength;
        (alpha + (T::ONE - alpha) * s2, alpha)
    }

    /// The normal the environment's prefiltered light is read about, for the unit normal `n`,
    /// view `v` and perceptual `roughness`: `n` bent towards the one that sees `v` across
    /// the direction, the more the stronger and smoother (`(1 - strength (1 -
    /// roughness))⁴` of `n` left).
    #[inline(always)]
    #[must_use]
    pub fn bent(&self, n: T::V, v: T::V, roughness: T) -> T::V {
        let across = T::normalize_or_zero(T::cross(T::cross(self.b, v), self.b));
        let k = T::ONE - self.strength * (T::ONE - roughness);
        let k2 = k * k;
        T::normalize_or_zero(across + (n - across) * (k2 * k2))
    }
}

/// The anisotropic GGX `D` at `N·H`, `T·H`, `B·H` for `α_t`, `α_b`
/// (`KHR_materials_anisotropy`).
#[inline(always)]
#[must_use]
pub fn ggx_aniso<T: Num>(nh: T, th: T, bh: T, at: T, ab: T) -> T {
    let a2 = at * ab;
    let (x, y, z) = (ab * th, at * bh, a2 * nh);
    let w2 = a2 / (x * x + y * y + z * z).max(T::of(1e-30));
    a2 * w2 * w2 * T::of64(std::f64::consts::FRAC_1_PI)
}

/// The anisotropic height-correlated Smith visibility (`KHR_materials_anisotropy`), at
/// most 1.
#[inline(always)]
#[must_use]
#[allow(clippy::too_many_arguments)]
pub fn smith_vis_aniso<T: Num>(nl: T, nv: T, tv: T, bv: T, tl: T, bl: T, at: T, ab: T) -> T {
    let gv = nl * length3(at * tv, ab * bv, nv);
    let gl = nv * length3(at * tl, ab * bl, nl);
    (T::of(0.5) / (gv + gl).max(T::of(1e-30))).min(T::ONE)
}

/// `√(x² + y² + z²)` (a function, not a closure: lane code stays inline).
#[inline(always)]
fn length3<T: Num>(x: T, y: T, z: T) -> T {
    (x * x + y * y + z * z).sqrt()
}

/// A thin film on the base (`KHR_materials_iridescence`): each lobe's Fresnel becomes
/// `mix(F_schlick, F_film, iridescence)`, `F_film` the film's reflectance
/// ([`crate::iridescence::fresnel`]) over the lobe's `F0` (the dielectric's, and the base
/// colour for the metal), evaluated once per point at `N·V` as the Khronos sample viewer and
/// three.js do (the extension's model takes it at `V·H` per light; `N·V` is its value for
/// a light reflected towards the eye along the normal). Under the environment the film's
/// Fresnel is taken back to an `F0` for the split sum (three.js's `Schlick_to_F0`).
#[derive(Clone, Copy, Debug)]
pub struct Iridescence<T: Num> {
    /// `iridescenceFactor` (0: no film).
    pub factor: T,
    /// The film's IOR and thickness (nm).
    pub ior: T,
    pub thickness: T,
    /// At the point, set with the view ([`Iridescence::view`]): the film's Fresnel over
    /// the dielectric lobe and over the metal.
    pub dielectric: T::V,
    pub metal: T::V,
}

impl<T: Num> Iridescence<T> {
    /// Sets the film's Fresnel at `nv` over the dielectric's `f0` and the metal's base
    /// colour `kd`.
    #[inline(always)]
    pub fn view(&mut self, nv: T, f0: T::V, kd: T::V)
    where
        T: Shade,
    {
        self.dielectric = T::film(self.ior, nv, self.thickness, f0);
        self.metal = T::film(self.ior, nv, self.thickness, kd);
    }

    /// `F` mixed with the film's `film` by the factor.
    #[inline(always)]
    #[must_use]
    pub fn mix(&self, f: T::V, film: T::V) -> T::V {
        f + (film - f) * self.factor
    }

    /// The `F0` whose Schlick Fresnel (`F90 = 1`) is `f` at `nv` (three.js's
    /// `Schlick_to_F0`, the weight clamped below 1), for the split sum.
    #[inline(always)]
    #[must_use]
    pub fn to_f0(f: T::V, nv: T) -> T::V {
        let x5 = schlick_weight(nv).min(T::of(0.9999));
        (f - T::splat(x5)) * (T::ONE / (T::ONE - x5))
    }
}

/// The layers over a `pbr` base (`KHR_materials_clearcoat`, `KHR_materials_sheen`), as the
/// specifications stack them: `coated = mix(sheened, coat, clearcoat Fr(N·V))`, `sheened =
/// sheen + base (1 - max(sheenColor) E)`, with `Fr` the coat's Schlick Fresnel (F0 0.04:
/// its IOR is 1.5) at the view and `E` the sheen's directional albedo
/// ([`crate::sheen::albedo`]) at the view and, for a light, the larger of it at the view and
/// at the light.
#[derive(Clone, Copy, Debug)]
pub struct Layers<T: Num> {
    /// `clearcoatFactor` (0: none), the coat's perceptual roughness and α.
    pub coat: T,
    pub coat_roughness: T,
    pub coat_alpha: T,
    /// `sheenColorFactor` (black: none), its largest component, its roughness and α
    /// ([`crate::sheen::alpha`]).
    pub sheen: T::V,
    pub sheen_max: T,
    pub sheen_roughness: T,
    pub sheen_alpha: T,
    /// At the point, set with the view ([`Layers::view`]): what the coat lets through,
    /// `1 - clearcoat Fr(N·V)`, and the sheen's albedo at the view.
    pub coat_keep: T,
    pub sheen_ev: T,
    /// The coat's own unit normal at the point, where it differs from the shading normal:
    /// the interpolated (geometric) normal when the base has a normal or bump map, which the
    /// coat does not follow (`KHR_materials_clearcoat`: without a `clearcoatNormalTexture`
    /// no normal mapping applies to the coat).
    pub coat_normal: Option<T::V>,
}

/// The clear coat's Fresnel at normal incidence (IOR 1.5).
pub const COAT_F0: f32 = 0.04;

impl<T: Num> Layers<T> {
    /// Sets the per-point values for `N·V` (`nv` with the coat's normal: `sheen_ev` from
    /// the sheen's table at the shading normal's `N·V` and the sheen roughness).
    #[inline(always)]
    pub fn view(&mut self, nv: T, sheen_ev: T) {
        let fr = T::of(COAT_F0) + T::of(1.0 - COAT_F0) * schlick_weight(nv);
        self.coat_keep = T::ONE - self.coat * fr;
        self.sheen_ev = sheen_ev;
    }
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
    /// The sheen and clear-coat layers' own reflection times `NL` (included in
    /// `specular`; zero without layers).
    pub sheen: T::V,
    pub coat: T::V,
}

/// The metallic-roughness BRDF times `NL` for unit normal `n`, light direction `l` and
/// view vector `v`, on the lanes where `lit` (`NL = ndl > 0` there).
#[inline(always)]
#[must_use]
pub fn pbr<T: Shade>(
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
    let (d, vis) = match &p.anisotropy {
        Some(a) => {
            let (at, ab) = a.alphas(alpha);
            let (th, bh) = (T::dot(a.t, h), T::dot(a.b, h));
            let (tv, bv, tl, bl) = (
                T::dot(a.t, v),
                T::dot(a.b, v),
                T::dot(a.t, l),
                T::dot(a.b, l),
            );
            (
                ggx_aniso(nh, th, bh, at, ab),
                smith_vis_aniso(ndl, nv, tv, bv, tl, bl, at, ab),
            )
        }
        None => (ggx(nh, alpha), smith_vis(ndl, nv, alpha)),
    };
    let w = schlick_weight(vh);
    let mut fd = schlick::<T>(p.f0, p.f90, w);
    let mut fm = schlick::<T>(s.kd, T::ONE, w);
    if let Some(i) = &p.iridescence {
        fd = i.mix(fd, i.dielectric);
        fm = i.mix(fm, i.metal);
    }
    let dielectric = T::ONE - p.metallic;
    let fresnel = fd * dielectric + fm * p.metallic;
    let inv_pi = T::of64(std::f64::consts::FRAC_1_PI);
    let mut diffuse = s.kd * (dielectric * (T::ONE - T::vmax(fd)) * inv_pi * ndl);
    if let Some(tr) = &p.translucency {
        diffuse = diffuse * (T::ONE - tr.factor);
    }
    if let Some(t) = &p.transmission {
        diffuse = diffuse * (T::ONE - t.factor);
    }
    // The energy lost between microfacets, given back: each lobe times 1 + F0 (1/E_ss - 1)
    // (exactly 1 when E_ss = 1).
    let k = T::ONE / p.ess.max(T::of(1e-3)) - T::ONE;
    let one = T::splat(T::ONE);
    let lobes = fd * (one + p.f0 * k) * dielectric + fm * (one + s.kd * k) * p.metallic;
    let specular = lobes * (vis * d * ndl);
    let zero = T::splat(T::ZERO);
    let Some(y) = &p.layers else {
        return Terms {
            diffuse,
            specular,
            d,
            vis,
            fresnel,
            sheen: zero,
            coat: zero,
        };
    };
    // The coat's angles: with its own normal where it has one.
    let (cnh, cnl, cnv) = match y.coat_normal {
        Some(nc) => (
            T::dot(nc, h).max(T::ZERO),
            T::dot(nc, l).max(T::ZERO),
            T::dot(nc, v).max(T::of(1e-4)),
        ),
        None => (nh, ndl, nv),
    };
    let [diffuse, specular, sheen, coat] =
        layer(y, diffuse, specular, [nh, ndl, nv], [cnh, cnl, cnv]);
    Terms {
        diffuse,
        specular: specular + sheen + coat,
        d,
        vis,
        fresnel,
        sheen,
        coat,
    }
}

/// The base's diffuse and specular reflection under the layers `y` for one light, and the
/// layers' own reflection (sheen, coat), all times `NL` (see [`Layers`]).
#[inline(always)]
fn layer<T: Shade>(
    y: &Layers<T>,
    diffuse: T::V,
    specular: T::V,
    [nh, ndl, nv]: [T; 3],
    [cnh, cnl, cnv]: [T; 3],
) -> [T::V; 4] {
    let zero = T::splat(T::ZERO);
    let (mut diffuse, mut specular, mut sheen, mut coat) = (diffuse, specular, zero, zero);
    if T::any(y.sheen_max.gt(T::ZERO)) {
        let el = T::sheen_albedo(ndl, y.sheen_roughness);
        let scale = (T::ONE - y.sheen_max * y.sheen_ev.max(el)).max(T::ZERO);
        diffuse = diffuse * scale;
        specular = specular * scale;
        sheen = y.sheen * crate::sheen::lobe(nh, ndl, nv, y.sheen_alpha);
    }
    if T::any(y.coat.gt(T::ZERO)) {
        // mix(beneath, coat, clearcoat Fr(N·V)): the coat lobe is D Vis without a Fresnel
        // of its own (the mix weight is its Fresnel).
        let lobe = ggx(cnh, y.coat_alpha) * smith_vis(cnl, cnv, y.coat_alpha) * cnl;
        coat = T::splat((T::ONE - y.coat_keep) * lobe);
        diffuse = diffuse * y.coat_keep;
        specular = specular * y.coat_keep;
        sheen = sheen * y.coat_keep;
    }
    [diffuse, specular, sheen, coat]
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
