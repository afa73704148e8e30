//! Fragment shaders, one type per shading mode, each shading eight pixels (lanes) at a time
//! from the varyings the vertex stage laid out (see [`LitLayout`], one per draw). Per-draw
//! material parameters are looked up by `TriInfo::draw`.

use glam::{Vec2, Vec3, Vec4};

use super::lighting::{illuminate, Fog, LightSet, Surface};
use super::maps::perturb_lanes;
use super::texlab;
use crate::raster::{Colors, FragmentShader, Fragments};
use crate::scene::{AlphaMode, TextureSource, UvTransform};
use crate::simd::{Kernel, Lanes, F8, V3};
use crate::texture::{srgb_to_linear, Sampler};

/// A texture one draw samples: the image or procedural texture, how it is read, and where
/// its coordinates are among the draw's varyings: a UV (already through the slot's
/// `KHR_texture_transform`), or for a solid texture the object-space position.
#[derive(Clone, Debug)]
pub struct SlotParams {
    pub source: TextureSource,
    pub sampler: Sampler,
    /// Index of the coordinates' first float in the draw's varyings: a UV channel
    /// ([`LitLayout::uv_at`]) or the object position ([`LitLayout::object_at`]).
    pub uv_at: u8,
    /// The slot's scalar: normal scale, occlusion strength, bump height (1 for the others).
    pub scale: f32,
}

/// What the lit shader shows: the lit surface, or one of the texture-mapping debug views
/// (each colour is a display value, see the README's "Debug views").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum TexView {
    #[default]
    Lit,
    /// The mip level the measured texture's trilinear filter reads, one colour per level.
    MipLevel,
    /// Texels per pixel of the measured texture: blue magnified, green 1:1, red minified.
    TexelDensity,
    /// The pixel footprint's anisotropy in texture space: green 1:1 to red 16:1 and beyond.
    Anisotropy,
    /// The world tangent, mapped from [-1, 1] to [0, 1] per channel.
    Tangents,
    /// The shading normal (after normal and bump maps) in the tangent frame, mapped as a
    /// normal map stores it: (0.5, 0.5, 1) where the maps leave the surface as it is.
    TangentNormals,
}

/// Material parameters of one draw.
#[derive(Clone, Debug)]
pub struct DrawParams {
    pub base: Vec4,
    pub surface: Surface,
    /// Emitted light (linear RGB), added to the lit colour before fog.
    pub emissive: Vec3,
    /// Base colour (textured mode): multiplies `base`.
    pub base_map: Option<SlotParams>,
    /// The gloss map: its RGB multiplies the specular colour (per-pixel modes).
    pub gloss: Option<SlotParams>,
    /// Tangent-space normal map (textured mode; the layout carries the tangent).
    pub normal_map: Option<SlotParams>,
    /// Ambient occlusion (R), on the ambient term only (textured mode).
    pub occlusion: Option<SlotParams>,
    /// Emissive map: multiplies `emissive` (textured mode).
    pub emissive_map: Option<SlotParams>,
    /// Bump map (a height image or a procedural height): tilts the normal (textured mode).
    pub bump: Option<SlotParams>,
    /// The metallic-roughness texture (`pbr` mode): G multiplies the roughness, B the
    /// metallic factor.
    pub metal_rough: Option<SlotParams>,
    /// `KHR_materials_unlit` in the `pbr` mode: the base colour is the colour.
    pub unlit: bool,
    /// The lit surface or a debug view.
    pub view: TexView,
    /// The UV channel (varying index) and texel size of the texture the mip-level,
    /// texel-density and anisotropy views measure.
    pub measure: Option<(u8, [f32; 2])>,
    /// Where this draw's varyings are (lit modes).
    pub layout: LitLayout,
    /// True if any of the maps above is set (see [`DrawParams::maps`]); kept in step by
    /// the renderer, read by the shader so a draw without maps skips them in one test.
    pub mapped: bool,
    /// Blinn's `N·H` highlight (else Phong's `R·V`), per pixel or, in Gouraud and flat, per
    /// vertex and facet ([`crate::render::VertexLighting`]).
    pub blinn: bool,
    /// Flat shading lights each triangle at its last vertex with its plane normal (else
    /// each facet at its centroid).
    pub provoking_vertex: bool,
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

