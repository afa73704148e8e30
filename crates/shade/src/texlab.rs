//! The texture-mapping experiments' per-pixel work that is not an image lookup: procedural
//! textures (the textbook's §9.5), bump mapping, and the debug views of
//! [`TexView`]. Each runs one live lane at a time in scalar code, outlined (`#[inline(never)]`)
//! so the kernels' entry points stay small: these are experiments, read by few draws, and the
//! image path of the lit shader pays nothing for them (one test of `DrawParams::mapped`).
//!
//! Bump mapping follows Blinn (a height field tilts the normal against its slope) computed
//! as Mikkelsen's surface gradient ([`maps::surface_gradient`]) from the screen-space
//! derivatives the fill computes, so it needs no tangent attribute and works on any mesh,
//! with UVs (height images, 2D patterns) or without (solid noise). The f64 reference in
//! [`crate::quality`] applies the same formulas with a triangle's edges in place of the
//! screen-space derivatives.

use glam::{Vec2, Vec3};

use super::maps;
use super::shaders::{DrawParams, SlotParams, TexView};
use crate::raster::{Colors, Fragments};
use crate::scene::TextureSource;
use crate::simd::{Lane, Level, Real, F8, LANES, V3};
use crate::texture::{srgb_to_linear, Filter, ProceduralTexture, SamplePoint, Sampler, Texture};

/// Lane `i` of three consecutive varyings from `k`.
#[inline]
fn lane3(v: &[Lane], k: usize, i: usize) -> Vec3 {
    Vec3::new(v[k].0[i], v[k + 1].0[i], v[k + 2].0[i])
}

/// Lane `i` of two consecutive varyings from `k`.
#[inline]
fn lane2(v: &[Lane], k: usize, i: usize) -> Vec2 {
    Vec2::new(v[k].0[i], v[k + 1].0[i])
}

/// The screen-space derivatives (along x, along y) of the `n` varyings from `k`, lane `i`,
/// when the fill computed them (`first`: the first varying with derivatives).
#[inline]
fn derivs(f: &Fragments<'_>, k: usize, n: usize, first: usize, i: usize) -> Option<(Vec3, Vec3)> {
    let d = k.checked_sub(first)?;
    let (x, y) = (f.ddx.get(d..d + n)?, f.ddy.get(d..d + n)?);
    let get = |s: &[Lane]| {
        let mut v = [0.0; 3];
        for (o, x) in v.iter_mut().zip(s) {
            *o = x.0[i];
        }
        Vec3::from(v)
    };
    Some((get(x), get(y)))
}

/// The sample point of procedural texture `p` at lane `i`: the UV at `at` with its
/// footprint, or the object position at `at` with its width (`lod_scale` scales both, as it
/// does an image's level of detail).
fn sample_point(
    p: &ProceduralTexture,
    f: &Fragments<'_>,
    at: usize,
    first: usize,
    lod_scale: f32,
    i: usize,
) -> SamplePoint {
    match p.domain() {
        crate::texture::Domain::Uv => {
            let uv = lane2(f.var, at, i);
            let (dx, dy) = derivs(f, at, 2, first, i).unwrap_or((Vec3::ZERO, Vec3::ZERO));
            SamplePoint::uv_grad(uv, dx.truncate() * lod_scale, dy.truncate() * lod_scale)
        }
        crate::texture::Domain::Object => {
            let (dx, dy) = derivs(f, at, 3, first, i).unwrap_or((Vec3::ZERO, Vec3::ZERO));
            let width = dx.length().max(dy.length()) * lod_scale;
            SamplePoint::position(lane3(f.var, at, i), width)
        }
    }
}

/// Procedural texture `p` on the live lanes of `f` (linear RGBA; 1 in dead lanes), its
/// coordinates at varying `at`.
#[inline(never)]
pub(super) fn procedural_lanes<L: Level>(
    p: &ProceduralTexture,
    f: &Fragments<'_>,
    at: usize,
    first: usize,
    lod_scale: f32,
) -> [F8<L>; 4] {
    procedural_arrays(p, f, at, first, lod_scale).map(F8::from_array)
}

/// [`procedural_lanes`] as arrays (not generic: one copy for every kernel).
#[inline(never)]
fn procedural_arrays(
    p: &ProceduralTexture,
    f: &Fragments<'_>,
    at: usize,
    first: usize,
    lod_scale: f32,
) -> [[f32; LANES]; 4] {
    let mut out = [[1.0; LANES]; 4];
    for i in (0..LANES).filter(|i| f.mask >> i & 1 == 1) {
        let c = p.color(&sample_point(p, f, at, first, lod_scale, i));
        for (o, v) in out.iter_mut().zip(c.to_array()) {
            o[i] = v;
        }
    }
    out
}

