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

use super::brdf::{self, Pbr, Terms};
use super::shadow::ShadowMap;
use crate::scene::{Attenuation, Light, LightKind};
use crate::simd::{mad, Level, Num, Real, F8, M8, V3};
use crate::texture::env::{brdf_lut, EnvView};
use crate::texture::{Filter, Sampler, Texture, Wrap};

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
                s.cos_inner = inner.cos();
                s.cos_outer = outer.cos();
                s.spread = outer;
            }
            LightKind::Rect => {
                let r = light.rect;
                if !(r.is_finite() && r.x > 0.0 && r.y > 0.0) {
                    return None;
                }
                let r = r.min(Vec2::splat(MAX_HALF_ANGLE));
                s.tan = Vec2::new(r.x.tan(), r.y.tan());
                s.spread = s.tan.length().atan();
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
        let angle = (to.dot(self.axis) / d).clamp(-1.0, 1.0).acos();
        angle - (radius / d).asin() <= self.spread * 1.0001 + 1e-5
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
    /// The dielectric lobe's `F90` (see [`Pbr::f90`]).
    pub f90: f32,
}

impl Default for PbrParams {
    fn default() -> Self {
        Self {
            metallic: 1.0,
            roughness: 1.0,
            f0: Vec3::splat(0.04),
            f90: 1.0,
        }
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
            pbr: self.pbr.map(|p| Pbr {
                metallic: T::of(p.metallic),
                roughness: T::of(p.roughness),
                f0: T::vec(p.f0),
                f90: T::of(p.f90),
            }),
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
    /// The split-sum BRDF table's scale and bias `(A, B)` at `NV` and perceptual roughness.
    fn brdf_lut(nv: Self, roughness: Self) -> (Self, Self);
    /// The environment's prefiltered radiance along `r` for `roughness`, and its
    /// irradiance at normal `n` over π.
    fn env(env: &EnvView, n: Self::V, r: Self::V, roughness: Self) -> (Self::V, Self::V);
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
            fn brdf_lut(nv: $t, roughness: $t) -> ($t, $t) {
                let (a, b) = brdf_lut().lookup(nv as f32, roughness as f32);
                (a as $t, b as $t)
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
    fn brdf_lut(nv: Self, roughness: Self) -> (Self, Self) {
        let lut = brdf_lut();
        let (nv, r) = (nv.to_array(), roughness.to_array());
        let (mut a, mut b) = ([0.0; 8], [0.0; 8]);
        for i in 0..crate::simd::LANES {
            (a[i], b[i]) = lut.lookup(nv[i], r[i]);
        }
        (F8::from_array(a), F8::from_array(b))
    }
    #[inline(always)]
    fn env(env: &EnvView, n: V3<L>, r: V3<L>, roughness: Self) -> (V3<L>, V3<L>) {
        // The rotation and the image coordinates on all lanes at once (`F8::atan2` and
        // `F8::acos`, within 2e-5 rad: a thousandth of a texel of the largest level); the
        // texel reads per lane.
        let (sin, cos) = env.rotation_sin_cos();
        let (sin, cos) = (F8::splat(sin), F8::splat(cos));
        let ((ur, vr), (un, vn)) = (env_uv(r, sin, cos), env_uv(n, sin, cos));
        let (ur, vr, un, vn) = (ur.to_array(), vr.to_array(), un.to_array(), vn.to_array());
        let rough = roughness.to_array();
        let k = env.intensity;
        let (mut s, mut e) = ([[0.0; 8]; 3], [[0.0; 8]; 3]);
        for i in 0..crate::simd::LANES {
            let si = env.env.specular_uv(ur[i], vr[i], rough[i]) * k;
            let ei = env.env.irradiance_uv(un[i], vn[i]) * k;
            for c in 0..3 {
                s[c][i] = si[c];
                e[c][i] = ei[c];
            }
        }
        let v3 = |a: [[f32; 8]; 3]| {
            V3::new(
                F8::from_array(a[0]),
                F8::from_array(a[1]),
                F8::from_array(a[2]),
            )
        };
        (v3(s), v3(e))
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

/// The attenuation factor of `a` at distance `d`.
#[inline(always)]
#[must_use]
pub fn attenuate<T: Num>(a: Attenuation, d: T) -> T {
    match a {
        Attenuation::None => T::ONE,
        Attenuation::Linear { near, far } => {
            let ramp = (T::of(far) - d) / T::of((far - near).max(f32::MIN_POSITIVE));
            T::select(d.gt(T::of(near)), ramp.clamp01(), T::ONE)
        }
        Attenuation::InverseSquare => (d * d).max(T::of64(crate::scene::MIN_D2)).recip(),
        Attenuation::Range(r) => {
            let q = d / T::of(r);
            let q2 = q * q;
            (T::ONE - q2 * q2).clamp01() / (d * d).max(T::of64(crate::scene::MIN_D2))
        }
    }
}

/// The spot factor for `cos_axis`, the cosine of the angle between the spot's axis and the
/// ray to the point: 1 inside the hotspot, 0 outside the falloff, smoothstep between.
#[inline(always)]
#[must_use]
pub fn cone<T: Num>(s: &Source, cos_axis: T) -> T {
    let (ci, co) = (T::of(s.cos_inner), T::of(s.cos_outer));
    let w = (ci - co).max(T::of(1e-4));
    let t = ((cos_axis - co) / w).clamp01();
    t * t * (T::of(3.0) - t - t)
}

/// Where the ray from a rectangular spot to a point falls on its image, as (u, v) with the
/// pyramid at |u|, |v| <= 1, and where that is inside the pyramid (in front of the light
/// and within it). `ray` need not be unit.
#[inline(always)]
#[must_use]
pub fn pyramid<T: Num>(s: &Source, ray: T::V) -> (T, T, T::M) {
    let z = T::dot(ray, T::vec(s.axis));
    let x = T::dot(ray, T::vec(s.right)) / (z * T::of(s.tan.x));
    let y = T::dot(ray, T::vec(s.up)) / (z * T::of(s.tan.y));
    let one = T::ONE;
    let inside = z.gt(T::ZERO) & x.ge(-one) & one.ge(x) & y.ge(-one) & one.ge(y);
    (x, y, inside)
}

/// What arrives at `p` from `s` before shadowing: the unit direction towards the light,
/// the radiance after attenuation, cone or pyramid and projected image, and where any
/// arrives; `None` when nothing does anywhere.
#[inline(always)]
#[must_use]
pub fn arriving<T: Shade>(s: &Source, p: T::V) -> Option<(T::V, T::V, T::M)> {
    let mut rad = T::vec(s.radiance);
    if s.kind == LightKind::Directional {
        return Some((-T::vec(s.axis), rad, T::ONE.gt(T::ZERO)));
    }
    let to = T::vec(s.position) - p;
    let d = T::length(to);
    let ok = d.gt(T::ZERO) & d.finite();
    let l = to * T::select(ok, d.recip(), T::ZERO);
    let mut f = attenuate(s.attenuation, d);
    match s.kind {
        LightKind::Spot => f = f * cone(s, -T::dot(l, T::vec(s.axis))),
        LightKind::Rect => {
            let (x, y, inside) = pyramid::<T>(s, -l);
            f = T::select(inside, f, T::ZERO);
            if let Some(img) = &s.image {
                let half = T::of(0.5);
                let c = T::image(img, (x + T::ONE) * half, (T::ONE - y) * half, inside & ok);
                rad = rad * c;
            }
        }
        _ => {}
    }
    let live = f.gt(T::ZERO) & ok;
    if T::any(live) {
        Some((l, rad * f, live))
    } else {
        None
    }
}

/// Diffuse and specular reflection of unit light direction `l` at unit normal `n`, unit
/// view vector `v` (zero without a specular term), per unit irradiance, where `lit`
/// (`ndl = N·L > 0` there): `K_d (N·L)` and `K_s S` with `S` as in the module
/// documentation, or the glTF BRDF times `N·L` ([`brdf::pbr`]) when the surface has PBR
/// parameters; zero elsewhere.
#[inline(always)]
#[must_use]
pub fn reflect<T: Num>(
    s: &SurfaceAt<T>,
    n: T::V,
    l: T::V,
    v: T::V,
    lit: T::M,
    ndl: T,
    blinn: bool,
) -> Terms<T> {
    let zero = T::splat(T::ZERO);
    let ndl = T::select(lit, ndl, T::ZERO);
    if let Some(p) = &s.pbr {
        let t = brdf::pbr(s, p, brdf::alpha(p.roughness), n, l, v, ndl);
        return Terms {
            diffuse: T::vselect(lit, t.diffuse, zero),
            specular: T::vselect(lit, t.specular, zero),
            ..t
        };
    }
    let diffuse = s.kd * ndl;
    let mut specular = zero;
    if s.has_specular {
        let base = if blinn {
            T::dot(n, T::normalize_or_zero(l + v))
        } else {
            T::dot(n * (ndl + ndl) - l, v)
        };
        let on = lit & base.gt(T::ZERO);
        if T::any(on) {
            let lobe = match s.whole_shininess {
                Some(n) => base.powi(n),
                None => base.powf(s.shininess),
            };
            let lobe = T::select(on, lobe, T::ZERO);
            specular = s.ks * lobe;
        }
    }
    Terms {
        diffuse,
        specular,
        d: T::ZERO,
        vis: T::ZERO,
        fresnel: zero,
    }
}

/// Light `s`'s share of the colour at `p` (normal `n`, view vector `v`), shadow included.
#[inline(always)]
#[must_use]
pub fn contribution<T: Shade>(
    set: &LightSet,
    s: &Source,
    surf: &SurfaceAt<T>,
    p: T::V,
    n: T::V,
    v: T::V,
    blinn: bool,
) -> T::V {
    let zero = T::splat(T::ZERO);
    let Some((l, rad, live)) = arriving::<T>(s, p) else {
        return zero;
    };
    let ndl = T::dot(n, l);
    let lit = ndl.gt(T::ZERO) & live;
    if !T::any(lit) {
        return zero;
    }
    let r = reflect(surf, n, l, v, lit, ndl, blinn);
    let t = (r.diffuse + r.specular) * rad;
    match set.shadow_of(s) {
        Some(map) => t * T::shadow(map, p, n, l, lit),
        None => t,
    }
}

/// The view vector for the specular term: unit towards the eye, or zero when the surface
/// has no specular term (none is needed).
#[inline(always)]
#[must_use]
pub fn view_vector<T: Num>(surf: &SurfaceAt<T>, p: T::V, eye: T::V) -> T::V {
    if surf.has_specular {
        T::normalize_or_zero(eye - p)
    } else {
        T::splat(T::ZERO)
    }
}

/// The ambient term: `g_amb K_a K_d` times the occlusion (Phong), or for `pbr` the
/// ambient light as a uniform environment of that radiance, reflected by the split-sum
/// image-based term ([`brdf::ibl_fresnel`]) and times the occlusion.
#[inline(always)]
#[must_use]
pub fn ambient<T: Shade>(set: &LightSet, s: &SurfaceAt<T>, n: T::V, v: T::V) -> T::V {
    let (diffuse, specular) = ambient_split(set, s, n, v);
    let c = diffuse + specular;
    match s.occlusion {
        Some(ao) => c * ao,
        None => c,
    }
}

/// [`ambient`] before the occlusion, as its diffuse and specular parts (the pixel probe
/// lists both; Phong's is all diffuse).
#[inline(always)]
#[must_use]
pub fn ambient_split<T: Shade>(set: &LightSet, s: &SurfaceAt<T>, n: T::V, v: T::V) -> (T::V, T::V) {
    let g = T::vec(set.ambient);
    let Some(p) = &s.pbr else {
        return (g * s.ka * s.kd, T::splat(T::ZERO));
    };
    let nv = T::dot(n, v).max(T::of(1e-4));
    let (a, b) = T::brdf_lut(nv, p.roughness);
    // Prefiltered radiance along the reflection and irradiance over π: the ambient light
    // is a uniform environment, where both equal its radiance.
    let (prefiltered, irradiance) = match &set.env {
        Some(env) => {
            // Frostbite's dominant direction (Lagarde & de Rousiers 2014, §4.9.3): a rough
            // lobe's peak leans from the mirror direction toward the normal; at grazing
            // views on rough metal, reading the chain along the mirror direction measured
            // 18 % too bright against the integral.
            let alpha = brdf::alpha(p.roughness);
            let smooth = T::ONE - alpha;
            let lean = smooth * (smooth.sqrt() + alpha);
            let r = n + (n * (nv + nv) - v - n) * lean;
            let (s, e) = T::env(env, n, r, p.roughness);
            (s + g, e + g)
        }
        None => (g, g),
    };
    let (d_ss, d_ms) = brdf::ibl_fresnel::<T>(p.f0, p.f90, a, b);
    let (m_ss, m_ms) = brdf::ibl_fresnel::<T>(s.kd, T::ONE, a, b);
    // Dielectric: the diffuse term gets the energy the specular lobe leaves.
    let left = T::splat(T::ONE) - d_ss - d_ms;
    let dielectric = T::ONE - p.metallic;
    let diffuse = s.kd * left * irradiance * dielectric;
    let specular = (d_ss * prefiltered + d_ms * irradiance) * dielectric
        + (m_ss * prefiltered + m_ms * irradiance) * p.metallic;
    (diffuse, specular)
}

/// The lighting equation at `p` with unit normal `n` and the eye at `eye`, summed over the
/// sources `active` (indices into `set.sources`; all of them if `None`), plus the
/// surface's emission. Fog is applied separately ([`Fog::apply`]).
#[must_use]
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn illuminate<T: Shade>(
    set: &LightSet,
    active: Option<&[u32]>,
    surf: &SurfaceAt<T>,
    p: T::V,
    n: T::V,
    eye: T::V,
    blinn: bool,
) -> T::V {
    let v = view_vector(surf, p, eye);
    let mut c = ambient(set, surf, n, v);
    if let Some(e) = surf.emitted {
        c = c + e;
    }
    // One loop body for both cases: it is inlined into every shader of every kernel, so a
    // second copy would double the largest functions the compiler sees.
    let count = active.map_or(set.sources.len(), <[u32]>::len);
    for k in 0..count {
        let i = active.map_or(k, |a| a[k] as usize);
        if let Some(s) = set.sources.get(i) {
            c = c + contribution(set, s, surf, p, n, v, blinn);
        }
    }
    c
}

/// How fog measures distance.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub enum FogDistance {
    /// From the eye (spherical fog; does not change as the camera turns).
    #[default]
    Euclidean,
    /// Camera-space depth (cheaper on old hardware, changes as the camera turns).
    Depth,
}

impl FogDistance {
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            FogDistance::Euclidean => "euclidean",
            FogDistance::Depth => "depth",
        }
    }
}

impl std::str::FromStr for FogDistance {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "euclidean" | "spherical" | "radial" => Ok(FogDistance::Euclidean),
            "depth" | "z" | "planar" => Ok(FogDistance::Depth),
            _ => Err(format!(
                "unknown fog distance '{s}' (expected euclidean or depth)"
            )),
        }
    }
}

