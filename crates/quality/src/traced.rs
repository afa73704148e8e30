//! Scenes whose reference is the path tracer (the textbook's §9.6): the rasterizer's
//! approximations of light that needs rays, measured against light that has them.
//!
//! - [`Light::Shadows`]: objects on a ground plane under one directional light that casts
//!   shadows, nothing else. The rasterizer's shadow maps (resolution, PCF filter) and
//!   `whitted`'s traced shadows are measured against the path tracer's *direct* light (no
//!   bounce, [`Settings::ray_depth`] 0): the same light with exact visibility, integrated
//!   over each pixel, so the error is the shadows' alone.
//! - [`Light::Environment`]: the same objects lit by a uniform sky alone.
//!   `pbr` lights every point by the whole environment, as if nothing stood in the way;
//!   the path tracer's direct light is occluded by the objects and the ground, so the error
//!   is that of environment light without occlusion.
//!
//! One-sample renders are measured against the direct light at pixel centres, supersampled
//! ones and the path tracer's own against the direct light averaged over each pixel.
//! Both scenes also have the *global* reference (every bounce, [`crate::render::DEFAULT_RAY_DEPTH`]):
//! the error left when the interreflection the rasterizer does not draw counts too.

use glam::{Mat4, Quat, Vec3, Vec4};

use super::LinearImage;
use crate::mesh::Mesh;
use crate::render::{
    self,
    path::{path_image_f64, path_image_sampled},
    Environment, Ground, Lights, PreparedScene, Settings, Shot, ToneMap,
};
use crate::scene::{Camera, Instance, LightKind, Material, PbrMaterial, Scene, Style};
use crate::shade::Shading;

/// Which light the scene has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Light {
    /// One directional light with shadows, no environment, no ambient light.
    Shadows,
    /// A uniform sky (the built-in `uniform` environment), no lights.
    Environment,
}

impl Light {
    /// The `--scene` name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Light::Shadows => "shadows",
            Light::Environment => "environment",
        }
    }
}

/// The number type a path-traced image is computed in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Precision {
    /// What `--shading path` renders with.
    F32,
    /// The references'.
    F64,
}

/// The references' stream of random numbers.
pub const REFERENCE_SEED: u64 = 0x5eed_0001;

/// The largest reference: paths per pixel side (128 x 128 = 16,384 paths a pixel).
pub const MAX_SAMPLES: u32 = 128;

/// A scene on a ground plane, its camera and light, measured against the path tracer.
#[derive(Clone, Debug)]
pub struct TracedSetup {
    pub light: Light,
    pub scene: Scene,
    pub width: u32,
    pub height: u32,
    pub camera: Camera,
    /// Paths per pixel side of the references.
    pub samples: u32,
}

impl TracedSetup {
    /// The built-in stage: a sphere, a torus lying flat and a turned cube on the ground,
    /// each casting shadows on the ground and (the torus) on itself.
    #[must_use]
    pub fn standard(light: Light, width: u32, height: u32, samples: u32) -> Self {
        Self::with_scene(light, stage(), width, height, samples)
    }

    /// `scene` (e.g. a loaded model) on the ground under `light`, from the default
    /// three-quarter view.
    #[must_use]
    pub fn with_scene(light: Light, scene: Scene, width: u32, height: u32, samples: u32) -> Self {
        let camera = render::default_camera(&scene, width as f32 / height.max(1) as f32);
        Self {
            light,
            scene,
            width,
            height,
            camera,
            samples: samples.clamp(1, MAX_SAMPLES),
        }
    }

    /// The settings every render and reference starts from: the light, the ground, no
    /// background (black), linear output compared before tone mapping.
    #[must_use]
    pub fn settings(&self) -> Settings {
        let (lights, environment) = match self.light {
            Light::Shadows => (
                Lights::Custom {
                    lights: vec![crate::scene::Light {
                        kind: LightKind::Directional,
                        direction: Vec3::new(-0.45, -1.0, -0.35).normalize(),
                        intensity: 2.5,
                        shadow: true,
                        ..crate::scene::Light::default()
                    }],
                    follow_camera: false,
                },
                Environment::Off,
            ),
            Light::Environment => (
                Lights::Custom {
                    lights: Vec::new(),
                    follow_camera: false,
                },
                // A uniform sky of radiance 1: what reaches a point is then the share of
                // the sky it sees (its ambient occlusion), and the path tracer's reference
                // converges in hundreds of paths (a sun or a studio's small lamps need
                // many thousands).
                Environment::builtin("uniform").map_or(Environment::Auto, |env| {
                    Environment::On(crate::texture::env::EnvView::new(env))
                }),
            ),
        };
        Settings {
            shading: Some(Shading::Pbr),
            background: Vec4::new(0.0, 0.0, 0.0, 1.0),
            lights,
            environment,
            env_background: None,
            ground: Some(Ground {
                color: Vec3::splat(0.6),
                extent: 4.0,
            }),
            tone: ToneMap::Clamp,
            ..Settings::default()
        }
    }

    /// The one-shot frame of `settings` from the setup's camera and size.
    #[must_use]
    pub fn shot(&self, settings: Settings) -> Shot {
        Shot {
            width: self.width,
            height: self.height,
            camera: Some(self.camera.clone()),
            settings,
        }
    }