    /// The textures the draw samples (for preparing their mip chains).
    pub fn maps(&self) -> impl Iterator<Item = &SlotParams> {
        [
            &self.base_map,
            &self.gloss,
            &self.normal_map,
            &self.occlusion,
            &self.emissive_map,
            &self.bump,
            &self.metal_rough,
        ]
        .into_iter()
        .flatten()
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

/// Texture coordinate channels a lit draw can carry: one per slot the lit shader samples
/// (base colour, gloss, normal, occlusion, emissive), so a layout never runs out.
pub const MAX_UV_CHANNELS: usize = 5;

/// A texture coordinate channel: UV set `set` through `transform`.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct UvChannel {
    pub set: u32,
    pub transform: UvTransform,
}

/// Where a lit draw's varyings are: world position at 0..3, world normal at 3..6, then its
/// texture coordinate channels (2 floats each: a UV set through a slot's transform, one per
/// distinct pair its slots read), the object-space position in the solid-texture frame (3
/// floats) if a solid texture is read, the vertex colour (4 floats) if the mesh has colours,
/// and the world tangent with its handedness (4 floats) if a normal map needs it. A draw
/// interpolates only these: a slot the material does not use costs nothing per pixel.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct LitLayout {
    pub channels: [UvChannel; MAX_UV_CHANNELS],
    /// Channels in use.
    pub uv_count: u8,
    /// The object-space position for solid textures.
    pub object: bool,
    /// The fill also computes the screen-space derivatives of the world position (bump
    /// mapping's surface gradient).
    pub position_derivatives: bool,
    pub color: bool,
    pub tangent: bool,
}

impl LitLayout {
    /// Floats per vertex (at most 6 + 2 · 5 + 3 + 4 + 4 = 27).
    #[must_use]
    pub fn stride(self) -> usize {
        6 + 2 * self.uv_count as usize
            + 3 * usize::from(self.object)
            + 4 * usize::from(self.color)
            + 4 * usize::from(self.tangent)
    }

    /// End of the UV channels and the object position: the varyings with derivatives.
    fn coordinates_end(self) -> usize {
        6 + 2 * self.uv_count as usize + 3 * usize::from(self.object)
    }

    /// The varyings `(first, count)` whose screen-space derivatives the draw needs: its
    /// texture coordinates (for the level of detail and procedural footprints), from the
    /// world position on when it is bump mapped.
    #[must_use]
    pub fn derivatives(self) -> Option<(usize, usize)> {
        let first = if self.position_derivatives {
            0
        } else {
            Self::uv_at(0)
        };
        let end = self.coordinates_end();
        (end > first).then_some((first, end - first))
    }

    /// Index of the object position's first float.
    #[must_use]
    pub fn object_at(self) -> Option<usize> {
        self.object.then_some(6 + 2 * self.uv_count as usize)
    }

    /// Index of channel `k`'s first float.
    #[must_use]
    pub fn uv_at(k: usize) -> usize {
        6 + 2 * k
    }

    /// Index of the colour's first float.
    #[must_use]
    pub fn color_at(self) -> Option<usize> {
        self.color.then_some(self.coordinates_end())
    }

    /// Index of the tangent's first float.
    #[must_use]
    pub fn tangent_at(self) -> Option<usize> {
        self.tangent
            .then_some(self.coordinates_end() + 4 * usize::from(self.color))
    }

    /// The varying index of the UV of set `set` through `transform`: an existing channel
    /// with the same pair, else a new one. `None` only if all [`MAX_UV_CHANNELS`] are taken
    /// by other pairs.
    pub fn channel(&mut self, set: u32, transform: UvTransform) -> Option<u8> {
        let c = UvChannel { set, transform };
        let n = self.uv_count as usize;
        let k = match self.channels[..n].iter().position(|x| *x == c) {
            Some(k) => k,
            None if n < MAX_UV_CHANNELS => {
                self.channels[n] = c;
                self.uv_count += 1;
                n
            }
            None => return None,
        };
        Some(Self::uv_at(k) as u8)
    }

    /// The channel whose UV starts at varying `uv_at` (see [`LitLayout::uv_at`]).
    #[must_use]
    pub fn channel_at(&self, uv_at: u8) -> UvChannel {
        let k = (uv_at as usize).saturating_sub(Self::uv_at(0)) / 2;
        self.channels.get(k).copied().unwrap_or_default()
    }

