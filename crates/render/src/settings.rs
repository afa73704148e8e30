//! What to render, in two parts: [`Settings`], which change rarely (shading, lights,
//! materials, quality), and the per-frame [`View`] (camera and size). A viewer keeps one
//! `Settings` while the user drags the camera, and sends a new `View` every frame.

use glam::Vec4;

use crate::scene::{Camera, Light, Material, Scene, SlotOverrides, Style};
use crate::shade::{Fog, Shading, ShadowSettings};
use crate::simd::KernelKind;
use crate::texture::Filter;

mod environment;
mod sections;
#[cfg(test)]
mod tests;
mod tone;

pub use environment::Environment;
pub use sections::Sections;
pub use tone::ToneMap;

/// [`Settings::ray_depth`]'s default: deep enough that a white room's paths lose well under
/// 0.1% of their light to the limit (0.8³² of it), while Russian roulette ends most paths
/// long before.
pub const DEFAULT_RAY_DEPTH: u32 = 32;
/// The largest [`Settings::ray_depth`] accepted: Whitted's rays recurse once per surface,
/// and 64 levels stay far inside a rendering thread's stack.
pub const MAX_RAY_DEPTH: u32 = 64;

/// The lights a frame uses.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Lights {
    /// The scene's lights; if it has none, [`Light::default_rig`] attached to the camera,
    /// except for a scene drawn entirely in the `pbr` mode under an environment, which the
    /// environment alone lights, as the Khronos glTF Sample Viewer does
    /// ([`Settings::default_rig`]).
    #[default]
    Auto,
    /// These lights instead of the scene's. With `follow_camera`, positions and directions
    /// are in camera space (x right, y up, z towards the viewer) and move with the camera;
    /// otherwise they are in world space.
    Custom {
        lights: Vec<Light>,
        follow_camera: bool,
    },
}

/// What the frame shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Output {
    /// The shaded image.
    #[default]
    Shaded,
    /// How many fragments each pixel received (every triangle that survives culling and
    /// clipping, depth test off), as a colour ramp: see [`overdraw_color`](super::overdraw_color).
    Overdraw,
}

/// A ground plane that catches shadows, placed just under the scene's bounds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ground {
    /// Linear RGB diffuse colour.
    pub color: glam::Vec3,
    /// Half-size as a multiple of the scene's bounding radius.
    pub extent: f32,
}

impl Default for Ground {
    fn default() -> Self {
        Self {
            color: glam::Vec3::splat(0.5),
            extent: 4.0,
        }
    }
}

/// Settings that change rarely: everything but the camera and the size.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Forces one mode on every instance; `None` = each instance's style, else textured
    /// for meshes with a texture, else Phong.
    pub shading: Option<Shading>,
    /// Draws the mesh edges (hidden lines removed) over the shaded opaque instances.
    pub wireframe_overlay: bool,
    pub output: Output,
    /// Linear RGBA.
    pub background: Vec4,
    /// Draw every material double-sided: no back-face culling, back faces lit from behind.
    pub double_sided: bool,
    /// Sub-pixel bits of the vertex snap (see [`crate::raster::DrawState::subpixel_bits`]).
    pub subpixel_bits: u8,
    /// Per-slot replacements of every material's textures (`--texture`, `--bump`,
    /// `--normal-map off`; the viewer's texture panel): a slot's source, or the slot off.
    pub slots: SlotOverrides,
    /// Reads every texture with this filter instead of its sampler's.
    pub filter: Option<Filter>,
    pub lights: Lights,
    /// Replaces the scene's materials (same order and count; missing entries keep the
    /// scene's): what a material editor changes.
    pub materials: Option<Vec<Material>>,
    /// Supersampling: `samples` x `samples` sub-pixel positions per pixel on a regular grid,
    /// each rendered as a whole pass with the projection shifted by a fraction of a pixel
    /// and averaged in linear light (1 = one sample at the pixel centre). Clamped to 1..=8.
    pub samples: u32,
    /// Multisampling: coverage and depth samples per pixel, 1 or 4 (see
    /// [`crate::raster::Target::set_samples`]), shaded once per pixel and triangle and
    /// resolved in linear light. Combines with `samples` (each supersampling pass is
    /// multisampled).
    pub msaa: u32,
    /// The most surfaces a traced ray may meet after the first (the textbook's depth
    /// limit, §9.6.1): Whitted's reflection and refraction depth, the path tracer's bounce
    /// limit. 0 to [`MAX_RAY_DEPTH`]; a ray at the limit keeps its surface's environment
    /// light (Whitted) or ends (path; its last surface's direct light is complete: 0 gives
    /// the direct light alone).
    pub ray_depth: u32,
    /// The kernel the fill and shaders run with; `None` is [`KernelKind::best`] (a kernel the
    /// CPU lacks runs as the portable one).
    pub kernel: Option<KernelKind>,
    /// Linear fog: per pixel in the per-pixel modes, per vertex in Gouraud, per facet in
    /// flat; `None` costs nothing.
    pub fog: Option<Fog>,
    /// Exposure in EV: colours are multiplied by `2^exposure` before the tone map (0: as
    /// rendered). glTF light units (lux, candela) and environments in cd/m² need it.
    pub exposure: f32,
    /// Out-of-range colour handling.
    pub tone: ToneMap,
    /// The environment of the `pbr` draws.
    pub environment: Environment,
    /// Shows the environment behind the scene, blurred to this roughness (0: sharp), instead
    /// of the background colour; `None`: the colour.
    pub env_background: Option<f32>,
    /// Shadow-map size and filtering for the lights that cast shadows (each light's
    /// `shadow` flag turns them on; none costs nothing).
    pub shadow: ShadowSettings,
    /// Shows a ground plane under the scene (it catches shadows).
    pub ground: Option<Ground>,
    /// Size of the meshes' points, in pixels of the image (default 1; rounded to whole
    /// pixels, 1 to [`crate::raster::MAX_STROKE_PX`]; see [`crate::raster::draw_points`]).
    pub point_size: f32,
    /// Width of the meshes' lines, in pixels of the image (default 1; rounded to whole
    /// pixels, 1 to [`crate::raster::MAX_STROKE_PX`]; see [`crate::raster::draw_wide_lines`]).
    pub line_width: f32,
    /// How Gouraud and flat shading light their vertices and facets.
    pub vertex_lighting: VertexLighting,
    /// Section planes that cut the model open, with caps where a solid's inside shows.
    pub sections: Sections,
    /// The punctual lights reflect off `pbr` surfaces by the specification's
    /// single-scattering BRDF, without the compensation for the energy rough surfaces lose
    /// between microfacets (on by default, as in three.js; the environment is always
    /// compensated).
    pub single_scatter: bool,
    /// Scene instances left out (the viewer's hide and isolate in its node tree).
    pub hidden: Hidden,
    /// The material variant drawn, by name (`KHR_materials_variants`; one of
    /// [`crate::scene::Scene::variants`]), or `None` for the file's default materials. A
    /// name the scene does not have draws the defaults (the command line and scene files
    /// check it against the model first).
    pub variant: Option<String>,
}