/// Linear fog (003 §5.1): `f = clamp((d - near) / (far - near), 0, 1)`,
/// `C = C_lit + f (g_fog - C_lit)`; alpha is kept.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fog {
    /// Linear RGB.
    pub color: Vec3,
    /// d_min: no fog nearer.
    pub near: f32,
    /// d_max: only fog farther.
    pub far: f32,
    pub distance: FogDistance,
}

impl Default for Fog {
    fn default() -> Self {
        Self {
            color: Vec3::splat(0.6),
            near: 2.0,
            far: 12.0,
            distance: FogDistance::Euclidean,
        }
    }
}

impl Fog {
    /// Whether its numbers make sense (finite colour and distances, `0 <= near < far`).
    #[must_use]
    pub fn is_valid(&self) -> bool {
        self.color.is_finite()
            && self.near.is_finite()
            && self.far.is_finite()
            && self.near >= 0.0
            && self.near < self.far
    }

    /// The fog distance of `p` seen from `eye` looking along unit `forward`.
    #[inline(always)]
    #[must_use]
    pub fn distance<T: Num>(&self, p: T::V, eye: T::V, forward: T::V) -> T {
        match self.distance {
            FogDistance::Euclidean => T::length(p - eye),
            FogDistance::Depth => T::dot(p - eye, forward),
        }
    }

    /// The fog factor f at distance `d`.
    #[inline(always)]
    #[must_use]
    pub fn factor<T: Num>(&self, d: T) -> T {
        ((d - T::of(self.near)) / T::of(self.far - self.near)).clamp01()
    }

    /// `c` fogged as seen at `p`.
    #[inline(always)]
    #[must_use]
    pub fn apply<T: Num>(&self, c: T::V, p: T::V, eye: T::V, forward: T::V) -> T::V {
        let f = self.factor(self.distance::<T>(p, eye, forward));
        c + (T::vec(self.color) - c) * f
    }
}

#[cfg(test)]
mod tests;
