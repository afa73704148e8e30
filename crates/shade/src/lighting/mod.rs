//! The one lighting model of the textbook (§9.2 and its pipeline chapter's §4), in linear RGB:
//!
//! `I = g_amb m_amb + Σ_i att_i cone_i vis_i I_i (K_d max(N·L_i, 0) + K_s S_i)`, then fog,
//!
//! with `S_i = max(R·V, 0)^n`, `R = 2N(N·L) - L` (Phong) or `S_i = max(N·H, 0)^n`,
//! `H = (L + V)/|L + V|` (Blinn). `m_amb = K_a K_d` (003: the ambient colour follows the
//! diffuse colour, `K_a` scales it). `att_i` is the light's [`Attenuation`], `cone_i` the
//! spot cone (smoothstep in `cos` between the falloff and hotspot angles) or the
//! rectangular spot's pyramid times its projected image, `vis_i` the shadow-map visibility
//! ([`ShadowMap`]). Ambient light is never attenuated or shadowed. No specular work is done
//! when `K_s = 0`, none for a light the surface faces away from, and none for a light that
//! cannot reach the object being drawn ([`Source::reaches`]).
//!
//! In the `pbr` mode the reflection of each light is the glTF BRDF ([`brdf`]) times
//! `N·L` (light intensities are irradiance: lux), and the ambient term becomes the split-sum
//! image-based term of a uniform environment whose radiance is the ambient light
//! ([`ambient`]).
//!
//! Written once, over [`Num`]: `f32` (the vertex stage and the pixel probe), `f64` (the
//! references in [`crate::quality`]) and [`F8`] (the pixel stages, eight pixels at a
//! time). Every decision is a mask and a select, with an early exit only when no lane needs
//! the work; the few reads that differ between scalars and lanes (a projected image, a
//! shadow map, the BRDF table) are the [`Shade`] trait.

use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3};

use super::brdf::{self, Layers, Pbr, Terms};
use super::shadow::ShadowMap;
use crate::scene::{Attenuation, Light, LightKind};
use crate::simd::{mad, Level, Num, Real, F8, M8, V3};
use crate::texture::env::{brdf_lut, EnvView};
use crate::texture::{Filter, Sampler, Texture, Wrap};

mod terms;
pub use terms::*;
mod fog;
pub use fog::*;

/// Largest half-angle of a spot cone or rectangular spot (just under 90 degrees: a wider
/// one is not a spot).
pub const MAX_HALF_ANGLE: f32 = 89.0 * std::f32::consts::PI / 180.0;

/// One light converted for shading: unit vectors, cosines and tangents precomputed.
#[derive(Clone, Debug)]
pub struct Source {
    /// Position in the frame's light list (what the probe and the statistics report).
    pub index: usize,
    /// Never [`LightKind::Ambient`].
    pub kind: LightKind,
    /// `color * intensity`.
    pub radiance: Vec3,
    pub position: Vec3,
    /// Unit direction the light travels (directional, spot, rectangular).
    pub axis: Vec3,
    /// Rectangular spot: unit right and up of the image, perpendicular to `axis`.
    pub right: Vec3,
    pub up: Vec3,
    pub attenuation: Attenuation,
    /// Spot: cosines of the hotspot and falloff half-angles.
    pub cos_inner: f32,
    pub cos_outer: f32,
    /// Rectangular spot: tangents of the half-angles.
    pub tan: Vec2,
    pub image: Option<Arc<Texture>>,
    /// The light asks for shadows (its `shadow` flag, for a kind that can cast them).
    pub casts: bool,
    /// Index into [`LightSet::shadows`] when the light casts shadows this frame.
    pub shadow: Option<u32>,
    /// Distance beyond which nothing arrives.
    pub reach: f32,
    /// Half-angle of a cone around `axis` that holds all the light (spot, rectangular).
    pub spread: f32,
}

/// The sampler of a projected image: bilinear, clamped to its edges.
pub const IMAGE_SAMPLER: Sampler = Sampler {
    wrap_u: Wrap::ClampToEdge,
    wrap_v: Wrap::ClampToEdge,
    filter: Filter::Bilinear,
};

