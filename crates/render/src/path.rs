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

use glam::{DVec3, Mat4, Vec2, Vec3};
use rayon::prelude::*;

use super::prepare::PreparedScene;
use super::raylog::{RayHit, RayKind, RayStep};
use super::settings::{Settings, View};
use super::whitted::{fresnel_refract, Tracer};
use crate::scalar::Scalar;
use crate::texture::env::brdf_lut;
use crate::texture::microfacet::alpha as alpha_of;
use realist_trace::Ray;

mod emitters;
mod sampling;

pub(crate) use emitters::Emitters;
use sampling::{g1, luminance, mis, vndf, Lobes, Rng};

/// Bounces before Russian roulette may end a path.
const ROULETTE_AFTER: u32 = 3;

impl Tracer<'_> {
    /// One path's estimate of the radiance arriving at `o` from unit direction `d`, in `T`
    /// (`f32` renders, `f64` is the reference); the rays are cast in `f32` and their hits
    /// placed on the ray in `T`.
    fn path<T: Scalar>(
        &self,
        o: T::V,
        d: T::V,
        reach: f32,
        rng: &mut Rng,
        ambient: Vec3,
        emitters: &Emitters,
    ) -> T::V {
        let zero = T::splat(T::ZERO);
        let f = |x: f32| T::of(x);
        let ambient = T::vec(ambient);
        let mut l = zero;
        let mut beta = T::splat(T::ONE);
        let (mut o, mut d) = (o, d);
        // The BRDF density that chose `d` (`None`: the camera or a mirror-like choice,
        // which the environment's samples cannot take).
        let mut chose: Option<T> = None;
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
            let (o32, d32) = (T::to_vec3(o), T::to_vec3(d));
            let hit = self.rays.closest(&Ray::new(o32, d32, 0.0, tmax));
            self.note_ray(hit.as_ref(), bounce, why, T::to_vec3(beta));
            let Some(h) = hit else {
                // The camera sees the background (the environment if the settings show
                // it); light comes from the environment and the ambient light only.
                let sky = if bounce == 0 {
                    match (&self.env, self.settings.env_background) {
                        (Some(env), Some(blur)) => T::vec(env.background(d32, blur)),
                        _ => T::vec(self.background),
                    }
                } else {
                    self.env
                        .as_ref()
                        .map_or(zero, |e| T::vec(e.background(d32, 0.0)))
                        + ambient
                };
                let w = match (chose, &self.env) {
                    (Some(p), Some(env)) => mis(p, f(env.pdf(d32))),
                    _ => T::ONE,
                };
                l = l + beta * sky * w;
                break;
            };
            if let Some((color, dist)) = medium {
                if dist.is_finite() {
                    let fade = T::vpowf(
                        T::vmaxv(T::vec(color), T::splat(f(1e-6))),
                        (f(h.t) / f(dist)).min(f(1e4)),
                    );
                    beta = beta * fade;
                }
            }
            let Some((pt, r)) = self.point::<T>(&h, o, d) else {
                break;
            };
            if pt.unlit {
                l = l + beta * T::vec(pt.base.truncate());
                break;
            }
            // Emission met by a BRDF sample is weighed against the emitter sampling of the
            // same light (camera rays and mirror-like choices take it all).
            let w = match chose {
                Some(p) if !T::is_zero(pt.emitted) => {
                    let cos = T::dot(pt.face_normal, d).abs();
                    emitters
                        .pdf(h.key, h.triangle, f(h.t), cos)
                        .map_or(T::ONE, |pl| mis(p, pl))
                }
                _ => T::ONE,
            };
            l = l + beta * pt.emitted * w;
            let Some(p) = pt.surf.pbr.as_ref().filter(|_| bounce <= depth) else {
                break;
            };
            let n = pt.normal;
            let v = -d;
            let ng = if T::dot(pt.face_normal, d) < T::ZERO {
                pt.face_normal
            } else {
                -pt.face_normal
            };
            let eps = f(2e-5) * (T::vmax(T::vabs(pt.position)) + f(self.radius));
            let above = pt.position + ng * eps;
            let below = pt.position - ng * eps;
            let base = pt.surf.kd;
            let params = r.params.surface.pbr.as_ref();
            let transmission = p.transmission.map_or(T::ZERO, |t| t.factor) * (T::ONE - p.metallic);
            let thin = p.transmission.is_some_and(|t| t.thickness <= T::ZERO);
            let p_trans = transmission.max(T::ZERO).min(f(0.95));
            let ior = params.map_or(f(1.5), |q| f(q.ior.max(1.0)));
            // A rough interface refracts and reflects about a microfacet normal drawn
            // among those the ray sees (Walter et al. 2007 with Heitz's visible normals),
            // weighed by the masking of the way out, Smith's G1; a smooth one (roughness 0)
            // about the shading normal itself.
            let alpha = alpha_of::<T>(p.roughness);
            let smooth = alpha <= f(crate::texture::microfacet::MIN_ALPHA);
            let facet = |rng: &mut Rng| {
                if smooth {
                    Some(n)
                } else {
                    vndf::<T>(n, v, alpha, rng)
                }
            };
            let masked = |l: T::V| {
                if smooth {
                    T::ONE
                } else {
                    g1(T::dot(n, l).abs(), alpha)
                }
            };
            if transmission > T::ZERO && !thin && !pt.front {
                // Inside a volume: its boundary is the bare interface, by Fresnel's
                // equations (reflection, total beyond the critical angle, or refraction
                // out; the base colour tinted the light once, on the way in).
                let Some(m) = facet(rng) else { break };
                let cos = T::dot(v, m).clamp01();
                let (fr, refracted) = fresnel_refract::<T>(d, m, cos, ior, false);
                match refracted {
                    Some(t) if f(rng.f()) >= fr => {
                        if T::dot(t, n) >= T::ZERO {
                            break;
                        }
                        beta = beta * masked(t);
                        why = (
                            RayKind::Refraction,
                            Vec3::splat(T::to_f64(masked(t)) as f32),
                        );
                        d = t;
                        o = below;
                        medium = None;
                    }
                    _ => {
                        let r = T::normalize_or_zero(d - m * (f(2.0) * T::dot(d, m)));
                        if T::dot(r, n) <= T::ZERO {
                            break;
                        }
                        beta = beta * masked(r);
                        why = (
                            RayKind::Reflection,
                            Vec3::splat(T::to_f64(masked(r)) as f32),
                        );
                        d = r;
                        o = above;
                    }
                }
                chose = None;
            } else if p_trans > T::ZERO && f(rng.f()) < p_trans {
                // Into the surface: the transmitted share (1 - F) T base, refracted (a
                // thin wall passes it on: unbent when smooth, and when rough the reflection
                // about the facet mirrored through the surface). Its reflection is the
                // BRDF's.
                let Some(m) = facet(rng) else { break };
                let cos = T::dot(v, m).clamp01();
                let (fr, refracted) = fresnel_refract::<T>(d, m, cos, T::ONE / ior, thin);
                let Some(t) = refracted else { break };
                // The mirrored lobe loses what a white rough mirror loses (reflections
                // into the surface, masking): given back by its albedo `A + B`, as the
                // multiple-scattering compensation of the reflection does (unless
                // single-scattering is asked for).
                let (t, regain) = if thin && !smooth {
                    let r = m * (f(2.0) * T::dot(v, m)) - v;
                    let regain = if self.settings.single_scatter {
                        T::ONE
                    } else {
                        let (a, b) = brdf_lut().lookup(
                            T::to_f64(T::dot(v, n).clamp01()) as f32,
                            T::to_f64(p.roughness) as f32,
                        );
                        T::ONE / f(a + b).max(f(0.05))
                    };
                    (
                        T::normalize_or_zero(r - n * (f(2.0) * T::dot(r, n))),
                        regain,
                    )
                } else {
                    (t, T::ONE)
                };
                if T::dot(t, n) >= T::ZERO {
                    break;
                }
                let share = base * ((T::ONE - fr) * transmission / p_trans * masked(t) * regain);
                beta = beta * share;
                why = (RayKind::Refraction, T::to_vec3(share));
                d = t;
                o = below;
                medium = match params {
                    Some(q) if !thin => Some((q.attenuation_color, q.attenuation_distance)),
                    _ => None,
                };
                chose = None;
            } else {
                let keep = T::ONE - p_trans;
                // Next-event estimation: every punctual light (shadow rays), then the
                // environment.
                let rays = &self.rays;
                // The shares themselves only for the probe's log.
                let lit = self.light(&pt, false, self.log.is_some());
                self.note_shadows(&lit.lights, bounce, T::to_vec3(beta));
                l = l + T::vdiv(beta * lit.direct, keep);
                let diffuse_albedo =
                    luminance::<T>(base) * (T::ONE - p.metallic) * (T::ONE - transmission);
                let spec_albedo = luminance::<T>(p.f0 * (T::ONE - p.metallic) + base * p.metallic);
                let lobes = Lobes {
                    n,
                    v,
                    alpha,
                    p_spec: (spec_albedo / (spec_albedo + diffuse_albedo + f(1e-6)))
                        .max(f(0.1))
                        .min(f(0.9)),
                };
                let brdf = |dir: T::V| {
                    let ndl = T::dot(n, dir);
                    let t = crate::shade::reflect::<T>(
                        &pt.surf,
                        n,
                        dir,
                        v,
                        ndl > T::ZERO,
                        ndl,
                        false,
                        pt.blinn,
                    );
                    t.diffuse + t.specular
                };
                if let Some(e) = emitters.sample::<T>(pt.position, rng) {
                    let (wi, pdf) = (e.dir, e.pdf);
                    let fl = brdf(wi);
                    // A textured emitter's point shaded for its own emission.
                    let le = match &e.textured {
                        Some(h) => self
                            .point::<T>(h, above, wi)
                            .map_or(zero, |(q, _)| q.emitted),
                        None => T::vec(e.emitted),
                    };
                    if !T::is_zero(fl) && !T::is_zero(le) {
                        let reach = T::to_f64(e.dist) as f32 * (1.0 - 1e-4);
                        let from = T::to_vec3(above);
                        let open = !rays.occluded(&Ray::new(from, T::to_vec3(wi), 0.0, reach));
                        self.note(|| RayStep {
                            kind: RayKind::LightSample,
                            depth: bounce,
                            share: Vec3::ONE,
                            weight: T::to_vec3(beta),
                            hit: RayHit::Emitter {
                                instance: super::rays::unkey(e.key.0).0,
                                triangle: e.key.1 as usize,
                                lit: open,
                            },
                        });
                        if open {
                            let w = mis(pdf, lobes.pdf(wi));
                            l = l + beta * fl * le * (w / (pdf * keep));
                        }
                    }
                }
                if let Some(env) = &self.env {
                    let (wi, le, pdf) = env.sample(rng.f(), rng.f());
                    let (wi_t, pdf) = (T::vec(wi), f(pdf));
                    let fl = brdf(wi_t);
                    if pdf > T::ZERO && !T::is_zero(fl) {
                        let from = T::to_vec3(above);
                        let open = !rays.occluded(&Ray::new(from, wi, 0.0, f32::INFINITY));
                        self.note(|| RayStep {
                            kind: RayKind::LightSample,
                            depth: bounce,
                            share: Vec3::ONE,
                            weight: T::to_vec3(beta),
                            hit: RayHit::Sky { lit: open },
                        });
                        if open {
                            let w = mis(pdf, lobes.pdf(wi_t));
                            l = l + beta * fl * (T::vec(le) + ambient) * (w / (pdf * keep));
                        }
                    }
                }
                let Some((wi, pdf)) = lobes.sample(rng) else {
                    break;
                };
                let fl = brdf(wi);
                if T::is_zero(fl) {
                    break;
                }
                let step = T::vdiv(fl, pdf * keep);
                beta = beta * step;
                why = (RayKind::Bounce, T::to_vec3(step));
                d = wi;
                o = above;
                chose = Some(pdf);
                medium = None;
            }
            if !T::vfinite(beta) {
                break;
            }
            if bounce >= ROULETTE_AFTER {
                let q = T::vmax(beta).max(f(0.05)).min(f(0.95));
                if f(rng.f()) >= q {
                    break;
                }
                beta = T::vdiv(beta, q);
            }
        }
        if T::vfinite(l) {
            l
        } else {
            zero
        }
    }
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
    image::<f32>(scene, settings, view, (spp, seed, jitter))
}

