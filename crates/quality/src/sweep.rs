//! The time-versus-error sweep: vary one knob at a time from a base setting, record the
//! median warm render time and every metric against the reference, find the Pareto front
//! (no other setting is both faster and more accurate), write `results.csv` and a log-log
//! plot of time against mean ΔE00 with the front highlighted.
//!
//! Knobs: tessellation (slices x stacks of the latitude/longitude sphere, or the sides of
//! the capped cylinder), shading mode (flat, Gouraud, Phong, Blinn; each against the reference of its
//! own highlight model), texture filter (nearest, bilinear, trilinear, aniso:2/4/8/16),
//! and supersampling (1, 2x2, 4x4, resolved by a box filter in linear light).

use std::time::Instant;

use glam::Vec4;

use super::general;
use super::plane::PlaneSetup;
use super::sphere::{Shape, SphereSetup};
use super::traced::{Light, Reference, TracedSetup};
use super::{compare, metrics, LinearImage, Metrics};
use crate::raster::SUBPIXEL_BITS;
use crate::render::{self, PreparedScene, Renderer, Settings, Shot};
use crate::scene::{Camera, Scene};
use crate::shade::Shading;
use crate::texture::Filter;

mod knobs;

pub use knobs::{filter_name, shape_settings, Setting};
use knobs::{model_settings, plane_settings, traced_settings};

/// The result of one setting.
#[derive(Clone, Debug)]
pub struct Row {
    /// Which knob this row varies ("tessellation", "shading", "filter", "supersampling").
    pub knob: &'static str,
    pub setting: Setting,
    /// Median of the warm runs, milliseconds.
    pub ms: f64,
    pub metrics: Metrics,
}

/// What a sweep measures: a scene, its reference and the knobs that apply to it.
#[derive(Clone, Debug)]
pub enum Subject {
    /// The ray-cast sphere or capped cylinder: tessellation, shading mode, supersampling.
    Shape(SphereSetup),
    /// The exactly filtered textured plane: texture filter, supersampling.
    Plane(PlaneSetup),
    /// Any scene against the general f64 reference: shading mode, supersampling, texture
    /// filter (if textured), sub-pixel bits.
    Model(ModelSetup),
    /// A scene on the ground under one shadow-casting light or the environment, against the
    /// path tracer: shadow map size and filter, traced shadows, environment light without
    /// occlusion, the path tracer's own samples.
    Traced(TracedSetup),
}

/// A loaded scene under a fixed camera, measured against [`general::reference`].
#[derive(Clone, Debug)]
pub struct ModelSetup {
    pub scene: Scene,
    pub width: u32,
    pub height: u32,
    pub camera: Camera,
    /// Samples per pixel side of the reference.
    pub samples: u32,
    /// What every render and reference of the sweep starts from (lights, fog, tone
    /// mapping, sidedness, texture; e.g. from a scene file); size, shading, camera,
    /// background and the knobs are set by the sweep.
    pub base: Box<Shot>,
}

impl ModelSetup {
    /// `scene` from the default three-quarter view, referenced with `samples` x `samples`
    /// samples per pixel.
    #[must_use]
    pub fn new(scene: Scene, width: u32, height: u32, samples: u32) -> Self {
        let camera = render::default_camera(&scene, width as f32 / height.max(1) as f32);
        Self {
            scene,
            width,
            height,
            camera,
            samples,
            base: Box::default(),
        }
    }

    /// True if some instance would be drawn with a texture.
    #[must_use]
    pub fn textured(&self) -> bool {
        let s = &self.scene;
        s.instances.iter().any(|i| {
            s.meshes.get(i.mesh).is_some_and(|m| {
                s.material_of(m).base_color_texture.is_some_and(|t| {
                    t.texture < s.textures.len() && m.uvs.len() > t.uv_set as usize
                })
            })
        })
    }

    fn options(&self, shading: Shading) -> Shot {
        Shot {
            width: self.width,
            height: self.height,
            camera: Some(self.camera.clone()),
            settings: Settings {
                shading: Some(shading),
                background: Vec4::new(0.0, 0.0, 0.0, 1.0),
                ..self.base.settings.clone()
            },
        }
    }
}