impl Source {
    /// Converts `light` (in world space; `to_world` moves a camera-attached light), or
    /// `None` for ambient light and for a light that cannot shine: non-finite numbers, a
    /// zero direction, a spot without a cone, an attenuation that makes no sense.
    #[must_use]
    pub fn new(light: &Light, to_world: Option<Mat4>, index: usize) -> Option<Self> {
        let m = to_world.unwrap_or(Mat4::IDENTITY);
        let radiance = light.radiance();
        let position = m.transform_point3(light.position);
        let axis = m.transform_vector3(light.direction).normalize_or_zero();
        let kind = light.kind;
        let ok = kind != LightKind::Ambient
            && radiance.is_finite()
            && (!kind.positional() || position.is_finite())
            && (!kind.directed() || axis != Vec3::ZERO)
            && (!kind.positional() || light.attenuation.is_valid());
        if !ok {
            return None;
        }
        let attenuation = if kind.positional() {
            light.attenuation
        } else {
            Attenuation::None
        };
        let mut s = Source {
            index,
            kind,
            radiance,
            position,
            axis,
            right: Vec3::X,
            up: Vec3::Y,
            attenuation,
            cos_inner: 1.0,
            cos_outer: -1.0,
            tan: Vec2::ONE,
            image: None,
            casts: light.shadow && kind.can_shadow(),
            shadow: None,
            reach: attenuation.reach(),
            spread: std::f32::consts::PI,
        };
        match kind {
            LightKind::Spot => {
                if !(light.outer.is_finite() && light.outer > 0.0 && light.inner.is_finite()) {
                    return None;
                }
                let outer = light.outer.min(MAX_HALF_ANGLE);
                let inner = light.inner.clamp(0.0, outer);
                s.cos_inner = libm::cosf(inner);
                s.cos_outer = libm::cosf(outer);
                s.spread = outer;
            }
            LightKind::Rect => {
                let r = light.rect;
                if !(r.is_finite() && r.x > 0.0 && r.y > 0.0) {
                    return None;
                }
                let r = r.min(Vec2::splat(MAX_HALF_ANGLE));
                s.tan = Vec2::new(libm::tanf(r.x), libm::tanf(r.y));
                s.spread = libm::atanf(s.tan.length());
                let up = m.transform_vector3(light.up);
                let up = (up - axis * up.dot(axis)).normalize_or_zero();
                let up = if up == Vec3::ZERO || !up.is_finite() {
                    axis.any_orthonormal_vector()
                } else {
                    up
                };
                s.up = up;
                // Right-handed image frame looking along the axis: right = axis x up.
                s.right = axis.cross(up);
                s.image.clone_from(&light.image);
            }
            _ => {}
        }
        Some(s)
    }

    /// Whether any light can arrive inside the sphere (`center`, `radius`): false when it is
    /// beyond the attenuation's reach or outside the spot's cone (the test behind the
    /// per-object skips that `--stats` counts).
    #[must_use]
    pub fn reaches(&self, center: Vec3, radius: f32) -> bool {
        if self.kind == LightKind::Directional || !center.is_finite() || !radius.is_finite() {
            return true;
        }
        let to = center - self.position;
        let d = to.length();
        if d - radius > self.reach {
            return false;
        }
        if self.spread >= std::f32::consts::PI || d <= radius {
            return true;
        }
        // The sphere subtends asin(r / d) around its centre direction.
        let angle = libm::acosf((to.dot(self.axis) / d).clamp(-1.0, 1.0));
        angle - libm::asinf(radius / d) <= self.spread * 1.0001 + 1e-5
    }
}

/// The light set of a frame: the summed ambient light, the other lights converted, and the
/// shadow maps of those that cast shadows.
#[derive(Clone, Debug, Default)]
pub struct LightSet {
    /// Sum of ambient lights.
    pub ambient: Vec3,
    pub sources: Vec<Source>,
    /// Shadow maps, indexed by [`Source::shadow`].
    pub shadows: Vec<ShadowMap>,
    /// Lights dropped because they cannot shine (non-finite, zero direction, no cone).
    pub dropped: u32,
    /// The environment that lights `pbr` surfaces (besides the ambient light).
    pub env: Option<EnvView>,
    /// The punctual lights reflect off `pbr` surfaces by the specification's
    /// single-scattering BRDF alone, without the compensation for the energy lost between
    /// microfacets ([`crate::brdf::Pbr::ess`]).
    pub single_scatter: bool,
}