/// The height of image `t` (its R channel) at `uv`, on the base level: nearest for a
/// nearest sampler, else bilinear.
fn image_height(t: &Texture, uv: Vec2, s: Sampler) -> f32 {
    let filter = if s.filter == Filter::Nearest {
        Filter::Nearest
    } else {
        Filter::Bilinear
    };
    t.sample_with(uv, Sampler { filter, ..s }).x
}

/// The slope of a height image per texel along u and v, by central differences one texel
/// of the base level apart (so a bump map reads the image at its own resolution, whatever
/// the distance): the bump slot's height of an image is in texels.
#[must_use]
pub fn image_height_slope(t: &Texture, uv: Vec2, s: Sampler) -> Vec2 {
    let step = Vec2::new(1.0 / t.width.max(1) as f32, 1.0 / t.height.max(1) as f32);
    let d = |e: Vec2| (image_height(t, uv + e, s) - image_height(t, uv - e, s)) * 0.5;
    let g = Vec2::new(d(Vec2::new(step.x, 0.0)), d(Vec2::new(0.0, step.y)));
    if g.is_finite() {
        g
    } else {
        Vec2::ZERO
    }
}

/// The surface gradient of bump slot `b`'s displacement at lane `i` (world units), or
/// `None` where it cannot be formed (no derivatives, a surface seen edge-on).
fn bump_gradient(
    b: &SlotParams,
    f: &Fragments<'_>,
    first: usize,
    lod_scale: f32,
    n: Vec3,
    i: usize,
) -> Option<Vec3> {
    let (sx, sy) = derivs(f, 0, 3, first, i)?;
    let at = b.uv_at as usize;
    let uv_slope = |slope: Vec2| {
        let (dx, dy) = derivs(f, at, 2, first, i)?;
        maps::uv_height_gradient::<f32>(
            n,
            sx,
            sy,
            (dx.x, dy.x),
            (dx.y, dy.y),
            (slope.x, slope.y),
            b.scale,
        )
    };
    match &b.source {
        TextureSource::Image(t) => uv_slope(image_height_slope(t, lane2(f.var, at, i), b.sampler)),
        TextureSource::Procedural(p) => {
            let s = sample_point(p, f, at, first, lod_scale, i);
            let g = p.height_gradient(&s);
            match p.domain() {
                crate::texture::Domain::Uv => uv_slope(g.truncate()),
                crate::texture::Domain::Object => {
                    let (lx, ly) = derivs(f, at, 3, first, i)?;
                    solid_height_gradient::<f32>(n, (sx, sy), (lx, ly), g, b.scale)
                }
            }
        }
    }
}

/// The surface gradient (world units) of a solid texture's displacement `scale · h`
/// measured in the texture's object frame (where the model's largest half extent is 1):
/// `g` is `h`'s gradient in that frame, `s` the world position's and `l` the frame
/// position's changes along two directions in the surface.
#[must_use]
pub fn solid_height_gradient<T: Real>(
    n: T::V,
    s: (T::V, T::V),
    l: (T::V, T::V),
    g: T::V,
    scale: T,
) -> Option<T::V> {
    let sg = maps::surface_gradient::<T>(n, s.0, s.1, T::dot(g, l.0), T::dot(g, l.1))?;
    // World length of one frame unit, from whichever direction moved more.
    let (ws, ls) = if T::dot(l.0, l.0) >= T::dot(l.1, l.1) {
        (T::length(s.0), T::length(l.0))
    } else {
        (T::length(s.1), T::length(l.1))
    };
    (ls > T::ZERO).then(|| sg * (scale * ws / ls))
}

/// Bump slot `b` applied to the unit normals `n` on the live lanes of `f`.
#[inline(always)]
pub(super) fn bump_lanes<L: Level>(
    b: &SlotParams,
    f: &Fragments<'_>,
    first: usize,
    lod_scale: f32,
    n: V3<L>,
) -> V3<L> {
    let mut a = [n.x.to_array(), n.y.to_array(), n.z.to_array()];
    bump_arrays(b, f, first, lod_scale, &mut a);
    V3::new(
        F8::from_array(a[0]),
        F8::from_array(a[1]),
        F8::from_array(a[2]),
    )
}

/// [`bump_lanes`] on arrays (not generic: one copy for every kernel).
#[inline(never)]
fn bump_arrays(
    b: &SlotParams,
    f: &Fragments<'_>,
    first: usize,
    lod_scale: f32,
    n: &mut [[f32; LANES]; 3],
) {
    for i in (0..LANES).filter(|i| f.mask >> i & 1 == 1) {
        let ni = Vec3::new(n[0][i], n[1][i], n[2][i]);
        if let Some(g) = bump_gradient(b, f, first, lod_scale, ni, i) {
            let p = maps::bump::<f32>(ni, g);
            (n[0][i], n[1][i], n[2][i]) = (p.x, p.y, p.z);
        }
    }
}