/// Why a sweep could not run.
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    #[error(transparent)]
    Mesh(#[from] crate::mesh::MeshError),
    #[error("reference: {0}")]
    Reference(#[from] general::ReferenceError),
}

impl Subject {
    /// Output size in pixels.
    #[must_use]
    pub fn size(&self) -> (u32, u32) {
        match self {
            Subject::Shape(s) => (s.width, s.height),
            Subject::Plane(p) => (p.width, p.height),
            Subject::Model(m) => (m.width, m.height),
            Subject::Traced(t) => (t.width, t.height),
        }
    }

    /// The options every render of the subject starts from ([`ModelSetup::base`]).
    fn base_options(&self) -> Shot {
        match self {
            Subject::Model(m) => (*m.base).clone(),
            Subject::Traced(t) => t.shot(t.settings()),
            Subject::Shape(_) | Subject::Plane(_) => Shot::default(),
        }
    }

    fn camera(&self) -> &Camera {
        match self {
            Subject::Shape(s) => &s.camera,
            Subject::Plane(p) => &p.camera,
            Subject::Model(m) => &m.camera,
            Subject::Traced(t) => &t.camera,
        }
    }

    /// The rasterizer's scene for `s`.
    ///
    /// # Errors
    /// If the tessellation is invalid.
    pub fn scene(&self, s: &Setting) -> Result<Scene, crate::mesh::MeshError> {
        match self {
            Subject::Shape(setup) => setup.scene(s.slices, s.stacks),
            Subject::Plane(p) => Ok(p.scene(s.filter.unwrap_or_default())),
            Subject::Model(m) => {
                let mut scene = m.scene.clone();
                if let Some(filter) = s.filter {
                    for m in &mut scene.materials {
                        for slot in crate::scene::Slot::ALL {
                            if let Some(t) = m.slot_mut(slot) {
                                t.sampler.filter = filter;
                            }
                        }
                    }
                }
                Ok(scene)
            }
            Subject::Traced(t) => Ok(t.scene.clone()),
        }
    }

    /// Which reference a setting is measured against: 0 = Phong (R·V), 1 = Blinn (N·H),
    /// 2 = Blinn with textures (the textured mode). Flat and Gouraud approximate Phong.
    #[must_use]
    pub fn reference_index(&self, s: &Setting) -> usize {
        match (self, s.shading) {
            (Subject::Plane(_), _) => 0,
            (Subject::Traced(_), shading) => {
                let r = if s.global {
                    Reference::Global
                } else if s.ss == 1 && shading != Shading::Path {
                    Reference::Centres
                } else {
                    Reference::Areas
                };
                r.index()
            }
            (_, Shading::Blinn) => 1,
            (_, Shading::Textured) => 2,
            (
                Subject::Shape(_) | Subject::Model(_),
                Shading::Wireframe
                | Shading::Flat
                | Shading::Gouraud
                | Shading::Phong
                | Shading::Pbr
                | Shading::Whitted
                | Shading::Path
                | Shading::Radiosity
                | Shading::Normals
                | Shading::Depth
                | Shading::Uv
                | Shading::UvChecker
                | Shading::MipLevel
                | Shading::TexelDensity
                | Shading::Anisotropy
                | Shading::Tangents
                | Shading::TangentNormals,
            ) => 0,
        }
    }

    /// Reference `index` (see [`Subject::reference_index`]).
    ///
    /// # Errors
    /// If the general reference refuses the model's request (see [`general::reference`]).
    pub fn reference(&self, index: usize) -> Result<LinearImage, SweepError> {
        Ok(match self {
            Subject::Shape(setup) => setup.reference(index == 1),
            // No highlight on the plane: one reference for every setting.
            Subject::Plane(p) => p.reference(),
            Subject::Model(m) => {
                let shading = [Shading::Phong, Shading::Blinn, Shading::Textured][index.min(2)];
                general::reference(&m.scene, &m.options(shading), m.samples, index > 0)?
            }
            Subject::Traced(t) => t.reference(Reference::ALL[index.min(2)]),
        })
    }

    /// The file name of reference `index`'s image.
    #[must_use]
    pub fn reference_name(&self, index: usize) -> &'static str {
        match self {
            Subject::Traced(_) => Reference::ALL[index.min(2)].file_name(),
            Subject::Shape(_) | Subject::Plane(_) | Subject::Model(_) => [
                "reference.png",
                "reference-blinn.png",
                "reference-textured.png",
            ][index.min(2)],
        }
    }

    /// The settings of the sweep: a base setting and one knob at a time around it.
    #[must_use]
    pub fn settings(&self) -> Vec<(&'static str, Setting)> {
        match self {
            Subject::Shape(s) => shape_settings(s.shape),
            Subject::Plane(_) => plane_settings(),
            Subject::Model(m) => model_settings(m.textured()),
            Subject::Traced(t) => traced_settings(t.light),
        }
    }
}