impl LightSet {
    /// Collects lights in world space.
    #[must_use]
    pub fn new(lights: &[Light]) -> Self {
        let mut set = Self::default();
        for (i, l) in lights.iter().enumerate() {
            set.push(l, None, i);
        }
        set
    }

    /// Empties the set, keeping its memory (a renderer refills it every frame). Shadow maps
    /// are kept for reuse; sources no longer point at them.
    pub fn clear(&mut self) {
        self.ambient = Vec3::ZERO;
        self.sources.clear();
        self.dropped = 0;
    }

    /// Adds light number `index` of the frame, moved by `to_world` if it is attached to the
    /// camera; one that cannot shine is counted in `dropped`.
    pub fn push(&mut self, light: &Light, to_world: Option<Mat4>, index: usize) {
        if light.kind == LightKind::Ambient {
            let c = light.radiance();
            if c.is_finite() {
                self.ambient += c;
            } else {
                self.dropped += 1;
            }
            return;
        }
        match Source::new(light, to_world, index) {
            Some(s) => self.sources.push(s),
            None => self.dropped += 1,
        }
    }

    /// The shadow map of `s`, if it has one.
    #[must_use]
    #[inline(always)]
    pub fn shadow_of(&self, s: &Source) -> Option<&ShadowMap> {
        s.shadow.and_then(|i| self.shadows.get(i as usize))
    }
}

/// The reflection parameters of a material (constant over a draw): Phong's, and the
/// metallic-roughness ones when the draw is shaded `pbr`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    pub diffuse: Vec3,
    pub specular: Vec3,
    /// Ambient factor on the diffuse colour.
    pub ambient: Vec3,
    /// Exponent n, clamped to 1..=2000 by the caller.
    pub shininess: f32,
    /// `Some` in the `pbr` mode: the glTF BRDF replaces Phong's terms, with `diffuse` as the
    /// base colour.
    pub pbr: Option<PbrParams>,
}

/// The metallic-roughness parameters of a material (factors; textures multiply them per
/// point).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PbrParams {
    pub metallic: f32,
    pub roughness: f32,
    /// The dielectric lobe's `F0` per channel (see [`Pbr::f0`]).
    pub f0: Vec3,
    /// The dielectric lobe's `F90` (see [`Pbr::f90`]): `specularFactor`.
    pub f90: f32,
    /// `F0_ior · specularColorFactor` before the clamp to 1, which a specular colour
    /// texture multiplies ([`crate::layer_maps`]).
    pub f0_tint: Vec3,
    /// `KHR_materials_clearcoat`'s factor (0: no coat) and roughness.
    pub clearcoat: f32,
    pub clearcoat_roughness: f32,
    /// `KHR_materials_sheen`'s colour (black: no sheen) and roughness.
    pub sheen_color: Vec3,
    pub sheen_roughness: f32,
    /// `KHR_materials_iridescence`'s factor (0: no film), the film's IOR and its thickness
    /// range in nm (minimum, maximum; the maximum without a thickness texture).
    pub iridescence: f32,
    pub iridescence_ior: f32,
    pub iridescence_thickness: [f32; 2],
    /// `KHR_materials_anisotropy`'s strength (0: isotropic) and rotation (radians).
    pub anisotropy: f32,
    pub anisotropy_rotation: f32,
    /// `KHR_materials_diffuse_transmission`'s factor (0: none) and colour.
    pub diffuse_transmission: f32,
    pub diffuse_transmission_color: Vec3,
    /// `KHR_materials_transmission`'s factor (0: none); `KHR_materials_volume`'s
    /// thickness (0: thin-walled), attenuation distance (infinite: none) and colour;
    /// `KHR_materials_dispersion`'s dispersion; the dielectric's IOR.
    pub transmission: f32,
    pub thickness: f32,
    pub attenuation_distance: f32,
    pub attenuation_color: Vec3,
    pub dispersion: f32,
    pub ior: f32,
}

