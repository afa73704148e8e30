//! Fragment shaders, one type per shading mode, each shading eight pixels (lanes) at a time
//! from the varyings the vertex stage laid out (see [`LitLayout`]). Per-draw material
//! parameters are looked up by `TriInfo::draw`.

use std::sync::Arc;

use glam::{Vec2, Vec3, Vec4};

use super::lighting::{illuminate_lanes, Fog, LightSet, Surface, SurfaceLanes};
use crate::raster::{Colors, FragmentShader, Fragments, Kernel, F8, V3};
use crate::scene::AlphaMode;
use crate::texture::{srgb_to_linear, Sampler, Texture};

/// Material parameters of one draw.
#[derive(Clone, Debug)]
pub struct DrawParams {
    pub base: Vec4,
    pub surface: Surface,
    /// The base-colour texture (textured mode only).
    pub texture: Option<Arc<Texture>>,
    /// The gloss map: its RGB multiplies the specular colour (per-pixel modes, meshes with
    /// UVs).
    pub gloss: Option<Arc<Texture>>,
    /// How `texture` (or, without one, `gloss`) is read (its own sampler, or a filter the renderer's settings force).
    pub sampler: Sampler,
    pub alpha: AlphaMode,
    pub double_sided: bool,
    /// This draw's lights: `start..end` in the shader's `active` list (the frame's lights
    /// that can reach the object).
    pub lights: (u32, u32),
}

impl DrawParams {
    /// This draw's slice of the frame's active-light list.
    #[inline(always)]
    #[must_use]
    pub fn active<'a>(&self, active: &'a [u32]) -> &'a [u32] {
        active
            .get(self.lights.0 as usize..self.lights.1 as usize)
            .unwrap_or(&[])
    }

    /// Applies the alpha mode to lanes `mask` with alpha `a`: returns the alpha to store and
    /// the lanes kept (`Mask` discards those below the cutoff).
    #[inline(always)]
    fn alpha_lanes(&self, a: F8, mask: u32) -> (F8, u32) {
        match self.alpha {
            AlphaMode::Opaque => (F8::ONE, mask),
            AlphaMode::Mask(cutoff) => (F8::ONE, mask & a.ge(F8::splat(cutoff)).bits()),
            AlphaMode::Blend => (a, mask),
        }
    }
}

/// Flat and Gouraud: the colour was computed per facet or per vertex and is interpolated.
/// Varyings: RGBA (4 floats). Gouraud on a double-sided material lights each vertex from
/// both sides (8 floats, front then back) and draws with
/// [`DrawState::facing_varyings`](crate::raster::DrawState), so set-up keeps the side each
/// triangle shows.
pub struct ColorShader<'a> {
    pub draws: &'a [DrawParams],
}

impl FragmentShader for ColorShader<'_> {
    #[inline(always)]
    fn shade<K: Kernel>(&self, f: &Fragments<'_>, out: &mut Colors) -> u32 {
        let d = &self.draws[f.tri.draw as usize];
        let Some(c) = f.var.get(..4) else {
            return 0;
        };
        let (a, keep) = d.alpha_lanes(c[3], f.mask);
        *out = Colors {
            r: c[0],
            g: c[1],
            b: c[2],
            a,
        };
        keep
    }
}

/// Where a lit draw's varyings are: world position at 0..3, world normal at 3..6, then the
/// UV (2 floats) if textured, then the vertex colour (4 floats) if the mesh has colours.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct LitLayout {
    pub uv: bool,
    pub color: bool,
}

impl LitLayout {
    /// Floats per vertex.
    #[must_use]
    pub fn stride(self) -> usize {
        6 + if self.uv { 2 } else { 0 } + if self.color { 4 } else { 0 }
    }

    /// Index of the UV's first float.
    #[must_use]
    pub fn uv_at(self) -> Option<usize> {
        self.uv.then_some(6)
    }

    /// Index of the colour's first float.
    #[must_use]
    pub fn color_at(self) -> Option<usize> {
        self.color.then_some(if self.uv { 8 } else { 6 })
    }

    /// Writes one vertex's varyings into `out` (`stride()` floats).
    #[inline]
    pub fn write(self, out: &mut [f32], p: Vec3, n: Vec3, uv: Vec2, color: Vec4) {
        out[..3].copy_from_slice(&p.to_array());
        out[3..6].copy_from_slice(&n.to_array());
        if let Some(k) = self.uv_at() {
            out[k..k + 2].copy_from_slice(&uv.to_array());
        }
        if let Some(k) = self.color_at() {
            out[k..k + 4].copy_from_slice(&color.to_array());
        }
    }
}

/// Phong (R·V) or Blinn-Phong (N·H, `blinn`) per-pixel lighting; with a UV in the layout,
/// the base-colour texture modulates the diffuse colour (filtered in linear light by the
/// texture's sampler: trilinear by default, its level of detail from the UV's exact
/// screen-space derivatives, which the rasterizer computes only for draws with a texture).
pub struct LitShader<'a> {
    pub draws: &'a [DrawParams],
    pub lights: &'a LightSet,
    /// Indices into `lights.sources`, per draw ([`DrawParams::lights`]).
    pub active: &'a [u32],
    pub eye: Vec3,
    /// Unit view direction (for depth fog).
    pub forward: Vec3,
    /// Linear fog per pixel; `None` costs nothing.
    pub fog: Option<Fog>,
    pub layout: LitLayout,
    pub blinn: bool,
    /// Scale of the UV derivatives before the texture's level of detail is chosen: 1 for
    /// one sample per pixel, 1/n for a pass of an n x n supersampled frame (whose samples
    /// are 1/n pixel apart, as if rendered n times larger).
    pub lod_scale: f32,
}

