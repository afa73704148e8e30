//! Fragment shaders, one type per shading mode, each with the smallest varying it needs.
//! Per-draw material parameters are looked up by `TriInfo::draw`.

use std::sync::Arc;

use glam::{Vec2, Vec3, Vec4};

use super::lighting::{illuminate, LightSet, Surface};
use crate::raster::{FragmentShader, TriInfo, Varying};
use crate::scene::AlphaMode;
use crate::texture::{srgb_to_linear, Sampler, Texture};

/// Material parameters of one draw.
#[derive(Clone, Debug)]
pub struct DrawParams {
    pub base: Vec4,
    pub surface: Surface,
    pub texture: Option<Arc<Texture>>,
    /// How `texture` is read (its own sampler, or a filter the renderer's settings force).
    pub sampler: Sampler,
    pub alpha: AlphaMode,
    pub double_sided: bool,
}

impl DrawParams {
    /// Applies the alpha mode: `None` discards.
    #[inline]
    fn alpha(&self, c: Vec4) -> Option<Vec4> {
        match self.alpha {
            AlphaMode::Opaque => Some(c.truncate().extend(1.0)),
            AlphaMode::Mask(cutoff) => (c.w >= cutoff).then(|| c.truncate().extend(1.0)),
            AlphaMode::Blend => Some(c),
        }
    }
}

/// Flat and Gouraud: the colour was computed per facet or per vertex and is interpolated.
pub struct ColorShader<'a, V> {
    pub draws: &'a [DrawParams],
    pub _v: std::marker::PhantomData<V>,
}

/// A precomputed colour: one (flat: the facet's side is known per facet) or a front and a
/// back colour (Gouraud on double-sided materials: which side is seen is known only per
/// triangle, not per vertex).
pub trait ColorVarying: Varying {
    fn color(&self, front: bool) -> Vec4;
}

impl ColorVarying for Vec4 {
    #[inline(always)]
    fn color(&self, _: bool) -> Vec4 {
        *self
    }
}

impl ColorVarying for (Vec4, Vec4) {
    #[inline(always)]
    fn color(&self, front: bool) -> Vec4 {
        if front {
            self.0
        } else {
            self.1
        }
    }
}

impl<V: ColorVarying> FragmentShader for ColorShader<'_, V> {
    type Varying = V;
    #[inline]
    fn fragment(&self, tri: TriInfo, v: &V) -> Option<Vec4> {
        self.draws[tri.draw as usize].alpha(v.color(tri.front))
    }
}

/// Per-pixel lighting varyings: world position and normal, plus UV and/or colour.
pub trait LitVarying: Varying {
    /// Whether the varying carries a UV ([`LitVarying::uv`] is `Some`).
    const UV: bool;
    fn new(p: Vec3, n: Vec3, uv: Vec2, color: Vec4) -> Self;
    fn position(&self) -> Vec3;
    fn normal(&self) -> Vec3;
    fn uv(&self) -> Option<Vec2>;
    fn color(&self) -> Option<Vec4>;
}

/// What a lit varying carries besides position and normal: nothing (`()`), a UV (`Vec2`), a
/// vertex colour (`Vec4`) or both.
pub trait Extra: Varying {
    const UV: bool = false;
    fn new(uv: Vec2, color: Vec4) -> Self;
    fn uv(&self) -> Option<Vec2> {
        None
    }
    fn color(&self) -> Option<Vec4> {
        None
    }
}

impl Extra for () {
    fn new(_: Vec2, _: Vec4) -> Self {}
}

impl Extra for Vec2 {
    const UV: bool = true;
    fn new(uv: Vec2, _: Vec4) -> Self {
        uv
    }
    fn uv(&self) -> Option<Vec2> {
        Some(*self)
    }
}

impl Extra for Vec4 {
    fn new(_: Vec2, color: Vec4) -> Self {
        color
    }
    fn color(&self) -> Option<Vec4> {
        Some(*self)
    }
}

impl Extra for (Vec2, Vec4) {
    const UV: bool = true;
    fn new(uv: Vec2, color: Vec4) -> Self {
        (uv, color)
    }
    fn uv(&self) -> Option<Vec2> {
        Some(self.0)
    }
    fn color(&self) -> Option<Vec4> {
        Some(self.1)
    }
}

impl<E: Extra> LitVarying for (Vec3, Vec3, E) {
    const UV: bool = E::UV;
    #[inline(always)]
    fn new(p: Vec3, n: Vec3, uv: Vec2, color: Vec4) -> Self {
        (p, n, E::new(uv, color))
    }
    #[inline(always)]
    fn position(&self) -> Vec3 {
        self.0
    }
    #[inline(always)]
    fn normal(&self) -> Vec3 {
        self.1
    }
    #[inline(always)]
    fn uv(&self) -> Option<Vec2> {
        self.2.uv()
    }
    #[inline(always)]
    fn color(&self) -> Option<Vec4> {
        self.2.color()
    }
}