/// Colours of the mip-level view, one per level from 0 (display values).
const LEVELS: [Vec3; 9] = [
    Vec3::new(0.85, 0.1, 0.1),
    Vec3::new(0.95, 0.55, 0.1),
    Vec3::new(0.95, 0.9, 0.15),
    Vec3::new(0.2, 0.8, 0.2),
    Vec3::new(0.1, 0.8, 0.85),
    Vec3::new(0.15, 0.3, 0.9),
    Vec3::new(0.55, 0.2, 0.85),
    Vec3::new(0.9, 0.3, 0.7),
    Vec3::new(0.95, 0.95, 0.95),
];

/// Level `lod` of the mip-level view: the level colours blended between levels, darkened
/// towards black below level 0 (magnified: one texel covers 2^-lod pixels).
#[must_use]
pub fn level_colour(lod: f32) -> Vec3 {
    if !lod.is_finite() {
        return Vec3::ZERO;
    }
    if lod < 0.0 {
        return LEVELS[0] * (1.0 + lod / 4.0).max(0.25);
    }
    let top = (LEVELS.len() - 1) as f32;
    let l = lod.min(top);
    let k = l.floor() as usize;
    let next = (k + 1).min(LEVELS.len() - 1);
    LEVELS[k].lerp(LEVELS[next], l - k as f32)
}

/// A ramp over `t` in [0, 1]: blue, green, red (display values).
#[must_use]
pub fn ramp(t: f32) -> Vec3 {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        1.0
    };
    if t < 0.5 {
        Vec3::new(0.1, 0.25, 0.95).lerp(Vec3::new(0.15, 0.85, 0.2), t * 2.0)
    } else {
        Vec3::new(0.15, 0.85, 0.2).lerp(Vec3::new(0.95, 0.15, 0.1), t * 2.0 - 1.0)
    }
}

/// The singular values (largest first) of the 2x2 Jacobian with columns `a` (change along
/// screen x) and `b` (along y), in texels: the pixel footprint's axes in texture space.
#[must_use]
pub fn footprint_axes(a: Vec2, b: Vec2) -> (f32, f32) {
    let s = a.length_squared() + b.length_squared();
    let det = (a.x * b.y - a.y * b.x).abs();
    let disc = (s * s - 4.0 * det * det).max(0.0).sqrt();
    let major = ((s + disc) * 0.5).sqrt();
    let minor = if major > 0.0 { det / major } else { 0.0 };
    (major, minor)
}

/// A tangent frame for a mesh without tangents, at lane `i`: `T` = dP/du, from the
/// screen-space derivatives of the position and of the measured UV set (the 2 x 2 system of
/// the chain rule, as glTF viewers derive it), and the handedness `w` that makes
/// `B = w (N × T)` run along -v, the convention of [`crate::mesh::Mesh::tangents`]. `None`
/// where the UVs do not span the pixel (degenerate or missing derivatives).
fn uv_tangent(
    d: &DrawParams,
    f: &Fragments<'_>,
    first: usize,
    n: Vec3,
    i: usize,
) -> Option<(Vec3, f32)> {
    let (at, _) = d.measure?;
    derived_tangent(f, at as usize, first, n, i)
}

/// [`maps::uv_tangent`] at lane `i` from the screen-space derivatives of the position and
/// of the UV channel at `at`.
fn derived_tangent(
    f: &Fragments<'_>,
    at: usize,
    first: usize,
    n: Vec3,
    i: usize,
) -> Option<(Vec3, f32)> {
    let (sx, sy) = derivs(f, 0, 3, first, i)?;
    let (dx, dy) = derivs(f, at, 2, first, i)?;
    maps::uv_tangent::<f32>(n, sx, sy, (dx.x, dy.x), (dx.y, dy.y))
}

/// A normal map on a mesh without tangents, on the live lanes of `f`: each lane's frame
/// from [`derived_tangent`] (the map's UV channel), then [`maps::perturb`] with the
/// sampled texels `texel`; a lane without a frame keeps `n`.
#[inline(always)]
pub(super) fn derived_normal_lanes<L: Level>(
    map: &SlotParams,
    f: &Fragments<'_>,
    first: usize,
    texel: &[F8<L>; 4],
    n: V3<L>,
) -> V3<L> {
    let mut a = [n.x.to_array(), n.y.to_array(), n.z.to_array()];
    let t = [
        texel[0].to_array(),
        texel[1].to_array(),
        texel[2].to_array(),
    ];
    derived_normal_arrays(map, f, first, &t, &mut a);
    V3::new(
        F8::from_array(a[0]),
        F8::from_array(a[1]),
        F8::from_array(a[2]),
    )
}