impl Default for PbrParams {
    fn default() -> Self {
        Self {
            metallic: 1.0,
            roughness: 1.0,
            f0: Vec3::splat(0.04),
            f90: 1.0,
            f0_tint: Vec3::splat(0.04),
            clearcoat: 0.0,
            clearcoat_roughness: 0.0,
            sheen_color: Vec3::ZERO,
            sheen_roughness: 0.0,
            iridescence: 0.0,
            iridescence_ior: 1.3,
            iridescence_thickness: [100.0, 400.0],
            anisotropy: 0.0,
            anisotropy_rotation: 0.0,
            diffuse_transmission: 0.0,
            diffuse_transmission_color: Vec3::ONE,
            transmission: 0.0,
            thickness: 0.0,
            attenuation_distance: f32::INFINITY,
            attenuation_color: Vec3::ONE,
            dispersion: 0.0,
            ior: 1.5,
        }
    }
}

impl PbrParams {
    /// Whether the surface has a clear coat or a sheen over its base.
    #[must_use]
    pub fn layered(&self) -> bool {
        self.clearcoat > 0.0 || self.sheen_color.max_element() > 0.0
    }
}

impl Surface {
    /// The surface at one point whose diffuse (or base) colour is `kd` (material times
    /// texture and vertex colour), in number type `T`.
    #[must_use]
    #[inline(always)]
    pub fn at<T: Num>(&self, kd: T::V) -> SurfaceAt<T> {
        SurfaceAt {
            kd,
            ks: T::vec(self.specular),
            ka: T::vec(self.ambient),
            shininess: T::of(self.shininess),
            whole_shininess: whole_exponent(self.shininess),
            has_specular: self.specular != Vec3::ZERO || self.pbr.is_some(),
            occlusion: None,
            emitted: None,
            // `match` and `if`, not closures: a closure is compiled once, outside the
            // kernels' copies, and calls its lane instructions out of line.
            pbr: match &self.pbr {
                Some(p) => Some(Pbr {
                    metallic: T::of(p.metallic),
                    roughness: T::of(p.roughness),
                    f0: T::vec(p.f0),
                    f90: T::of(p.f90),
                    ess: T::ONE,
                    layers: if p.layered() {
                        Some(Layers {
                            coat: T::of(p.clearcoat),
                            coat_alpha: brdf::alpha(T::of(p.clearcoat_roughness)),
                            coat_roughness: T::of(p.clearcoat_roughness),
                            sheen: T::vec(p.sheen_color),
                            sheen_max: T::of(p.sheen_color.max_element()),
                            sheen_roughness: T::of(p.sheen_roughness),
                            sheen_alpha: crate::sheen::alpha(T::of(p.sheen_roughness)),
                            coat_keep: T::ONE,
                            sheen_ev: T::ZERO,
                            coat_normal: None,
                        })
                    } else {
                        None
                    },
                    iridescence: if p.iridescence > 0.0 {
                        Some(brdf::Iridescence {
                            factor: T::of(p.iridescence),
                            ior: T::of(p.iridescence_ior),
                            thickness: T::of(p.iridescence_thickness[1]),
                            dielectric: T::splat(T::ZERO),
                            metal: T::splat(T::ZERO),
                        })
                    } else {
                        None
                    },
                    // Set where the point has a tangent frame.
                    anisotropy: None,
                    transmission: if p.transmission > 0.0 {
                        Some(brdf::Transmission {
                            factor: T::of(p.transmission),
                            thickness: T::of(p.thickness),
                        })
                    } else {
                        None
                    },
                    translucency: if p.diffuse_transmission > 0.0 {
                        Some(brdf::Translucency {
                            factor: T::of(p.diffuse_transmission),
                            color: T::vec(p.diffuse_transmission_color),
                        })
                    } else {
                        None
                    },
                }),
                None => None,
            },
        }
    }
}

/// `n` as a whole number from 1 to 128 if it is one (the highlight exponents squaring
/// serves: at most 7 squarings and 7 products).
#[inline(always)]
#[must_use]
pub fn whole_exponent(n: f32) -> Option<u32> {
    ((1.0..=128.0).contains(&n) && n.fract() == 0.0).then_some(n as u32)
}

/// The reflection parameters at one point (or eight, on lanes).
#[derive(Clone, Copy, Debug)]
pub struct SurfaceAt<T: Num> {
    /// Diffuse colour `K_d` (Phong) or base colour (`pbr`).
    pub kd: T::V,
    /// Specular colour `K_s` (Phong; unused by `pbr`).
    pub ks: T::V,
    /// Ambient factor `K_a`.
    pub ka: T::V,
    pub shininess: T,
    /// `shininess` when it is a whole number from 1 to 128: the highlight is then raised to
    /// it by repeated squaring ([`Num::powi`]).
    pub whole_shininess: Option<u32>,
    /// Whether any point has a specular term (none is computed otherwise).
    pub has_specular: bool,
    /// Ambient occlusion (multiplies the ambient or image-based term only).
    pub occlusion: Option<T>,
    /// Light the surface emits, added to what it reflects.
    pub emitted: Option<T::V>,
    pub pbr: Option<Pbr<T>>,
}