/// Phong (`BLINN = false`) or Blinn-Phong per-pixel lighting; with a UV varying, the
/// base-colour texture modulates the diffuse colour (filtered in linear light by the
/// texture's sampler: trilinear by default, its level of detail from the UV's exact
/// screen-space derivatives, which the rasterizer computes only for varyings with a UV).
pub struct LitShader<'a, V, const BLINN: bool> {
    pub draws: &'a [DrawParams],
    pub lights: &'a LightSet,
    pub eye: Vec3,
    /// Scale of the UV derivatives before the texture's level of detail is chosen: 1 for
    /// one sample per pixel, 1/n for a pass of an n x n supersampled frame (whose samples
    /// are 1/n pixel apart, as if rendered n times larger).
    pub lod_scale: f32,
    pub _v: std::marker::PhantomData<V>,
}

impl<V: LitVarying, const BLINN: bool> LitShader<'_, V, BLINN> {
    /// Shades with the UV's derivatives along x and y, if known.
    #[inline(always)]
    fn shade(&self, tri: TriInfo, v: &V, duv: Option<(Vec2, Vec2)>) -> Option<Vec4> {
        let d = &self.draws[tri.draw as usize];
        let mut base = d.base;
        if let Some(c) = v.color() {
            base *= c;
        }
        if let (Some(uv), Some(t)) = (v.uv(), &d.texture) {
            let (s, k) = (d.sampler, self.lod_scale);
            base *= match duv {
                Some((dx, dy)) => t.sample_grad_with(uv, dx * k, dy * k, s),
                None => t.sample_with(uv, s),
            };
        }
        let mut n = v.normal().normalize_or_zero();
        if !tri.front {
            n = -n;
        }
        let s = Surface {
            diffuse: base.truncate(),
            ..d.surface
        };
        let c = illuminate::<BLINN>(self.lights, &s, v.position(), n, self.eye);
        d.alpha(c.extend(base.w))
    }
}

impl<V: LitVarying, const BLINN: bool> FragmentShader for LitShader<'_, V, BLINN> {
    type Varying = V;
    const DERIVATIVES: bool = V::UV;
    #[inline]
    fn fragment(&self, tri: TriInfo, v: &V) -> Option<Vec4> {
        self.shade(tri, v, None)
    }
    #[inline]
    fn fragment_grad(&self, tri: TriInfo, v: &V, dvdx: &V, dvdy: &V) -> Option<Vec4> {
        let duv = dvdx.uv().zip(dvdy.uv());
        self.shade(tri, v, duv)
    }
}

/// Which debug quantity to show.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Debug {
    /// World-space normal, mapped from [-1, 1] to [0, 1] per channel.
    Normals,
    /// Linear view distance, white at the near plane to black at the far plane.
    Depth,
    /// (fract(u), fract(v), 0).
    Uv,
}

/// Debug views; the varying is the quantity itself (normal, view distance, or UV in a Vec3).
pub struct DebugShader {
    pub mode: Debug,
    pub near: f32,
    pub far: f32,
}

impl FragmentShader for DebugShader {
    type Varying = Vec3;
    #[inline]
    fn fragment(&self, _: TriInfo, v: &Vec3) -> Option<Vec4> {
        // Debug colours are display values: decode so the PNG shows them as computed.
        let display = match self.mode {
            // Raw interpolated normals, not flipped on back faces: this view is for finding
            // inverted normals.
            Debug::Normals => v.normalize_or_zero() * 0.5 + 0.5,
            Debug::Depth => {
                Vec3::splat(1.0 - ((v.x - self.near) / (self.far - self.near)).clamp(0.0, 1.0))
            }
            Debug::Uv => {
                let f = |x: f32| if x.is_finite() { x - x.floor() } else { 0.0 };
                Vec3::new(f(v.x), f(v.y), 0.0)
            }
        };
        Some(Vec4::new(
            srgb_to_linear(display.x),
            srgb_to_linear(display.y),
            srgb_to_linear(display.z),
            1.0,
        ))
    }
}

/// Counts fragments: red = 1 per fragment, for an additive pass with the depth test off
/// (the overdraw view: how many fragments each pixel received).
pub struct CountShader;

impl FragmentShader for CountShader {
    type Varying = ();
    #[inline]
    fn fragment(&self, _: TriInfo, _: &()) -> Option<Vec4> {
        Some(Vec4::new(1.0, 0.0, 0.0, 0.0))
    }
}

/// Writes depth only (hidden-line pass of wireframe).
pub struct DepthOnly;

impl FragmentShader for DepthOnly {
    type Varying = ();
    #[inline]
    fn fragment(&self, _: TriInfo, _: &()) -> Option<Vec4> {
        Some(Vec4::ZERO)
    }
}