/// A set of [`crate::scene::Scene::instances`] indices that the frame leaves out: they are
/// not drawn, cast no shadow and are not picked by the probe or the measurement. One bit
/// per instance up to the highest hidden one, so equal sets compare equal however they
/// were made.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Hidden {
    bits: Vec<u64>,
}

impl Hidden {
    /// The highest instance number a set takes (a scene file's `hidden` is checked
    /// against it, so a stray number cannot make the set huge).
    pub const MAX_INSTANCE: usize = (1 << 24) - 1;

    /// The hidden instance numbers, ascending.
    pub fn iter(&self) -> impl Iterator<Item = usize> + '_ {
        self.bits.iter().enumerate().flat_map(|(w, &bits)| {
            (0..64)
                .filter(move |b| bits & (1u64 << b) != 0)
                .map(move |b| w * 64 + b)
        })
    }

    /// Whether instance `k` is hidden.
    #[must_use]
    #[inline]
    pub fn contains(&self, k: usize) -> bool {
        self.bits
            .get(k / 64)
            .is_some_and(|w| w & (1u64 << (k % 64)) != 0)
    }

    /// Hides (`hidden`) or shows instance `k` (numbers above [`Hidden::MAX_INSTANCE`] are
    /// ignored).
    pub fn set(&mut self, k: usize, hidden: bool) {
        if k > Self::MAX_INSTANCE {
            return;
        }
        let (word, bit) = (k / 64, 1u64 << (k % 64));
        if hidden {
            if self.bits.len() <= word {
                self.bits.resize(word + 1, 0);
            }
            self.bits[word] |= bit;
        } else if let Some(w) = self.bits.get_mut(word) {
            *w &= !bit;
            while self.bits.last() == Some(&0) {
                self.bits.pop();
            }
        }
    }

    /// Every one of the `count` instances hidden except those of `keep` (isolate).
    #[must_use]
    pub fn all_but(count: usize, keep: impl IntoIterator<Item = usize>) -> Self {
        let mut h = Self::default();
        for k in 0..count {
            h.set(k, true);
        }
        for k in keep {
            h.set(k, false);
        }
        h
    }

    /// How many instances are hidden.
    #[must_use]
    pub fn count(&self) -> usize {
        self.bits.iter().map(|w| w.count_ones() as usize).sum()
    }

    /// Nothing hidden.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.bits.is_empty()
    }
}

