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
//! The scalar form ([`illuminate`], [`contribution`], [`arriving`]) is generic over
//! [`Real`] (`f32` for the vertex stage and the pixel probe, `f64` for the references in
//! [`crate::quality`]); the eight-lane form ([`illuminate_lanes`]) is what the pixel shaders
//! run and is tested against it.

use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3};

use super::real::Real;
use super::shadow::ShadowMap;
use crate::raster::{Kernel, F8, M8, V3};
use crate::scene::{Attenuation, Light, LightKind};
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

/// Phong parameters of a material (constant over a draw).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    pub diffuse: Vec3,
    pub specular: Vec3,
    /// Ambient factor on the diffuse colour.
    pub ambient: Vec3,
    /// Exponent n, clamped to 1..=2000 by the caller.
    pub shininess: f32,
}

impl Surface {
    /// The surface at one point whose diffuse colour is `kd` (material times texture and
    /// vertex colour), in precision `T`.
    #[must_use]
    #[inline(always)]
    pub fn at<T: Real>(&self, kd: T::V) -> SurfaceAt<T> {
        SurfaceAt {
            kd,
            ks: T::vec(self.specular),
            ka: T::vec(self.ambient),
            shininess: T::of(self.shininess),
        }
    }
}

/// The Phong parameters at one point.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceAt<T: Real> {
    pub kd: T::V,
    pub ks: T::V,
    pub ka: T::V,
    pub shininess: T,
}