    /// The path tracer's image with `samples`² paths per pixel from stream `seed`: the
    /// direct light alone (exact visibility, no bounce) or, `global`, every bounce; through
    /// random points of each pixel (`jitter`) or its centre; computed in `f64`.
    #[must_use]
    pub fn path(&self, global: bool, samples: u32, seed: u64, jitter: bool) -> LinearImage {
        self.path_in(Precision::F64, global, samples, seed, jitter)
    }

    /// [`TracedSetup::path`] computed in `precision`: in `f32` it is what `--shading path`
    /// renders, from the same random numbers as the `f64` reference.
    #[must_use]
    pub fn path_in(
        &self,
        precision: Precision,
        global: bool,
        samples: u32,
        seed: u64,
        jitter: bool,
    ) -> LinearImage {
        let mut settings = self.settings();
        settings.shading = Some(Shading::Path);
        if !global {
            settings.ray_depth = 0;
        }
        let shot = self.shot(settings);
        let prepared = PreparedScene::new(self.scene.clone());
        let view = shot.view(prepared.scene());
        let spp = samples.clamp(1, MAX_SAMPLES).pow(2);
        let (s, v) = (&shot.settings, &view);
        let rgb = match precision {
            Precision::F64 => path_image_f64(&prepared, s, v, spp, seed, jitter)
                .iter()
                .map(|c| c.to_array())
                .collect(),
            Precision::F32 => path_image_sampled(&prepared, s, v, spp, seed, jitter)
                .iter()
                .map(|c| c.as_dvec3().to_array())
                .collect(),
        };
        LinearImage {
            width: view.width,
            height: view.height,
            rgb,
        }
    }

    /// Reference `r`: [`TracedSetup::path`] at the setup's samples from stream
    /// [`REFERENCE_SEED`] (the renderer's own paths use stream 0, so a short run is not
    /// the reference's first samples). The direct light of one directional light at pixel centres has nothing
    /// random left (one shadow ray from each centre's point), so one path is exact.
    #[must_use]
    pub fn reference(&self, r: Reference) -> LinearImage {
        match r {
            Reference::Centres if self.light == Light::Shadows => {
                self.path(false, 1, REFERENCE_SEED, false)
            }
            Reference::Centres => self.path(false, self.samples, REFERENCE_SEED, false),
            Reference::Areas => self.path(false, self.samples, REFERENCE_SEED, true),
            Reference::Global => self.path(true, self.samples, REFERENCE_SEED, true),
        }
    }

    /// The reference's own noise: the direct light over pixels from another stream of
    /// random numbers, compared with `reference` ([`Reference::Areas`]). Each reference is
    /// about `1/√2` of this from the truth; an error well above it is the renderer's.
    #[must_use]
    pub fn noise(&self, reference: &LinearImage) -> super::Metrics {
        let other = self.path(false, self.samples, REFERENCE_SEED + 1, true);
        super::compare(&other, reference, super::metrics::DEFAULT_DE_THRESHOLD)
    }
}

/// The traced scenes' references.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reference {
    /// The direct light at each pixel's centre: what a renderer sampling pixel centres
    /// should show (the one-sample renders are measured against it, so that the
    /// silhouettes' aliasing, the same in every setting, does not hide the shadows' error).
    Centres = 0,
    /// The direct light averaged over each pixel (supersampled renders, the path tracer).
    Areas = 1,
    /// Every bounce, averaged over each pixel.
    Global = 2,
}

impl Reference {
    /// By index ([`Reference::index`]).
    pub const ALL: [Reference; 3] = [Reference::Centres, Reference::Areas, Reference::Global];

    /// Its place in [`Reference::ALL`] and in a sweep's references.
    #[must_use]
    pub fn index(self) -> usize {
        self as usize
    }

    /// The image's file name.
    #[must_use]
    pub fn file_name(self) -> &'static str {
        match self {
            Reference::Centres => "reference-direct-centres.png",
            Reference::Areas => "reference-direct.png",
            Reference::Global => "reference-global.png",
        }
    }
}

/// The built-in stage's objects (glTF metal-rough dielectrics of roughness 0.5).
fn stage() -> Scene {
    let mut s = Scene::default();
    let material = |name: &str, rgb: [f32; 3]| Material {
        name: name.into(),
        base_color: Vec3::from(rgb).extend(1.0),
        metallic: 0.0,
        roughness: 0.5,
        pbr: Some(PbrMaterial::default()),
        ..Material::default()
    };
    let parts = [
        (
            Mesh::sphere(0.8, 64, 32),
            material("orange", [0.8, 0.35, 0.1]),
            Mat4::from_translation(Vec3::new(-1.7, 0.8, 0.2)),
        ),
        (
            Mesh::torus(0.9, 0.32, 64, 32),
            material("blue", [0.15, 0.3, 0.7]),
            Mat4::from_translation(Vec3::new(0.8, 0.32, 0.6)),
        ),
        (
            Mesh::cube(1.1),
            material("white", [0.75, 0.75, 0.75]),
            Mat4::from_rotation_translation(Quat::from_rotation_y(0.5), Vec3::new(0.1, 0.55, -1.5)),
        ),
    ];
    for (k, (mesh, material, world)) in parts.into_iter().enumerate() {
        let mut mesh = mesh.expect("the stage's shapes have valid parameters");
        mesh.name = material.name.clone();
        mesh.material = Some(k);
        s.materials.push(material);
        s.meshes.push(mesh);
        s.instances.push(Instance {
            mesh: k,
            world,
            name: s.materials[k].name.clone(),
            style: Style::Inherit,
            node: None,
            skin: None,
            copies: None,
        });
    }
    s
}

#[cfg(test)]
mod tests;