/// The lighting formulas of the vertex modes (Gouraud and flat). The default is the
/// textbook's: Phong's `R·V` highlight, and flat shading lit once per facet at its centroid
/// (the textbook's §9.2.2). [`VertexLighting::GL`] is what GPU shaders and Mesa's llvmpipe
/// commonly do: Blinn's `N·H`, and flat shading lit at each triangle's last vertex (OpenGL's
/// provoking vertex) with the triangle's plane normal.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct VertexLighting {
    /// Blinn's `N·H` highlight instead of Phong's `R·V`.
    pub blinn: bool,
    /// Flat shading lights each triangle at its last vertex, with the triangle's own plane
    /// normal, instead of each facet at its centroid.
    pub provoking_vertex: bool,
}

impl VertexLighting {
    /// Blinn's highlight and the provoking vertex: the formulas of `bench frame`'s peer.
    pub const GL: VertexLighting = VertexLighting {
        blinn: true,
        provoking_vertex: true,
    };
}

impl Settings {
    /// Every instance of `scene` that draws triangles is drawn in the `pbr` mode (glTF
    /// materials as authored, or `pbr` forced), and there is one: the glTF look, whose
    /// defaults are the Khronos glTF Sample Viewer's ([`ToneMap::Auto`], [`Lights::Auto`]).
    #[must_use]
    pub fn pbr_look(&self, scene: &Scene) -> bool {
        if let Some(mode) = self.shading {
            return mode.mode().base == crate::shade::mode::Base::Pbr
                && !scene.instances.is_empty();
        }
        let mut any = false;
        for inst in &scene.instances {
            let Some(mesh) = scene.meshes.get(inst.mesh) else {
                continue;
            };
            if mesh.corners.is_empty() {
                // Points and lines only: not shaded by a mode.
                continue;
            }
            let material = mesh.material_in(self.variant_index(scene)).and_then(|k| {
                self.materials
                    .as_ref()
                    .and_then(|ms| ms.get(k))
                    .or_else(|| scene.materials.get(k))
            });
            let pbr = material.is_some_and(|m| m.pbr.is_some());
            if !pbr || inst.style != Style::Inherit {
                return false;
            }
            any = true;
        }
        any
    }

    /// The index in `scene`'s [`crate::scene::Scene::variants`] of [`Settings::variant`].
    #[must_use]
    pub fn variant_index(&self, scene: &Scene) -> Option<usize> {
        let name = self.variant.as_deref()?;
        scene.variants.iter().position(|v| v == name)
    }

    /// What rays the shading mode traces beside rasterizing (the textbook's §9.6).
    #[must_use]
    pub fn rays(&self) -> crate::shade::mode::Rays {
        self.shading
            .map_or(crate::shade::mode::Rays::None, |s| s.mode().rays)
    }

    /// [`Lights::Auto`] with no lights in `scene` lights the frame with the default rig;
    /// not when the pbr look ([`Settings::pbr_look`]) is lit by an environment.
    #[must_use]
    pub fn default_rig(&self, scene: &Scene) -> bool {
        matches!(self.lights, Lights::Auto)
            && scene.lights.is_empty()
            && (self.environment == Environment::Off || !self.pbr_look(scene))
    }

    /// The tone map of a frame of `scene`: [`ToneMap::Auto`] resolved.
    #[must_use]
    pub fn tone_for(&self, scene: &Scene) -> ToneMap {
        match self.tone {
            ToneMap::Auto if self.pbr_look(scene) => ToneMap::PbrNeutral,
            ToneMap::Auto => ToneMap::Clamp,
            t => t,
        }
    }

    /// `2^exposure`, or 1 when the exposure is not finite or beyond +-64 EV.
    #[must_use]
    pub fn exposure_scale(&self) -> f32 {
        if self.exposure.is_finite() && self.exposure.abs() <= 64.0 {
            libm::exp2f(self.exposure)
        } else {
            1.0
        }
    }
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            shading: None,
            wireframe_overlay: false,
            output: Output::Shaded,
            background: Vec4::new(0.018, 0.02, 0.026, 1.0),
            double_sided: false,
            subpixel_bits: crate::raster::SUBPIXEL_BITS as u8,
            slots: SlotOverrides::default(),
            filter: None,
            lights: Lights::Auto,
            materials: None,
            samples: 1,
            msaa: 1,
            kernel: None,
            fog: None,
            exposure: 0.0,
            tone: ToneMap::Auto,
            environment: Environment::Auto,
            env_background: None,
            shadow: ShadowSettings::default(),
            ground: None,
            point_size: 1.0,
            line_width: 1.0,
            vertex_lighting: VertexLighting::default(),
            sections: Sections::default(),
            hidden: Hidden::default(),
            variant: None,
            single_scatter: false,
            ray_depth: DEFAULT_RAY_DEPTH,
        }
    }
}

/// The per-frame part: the camera and the image size in pixels.
#[derive(Clone, Debug, PartialEq)]
pub struct View {
    pub camera: Camera,
    /// Image width in pixels (at least 1).
    pub width: u32,
    /// Image height in pixels (at least 1).
    pub height: u32,
}

impl View {
    /// Width over height.
    #[must_use]
    pub fn aspect(&self) -> f32 {
        self.width.max(1) as f32 / self.height.max(1) as f32
    }
}