/// Renders `setting` `runs` times (after one warm-up) and returns the median time and the
/// resolved image.
///
/// # Errors
/// If the tessellation is invalid.
pub fn run_setting(
    subject: &Subject,
    s: Setting,
    runs: usize,
) -> Result<(f64, LinearImage), crate::mesh::MeshError> {
    let scene = subject.scene(&s)?;
    let prepared = PreparedScene::new(scene);
    let (w, h) = subject.size();
    // The path tracer's samples are its paths per pixel; every other mode supersamples.
    let (enlarge, samples) = if s.shading == Shading::Path {
        (1, s.ss)
    } else {
        (s.ss, 1)
    };
    let mut opts = Shot {
        width: w * enlarge,
        height: h * enlarge,
        camera: Some(subject.camera().clone()),
        settings: Settings {
            shading: Some(s.shading),
            background: Vec4::new(0.0, 0.0, 0.0, 1.0),
            subpixel_bits: s.bits,
            msaa: s.msaa,
            samples,
            ..subject.base_options().settings
        },
    };
    if matches!(subject, Subject::Traced(_)) && s.shading == Shading::Path && !s.global {
        // Against the direct light, the path tracer draws the direct light.
        opts.settings.ray_depth = 0;
    }
    if s.shadow_size > 0 {
        opts.settings.shadow.size = s.shadow_size;
        opts.settings.shadow.pcf = s.pcf;
    }
    // Frames into one reused renderer, as a viewer renders them (no allocation after the
    // warm-up), timed alone: resolving to f64 is the metric's cost, not the renderer's.
    let view = opts.view(prepared.scene());
    let settings = opts.settings;
    let mut renderer = Renderer::new();
    renderer.render(&prepared, &settings, &view);
    let mut times = Vec::with_capacity(runs);
    for _ in 0..runs.max(1) {
        let start = Instant::now();
        renderer.render(&prepared, &settings, &view);
        times.push(start.elapsed().as_secs_f64() * 1e3);
    }
    let target = renderer
        .take_target()
        .expect("the renderer has rendered a frame");
    let image = LinearImage::from_framebuffer(&target.resolve()).downsample(enlarge);
    times.sort_by(f64::total_cmp);
    Ok((times[times.len() / 2], image))
}

/// Indices of the rows on the Pareto front of (time, mean ΔE00), fastest first.
#[must_use]
pub fn pareto(rows: &[Row]) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..rows.len()).collect();
    idx.sort_by(|&a, &b| rows[a].ms.total_cmp(&rows[b].ms));
    let mut best = f64::INFINITY;
    let mut front = Vec::new();
    for i in idx {
        if rows[i].metrics.mean_de2000 < best {
            best = rows[i].metrics.mean_de2000;
            front.push(i);
        }
    }
    front
}

/// `results.csv`: one line per row.
#[must_use]
pub fn csv(rows: &[Row], front: &[usize]) -> String {
    let mut out = String::from(
        "knob,shading,slices,stacks,filter,supersampling,multisampling,subpixel_bits,shadow_size,pcf,global,median_ms,rmse,psnr_db,max_abs,mean_de2000,p95_de2000,pixels_over_1de,pareto\n",
    );
    for (i, r) in rows.iter().enumerate() {
        let (s, m) = (&r.setting, &r.metrics);
        out.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{},{:.3},{:.6},{:.2},{:.6},{:.4},{:.4},{},{}\n",
            r.knob,
            s.shading,
            s.slices,
            s.stacks,
            s.filter.map_or("", filter_name),
            s.ss,
            s.msaa,
            s.bits,
            s.shadow_size,
            s.pcf,
            s.global,
            r.ms,
            m.rmse,
            m.psnr,
            m.max_abs,
            m.mean_de2000,
            m.p95_de2000,
            m.over_threshold,
            front.contains(&i)
        ));
    }
    out
}

/// The rows of a sweep and the references they were measured against.
#[derive(Clone, Debug)]
pub struct Sweep {
    pub rows: Vec<Row>,
    /// By [`Subject::reference_index`]; `None` where no setting needed it.
    pub references: [Option<LinearImage>; 3],
}

/// Runs the sweep of `subject` with `runs` timed renders per setting, each measured
/// against the reference of its highlight model.
///
/// # Errors
/// If the general reference refuses a model's request (size, samples, camera); never for
/// the built-in analytic scenes.
pub fn sweep(subject: &Subject, runs: usize) -> Result<Sweep, SweepError> {
    let mut references: [Option<LinearImage>; 3] = [None, None, None];
    let mut rows: Vec<Row> = Vec::new();
    for (knob, s) in subject.settings() {
        // A setting shared by several knobs (the base) is measured once.
        if let Some(done) = rows.iter().find(|r| r.setting == s) {
            let metrics = done.metrics;
            let ms = done.ms;
            rows.push(Row {
                knob,
                setting: s,
                ms,
                metrics,
            });
            continue;
        }
        let (ms, image) = run_setting(subject, s, runs)?;
        let index = subject.reference_index(&s);
        let slot = &mut references[index];
        let reference: &LinearImage = match slot {
            Some(r) => r,
            None => slot.insert(subject.reference(index)?),
        };
        rows.push(Row {
            knob,
            setting: s,
            ms,
            metrics: compare(&image, reference, metrics::DEFAULT_DE_THRESHOLD),
        });
    }
    Ok(Sweep { rows, references })
}