impl FragmentShader for LitShader<'_> {
    #[inline(always)]
    fn derivatives(&self, draw: u32) -> Option<(usize, usize)> {
        let d = &self.draws[draw as usize];
        let textured = d.texture.is_some() || d.gloss.is_some();
        self.layout.uv_at().filter(|_| textured).map(|k| (k, 2))
    }

    #[inline(always)]
    fn shade<K: Kernel>(&self, f: &Fragments<'_>, out: &mut Colors) -> u32 {
        let d = &self.draws[f.tri.draw as usize];
        let v = f.var;
        if v.len() < self.layout.stride() {
            return 0;
        }
        let mut base = Colors::splat(d.base);
        if let Some(k) = self.layout.color_at() {
            base.r *= v[k];
            base.g *= v[k + 1];
            base.b *= v[k + 2];
            base.a *= v[k + 3];
        }
        let sample = |t: &Texture| {
            let k = self.layout.uv_at().unwrap_or(0);
            let (s, l) = (d.sampler, self.lod_scale);
            let (u, w) = (v[k], v[k + 1]);
            if let ([dudx, dvdx, ..], [dudy, dvdy, ..]) = (f.ddx, f.ddy) {
                t.sample_grad_lanes::<K>(
                    u,
                    w,
                    *dudx * l,
                    *dvdx * l,
                    *dudy * l,
                    *dvdy * l,
                    f.mask,
                    s,
                )
            } else {
                t.sample_lanes::<K>(u, w, f.mask, s)
            }
        };
        let uv = self.layout.uv_at().is_some();
        if let (true, Some(t)) = (uv, &d.texture) {
            let c = sample(t);
            base.r *= c[0];
            base.g *= c[1];
            base.b *= c[2];
            base.a *= c[3];
        }
        let ks = d.surface.specular;
        let specular = match (uv, &d.gloss) {
            (true, Some(g)) => {
                let c = sample(g);
                V3::new(c[0] * ks.x, c[1] * ks.y, c[2] * ks.z)
            }
            _ => V3::splat(ks),
        };
        let mut n = V3::new(v[3], v[4], v[5]).normalize_or_zero::<K>();
        if !f.tri.front {
            n = -n;
        }
        let s = SurfaceLanes {
            diffuse: V3::new(base.r, base.g, base.b),
            specular,
            has_specular: ks != Vec3::ZERO,
            ambient: d.surface.ambient,
            shininess: F8::splat(d.surface.shininess),
        };
        let p = V3::new(v[0], v[1], v[2]);
        let active = d.active(self.active);
        let mut c = illuminate_lanes::<K>(self.lights, active, &s, p, n, self.eye, self.blinn);
        if let Some(fog) = &self.fog {
            c = fog.apply_lanes::<K>(c, p, self.eye, self.forward);
        }
        let (a, keep) = d.alpha_lanes(base.a, f.mask);
        *out = Colors {
            r: c.x,
            g: c.y,
            b: c.z,
            a,
        };
        keep
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

/// Debug views; the varyings are the quantity itself (normal, view distance, or UV; 3 floats).
pub struct DebugShader {
    pub mode: Debug,
    pub near: f32,
    pub far: f32,
}

impl FragmentShader for DebugShader {
    #[inline(always)]
    fn shade<K: Kernel>(&self, f: &Fragments<'_>, out: &mut Colors) -> u32 {
        let [x, y, z] = match f.var {
            [x, y, z, ..] => [*x, *y, *z],
            _ => return 0,
        };
        // Debug colours are display values: decode so the PNG shows them as computed.
        let [r, g, b] = match self.mode {
            // Raw interpolated normals, not flipped on back faces: this view is for finding
            // inverted normals.
            Debug::Normals => {
                let n = V3::new(x, y, z).normalize_or_zero::<K>();
                let half = F8::splat(0.5);
                [n.x * half + half, n.y * half + half, n.z * half + half]
            }
            Debug::Depth => {
                let t = (x - self.near) * (1.0 / (self.far - self.near));
                let v = F8::ONE - t.clamp(0.0, 1.0);
                [v, v, v]
            }
            Debug::Uv => {
                let fract = |v: F8| v.map(|x| if x.is_finite() { x - x.floor() } else { 0.0 });
                [fract(x), fract(y), F8::ZERO]
            }
        };
        *out = Colors {
            r: r.map(srgb_to_linear),
            g: g.map(srgb_to_linear),
            b: b.map(srgb_to_linear),
            a: F8::ONE,
        };
        f.mask
    }
}

/// Counts fragments: red = 1 per fragment, for an additive pass with the depth test off
/// (the overdraw view: how many fragments each pixel received).
pub struct CountShader;

impl FragmentShader for CountShader {
    #[inline(always)]
    fn shade<K: Kernel>(&self, f: &Fragments<'_>, out: &mut Colors) -> u32 {
        *out = Colors::splat(Vec4::new(1.0, 0.0, 0.0, 0.0));
        f.mask
    }
}

/// Writes depth only (hidden-line pass of wireframe, centre-depth pass).
pub struct DepthOnly;

impl FragmentShader for DepthOnly {
    #[inline(always)]
    fn shade<K: Kernel>(&self, f: &Fragments<'_>, out: &mut Colors) -> u32 {
        *out = Colors::default();
        f.mask
    }
}
