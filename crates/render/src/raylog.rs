//! The pixel probe's rays: in Whitted's model (the textbook's §9.6.1) every ray the tracer
//! casts for one pixel, in the order it casts them (a ray, the shadow rays from its hit,
//! then the rays it spawns); in the path tracer the pixel's first path (its sample 0, as
//! the renderer traces it): at each bounce the ray, the next-event rays towards the lights,
//! an emitter and the environment, and the direction drawn next. Each with what it met and
//! its share of the pixel. The tracer itself records them ([`Tracer::note`]), so the rays
//! are the ones the renderer follows, to the same limits.

use glam::Vec3;

use super::prepare::PreparedScene;
use super::settings::{Settings, View};
use super::whitted::Tracer;
use realist_trace::Ray;

/// Why a ray was cast.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RayKind {
    /// From the camera through the pixel centre.
    Primary,
    /// Off a mirror or a dielectric's surface.
    Reflection,
    /// Through a transmissive surface (Snell's law).
    Refraction,
    /// From a hit towards a light.
    Shadow,
    /// The path tracer's next direction, drawn from the BRDF.
    Bounce,
    /// The path tracer's next-event estimation: towards a point drawn on an emitter or a
    /// direction drawn from the environment.
    LightSample,
}

/// What a ray met.
#[derive(Clone, Debug, PartialEq)]
pub enum RayHit {
    /// A triangle of an instance: its scene mesh, its material (`None`: the default) and
    /// the distance along the ray.
    Surface {
        instance: usize,
        mesh: usize,
        material: Option<usize>,
        triangle: usize,
        t: f32,
    },
    /// Nothing: the environment is seen.
    Environment,
    /// Nothing: the background colour is seen.
    Background,
    /// A shadow ray towards light `index` of the frame: 1 lit, 0 blocked.
    Light { index: usize, lit: f32 },
    /// A ray towards a point drawn on triangle `triangle` of emissive instance `instance`:
    /// reached or blocked.
    Emitter {
        instance: usize,
        triangle: usize,
        lit: bool,
    },
    /// A ray along a direction drawn from the environment: open or blocked.
    Sky { lit: bool },
}

/// One ray of a pixel's tree.
#[derive(Clone, Debug, PartialEq)]
pub struct RayStep {
    pub kind: RayKind,
    /// Bounces from the camera: 0 for the primary ray and its hit's shadow rays.
    pub depth: u32,
    /// The share of its parent's colour it brings (Fresnel's reflectance, the metal's
    /// colour, the transmitted part); 1 for the primary and shadow rays.
    pub share: Vec3,
    /// Its share of the pixel: the product of the shares from the camera.
    pub weight: Vec3,
    pub hit: RayHit,
}

/// The Whitted ray tree of pixel (x, y) of `view` (its centre), as the tracer follows it.
/// Empty if the pixel's ray is degenerate.
#[must_use]
pub(crate) fn whitted_steps(
    scene: &PreparedScene,
    settings: &Settings,
    view: &View,
    x: u32,
    y: u32,
) -> Vec<RayStep> {
    let (mut tracer, vp, (w, h)) = Tracer::logging(scene, settings, view);
    let Some((near, d, len)) = super::path::pixel_ray(vp.inverse(), (w, h), (x, y), (0.5, 0.5))
    else {
        return Vec::new();
    };
    let hit = tracer.rays.closest(&Ray::new(near, d, 0.0, len));
    tracer.note_ray(hit.as_ref(), 0, (RayKind::Primary, Vec3::ONE), Vec3::ONE);
    if let Some(hit) = hit {
        tracer.shade_hit(&hit, near, d, 0, Vec3::ONE);
    }
    tracer.take_log()
}

impl<'a> Tracer<'a> {
    /// A tracer for `view` that keeps a log of its rays, the view's camera (world -> clip)
    /// and its size.
    pub(super) fn logging(
        scene: &'a PreparedScene,
        settings: &'a Settings,
        view: &View,
    ) -> (Self, glam::Mat4, (u32, u32)) {
        let size = (view.width.max(1), view.height.max(1));
        let vp = view.camera.projection(view.aspect()) * view.camera.view();
        let mut tracer = Tracer::new(scene, settings, view.camera.view().inverse());
        tracer.log = Some(std::sync::Mutex::new(Vec::new()));
        (tracer, vp, size)
    }

    /// The rays it logged, in order; it logs no more after.
    pub(super) fn take_log(&mut self) -> Vec<RayStep> {
        self.log
            .take()
            .map(|m| {
                m.into_inner()
                    .unwrap_or_else(std::sync::PoisonError::into_inner)
            })
            .unwrap_or_default()
    }

    /// Records a step if this tracer keeps a log.
    pub(super) fn note(&self, step: impl FnOnce() -> RayStep) {
        if let Some(log) = &self.log {
            log.lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .push(step());
        }
    }

    /// Records a ray `depth` bounces in, cast for `kind` with `share` of its parent's
    /// colour (`weight` of the pixel), that met `hit`.
    pub(super) fn note_ray(
        &self,
        hit: Option<&realist_trace::Hit>,
        depth: u32,
        (kind, share): (RayKind, Vec3),
        weight: Vec3,
    ) {
        self.note(|| RayStep {
            kind,
            depth,
            share,
            weight,
            hit: match hit {
                Some(h) => self.surface(h),
                None if self.env.is_some() => RayHit::Environment,
                None => RayHit::Background,
            },
        });
    }

    /// Records the shadow rays of a hit `depth` bounces in (`weight` of the pixel), lit or
    /// blocked as the `lights`' shares found.
    pub(super) fn note_shadows(
        &self,
        lights: &[super::probe::LightShare],
        depth: u32,
        weight: Vec3,
    ) {
        if self.log.is_none() {
            return;
        }
        // Whitted's model casts one to every light that can shadow and could light the
        // point; those behind it (no ray) are left out, as lights that bring nothing.
        let cast = |s: &&super::probe::LightShare| {
            s.light.kind.can_shadow() && (s.shadow < 1.0 || s.diffuse + s.specular != Vec3::ZERO)
        };
        for s in lights.iter().filter(cast) {
            self.note(|| RayStep {
                kind: RayKind::Shadow,
                depth,
                share: Vec3::ONE,
                weight,
                hit: RayHit::Light {
                    index: s.index,
                    lit: s.shadow,
                },
            });
        }
    }

    /// A hit as the probe names it: the instance, its scene mesh and material.
    fn surface(&self, h: &realist_trace::Hit) -> RayHit {
        let (k, _) = super::rays::unkey(h.key);
        let inst = self.scene.instances.get(k);
        let mesh = inst.and_then(|i| self.scene.scene_mesh(i));
        RayHit::Surface {
            instance: k,
            mesh: mesh.map_or(usize::MAX, |m| m.0),
            material: mesh.and_then(|(_, m)| {
                m.material_in(self.settings.variant_index(self.scene.scene()))
                    .filter(|&i| i < self.scene.scene().materials.len())
            }),
            triangle: h.triangle as usize,
            t: h.t,
        }
    }
}
