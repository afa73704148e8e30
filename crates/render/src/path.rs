//! A path tracer (`--shading path`, the textbook's §9.6 carried to its end: the rendering
//! equation estimated by random light paths), the ground truth the rasterizer's
//! approximations are measured against. It evaluates surfaces exactly as the `pbr` mode
//! shades them (the probe's surface point and the shared BRDF, [`crate::shade::reflect`]),
//! and at each bounce:
//!
//! - next-event estimation: a shadow ray to every punctual light, and a direction drawn
//!   from the environment in proportion to its radiance
//!   ([`crate::texture::env::EnvView::sample`]);
//! - the next direction drawn from the BRDF: a mixture of the cosine (diffuse) and GGX
//!   visible-normal (specular) lobes, weighted by their albedos, or through a transmissive
//!   surface by Fresnel's equations (reflection or Snell's refraction);
//! - multiple importance sampling (the power heuristic) between the environment's and the
//!   BRDF's samples of the same light;
//! - Russian roulette after three bounces, and the depth limit
//!   [`Settings::ray_depth`] (surfaces met after the first).
//!
//! Emissive surfaces are lights too: a point drawn on them in proportion to their power,
//! weighed against the BRDF's samples that meet them. Under an emissive texture a
//! triangle's power is estimated at its centroid and the point drawn is shaded for its own
//! emission.
//! Every pixel's random numbers come from its position and sample number alone, so images
//! do not depend on the thread count.

use glam::{Mat4, Vec2, Vec3};
use rayon::prelude::*;

use super::prepare::PreparedScene;
use super::raylog::{RayHit, RayKind, RayStep};
use super::settings::{Settings, View};
use super::whitted::Tracer;
use crate::texture::env::brdf_lut;
use crate::texture::microfacet::alpha as alpha_of;
use realist_trace::Ray;

mod emitters;
mod sampling;

use emitters::Emitters;
use sampling::{g1, luminance, mis, vndf, Lobes, Rng};

/// Bounces before Russian roulette may end a path.
const ROULETTE_AFTER: u32 = 3;