/// [`path_image_sampled`] computed in `f64` (the references of `bench accuracy`): the
/// same paths from the same random numbers, every surface, light and step of the path in
/// `f64`, only the rays' walk through the scene's tree in `f32`.
#[must_use]
pub fn path_image_f64(
    scene: &PreparedScene,
    settings: &Settings,
    view: &View,
    spp: u32,
    seed: u64,
    jitter: bool,
) -> Vec<DVec3> {
    image::<f64>(scene, settings, view, (spp, seed, jitter))
}

/// The path-traced image in `T`: `spp` paths a pixel from stream `seed`, jittered or not.
fn image<T: Scalar>(
    scene: &PreparedScene,
    settings: &Settings,
    view: &View,
    (spp, seed, jitter): (u32, u64, bool),
) -> Vec<T::V> {
    let (w, h) = (view.width.max(1), view.height.max(1));
    let mut out = vec![T::splat(T::ZERO); w as usize * h as usize];
    let vp = view.camera.projection(view.aspect()) * view.camera.view();
    path_into::<T>(
        scene,
        settings,
        vp,
        view.camera.view().inverse(),
        (w, h),
        (0..spp, seed, jitter),
        Store::Mean,
        &mut out,
        &mut None,
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
/// their samples added and some not). The scene's emitters are drawn from `lights`, built
/// there when it is empty (a caller that continues a sum keeps them between calls).
#[allow(clippy::too_many_arguments)]
pub(crate) fn path_into<T: Scalar>(
    scene: &PreparedScene,
    settings: &Settings,
    vp: Mat4,
    cam_to_world: Mat4,
    (w, h): (u32, u32),
    (samples, seed, jitter): (std::ops::Range<u32>, u64, bool),
    store: Store,
    sum: &mut [T::V],
    lights: &mut Option<Emitters>,
    stop: &(dyn Fn() -> bool + Sync),
) -> bool {
    let tracer = Tracer::new(scene, settings, cam_to_world);
    let emitters = &*lights.get_or_insert_with(|| Emitters::new(&tracer));
    let inv = vp.inverse();
    let ambient = ambient_light(scene, settings, cam_to_world);
    let count = T::of(samples.len().max(1) as f32);
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
                    Store::Mean => T::splat(T::ZERO),
                    Store::Sum => *px,
                };
                for s in samples.clone() {
                    let mut rng = Rng::new(x as u32, y as u32, s, seed);
                    let Some((near, d, reach)) =
                        camera_ray(inv, (w, h), (x as u32, y as u32), &mut rng, jitter)
                    else {
                        continue;
                    };
                    let (near, d) = (T::vec(near), T::vec(d));
                    acc = acc + tracer.path::<T>(near, d, reach, &mut rng, ambient, emitters);
                }
                *px = match store {
                    Store::Mean => *px + T::vdiv(acc, count),
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

/// Paths the pixel probe averages for its colour in `path` mode.
pub const PROBE_PATHS: u32 = 256;

/// The first path of pixel (x, y) of `view` (its sample 0 of the renderer's stream, through
/// the same point of the pixel), as the pixel probe lists it ([`super::raylog`]), and the
/// pixel's colour as the renderer draws it after [`PROBE_PATHS`] paths (its samples
/// `0..PROBE_PATHS`, linear, before tone mapping). Empty and black if the pixel's ray is
/// degenerate.
#[must_use]
pub(crate) fn path_probe(
    scene: &PreparedScene,
    settings: &Settings,
    view: &View,
    x: u32,
    y: u32,
) -> (Vec<RayStep>, Vec3) {
    let (mut tracer, vp, (w, h)) = Tracer::logging(scene, settings, view);
    let emitters = Emitters::new(&tracer);
    let cam_to_world = view.camera.view().inverse();
    let ambient = ambient_light(scene, settings, cam_to_world);
    let inv = vp.inverse();
    let mut rng = Rng::new(x, y, 0, 0);
    if let Some((near, d, reach)) = camera_ray(inv, (w, h), (x, y), &mut rng, true) {
        let _ = tracer.path::<f32>(near, d, reach, &mut rng, ambient, &emitters);
    }
    let steps = tracer.take_log();
    let quiet = &tracer;
    let sum = (0..PROBE_PATHS)
        .into_par_iter()
        .map(|s| {
            let mut rng = Rng::new(x, y, s, 0);
            camera_ray(inv, (w, h), (x, y), &mut rng, true).map_or(Vec3::ZERO, |(o, d, reach)| {
                quiet.path::<f32>(o, d, reach, &mut rng, ambient, &emitters)
            })
        })
        .reduce(|| Vec3::ZERO, |a, b| a + b);
    (steps, sum / PROBE_PATHS as f32)
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
