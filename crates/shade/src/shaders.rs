//! Fragment shaders, one type per shading mode, each shading eight pixels (lanes) at a time
//! from the varyings the vertex stage laid out (see [`LitLayout`], one per draw). Per-draw
//! material parameters are looked up by `TriInfo::draw`.

use glam::{Vec2, Vec3, Vec4};

use super::lighting::{Fog, LightSet, Surface};
use super::stages::{alpha_lanes, Cx, Program, Regs};
use crate::raster::{Batch, Colors, FragmentShader, GROUPS};
use crate::scene::{AlphaMode, TextureSource, UvTransform};
use crate::simd::{KernelKind, Lane, Level, F8, V3};
use crate::texture::{srgb_to_linear, Sampler};

/// How many slots the `KHR_materials_*` extensions have ([`DrawParams::layer_maps`]).
pub const LAYER_SLOTS: usize = crate::scene::Slot::LAYERS.len();

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
    /// The `KHR_materials_*` extensions' textures ([`Slot::LAYERS`](crate::scene::Slot),
    /// in its order; `pbr` mode): see [`crate::layer_maps`].
    pub layer_maps: [Option<SlotParams>; LAYER_SLOTS],
    /// The per-axis scale of the instance's world matrix (`KHR_materials_volume`'s
    /// thickness is in the mesh's units).
    pub model_scale: Vec3,
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
        .chain(&self.layer_maps)
        .flatten()
    }

    /// The draw's texture in `slot`, one of the extensions' ([`Self::layer_maps`]).
    #[inline(always)]
    #[must_use]
    pub fn layer_map(&self, slot: crate::scene::Slot) -> Option<&SlotParams> {
        self.layer_maps.get(slot.layer_index()?)?.as_ref()
    }

    /// Whether the draw transmits light (`KHR_materials_transmission` in the lit `pbr`
    /// mode): drawn after the opaque surfaces, it reads them through the frame's
    /// [`Backdrop`].
    #[inline(always)]
    #[must_use]
    pub fn transmits(&self) -> bool {
        self.view == TexView::Lit
            && !self.unlit
            && self.surface.pbr.is_some_and(|p| p.transmission > 0.0)
    }

    /// The extensions' slots the draw reads: bit `i` for `Slot::LAYERS[i]`.
    #[inline(always)]
    #[must_use]
    pub fn layer_mask(&self) -> u8 {
        let mut mask = 0;
        for (i, m) in self.layer_maps.iter().enumerate() {
            if m.is_some() {
                mask |= 1 << i;
            }
        }
        mask
    }
}

/// Flat and Gouraud: the colour was computed per facet or per vertex and is interpolated.
/// Varyings: RGBA (4 floats). Gouraud on a double-sided material lights each vertex from
/// both sides (8 floats, front then back) and draws with
/// [`DrawState::facing_varyings`](crate::raster::DrawState), so set-up keeps the side each
/// triangle shows.
pub struct ColorShader<'a> {
    pub draws: &'a [DrawParams],
    /// The kernel the shading runs with.
    pub kernel: KernelKind,
}

impl FragmentShader for ColorShader<'_> {
    fn defers(&self, draw: u32) -> bool {
        !self.discards(draw)
    }

    /// Opaque draws: the colour is the interpolated RGB, alpha 1.
    fn colour_is_varyings(&self, draw: u32) -> bool {
        self.draws
            .get(draw as usize)
            .is_some_and(|d| d.alpha == AlphaMode::Opaque)
    }

    fn discards(&self, draw: u32) -> bool {
        self.draws
            .get(draw as usize)
            .is_none_or(|d| matches!(d.alpha, AlphaMode::Mask(_)))
    }

    fn shade(&self, b: &mut Batch) {
        let Some(d) = self.draws.get(b.draw as usize) else {
            b.mask = [0; GROUPS];
            return;
        };
        if b.stride < 4 {
            b.mask = [0; GROUPS];
            return;
        }
        color_groups::pick(self.kernel)(b, d.alpha);
    }
}

