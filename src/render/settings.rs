//! What to render, in two parts: [`Settings`], which change rarely (shading, lights,
//! materials, quality), and the per-frame [`View`] (camera and size). A viewer keeps one
//! `Settings` while the user drags the camera, and sends a new `View` every frame.

use std::sync::Arc;

use glam::Vec4;

use crate::raster::KernelKind;
use crate::scene::{Camera, Light, Material};
use crate::shade::Shading;
use crate::texture::{Filter, Texture};

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
    /// Applied to meshes that have UVs but no base-colour texture.
    pub texture: Option<Arc<Texture>>,
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
            texture: None,
            filter: None,
            lights: Lights::Auto,
            materials: None,
            samples: 1,
            msaa: 1,
            kernel: None,
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