/// What a number type needs beyond arithmetic to light a surface: reading a rectangular
/// spot's projected image and a shadow map at its points. Scalars read one point, lanes
/// the live lanes.
pub trait Shade: Num {
    /// The image's RGB at `(u, v)` (bilinear, clamped to its edges) where `live`.
    fn image(img: &Texture, u: Self, v: Self, live: Self::M) -> Self::V;
    /// The fraction of light `l` that reaches `p` (normal `n`) past the shadow map, where
    /// `live` (1 elsewhere).
    fn shadow(map: &ShadowMap, p: Self::V, n: Self::V, l: Self::V, live: Self::M) -> Self;
    /// The split-sum BRDF table's scale and bias `(A, B)` at `NV` and perceptual roughness,
    /// and the single-scattering albedo `E_c` the punctual lights' compensation uses
    /// (`realist_texture::env::BrdfLut::lookup_ess`).
    fn brdf_lut(nv: Self, roughness: Self) -> (Self, Self, Self);
    /// The environment's prefiltered radiance along `r` for `roughness`, and its
    /// irradiance at normal `n` over π.
    fn env(env: &EnvView, n: Self::V, r: Self::V, roughness: Self) -> (Self::V, Self::V);
    /// The sheen layer's directional albedo at `cos` (N·V or N·L) and sheen roughness
    /// ([`crate::sheen::albedo`]).
    fn sheen_albedo(cos: Self, roughness: Self) -> Self;
    /// The environment's radiance averaged over the sheen lobe of `roughness` around the
    /// normal `n` (`EnvView::sheen`).
    fn env_sheen(env: &EnvView, n: Self::V, roughness: Self) -> Self::V;
    /// A thin film's Fresnel ([`crate::iridescence::fresnel`] under air) for a film of IOR
    /// `ior` and `thickness` nm at `cos` over a base of `f0`: on lanes, lane by lane in
    /// `f32` out of line (a film is rare and its formula long: inlined into every kernel's
    /// copy of the lighting it would make the vertex shaders' functions 12 KB larger).
    fn film(ior: Self, cos: Self, thickness: Self, f0: Self::V) -> Self::V;
}

macro_rules! shade_scalar {
    ($t:ty) => {
        impl Shade for $t {
            #[inline(always)]
            fn image(img: &Texture, u: $t, v: $t, _live: bool) -> Self::V {
                let c = img.sample_with(Vec2::new(u as f32, v as f32), IMAGE_SAMPLER);
                <$t>::vec(c.truncate())
            }
            #[inline(always)]
            fn shadow(map: &ShadowMap, p: Self::V, n: Self::V, l: Self::V, _live: bool) -> $t {
                map.visibility::<$t>(p, n, l)
            }
            #[inline(always)]
            fn brdf_lut(nv: $t, roughness: $t) -> ($t, $t, $t) {
                let (a, b, e) = brdf_lut().lookup_ess(nv as f32, roughness as f32);
                (a as $t, b as $t, e as $t)
            }
            #[inline(always)]
            fn env_sheen(env: &EnvView, n: Self::V, roughness: $t) -> Self::V {
                <$t>::vec(env.sheen(<$t>::to_vec3(n), roughness as f32))
            }
            #[inline(always)]
            fn film(ior: $t, cos: $t, thickness: $t, f0: Self::V) -> Self::V {
                crate::iridescence::fresnel::<$t>(1.0, ior, cos, thickness, f0)
            }
            #[inline(always)]
            fn sheen_albedo(cos: $t, roughness: $t) -> $t {
                crate::sheen::albedo(cos as f32, roughness as f32) as $t
            }
            #[inline(always)]
            fn env(env: &EnvView, n: Self::V, r: Self::V, roughness: $t) -> (Self::V, Self::V) {
                let (n, r) = (<$t>::to_vec3(n), <$t>::to_vec3(r));
                let s = env.specular(r, roughness as f32);
                let e = env.irradiance(n) * std::f32::consts::FRAC_1_PI;
                (<$t>::vec(s), <$t>::vec(e))
            }
        }
    };
}
shade_scalar!(f32);
shade_scalar!(f64);