crate::simd::per_kernel! {
    /// The interpolated colours of the batch's groups, with alpha mode `alpha`.
    fn color_groups<L>(b: &mut Batch, alpha: AlphaMode) {
        for g in 0..b.len.min(GROUPS) {
            let c = &b.var[g];
            let (a, keep) = alpha_lanes(alpha, c[3].get::<L>(), b.mask[g]);
            b.out[g] = Colors {
                r: c[0],
                g: c[1],
                b: c[2],
                a: a.into(),
            };
            b.mask[g] = keep;
        }
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

/// Phong (R·V) or Blinn-Phong (N·H, per draw) per-pixel lighting from the varyings of each
/// draw's [`LitLayout`]. The slots a draw has modulate it: the base-colour texture the
/// diffuse colour and alpha, the gloss map the specular colour, the normal map the normal,
/// occlusion the ambient term, the emissive map the emitted light. Each is filtered in
/// linear light by its own sampler (trilinear by default, its level of detail from the UV's
/// exact screen-space derivatives, which the rasterizer computes only for draws that sample
/// a texture).
pub struct LitShader<'a> {
    pub draws: &'a [DrawParams],
    /// Each draw's stages ([`Program::build`]), parallel to `draws`.
    pub programs: &'a [Program],
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
    /// The opaque frame the transmissive draws see through, when the frame has any.
    pub backdrop: Option<&'a Backdrop>,
}

/// What a transmissive surface (`KHR_materials_transmission`) sees through: the frame's
/// opaque surfaces and background in linear light, with mips (the rougher the surface, the
/// blurrier the level read), and the world -> clip transform they were drawn with.
#[derive(Debug)]
pub struct Backdrop {
    pub image: std::sync::Arc<crate::texture::Texture>,
    pub view_proj: glam::Mat4,
}

impl FragmentShader for LitShader<'_> {
    fn derivatives(&self, draw: u32) -> Option<(usize, usize)> {
        self.draws.get(draw as usize)?.layout.derivatives()
    }

    /// Every draw but an alpha-tested one (which discards lanes): the lit shader is the
    /// expensive one, and on small triangles most of a row's lanes are empty.
    fn defers(&self, draw: u32) -> bool {
        !self.discards(draw)
    }

    fn discards(&self, draw: u32) -> bool {
        self.draws
            .get(draw as usize)
            .is_none_or(|d| matches!(d.alpha, AlphaMode::Mask(_)))
    }

    fn shade(&self, b: &mut Batch) {
        let (Some(d), Some(p)) = (
            self.draws.get(b.draw as usize),
            self.programs.get(b.draw as usize),
        ) else {
            b.mask = [0; GROUPS];
            return;
        };
        if b.stride < d.layout.stride() {
            b.mask = [0; GROUPS];
            return;
        }
        let cx = Cx { s: self, d };
        REGS.with(|cell| match cell.try_borrow_mut() {
            Ok(mut regs) => p.run(b, &mut regs[..], &cx),
            // Never (a shader does not call itself); fresh registers if it ever did.
            Err(_) => p.run(b, &mut [Regs::default(); GROUPS], &cx),
        });
    }
}

thread_local! {
    /// Each worker's stage registers (allocated once per thread).
    static REGS: std::cell::RefCell<Box<[Regs; GROUPS]>> =
        std::cell::RefCell::new(Box::new([Regs::default(); GROUPS]));
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
    /// The kernel the shading runs with.
    pub kernel: KernelKind,
}

impl FragmentShader for DebugShader {
    fn defers(&self, _: u32) -> bool {
        true
    }

    fn discards(&self, _: u32) -> bool {
        false
    }

    fn shade(&self, b: &mut Batch) {
        if b.stride < 3 {
            b.mask = [0; GROUPS];
            return;
        }
        let colours = debug_groups::pick(self.kernel);
        colours(self, b);
    }
}

crate::simd::per_kernel! {
    /// The debug view's colours of the batch's groups.
    fn debug_groups<L>(s: &DebugShader, b: &mut Batch) {
        for g in 0..b.len.min(GROUPS) {
            b.out[g] = s.colours::<L>(&b.var[g]);
        }
    }
}

impl DebugShader {
    /// The view's colours of eight lanes whose varyings are `v` (at least three).
    #[inline(always)]
    fn colours<L: Level>(&self, v: &[Lane]) -> Colors {
        let [x, y, z]: [F8<L>; 3] = [v[0].get(), v[1].get(), v[2].get()];
        // Debug colours are display values: decode so the PNG shows them as computed.
        let [r, g, b] = match self.mode {
            // Raw interpolated normals, not flipped on back faces: this view is for finding
            // inverted normals.
            Debug::Normals => {
                let n = V3::new(x, y, z).normalize_or_zero();
                let half = F8::splat(0.5);
                [n.x * half + half, n.y * half + half, n.z * half + half]
            }
            Debug::Depth => {
                let t = (x - self.near) * (1.0 / (self.far - self.near));
                let v = F8::ONE - t.clamp(0.0, 1.0);
                [v, v, v]
            }
            Debug::Uv => {
                let fract = |v: F8<L>| v.map(|x| if x.is_finite() { x - x.floor() } else { 0.0 });
                [fract(x), fract(y), F8::ZERO]
            }
        };
        Colors::of(
            r.map(srgb_to_linear),
            g.map(srgb_to_linear),
            b.map(srgb_to_linear),
            F8::ONE,
        )
    }
}

/// Counts fragments: red = 1 per fragment, for an additive pass with the depth test off
/// (the overdraw view: how many fragments each pixel received).
pub struct CountShader;

impl FragmentShader for CountShader {
    fn discards(&self, _: u32) -> bool {
        false
    }

    fn shade(&self, b: &mut Batch) {
        let one = Colors::splat(Vec4::new(1.0, 0.0, 0.0, 0.0));
        for g in 0..b.len.min(GROUPS) {
            b.out[g] = one;
        }
    }
}

/// One linear-light RGBA colour for every fragment (the caps of section planes).
pub struct Constant(pub Vec4);

impl FragmentShader for Constant {
    fn discards(&self, _: u32) -> bool {
        false
    }

    fn shade(&self, b: &mut Batch) {
        let c = Colors::splat(self.0);
        for g in 0..b.len.min(GROUPS) {
            b.out[g] = c;
        }
    }
}

/// Writes depth only (hidden-line pass of wireframe, centre-depth pass): the fill never
/// calls it for a draw that writes no colour.
pub struct DepthOnly;

impl FragmentShader for DepthOnly {
    fn discards(&self, _: u32) -> bool {
        false
    }

    fn shade(&self, b: &mut Batch) {
        for g in 0..b.len.min(GROUPS) {
            b.out[g] = Colors::default();
        }
    }
}