/// The attenuation factor of `a` at distance `d`.
#[inline(always)]
#[must_use]
pub fn attenuate<T: Real>(a: Attenuation, d: T) -> T {
    match a {
        Attenuation::None => T::ONE,
        Attenuation::Linear { near, far } => {
            let (near, far) = (T::of(near), T::of(far));
            if d <= near {
                T::ONE
            } else if d >= far {
                T::ZERO
            } else {
                (far - d) / (far - near)
            }
        }
        Attenuation::InverseSquare => T::ONE / (d * d).max(T::of64(crate::scene::MIN_D2)),
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
pub fn cone<T: Real>(s: &Source, cos_axis: T) -> T {
    let (ci, co) = (T::of(s.cos_inner), T::of(s.cos_outer));
    let w = (ci - co).max(T::of(1e-4));
    let t = ((cos_axis - co) / w).clamp01();
    t * t * (T::of(3.0) - t - t)
}

/// Where the ray from a rectangular spot to a point falls on its image, as (u, v) with the
/// pyramid at |u|, |v| <= 1, or `None` behind the light. `ray` need not be unit.
#[inline(always)]
#[must_use]
pub fn pyramid<T: Real>(s: &Source, ray: T::V) -> Option<(T, T)> {
    let z = T::dot(ray, T::vec(s.axis));
    if z <= T::ZERO {
        return None;
    }
    let x = T::dot(ray, T::vec(s.right)) / (z * T::of(s.tan.x));
    let y = T::dot(ray, T::vec(s.up)) / (z * T::of(s.tan.y));
    Some((x, y))
}

/// What arrives at `p` from `s` before shadowing: the unit direction towards the light and
/// the radiance after attenuation, cone or pyramid and projected image; `None` when nothing
/// does.
#[inline(always)]
#[must_use]
pub fn arriving<T: Real>(s: &Source, p: T::V) -> Option<(T::V, T::V)> {
    let rad = T::vec(s.radiance);
    if s.kind == LightKind::Directional {
        return Some((-T::vec(s.axis), rad));
    }
    let to = T::vec(s.position) - p;
    let d = T::length(to);
    if !(d > T::ZERO && d.is_finite()) {
        return None;
    }
    let l = to * (T::ONE / d);
    let mut f = attenuate(s.attenuation, d);
    let mut rad = rad;
    match s.kind {
        LightKind::Spot => f = f * cone(s, -T::dot(l, T::vec(s.axis))),
        LightKind::Rect => {
            let (x, y) = pyramid::<T>(s, -l)?;
            let one = T::ONE;
            if !(x >= -one && x <= one && y >= -one && y <= one) {
                return None;
            }
            if let Some(img) = &s.image {
                let u = (Real::to_f64(x) as f32 + 1.0) * 0.5;
                let v = (1.0 - Real::to_f64(y) as f32) * 0.5;
                let c = img.sample_with(Vec2::new(u, v), IMAGE_SAMPLER);
                rad = rad * T::vec(c.truncate());
            }
        }
        _ => {}
    }
    if f > T::ZERO {
        Some((l, rad * f))
    } else {
        None
    }
}

/// Diffuse plus specular reflection of unit light direction `l` at unit normal `n`, unit
/// view vector `v` (zero when `K_s = 0`): `K_d (N·L) + K_s S` with `S` as in the module
/// documentation; zero when `N·L <= 0`.
#[inline(always)]
#[must_use]
pub fn reflect<T: Real>(s: &SurfaceAt<T>, n: T::V, l: T::V, v: T::V, blinn: bool) -> T::V {
    let ndl = T::dot(n, l);
    if ndl <= T::ZERO {
        return T::splat(T::ZERO);
    }
    let mut t = s.kd * ndl;
    if T::vmax(s.ks) > T::ZERO {
        let base = if blinn {
            T::dot(n, T::normalize_or_zero(l + v))
        } else {
            T::dot(n * (ndl + ndl) - l, v)
        };
        if base > T::ZERO {
            t = t + s.ks * base.powf(s.shininess);
        }
    }
    t
}

/// Light `s`'s share of the colour at `p` (normal `n`, view vector `v`), shadow included.
#[inline(always)]
#[must_use]
pub fn contribution<T: Real>(
    set: &LightSet,
    s: &Source,
    surf: &SurfaceAt<T>,
    p: T::V,
    n: T::V,
    v: T::V,
    blinn: bool,
) -> T::V {
    let Some((l, rad)) = arriving::<T>(s, p) else {
        return T::splat(T::ZERO);
    };
    let r = reflect(surf, n, l, v, blinn);
    if T::vmax(r) <= T::ZERO {
        return r;
    }
    let vis = match set.shadow_of(s) {
        Some(map) => map.visibility::<T>(p, n, l),
        None => T::ONE,
    };
    r * rad * vis
}

/// The view vector for the specular term: unit towards the eye, or zero when the surface
/// has no specular colour (none is needed).
#[inline(always)]
#[must_use]
pub fn view_vector<T: Real>(surf: &SurfaceAt<T>, p: T::V, eye: T::V) -> T::V {
    if T::vmax(surf.ks) > T::ZERO {
        T::normalize_or_zero(eye - p)
    } else {
        T::splat(T::ZERO)
    }
}

/// The lighting equation at `p` with unit normal `n` and the eye at `eye`, summed over the
/// sources `active` (indices into `set.sources`; all of them if `None`). Fog is applied
/// separately ([`Fog::apply`]).
#[must_use]
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn illuminate<T: Real>(
    set: &LightSet,
    active: Option<&[u32]>,
    surf: &SurfaceAt<T>,
    p: T::V,
    n: T::V,
    eye: T::V,
    blinn: bool,
) -> T::V {
    let v = view_vector(surf, p, eye);
    let mut c = T::vec(set.ambient) * surf.ka * surf.kd;
    match active {
        Some(idx) => {
            for &i in idx {
                if let Some(s) = set.sources.get(i as usize) {
                    c = c + contribution(set, s, surf, p, n, v, blinn);
                }
            }
        }
        None => {
            for s in &set.sources {
                c = c + contribution(set, s, surf, p, n, v, blinn);
            }
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
    pub fn distance<T: Real>(&self, p: T::V, eye: T::V, forward: T::V) -> T {
        match self.distance {
            FogDistance::Euclidean => T::length(p - eye),
            FogDistance::Depth => T::dot(p - eye, forward),
        }
    }

    /// The fog factor f at distance `d`.
    #[inline(always)]
    #[must_use]
    pub fn factor<T: Real>(&self, d: T) -> T {
        ((d - T::of(self.near)) / T::of(self.far - self.near)).clamp01()
    }

    /// `c` fogged as seen at `p`.
    #[inline(always)]
    #[must_use]
    pub fn apply<T: Real>(&self, c: T::V, p: T::V, eye: T::V, forward: T::V) -> T::V {
        let f = self.factor(self.distance::<T>(p, eye, forward));
        c + (T::vec(self.color) - c) * f
    }

    /// [`Fog::apply`] on eight lanes.
    #[inline(always)]
    #[must_use]
    pub fn apply_lanes<K: Kernel>(&self, c: V3, p: V3, eye: Vec3, forward: Vec3) -> V3 {
        let rel = p - V3::splat(eye);
        let d = match self.distance {
            FogDistance::Euclidean => rel.dot::<K>(rel).sqrt(),
            FogDistance::Depth => rel.dot::<K>(V3::splat(forward)),
        };
        let f = ((d - self.near) * (1.0 / (self.far - self.near))).clamp(0.0, 1.0);
        c + (V3::splat(self.color) - c).scale(f)
    }
}

/// Phong parameters of eight surface points: the diffuse colour per lane (it may come from
/// a texture or vertex colours), the specular colour per lane (it may come from a gloss
/// map), the rest shared.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceLanes {
    pub diffuse: V3,
    pub specular: V3,
    /// Whether any lane has a specular colour (no specular work otherwise).
    pub has_specular: bool,
    pub ambient: Vec3,
    pub shininess: F8,
    /// Ambient occlusion per lane (multiplies the ambient term only), if the surface has it.
    pub occlusion: Option<F8>,
    /// Light the surface emits, added to what it reflects, if it emits any.
    pub emitted: Option<V3>,
}

/// [`illuminate`] on eight lanes: the same equation and the same decisions (no specular
/// term where `N·L <= 0` or `K_s = 0`), evaluated with the kernel's arithmetic and the lane
/// `pow` ([`F8::powf`]); agrees with [`illuminate`] to float rounding (tested). Work for a
/// light is skipped when no lane receives it.
#[must_use]
#[inline(always)]
pub fn illuminate_lanes<K: Kernel>(
    set: &LightSet,
    active: &[u32],
    s: &SurfaceLanes,
    p: V3,
    n: V3,
    eye: Vec3,
    blinn: bool,
) -> V3 {
    let v = if s.has_specular {
        (V3::splat(eye) - p).normalize_or_zero::<K>()
    } else {
        V3::default()
    };
    let mut c = s.diffuse * (set.ambient * s.ambient);
    if let Some(ao) = s.occlusion {
        c = c.scale(ao);
    }
    if let Some(e) = s.emitted {
        c = c + e;
    }
    for &i in active {
        let Some(src) = set.sources.get(i as usize) else {
            continue;
        };
        c = c + contribution_lanes::<K>(set, src, s, p, n, v, blinn);
    }
    c
}

/// Light `src`'s share on eight lanes ([`contribution`]).
#[inline(always)]
#[must_use]
pub fn contribution_lanes<K: Kernel>(
    set: &LightSet,
    src: &Source,
    s: &SurfaceLanes,
    p: V3,
    n: V3,
    v: V3,
    blinn: bool,
) -> V3 {
    let Some((l, rad, live)) = arriving_lanes::<K>(src, p) else {
        return V3::default();
    };
    let ndl = n.dot::<K>(l);
    let lit = ndl.gt(F8::ZERO) & live;
    if lit.bits() == 0 {
        return V3::default();
    }
    let ndl = F8::select(lit, ndl, F8::ZERO);
    let mut t = s.diffuse.scale(ndl);
    if s.has_specular {
        let base = if blinn {
            n.dot::<K>((l + v).normalize_or_zero::<K>())
        } else {
            (n.scale(ndl + ndl) - l).dot::<K>(v)
        };
        let lobe = base.powf::<K>(s.shininess);
        let lobe = F8::select(lit, lobe, F8::ZERO);
        t = t + s.specular.scale(lobe);
    }
    let mut t = V3::new(t.x * rad.x, t.y * rad.y, t.z * rad.z);
    if let Some(map) = set.shadow_of(src) {
        t = t.scale(map.visibility_lanes::<K>(p, n, l, lit.bits()));
    }
    t
}

/// [`arriving`] on eight lanes: unit direction to the light, arriving radiance, and the
/// lanes that receive any; `None` when no lane does.
#[inline(always)]
#[must_use]
pub fn arriving_lanes<K: Kernel>(src: &Source, p: V3) -> Option<(V3, V3, M8)> {
    let all = M8([u32::MAX; 8]);
    if src.kind == LightKind::Directional {
        return Some((V3::splat(-src.axis), V3::splat(src.radiance), all));
    }
    let to = V3::splat(src.position) - p;
    let d2 = to.dot::<K>(to);
    let d = d2.sqrt();
    let inv = F8::select(d.gt(F8::ZERO), d.recip(), F8::ZERO);
    let l = to.scale(inv);
    let mut f = match src.attenuation {
        Attenuation::None => F8::ONE,
        Attenuation::Linear { near, far } => {
            let ramp = (F8::splat(far) - d) * (1.0 / (far - near).max(f32::MIN_POSITIVE));
            F8::select(d.gt(F8::splat(near)), ramp.clamp(0.0, 1.0), F8::ONE)
        }
        Attenuation::InverseSquare => d2.max(F8::splat(crate::scene::MIN_D2 as f32)).recip(),
        Attenuation::Range(r) => {
            let q = d * (1.0 / r);
            let q2 = q * q;
            (F8::ONE - q2 * q2).clamp(0.0, 1.0)
                * d2.max(F8::splat(crate::scene::MIN_D2 as f32)).recip()
        }
    };
    let mut rad = V3::splat(src.radiance);
    match src.kind {
        LightKind::Spot => {
            let cos_axis = -l.dot::<K>(V3::splat(src.axis));
            let w = (src.cos_inner - src.cos_outer).max(1e-4);
            let t = ((cos_axis - src.cos_outer) * (1.0 / w)).clamp(0.0, 1.0);
            f = f * t * t * (F8::splat(3.0) - t - t);
        }
        LightKind::Rect => {
            let ray = -l;
            let z = ray.dot::<K>(V3::splat(src.axis));
            let x = ray.dot::<K>(V3::splat(src.right)) / (z * src.tan.x);
            let y = ray.dot::<K>(V3::splat(src.up)) / (z * src.tan.y);
            let inside = z.gt(F8::ZERO)
                & x.ge(F8::splat(-1.0))
                & F8::splat(1.0).ge(x)
                & y.ge(F8::splat(-1.0))
                & F8::splat(1.0).ge(y);
            f = F8::select(inside, f, F8::ZERO);
            if let Some(img) = &src.image {
                let u = (x + 1.0) * 0.5;
                let w = (F8::ONE - y) * 0.5;
                let c = img.sample_lanes::<K>(u, w, inside.bits(), IMAGE_SAMPLER);
                rad = V3::new(
                    c[0] * src.radiance.x,
                    c[1] * src.radiance.y,
                    c[2] * src.radiance.z,
                );
            }
        }
        _ => {}
    }
    let live = f.gt(F8::ZERO);
    if live.bits() == 0 {
        return None;
    }
    Some((l, rad.scale(f), live))
}

#[cfg(test)]
mod tests;