impl Tracer<'_> {
    /// One path's estimate of the radiance arriving at `o` from unit direction `d`.
    fn path(
        &self,
        o: Vec3,
        d: Vec3,
        reach: f32,
        rng: &mut Rng,
        ambient: Vec3,
        emitters: &Emitters,
    ) -> Vec3 {
        let mut l = Vec3::ZERO;
        let mut beta = Vec3::ONE;
        let (mut o, mut d) = (o, d);
        // The BRDF density that chose `d` (`None`: the camera or a mirror-like choice,
        // which the environment's samples cannot take).
        let mut chose: Option<f32> = None;
        let mut medium: Option<(Vec3, f32)> = None;
        // Why the current ray was cast, and its share of its parent's (the probe's log).
        let mut why = (RayKind::Primary, Vec3::ONE);
        // Surfaces shaded: the first and `depth` more; the last one's sampled direction is
        // still followed to the light it meets (the environment, an emitter), which is its
        // share of the direct light by multiple importance sampling.
        let depth = self.settings.ray_depth.min(super::MAX_RAY_DEPTH);
        for bounce in 0..=depth + 1 {
            // The camera's rays end at its far plane, as the rasterizer's view does.
            let tmax = if bounce == 0 { reach } else { f32::INFINITY };
            let hit = self.rays.closest(&Ray::new(o, d, 0.0, tmax));
            self.note_ray(hit.as_ref(), bounce, why, beta);
            let Some(h) = hit else {
                // The camera sees the background (the environment if the settings show
                // it); light comes from the environment and the ambient light only.
                let sky = if bounce == 0 {
                    match (&self.env, self.settings.env_background) {
                        (Some(env), Some(blur)) => env.background(d, blur),
                        _ => self.background,
                    }
                } else {
                    self.env
                        .as_ref()
                        .map_or(Vec3::ZERO, |e| e.background(d, 0.0))
                        + ambient
                };
                let w = match (chose, &self.env) {
                    (Some(p), Some(env)) => mis(p, env.pdf(d)),
                    _ => 1.0,
                };
                l += beta * sky * w;
                break;
            };
            if let Some((color, dist)) = medium {
                if dist.is_finite() {
                    beta *= color.max(Vec3::splat(1e-6)).powf((h.t / dist).min(1e4));
                }
            }
            let Some((pt, r)) = self.point(&h, o, d) else {
                break;
            };
            if pt.unlit {
                l += beta * pt.base.truncate();
                break;
            }
            // Emission met by a BRDF sample is weighed against the emitter sampling of the
            // same light (camera rays and mirror-like choices take it all).
            let w = match chose {
                Some(p) if pt.emitted != Vec3::ZERO => {
                    let cos = pt.face_normal.dot(d).abs();
                    emitters
                        .pdf(h.key, h.triangle, h.t, cos)
                        .map_or(1.0, |pl| mis(p, pl))
                }
                _ => 1.0,
            };
            l += beta * pt.emitted * w;
            let Some(p) = pt.surf.pbr.as_ref().filter(|_| bounce <= depth) else {
                break;
            };
            let n = pt.normal;
            let v = -d;
            let ng = if pt.face_normal.dot(d) < 0.0 {
                pt.face_normal
            } else {
                -pt.face_normal
            };
            let eps = 2e-5 * (pt.position.abs().max_element() + self.radius);
            let above = pt.position + ng * eps;
            let below = pt.position - ng * eps;
            let base = pt.surf.kd;
            let params = r.params.surface.pbr.as_ref();
            let transmission = p.transmission.map_or(0.0, |t| t.factor) * (1.0 - p.metallic);
            let thin = p.transmission.is_some_and(|t| t.thickness <= 0.0);
            let p_trans = transmission.clamp(0.0, 0.95);
            let ior = params.map_or(1.5, |q| q.ior.max(1.0));
            // A rough interface refracts and reflects about a microfacet normal drawn
            // among those the ray sees (Walter et al. 2007 with Heitz's visible normals),
            // weighed by the masking of the way out, Smith's G1; a smooth one (roughness 0)
            // about the shading normal itself.
            let alpha = alpha_of::<f32>(p.roughness);
            let smooth = alpha <= crate::texture::microfacet::MIN_ALPHA;
            let facet = |rng: &mut Rng| {
                if smooth {
                    Some(n)
                } else {
                    vndf(n, v, alpha, rng)
                }
            };
            let masked = |l: Vec3| {
                if smooth {
                    1.0
                } else {
                    g1(n.dot(l).abs(), alpha)
                }
            };
            if transmission > 0.0 && !thin && !pt.front {
                // Inside a volume: its boundary is the bare interface, by Fresnel's
                // equations (reflection, total beyond the critical angle, or refraction
                // out; the base colour tinted the light once, on the way in).
                let Some(m) = facet(rng) else { break };
                let cos = v.dot(m).clamp(0.0, 1.0);
                let (fr, refracted) = fresnel(d, m, cos, ior, false);
                match refracted {
                    Some(t) if rng.f() >= fr => {
                        if t.dot(n) >= 0.0 {
                            break;
                        }
                        beta *= masked(t);
                        why = (RayKind::Refraction, Vec3::splat(masked(t)));
                        d = t;
                        o = below;
                        medium = None;
                    }
                    _ => {
                        let r = (d - 2.0 * d.dot(m) * m).normalize_or_zero();
                        if r.dot(n) <= 0.0 {
                            break;
                        }
                        beta *= masked(r);
                        why = (RayKind::Reflection, Vec3::splat(masked(r)));
                        d = r;
                        o = above;
                    }
                }
                chose = None;
            } else if p_trans > 0.0 && rng.f() < p_trans {
                // Into the surface: the transmitted share (1 - F) T base, refracted (a
                // thin wall passes it on: unbent when smooth, and when rough the reflection
                // about the facet mirrored through the surface). Its reflection is the
                // BRDF's.
                let Some(m) = facet(rng) else { break };
                let cos = v.dot(m).clamp(0.0, 1.0);
                let (fr, refracted) = fresnel(d, m, cos, 1.0 / ior, thin);
                let Some(t) = refracted else { break };
                // The mirrored lobe loses what a white rough mirror loses (reflections
                // into the surface, masking): given back by its albedo `A + B`, as the
                // multiple-scattering compensation of the reflection does (unless
                // single-scattering is asked for).
                let (t, regain) = if thin && !smooth {
                    let r = 2.0 * v.dot(m) * m - v;
                    let regain = if self.settings.single_scatter {
                        1.0
                    } else {
                        let (a, b) = brdf_lut().lookup(v.dot(n).clamp(0.0, 1.0), p.roughness);
                        1.0 / (a + b).max(0.05)
                    };
                    ((r - 2.0 * r.dot(n) * n).normalize_or_zero(), regain)
                } else {
                    (t, 1.0)
                };
                if t.dot(n) >= 0.0 {
                    break;
                }
                let share = base * ((1.0 - fr) * transmission / p_trans * masked(t) * regain);
                beta *= share;
                why = (RayKind::Refraction, share);
                d = t;
                o = below;
                medium = match params {
                    Some(q) if !thin => Some((q.attenuation_color, q.attenuation_distance)),
                    _ => None,
                };
                chose = None;
            } else {
                let keep = 1.0 - p_trans;
                // Next-event estimation: every punctual light (shadow rays), then the
                // environment.
                let rays = &self.rays;
                let lit = self.light(&pt, false);
                self.note_shadows(&lit, bounce, beta);
                for s in &lit.lights {
                    l += beta * (s.diffuse + s.specular) / keep;
                }
                let diffuse_albedo = luminance(base) * (1.0 - p.metallic) * (1.0 - transmission);
                let spec_albedo = luminance(p.f0 * (1.0 - p.metallic) + base * p.metallic);
                let lobes = Lobes {
                    n,
                    v,
                    alpha: alpha_of::<f32>(p.roughness),
                    p_spec: (spec_albedo / (spec_albedo + diffuse_albedo + 1e-6)).clamp(0.1, 0.9),
                };
                let brdf = |dir: Vec3| {
                    let ndl = n.dot(dir);
                    let t = crate::shade::reflect::<f32>(
                        &pt.surf,
                        n,
                        dir,
                        v,
                        ndl > 0.0,
                        ndl,
                        false,
                        pt.blinn,
                    );
                    t.diffuse + t.specular
                };
                if let Some(e) = emitters.sample(pt.position, rng) {
                    let (wi, pdf) = (e.dir, e.pdf);
                    let f = brdf(wi);
                    // A textured emitter's point shaded for its own emission.
                    let le = match &e.textured {
                        Some(h) => self
                            .point(h, above, wi)
                            .map_or(Vec3::ZERO, |(q, _)| q.emitted),
                        None => e.emitted,
                    };
                    if f != Vec3::ZERO && le != Vec3::ZERO {
                        let open = !rays.occluded(&Ray::new(above, wi, 0.0, e.dist * (1.0 - 1e-4)));
                        self.note(|| RayStep {
                            kind: RayKind::LightSample,
                            depth: bounce,
                            share: Vec3::ONE,
                            weight: beta,
                            hit: RayHit::Emitter {
                                instance: super::rays::unkey(e.key.0).0,
                                triangle: e.key.1 as usize,
                                lit: open,
                            },
                        });
                        if open {
                            let w = mis(pdf, lobes.pdf(wi));
                            l += beta * f * le * (w / (pdf * keep));
                        }
                    }
                }
                if let Some(env) = &self.env {
                    let (wi, le, pdf) = env.sample(rng.f(), rng.f());
                    let f = brdf(wi);
                    if pdf > 0.0 && f != Vec3::ZERO {
                        let open = !rays.occluded(&Ray::new(above, wi, 0.0, f32::INFINITY));
                        self.note(|| RayStep {
                            kind: RayKind::LightSample,
                            depth: bounce,
                            share: Vec3::ONE,
                            weight: beta,
                            hit: RayHit::Sky { lit: open },
                        });
                        if open {
                            let w = mis(pdf, lobes.pdf(wi));
                            l += beta * f * (le + ambient) * (w / (pdf * keep));
                        }
                    }
                }
                let Some((wi, pdf)) = lobes.sample(rng) else {
                    break;
                };
                let f = brdf(wi);
                if f == Vec3::ZERO {
                    break;
                }
                beta *= f / (pdf * keep);
                why = (RayKind::Bounce, f / (pdf * keep));
                d = wi;
                o = above;
                chose = Some(pdf);
                medium = None;
            }
            if !beta.is_finite() {
                break;
            }
            if bounce >= ROULETTE_AFTER {
                let q = beta.max_element().clamp(0.05, 0.95);
                if rng.f() >= q {
                    break;
                }
                beta /= q;
            }
        }
        if l.is_finite() {
            l
        } else {
            Vec3::ZERO
        }
    }
}