/// [`derived_normal_lanes`] on arrays (not generic: one copy for every kernel).
#[inline(never)]
fn derived_normal_arrays(
    map: &SlotParams,
    f: &Fragments<'_>,
    first: usize,
    texel: &[[f32; LANES]; 3],
    n: &mut [[f32; LANES]; 3],
) {
    for i in (0..LANES).filter(|i| f.mask >> i & 1 == 1) {
        let ni = Vec3::new(n[0][i], n[1][i], n[2][i]);
        if let Some((t, w)) = derived_tangent(f, map.uv_at as usize, first, ni, i) {
            let c = [texel[0][i], texel[1][i], texel[2][i]];
            let p = maps::perturb::<f32>(ni, t, w, c, map.scale);
            (n[0][i], n[1][i], n[2][i]) = (p.x, p.y, p.z);
        }
    }
}

/// The debug colour of view `view` at one pixel (display values).
fn debug_colour(d: &DrawParams, f: &Fragments<'_>, lod_scale: f32, n: Vec3, i: usize) -> Vec3 {
    let first = d
        .layout
        .derivatives()
        .map_or(usize::MAX, |(first, _)| first);
    let texel_axes = || {
        let (at, size) = d.measure?;
        let (dx, dy) = derivs(f, at as usize, 2, first, i)?;
        let size = Vec2::from(size);
        Some((
            dx.truncate() * size * lod_scale,
            dy.truncate() * size * lod_scale,
        ))
    };
    let tangent = d
        .layout
        .tangent_at()
        .map(|k| (lane3(f.var, k, i), f.var[k + 3].0[i]));
    let grey = Vec3::splat(0.5);
    match d.view {
        TexView::Lit => grey,
        TexView::MipLevel => texel_axes().map_or(grey, |(a, b)| {
            level_colour(libm::log2f(a.length().max(b.length())))
        }),
        TexView::TexelDensity => texel_axes().map_or(grey, |(a, b)| {
            // Texels per pixel, as an area's square root: 1/8 to 8 on the ramp.
            let (major, minor) = footprint_axes(a, b);
            ramp((libm::log2f((major * minor).sqrt()) + 3.0) / 6.0)
        }),
        TexView::Anisotropy => texel_axes().map_or(grey, |(a, b)| {
            let (major, minor) = footprint_axes(a, b);
            let ratio = if minor > 0.0 { major / minor } else { 16.0 };
            ramp(0.5 + libm::log2f(ratio) / 8.0)
        }),
        TexView::Tangents => tangent.map_or(grey, |(t, _)| {
            t.normalize_or_zero() * 0.5 + Vec3::splat(0.5)
        }),
        TexView::TangentNormals => {
            let geo = lane3(f.var, 3, i).normalize_or_zero();
            let geo = if f.tri.front { geo } else { -geo };
            let Some((t, w)) = tangent.or_else(|| uv_tangent(d, f, first, geo, i)) else {
                return Vec3::new(0.5, 0.5, 1.0);
            };
            let t = (t - geo * geo.dot(t)).normalize_or_zero();
            let b = geo.cross(t) * if w < 0.0 { -1.0 } else { 1.0 };
            let m = Vec3::new(n.dot(t), n.dot(b), n.dot(geo));
            m * 0.5 + Vec3::splat(0.5)
        }
    }
}

/// The debug view of draw `d` on the live lanes of `f` (linear RGBA, alpha 1); `n` is the
/// shading normal after the maps, flipped to the side seen.
#[inline(always)]
pub(super) fn debug_lanes<L: Level>(
    d: &DrawParams,
    f: &Fragments<'_>,
    lod_scale: f32,
    n: V3<L>,
) -> Colors {
    let n = [n.x.to_array(), n.y.to_array(), n.z.to_array()];
    debug_arrays(d, f, lod_scale, &n)
}

/// [`debug_lanes`] on arrays (not generic: one copy for every kernel).
#[inline(never)]
fn debug_arrays(
    d: &DrawParams,
    f: &Fragments<'_>,
    lod_scale: f32,
    n: &[[f32; LANES]; 3],
) -> Colors {
    let mut out = Colors::splat(glam::Vec4::ONE);
    for i in (0..LANES).filter(|i| f.mask >> i & 1 == 1) {
        let ni = Vec3::new(n[0][i], n[1][i], n[2][i]);
        let c = debug_colour(d, f, lod_scale, ni, i);
        out.r.0[i] = srgb_to_linear(c.x.clamp(0.0, 1.0));
        out.g.0[i] = srgb_to_linear(c.y.clamp(0.0, 1.0));
        out.b.0[i] = srgb_to_linear(c.z.clamp(0.0, 1.0));
    }
    out
}