    /// Writes one vertex's varyings into `out` (`stride()` floats): position `p`, normal
    /// `n`, the UV of each channel from `uv(set)` (transformed), the object position
    /// `object()` (called only if the layout has it), colour `color`, tangent `tangent` (xyz
    /// and handedness).
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub fn write(
        self,
        out: &mut [f32],
        p: Vec3,
        n: Vec3,
        uv: impl Fn(u32) -> Vec2,
        object: impl Fn() -> Vec3,
        color: Vec4,
        tangent: Vec4,
    ) {
        out[..3].copy_from_slice(&p.to_array());
        out[3..6].copy_from_slice(&n.to_array());
        for (k, c) in self.channels[..self.uv_count as usize].iter().enumerate() {
            let at = Self::uv_at(k);
            out[at..at + 2].copy_from_slice(&c.transform.apply(uv(c.set)).to_array());
        }
        if let Some(k) = self.object_at() {
            out[k..k + 3].copy_from_slice(&object().to_array());
        }
        if let Some(k) = self.color_at() {
            out[k..k + 4].copy_from_slice(&color.to_array());
        }
        if let Some(k) = self.tangent_at() {
            out[k..k + 4].copy_from_slice(&tangent.to_array());
        }
    }
}

/// Samples slot `t` on the lanes of `f` from the draw's varyings `v`, with the exact UV
/// derivatives when the fill computed them, scaled by `lod_scale`; `first` is the first
/// varying with derivatives ([`LitLayout::derivatives`]). `#[inline(always)]`: a sampler
/// that is not inlined into the kernel's entry point loses the kernel's target features.
/// Procedural textures are evaluated one live lane at a time, outside the kernel
/// (`texlab.rs`).
#[inline(always)]
fn sample<K: Kernel>(t: &SlotParams, f: &Fragments<'_>, lod_scale: f32, first: usize) -> [F8; 4] {
    let k = t.uv_at as usize;
    let texture = match &t.source {
        TextureSource::Image(texture) => texture,
        TextureSource::Procedural(p) => {
            return texlab::procedural_lanes(p, f, k, first, lod_scale);
        }
    };
    let v = f.var;
    let (u, w) = (v[k], v[k + 1]);
    let d = k.wrapping_sub(first);
    match (f.ddx.get(d..d + 2), f.ddy.get(d..d + 2)) {
        (Some([dudx, dvdx]), Some([dudy, dvdy])) => texture.sample_grad_lanes::<K>(
            u,
            w,
            *dudx * lod_scale,
            *dvdx * lod_scale,
            *dudy * lod_scale,
            *dvdy * lod_scale,
            f.mask,
            t.sampler,
        ),
        _ => texture.sample_lanes::<K>(u, w, f.mask, t.sampler),
    }
}

/// What a draw's maps change at a pixel, beyond the base colour.
struct Mapped {
    specular: V3,
    /// The metallic-roughness texture's (roughness, metallic) factors.
    metal_rough: Option<(F8, F8)>,
    /// Unit, not yet flipped for back faces.
    normal: V3,
    occlusion: Option<F8>,
    emitted: V3,
}

/// Samples every slot of draw `d` on the lanes of `f` at one call site (the sampler is
/// inlined once, not once per slot) and applies them: the base-colour texture to `base`,
/// the gloss map, normal map, occlusion and emissive map to `m`.
#[inline(always)]
fn apply_maps<K: Kernel>(
    d: &DrawParams,
    f: &Fragments<'_>,
    lod_scale: f32,
    mut base: Colors,
    mut m: Mapped,
) -> (Colors, Mapped) {
    let slots = [
        &d.base_map,
        &d.gloss,
        &d.normal_map,
        &d.occlusion,
        &d.emissive_map,
        &d.metal_rough,
    ];
    let first = d
        .layout
        .derivatives()
        .map_or(usize::MAX, |(first, _)| first);
    let mut texel = [[F8::ONE; 4]; 6];
    for (t, out) in slots.iter().zip(&mut texel) {
        if let Some(t) = t {
            *out = sample::<K>(t, f, lod_scale, first);
        }
    }
    let [base_t, gloss_t, normal_t, occlusion_t, emissive_t, mr_t] = texel;
    if d.metal_rough.is_some() {
        m.metal_rough = Some((mr_t[1], mr_t[2]));
    }
    if d.base_map.is_some() {
        base.r *= base_t[0];
        base.g *= base_t[1];
        base.b *= base_t[2];
        base.a *= base_t[3];
    }
    if d.gloss.is_some() {
        let ks = d.surface.specular;
        m.specular = V3::new(gloss_t[0] * ks.x, gloss_t[1] * ks.y, gloss_t[2] * ks.z);
    }
    if let Some(map) = &d.normal_map {
        m.normal = match d.layout.tangent_at() {
            Some(k) => {
                let v = f.var;
                let t = V3::new(v[k], v[k + 1], v[k + 2]);
                perturb_lanes::<K>(m.normal, t, v[k + 3], normal_t, map.scale)
            }
            // A mesh without tangents: the frame from the derivatives, per lane.
            None => texlab::derived_normal_lanes(map, f, first, &normal_t, m.normal),
        };
    }
    if let Some(b) = &d.bump {
        m.normal = texlab::bump_lanes(b, f, first, lod_scale, m.normal);
    }
    // glTF: ao = 1 + strength (r - 1), on the ambient (indirect) light only.
    if let Some(o) = &d.occlusion {
        m.occlusion = Some(F8::ONE + (occlusion_t[0] - F8::ONE) * o.scale);
    }
    if d.emissive_map.is_some() {
        m.emitted = V3::new(emissive_t[0], emissive_t[1], emissive_t[2]) * d.emissive;
    }
    (base, m)
}