/// The dielectric's reflectance and refracted direction (as in Whitted's model).
fn fresnel(d: Vec3, n: Vec3, cos: f32, eta: f32, thin: bool) -> (f32, Option<Vec3>) {
    super::whitted::fresnel_refract(d, n, cos, eta, thin)
}

/// The path-traced image of `scene` seen through `view`: `spp` paths per pixel, the
/// stream of random numbers chosen by `seed` (sample `k` of a pixel is the same whatever
/// `spp`, so a longer run extends a shorter one). Linear RGB, row-major.
#[must_use]
pub fn path_image(
    scene: &PreparedScene,
    settings: &Settings,
    view: &View,
    spp: u32,
    seed: u64,
) -> Vec<Vec3> {
    path_image_sampled(scene, settings, view, spp, seed, true)
}

/// [`path_image`], every path through a random point of its pixel (`jitter`: the pixel's
/// average, antialiased) or through its centre (what a renderer taking one sample per
/// pixel, at the centre, should show).
#[must_use]
pub fn path_image_sampled(
    scene: &PreparedScene,
    settings: &Settings,
    view: &View,
    spp: u32,
    seed: u64,
    jitter: bool,
) -> Vec<Vec3> {
    let (w, h) = (view.width.max(1), view.height.max(1));
    let mut out = vec![Vec3::ZERO; w as usize * h as usize];
    let vp = view.camera.projection(view.aspect()) * view.camera.view();
    path_into(
        scene,
        settings,
        vp,
        view.camera.view().inverse(),
        (w, h),
        (0..spp, seed, jitter),
        Store::Mean,
        &mut out,
        &|| false,
    );
    out
}

