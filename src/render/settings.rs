//! What to render, in two parts: [`Settings`], which change rarely (shading, lights,
//! materials, quality), and the per-frame [`View`] (camera and size). A viewer keeps one
//! `Settings` while the user drags the camera, and sends a new `View` every frame.

use glam::Vec4;

use crate::raster::KernelKind;
use crate::scene::{Camera, Light, Material, SlotOverrides};
use crate::shade::{Fog, Shading, ShadowSettings};
use crate::texture::Filter;

/// The lights a frame uses.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Lights {
    /// The scene's lights, or [`Light::default_rig`] attached to the camera if it has none.
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

/// What happens to colours outside [0, 1] (the textbook's pipeline chapter, §4.2) before they are
/// encoded.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ToneMap {
    /// Each channel clamped to [0, 1]: (1, 2, 1) becomes white.
    #[default]
    Clamp,
    /// A colour whose largest channel exceeds 1 is divided by it, keeping its hue:
    /// (1, 2, 1) becomes (0.5, 1, 0.5), light green.
    ScaleMax,
    /// Reinhard's operator on luminance, `L / (1 + L)`, applied as a scale to the colour
    /// (then scaled by the largest channel if one still exceeds 1): every colour stays in
    /// range and keeps its hue; darkens everything a little.
    Reinhard,
}

impl ToneMap {
    pub const ALL: [ToneMap; 3] = [ToneMap::Clamp, ToneMap::ScaleMax, ToneMap::Reinhard];

    /// The name on the command line and in scene files.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            ToneMap::Clamp => "clamp",
            ToneMap::ScaleMax => "scale-max",
            ToneMap::Reinhard => "reinhard",
        }
    }

    /// Maps one linear colour (alpha kept).
    #[must_use]
    #[inline]
    pub fn apply(self, c: Vec4) -> Vec4 {
        let rgb = c.truncate();
        let scale_max = |rgb: glam::Vec3| {
            let m = rgb.max_element();
            if m > 1.0 && m.is_finite() {
                rgb / m
            } else {
                rgb
            }
        };
        let out = match self {
            ToneMap::Clamp => return c,
            ToneMap::ScaleMax => scale_max(rgb),
            ToneMap::Reinhard => {
                let l = rgb.dot(glam::Vec3::new(0.2126, 0.7152, 0.0722));
                if l > 0.0 && l.is_finite() {
                    scale_max(rgb / (1.0 + l))
                } else {
                    rgb
                }
            }
        };
        out.extend(c.w)
    }
}

impl std::str::FromStr for ToneMap {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        ToneMap::ALL
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(s))
            .ok_or_else(|| {
                format!("unknown tone map '{s}' (expected clamp, scale-max or reinhard)")
            })
    }
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
    /// The kernel the fill and shaders run with; `None` is [`KernelKind::best`] (a kernel the
    /// CPU lacks runs as the portable one).
    pub kernel: Option<KernelKind>,
    /// Linear fog: per pixel in the per-pixel modes, per vertex in Gouraud, per facet in
    /// flat; `None` costs nothing.
    pub fog: Option<Fog>,
    /// Out-of-range colour handling.
    pub tone: ToneMap,
    /// Shadow-map size and filtering for the lights that cast shadows (each light's
    /// `shadow` flag turns them on; none costs nothing).
    pub shadow: ShadowSettings,
    /// Shows a ground plane under the scene (it catches shadows).
    pub ground: Option<Ground>,
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
            tone: ToneMap::Clamp,
            shadow: ShadowSettings::default(),
            ground: None,
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