/// Phong (R·V) or Blinn-Phong (N·H, per draw) per-pixel lighting from the varyings of each
/// draw's [`LitLayout`]. The slots a draw has modulate it: the base-colour texture the
/// diffuse colour and alpha, the gloss map the specular colour, the normal map the normal,
/// occlusion the ambient term, the emissive map the emitted light. Each is filtered in
/// linear light by its own sampler (trilinear by default, its level of detail from the UV's
/// exact screen-space derivatives, which the rasterizer computes only for draws that sample
/// a texture).
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
    /// Scale of the UV derivatives before the texture's level of detail is chosen: 1 for
    /// one sample per pixel, 1/n for a pass of an n x n supersampled frame (whose samples
    /// are 1/n pixel apart, as if rendered n times larger).
    pub lod_scale: f32,
}

impl FragmentShader for LitShader<'_> {
    #[inline(always)]
    fn derivatives(&self, draw: u32) -> Option<(usize, usize)> {
        self.draws[draw as usize].layout.derivatives()
    }

    /// Every draw but an alpha-tested one (which discards lanes): the lit shader is the
    /// expensive one, and on small triangles most of a row's lanes are empty.
    #[inline(always)]
    fn packs(&self, draw: u32) -> bool {
        self.draws
            .get(draw as usize)
            .is_some_and(|d| !matches!(d.alpha, AlphaMode::Mask(_)))
    }

    #[inline(always)]
    fn shade<K: Kernel>(&self, f: &Fragments<'_>, out: &mut Colors) -> u32 {
        let d = &self.draws[f.tri.draw as usize];
        let v = f.var;
        if v.len() < d.layout.stride() {
            return 0;
        }
        let mut base = Colors::splat(d.base);
        if let Some(k) = d.layout.color_at() {
            base.r *= v[k];
            base.g *= v[k + 1];
            base.b *= v[k + 2];
            base.a *= v[k + 3];
        }
        let ks = d.surface.specular;
        let m = Mapped {
            specular: V3::splat(ks),
            metal_rough: None,
            normal: V3::new(v[3], v[4], v[5]).normalize_or_zero::<K>(),
            occlusion: None,
            emitted: V3::splat(d.emissive),
        };
        // One flag for a draw without maps: it pays for no slot.
        let (base, m) = if d.mapped {
            apply_maps::<K>(d, f, self.lod_scale, base, m)
        } else {
            (base, m)
        };
        if d.view != TexView::Lit {
            let n = if f.tri.front { m.normal } else { -m.normal };
            *out = texlab::debug_lanes(d, f, self.lod_scale, n);
            return f.mask;
        }
        if d.unlit {
            let (a, keep) = d.alpha_lanes(base.a, f.mask);
            *out = Colors { a, ..base };
            return keep;
        }
        let Mapped {
            specular,
            metal_rough,
            normal: mut n,
            occlusion,
            emitted,
        } = m;
        if !f.tri.front {
            n = -n;
        }
        let mut s = d.surface.at::<Lanes<K>>(V3::new(base.r, base.g, base.b));
        s.ks = specular;
        s.occlusion = occlusion.map(Lanes::new);
        if let (Some(p), Some((r, m))) = (&mut s.pbr, metal_rough) {
            p.roughness = p.roughness * Lanes::new(r);
            p.metallic = p.metallic * Lanes::new(m);
        }
        s.emitted = (d.emissive != Vec3::ZERO).then_some(emitted);
        let p = V3::new(v[0], v[1], v[2]);
        let active = d.active(self.active);
        let eye = V3::splat(self.eye);
        let mut c = illuminate::<Lanes<K>>(self.lights, Some(active), &s, p, n, eye, d.blinn);

        if let Some(fog) = &self.fog {
            c = fog.apply::<Lanes<K>>(c, p, eye, V3::splat(self.forward));
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