/// How [`path_into`] stores a pixel's samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Store {
    /// Adds the samples' mean to the pixel.
    Mean,
    /// Adds the samples one by one to the pixel, a running sum: the sum of samples
    /// `0..n` made in several calls is bit for bit the one made in one call (the same
    /// additions in the same order), so its mean is that of [`path_image`] with `n` paths.
    Sum,
}

/// Adds samples `samples` of every pixel to `sum` (row-major, `w` x `h`) for the camera
/// `vp` (world -> clip), from the random stream `seed`, through random points of each pixel
/// (`jitter`) or its centre, as `store` says. Returns false if stopped (some rows then have
/// their samples added and some not).
#[allow(clippy::too_many_arguments)]
pub(crate) fn path_into(
    scene: &PreparedScene,
    settings: &Settings,
    vp: Mat4,
    cam_to_world: Mat4,
    (w, h): (u32, u32),
    (samples, seed, jitter): (std::ops::Range<u32>, u64, bool),
    store: Store,
    sum: &mut [Vec3],
    stop: &(dyn Fn() -> bool + Sync),
) -> bool {
    let tracer = Tracer::new(scene, settings, cam_to_world);
    let emitters = Emitters::new(&tracer);
    let inv = vp.inverse();
    let ambient = ambient_light(scene, settings, cam_to_world);
    let count = samples.len().max(1) as f32;
    let stopped = std::sync::atomic::AtomicBool::new(false);
    sum.par_chunks_mut(w as usize)
        .enumerate()
        .for_each(|(y, row)| {
            if stopped.load(std::sync::atomic::Ordering::Relaxed) || stop() {
                stopped.store(true, std::sync::atomic::Ordering::Relaxed);
                return;
            }
            for (x, px) in row.iter_mut().enumerate() {
                let mut acc = match store {
                    Store::Mean => Vec3::ZERO,
                    Store::Sum => *px,
                };
                for s in samples.clone() {
                    let mut rng = Rng::new(x as u32, y as u32, s, seed);
                    let Some((near, d, reach)) =
                        camera_ray(inv, (w, h), (x as u32, y as u32), &mut rng, jitter)
                    else {
                        continue;
                    };
                    acc += tracer.path(near, d, reach, &mut rng, ambient, &emitters);
                }
                *px = match store {
                    Store::Mean => *px + acc / count,
                    Store::Sum => acc,
                };
            }
        });
    !stopped.into_inner()
}