impl<L: Level> Shade for F8<L> {
    #[inline(always)]
    fn image(img: &Texture, u: Self, v: Self, live: M8<L>) -> V3<L> {
        let c = img.sample_lanes(u, v, live.bits(), IMAGE_SAMPLER);
        V3::new(c[0], c[1], c[2])
    }
    #[inline(always)]
    fn shadow(map: &ShadowMap, p: V3<L>, n: V3<L>, l: V3<L>, live: M8<L>) -> Self {
        map.visibility_lanes(p, n, l, live.bits())
    }
    #[inline(always)]
    fn brdf_lut(nv: Self, roughness: Self) -> (Self, Self, Self) {
        let [a, b, e] = brdf_lut().lookup_ess_lanes(nv, roughness);
        (a, b, e)
    }
    #[inline(always)]
    fn env_sheen(env: &EnvView, n: V3<L>, roughness: Self) -> V3<L> {
        let (sin, cos) = env.rotation_sin_cos();
        let (u, v) = env_uv(n, F8::splat(sin), F8::splat(cos));
        let [r, g, b] = env.env.sheen_lanes(u, v, roughness);
        V3::new(r, g, b) * F8::splat(env.intensity)
    }
    #[inline(always)]
    fn film(ior: Self, cos: Self, thickness: Self, f0: V3<L>) -> V3<L> {
        let (ior, c, d) = (ior.to_array(), cos.to_array(), thickness.to_array());
        let (x, y, z) = (f0.x.to_array(), f0.y.to_array(), f0.z.to_array());
        let mut out = [[0.0; 8]; 3];
        for i in 0..crate::simd::LANES {
            let f = crate::iridescence::film_f32(ior[i], c[i], d[i], Vec3::new(x[i], y[i], z[i]));
            (out[0][i], out[1][i], out[2][i]) = (f.x, f.y, f.z);
        }
        V3::new(
            F8::from_array(out[0]),
            F8::from_array(out[1]),
            F8::from_array(out[2]),
        )
    }
    #[inline(always)]
    fn sheen_albedo(cos: Self, roughness: Self) -> Self {
        let (c, r) = (cos.to_array(), roughness.to_array());
        let mut e = [0.0; 8];
        for i in 0..crate::simd::LANES {
            e[i] = crate::sheen::albedo(c[i], r[i]);
        }
        F8::from_array(e)
    }
    #[inline(always)]
    fn env(env: &EnvView, n: V3<L>, r: V3<L>, roughness: Self) -> (V3<L>, V3<L>) {
        // The rotation and the image coordinates (`F8::atan2` and `F8::acos`, within 2e-5
        // rad: a thousandth of a texel of the largest level) and the reads (`lanes.rs` in
        // the environment's module) on all lanes at once.
        let (sin, cos) = env.rotation_sin_cos();
        let (sin, cos) = (F8::splat(sin), F8::splat(cos));
        let ((ur, vr), (un, vn)) = (env_uv(r, sin, cos), env_uv(n, sin, cos));
        let [sr, sg, sb] = env.env.specular_lanes(ur, vr, roughness);
        let [er, eg, eb] = env.env.irradiance_lanes(un, vn);
        let k = F8::splat(env.intensity);
        (V3::new(sr, sg, sb) * k, V3::new(er, eg, eb) * k)
    }
}

/// The equirect image coordinates of eight directions `d` turned by the rotation whose
/// sine and cosine are `sin`, `cos` (`EnvView::to_image`, `env::dir_to_uv`).
#[inline(always)]
fn env_uv<L: Level>(d: V3<L>, sin: F8<L>, cos: F8<L>) -> (F8<L>, F8<L>) {
    let d = V3::new(mad(d.x, cos, d.z * sin), d.y, mad(d.z, cos, -(d.x * sin))).normalize_or_zero();
    let u = mad(
        d.z.atan2(d.x),
        F8::splat(0.5 * std::f32::consts::FRAC_1_PI),
        F8::splat(0.5),
    );
    (u, d.y.acos() * F8::splat(std::f32::consts::FRAC_1_PI))
}
#[cfg(test)]
mod tests;
