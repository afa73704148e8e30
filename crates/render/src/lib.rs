//! The renderer's front end: it turns a [`Scene`] into draws for the
//! rasterizer, with shaders from [`crate::shade`].
//!
//! ```text
//! Scene --PreparedScene::new--> PreparedScene --Renderer::render(Settings, View)--> Target
//!       (triangulation, instance                (lights, culling, vertex stage,      |
//!        constants, materials)                   passes, supersampling)             v
//!                                                            Renderer::write_rgba8 -> sRGB8
//! ```
//!
//! - [`PreparedScene`]: camera-independent work, done once; owns its scene.
//! - [`Settings`] (rarely change: shading, lights, materials, quality) and [`View`] (camera
//!   and size, every frame).
//! - [`Renderer`]: owns the target and all scratch memory; a frame at an unchanged size
//!   allocates nothing; can be stopped between tiles; supersamples by whole jittered passes;
//!   records per-stage times, counters and per-tile cost; picks points from its depth.
//! - [`probe`]: one pixel re-shaded by the same lighting code, each light's share.
//! - [`render`]: a one-shot frame for the command line and tests.
//!
//! This module never loops over pixels itself: the rasterizer calls the shaders.

// The crates below this one, under the module names the code uses (`crate::scene::...`).
use realist_mesh as mesh;
use realist_raster as raster;
use realist_scene as scene;
use realist_shade as shade;
use realist_simd as simd;
use realist_texture as texture;

use glam::Vec4;

use crate::raster::{Framebuffer, Stats, Target};
use crate::scene::{Camera, Scene};

mod frame;
pub mod measure;
mod numeric;
mod passes;
pub mod path;
mod pool;
mod prepare;
mod probe;
pub mod radiosity;
mod raylog;
pub mod rays;
mod renderer;
mod scalar;
mod settings;
mod shadows;
mod vertex;
mod whitted;

pub use frame::{found, Found, Policy};
pub use frame::{frame_lights, material_emission, material_surface, pbr_surface};
pub use numeric::{numeric, Numeric, Range, NUMERIC};
pub use prepare::{FlatMesh, PreparedMesh, PreparedScene};
pub use probe::{probe, LightShare, Probe};
pub use raylog::{RayHit, RayKind, RayStep};
pub use renderer::{unproject, FrameReport, Interrupted, Renderer, StageTimes};
pub use settings::{
    Environment, Ground, Hidden, Lights, Output, Sections, Settings, ToneMap, VertexLighting, View,
    DEFAULT_RAY_DEPTH, MAX_RAY_DEPTH,
};

/// A one-shot frame: the [`Settings`], the size and the camera (`None`:
/// [`default_camera`] for the scene). The settings are the viewer's and the scene files',
/// whole, so a one-shot frame and the f64 reference see every one of them.
#[derive(Clone, Debug)]
pub struct Shot {
    pub settings: Settings,
    pub width: u32,
    pub height: u32,
    /// `None` = [`default_camera`].
    pub camera: Option<Camera>,
}

impl Default for Shot {
    fn default() -> Self {
        Self {
            settings: Settings::default(),
            width: 1280,
            height: 720,
            camera: None,
        }
    }
}

impl Shot {
    /// The view part, with [`default_camera`] for `scene` if no camera is set.
    #[must_use]
    pub fn view(&self, scene: &Scene) -> View {
        let (width, height) = (self.width.max(1), self.height.max(1));
        let camera = self
            .camera
            .clone()
            .unwrap_or_else(|| default_camera(scene, width as f32 / height as f32));
        View {
            camera,
            width,
            height,
        }
    }
}

/// A rendered frame, still in the rasterizer's tiled form.
#[derive(Clone, Debug)]
pub struct Frame {
    pub target: Target,
    pub stats: Stats,
    /// The camera actually used.
    pub camera: Camera,
}

impl Frame {
    /// The row-major linear-light image.
    #[must_use]
    pub fn image(&self) -> Framebuffer {
        self.target.resolve()
    }

    /// 8-bit sRGB RGB, row-major, ready for a PNG.
    #[must_use]
    pub fn srgb8(&self) -> Vec<u8> {
        self.target.to_srgb8()
    }
}

/// Renders one frame of `scene` on the current rayon pool (allocating its memory; a viewer
/// keeps a [`Renderer`] instead).
#[must_use]
pub fn render(scene: &PreparedScene, shot: &Shot) -> Frame {
    let view = shot.view(scene.scene());
    let mut r = Renderer::new();
    let stats = r.render(scene, &shot.settings, &view).stats;
    Frame {
        target: r.take_target().expect("a frame was rendered"),
        stats,
        camera: view.camera,
    }
}

/// The default camera: the scene's bounding box framed from a three-quarter view.
#[must_use]
pub fn default_camera(scene: &Scene, aspect: f32) -> Camera {
    default_camera_up(scene, aspect, crate::scene::Up::Y)
}

/// [`default_camera`] for a scene whose up axis is `up` (`--up z` for a scan lying on its
/// back).
#[must_use]
pub fn default_camera_up(scene: &Scene, aspect: f32, up: crate::scene::Up) -> Camera {
    match (scene.bounds(), up) {
        (Some((lo, hi)), crate::scene::Up::Y) => Camera::frame_box(lo, hi, aspect, 35.0, 25.0),
        (Some((lo, hi)), up) => {
            Camera::frame_box_up(lo, hi, aspect, 35.0, 25.0, crate::scene::DEFAULT_YFOV, up)
        }
        (None, _) => Camera::default(),
    }
}

/// The overdraw view's colour for `count` fragments (linear RGBA): black for none, then
/// blue (1), cyan (2), green (3), yellow (4), red (6), magenta (10) and white from 16 on,
/// interpolated in between.
#[must_use]
pub fn overdraw_color(count: f32) -> Vec4 {
    const STOPS: [(f32, [f32; 3]); 8] = [
        (0.0, [0.0, 0.0, 0.0]),
        (1.0, [0.02, 0.06, 0.6]),
        (2.0, [0.0, 0.45, 0.55]),
        (3.0, [0.05, 0.6, 0.05]),
        (4.0, [0.8, 0.75, 0.0]),
        (6.0, [0.85, 0.05, 0.0]),
        (10.0, [0.7, 0.0, 0.7]),
        (16.0, [1.0, 1.0, 1.0]),
    ];
    let c = if count.is_finite() {
        count.max(0.0)
    } else {
        0.0
    };
    let k = STOPS.iter().position(|s| s.0 > c).unwrap_or(STOPS.len());
    if k == STOPS.len() {
        return Vec4::ONE;
    }
    let (a, b) = (STOPS[k - 1], STOPS[k]);
    let t = (c - a.0) / (b.0 - a.0);
    let lerp = |i: usize| a.1[i] + (b.1[i] - a.1[i]) * t;
    Vec4::new(lerp(0), lerp(1), lerp(2), 1.0)
}