/// The camera ray of a path through pixel `(x, y)` (of `w` x `h`, clip -> world `inv`): a
/// random point of the pixel (`jitter`) or its centre; the two numbers are drawn either
/// way, so a pixel's stream does not depend on it.
fn camera_ray(
    inv: Mat4,
    size: (u32, u32),
    pixel: (u32, u32),
    rng: &mut Rng,
    jitter: bool,
) -> Option<(Vec3, Vec3, f32)> {
    let (jx, jy) = (rng.f(), rng.f());
    pixel_ray(inv, size, pixel, if jitter { (jx, jy) } else { (0.5, 0.5) })
}

/// The camera ray through point `(x + jx, y + jy)` of a `w` x `h` image (clip -> world
/// `inv`, y down): origin on the near plane, unit direction and the distance to the far
/// plane; `None` if degenerate.
pub(super) fn pixel_ray(
    inv: Mat4,
    (w, h): (u32, u32),
    (x, y): (u32, u32),
    (jx, jy): (f32, f32),
) -> Option<(Vec3, Vec3, f32)> {
    let ndc = Vec2::new(
        (x as f32 + jx) / w as f32 * 2.0 - 1.0,
        1.0 - (y as f32 + jy) / h as f32 * 2.0,
    );
    let near = inv.project_point3(ndc.extend(1.0));
    let far = inv.project_point3(ndc.extend(0.0));
    let reach = (far - near).length();
    let d = (far - near) / reach;
    (reach > 0.0 && d.is_finite() && near.is_finite()).then_some((near, d, reach))
}

/// The first path of pixel (x, y) of `view` (its sample 0 of the renderer's stream, through
/// the same point of the pixel), as the pixel probe lists it ([`super::raylog`]). Empty if
/// the pixel's ray is degenerate.
#[must_use]
pub(crate) fn path_steps(
    scene: &PreparedScene,
    settings: &Settings,
    view: &View,
    x: u32,
    y: u32,
) -> Vec<RayStep> {
    let (tracer, vp, (w, h)) = Tracer::logging(scene, settings, view);
    let emitters = Emitters::new(&tracer);
    let ambient = ambient_light(scene, settings, view.camera.view().inverse());
    let mut rng = Rng::new(x, y, 0, 0);
    if let Some((near, d, reach)) = camera_ray(vp.inverse(), (w, h), (x, y), &mut rng, true) {
        let _ = tracer.path(near, d, reach, &mut rng, ambient, &emitters);
    }
    tracer.into_log()
}

/// The frame's ambient lights' radiance, summed (a uniform environment for the paths).
fn ambient_light(scene: &PreparedScene, settings: &Settings, cam_to_world: Mat4) -> Vec3 {
    let mut sum = Vec3::ZERO;
    super::frame::for_each_light(
        scene.lights(),
        &settings.lights,
        settings.default_rig(scene.scene()),
        cam_to_world,
        |l, _| {
            if l.kind == crate::scene::LightKind::Ambient {
                sum += l.color * l.intensity;
            }
        },
    );
    sum
}
