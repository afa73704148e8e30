//! Ray-traced shadows for Whitted's model (the textbook's §9.6.1), as a hybrid: the frame's
//! rasterizer finds what each pixel sees (a depth pass with the frame's own projection and
//! sub-pixel shift), a shadow ray from that point to each light asks the scene's hierarchy
//! whether anything is in the way, and the answers form one screen-space mask per light,
//! which the shaders read where they would read a shadow map ([`ShadowMap::screen`]). Exact
//! where the shadow map approximates: no resolution, no bias, no acne, no peter-panning.

use glam::{Mat4, Vec3, Vec4};
use rayon::prelude::*;

use super::frame::FrameData;
use super::passes::{self, Cx};
use super::pool::Pool;
use super::prepare::PreparedScene;
use super::raylog::RayKind;
use super::settings::Settings;
use crate::raster::{Bins, Stats, Target};
use crate::scalar::Scalar;
use crate::scene::{Camera, LightKind};
use crate::shade::mode::Rays;
use crate::shade::ShadowMap;
use realist_trace::{Ray, PACKET};

/// The depth pass's target and its depth, kept between frames.
#[derive(Debug, Default)]
pub(super) struct ScreenShadows {
    target: Option<Target>,
    depth: Vec<f32>,
}

impl ScreenShadows {
    /// Fills a screen mask for every source of `fd.lights` that casts shadows (in Whitted's
    /// model, every one that can), seen through `jvp` (the pass's jittered projection) at
    /// `w` x `h`. Returns false if stopped.
    #[allow(clippy::too_many_arguments)]
    pub fn render(
        &mut self,
        scene: &PreparedScene,
        settings: &Settings,
        fd: &mut FrameData,
        camera: &Camera,
        jvp: Mat4,
        (w, h): (u32, u32),
        bins: &mut Bins,
        pool: &mut Pool,
        stats: &mut Stats,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> bool {
        let target = self
            .target
            .get_or_insert_with(|| Target::new(w, h, Vec4::ZERO));
        target.set_samples(1, Vec4::ZERO);
        target.reshape(w, h, Vec4::ZERO);
        target.clear(Vec4::ZERO);
        let mut cx = Cx {
            scene,
            camera,
            eye: camera.eye,
            jitter: Mat4::IDENTITY,
            lod_scale: 1.0,
            target,
            bins,
            pool,
            stats,
            stop,
            vertex_nanos: 0,
            light: Some(jvp),
            sort: false,
            sections: &[],
        };
        if !passes::shadow_depth(&mut cx, fd, &[]) {
            return false;
        }
        let n = w as usize * h as usize;
        self.depth.clear();
        self.depth.resize(n, 0.0);
        target.write_depth(&mut self.depth);
        let rays = scene.rays(settings);
        let inv = jvp.inverse();
        let depth = &self.depth;
        // The rasterizer snaps vertices to 2^-bits of a pixel, which tilts each triangle's
        // depth plane by up to the depth's slope times half that: a grazing surface's
        // depth can then lie behind the surface by far more than `lift` covers.
        let snap = 1.0 / (1u32 << settings.subpixel_bits.min(16)) as f32;
        let slope = |x: usize, y: usize| {
            let (w, h) = (w as usize, h as usize);
            let z = depth[y * w + x];
            // Each axis's smaller one-sided difference: the surface's own slope, not the
            // jump across an edge to whatever lies behind it.
            let along = |a: Option<f32>, b: Option<f32>| {
                [a, b]
                    .into_iter()
                    .flatten()
                    .filter(|n| *n > 0.0)
                    .map(|n| (n - z).abs())
                    .fold(f32::INFINITY, f32::min)
            };
            let gx = along(
                x.checked_sub(1).map(|x| depth[y * w + x]),
                (x + 1 < w).then(|| depth[y * w + x + 1]),
            );
            let gy = along(
                y.checked_sub(1).map(|y| depth[y * w + x]),
                (y + 1 < h).then(|| depth[(y + 1) * w + x]),
            );
            [gx, gy].into_iter().filter(|g| g.is_finite()).sum::<f32>()
        };
        let mut used = 0;
        for i in 0..fd.lights.sources.len() {
            let src = &fd.lights.sources[i];
            if !src.casts {
                continue;
            }
            let (kind, position, axis) = (src.kind, src.position, src.axis);
            if used == fd.lights.shadows.len() {
                fd.lights.shadows.push(ShadowMap::default());
            }
            let map = &mut fd.lights.shadows[used];
            map.screen = Some((w, h));
            map.view_proj = jvp;
            map.depth.clear();
            map.depth.resize(n, 1.0);
            map.depth
                .par_chunks_mut(w as usize)
                .enumerate()
                .for_each(|(y, row)| {
                    // Clip -> world along the row: linear in x before the divide.
                    let ny = 1.0 - (y as f32 + 0.5) / h as f32 * 2.0;
                    let dx = inv.x_axis * (2.0 / w as f32);
                    let at0 = inv * Vec4::new(-1.0 + 1.0 / w as f32, ny, 0.0, 1.0);
                    let at = |x: usize, z: f32| {
                        let q = at0 + dx * x as f32 + inv.z_axis * z;
                        q.truncate() / q.w
                    };
                    let ray = |from: Vec3, tmin: f32| match kind {
                        LightKind::Directional => Ray::new(from, -axis, tmin, f32::INFINITY),
                        _ => {
                            let to = position - from;
                            let reach = to.length().max(f32::MIN_POSITIVE);
                            Ray::new(from, to, tmin / reach, 1.0)
                        }
                    };
                    let blocked =
                        |from: Vec3, tmin: f32| from.is_finite() && rays.occluded(&ray(from, tmin));
                    // Eight neighbouring pixels' rays walk the hierarchy together.
                    let mut xs = [0usize; PACKET];
                    let mut batch = [ray(Vec3::ZERO, 0.0); PACKET];
                    let mut x = 0;
                    while x < row.len() {
                        let mut n = 0;
                        while x < row.len() && n < PACKET {
                            let z = depth[y * w as usize + x];
                            if z > 0.0 {
                                // A little nearer the camera than the depth buffer says
                                // (reversed Z: larger is nearer), so the ray starts in
                                // front of the surface. A point that is not finite makes
                                // an invalid ray, which nothing blocks.
                                (xs[n], batch[n]) = (x, ray(at(x, lift(z)), 0.0));
                                n += 1;
                            }
                            x += 1;
                        }
                        let mut hit = rays.occluded_packet(&batch[..n]);
                        while hit != 0 {
                            let k = hit.trailing_zeros() as usize;
                            hit &= hit - 1;
                            let x = xs[k];
                            let z = depth[y * w as usize + x];
                            // A blocked ray is tried again from past the snap's error in
                            // depth, passing over what lies within a pixel's width of its
                            // start (a face seen edge-on, a pixel thin, has no neighbour
                            // to measure its slope by). Few pixels are in shadow, so lit
                            // ones pay nothing.
                            let from = batch[k].origin;
                            let again = at(x, lift(z) + slope(x, y) * snap);
                            let next = at0 + dx * (x as f32 + 1.0) + inv.z_axis * lift(z);
                            let pixel = (next.truncate() / next.w - from).length();
                            if !pixel.is_finite() || blocked(again, pixel) {
                                row[x] = 0.0;
                            }
                        }
                    }
                });
            fd.lights.sources[i].shadow = Some(used as u32);
            used += 1;
        }
        true
    }
}

/// A depth-buffer value moved towards the camera by well over its rounding: in reversed Z
/// a perspective depth is about `near / distance`, so scaling it by `1 + 2e-5` moves the
/// point 2e-5 of its distance nearer; the constant term does the same for a parallel
/// projection's depth, linear in distance.
fn lift(z: f32) -> f32 {
    z * (1.0 + 2e-5) + 2e-6
}

/// Perceptual roughness at or below which a surface is a mirror in Whitted's model: its
/// reflection is traced (in place of the environment's prefiltered lobe).
pub const MIRROR_ROUGHNESS: f32 = 0.1;
/// Rays whose contribution to the pixel falls below this end (the textbook's
/// low-contribution limit): about an eighth of an 8-bit level.
pub const MIN_WEIGHT: f32 = 1.0 / 2048.0;

/// What a Whitted ray needs: the scene's hierarchy and each shown instance's material.
pub(crate) struct Tracer<'a> {
    pub(super) scene: &'a PreparedScene,
    pub(super) settings: &'a Settings,
    pub(super) rays: std::sync::Arc<realist_trace::Scene>,
    /// Per instance: its material as drawn, `None` if not shown.
    pub(super) resolved: Vec<Option<super::frame::Resolved>>,
    ground: Option<Mat4>,
    pub(super) cam_to_world: Mat4,
    pub(super) env: Option<crate::texture::env::EnvView>,
    pub(super) background: Vec3,
    pub(super) radius: f32,
    /// The probe's record of the rays cast ([`super::raylog`]); `None` when rendering.
    pub(super) log: Option<std::sync::Mutex<Vec<super::raylog::RayStep>>>,
}

/// The light a volume absorbs: its colour at `distance` and that distance.
#[derive(Clone, Copy)]
struct Medium {
    color: Vec3,
    distance: f32,
}

impl<'a> Tracer<'a> {
    #[must_use]
    pub fn new(scene: &'a PreparedScene, settings: &'a Settings, cam_to_world: Mat4) -> Self {
        let ground = settings.ground.as_ref().map(|g| scene.ground_world(g));
        let resolved = scene
            .instances
            .iter()
            .enumerate()
            .map(|(k, inst)| {
                let shown = if inst.ground {
                    ground.is_some()
                } else {
                    inst.drawable && !settings.hidden.contains(k)
                };
                shown.then(|| {
                    let mut r = super::frame::resolve(scene, settings, inst);
                    if let (true, Some(g)) = (inst.ground, &settings.ground) {
                        r.params.base = if g.color.is_finite() {
                            g.color.extend(1.0)
                        } else {
                            Vec3::splat(0.5).extend(1.0)
                        };
                    }
                    r
                })
            })
            .collect();
        Self {
            scene,
            settings,
            rays: scene.rays(settings),
            resolved,
            ground,
            cam_to_world,
            env: settings.environment.view(),
            background: settings.background.truncate(),
            radius: scene.bounding_sphere().1.max(1e-6),
            log: None,
        }
    }

    /// Whether instance `k`'s material can be a mirror or transmit (only then do its
    /// pixels need rays beyond the shadow rays).
    fn may_trace(&self, k: usize) -> bool {
        self.resolved
            .get(k)
            .and_then(Option::as_ref)
            .is_some_and(|r| {
                !r.params.unlit
                    && r.mode.mode().rays == Rays::Whitted
                    && r.params
                        .surface
                        .pbr
                        .as_ref()
                        .is_some_and(|p| p.transmission > 0.0 || p.roughness <= MIRROR_ROUGHNESS)
            })
    }

    /// Whether any shown instance needs them.
    #[must_use]
    pub fn any(&self) -> bool {
        (0..self.resolved.len()).any(|k| self.may_trace(k))
    }

    /// The light arriving along `d` at `o` (unit `d`), from `depth` bounces in, carrying
    /// `weight` of the pixel; inside `medium` (a volume being crossed) if any. `why`: the
    /// ray's kind and its share of the parent's colour, for the probe's log.
    fn radiance(
        &self,
        (o, d): (Vec3, Vec3),
        depth: u32,
        weight: Vec3,
        medium: Option<Medium>,
        why: (RayKind, Vec3),
    ) -> Vec3 {
        let hit = self.rays.closest(&Ray::new(o, d, 0.0, f32::INFINITY));
        self.note_ray(hit.as_ref(), depth, why, weight);
        let Some(h) = hit else {
            return self.miss(d);
        };
        let c = self.shade_hit(&h, o, d, depth, weight);
        match medium {
            // Beer's law over the path inside (KHR_materials_volume's attenuation).
            Some(m) if m.distance.is_finite() => {
                let k = (h.t / m.distance).min(1e4);
                c * m.color.max(Vec3::splat(1e-6)).powf(k)
            }
            _ => c,
        }
    }

    /// What a ray that meets nothing sees: the environment (its full-resolution image), or
    /// the background colour.
    pub(super) fn miss(&self, d: Vec3) -> Vec3 {
        match &self.env {
            Some(env) => env.background(d, 0.0),
            None => self.background,
        }
    }

    /// The surface a ray from `o` along unit `d` meets at `h`, and its instance's material.
    pub(super) fn point<T: Scalar>(
        &self,
        h: &realist_trace::Hit,
        o: T::V,
        d: T::V,
    ) -> Option<(super::probe::Point<T>, &super::frame::Resolved)> {
        let (k, copy) = super::rays::unkey(h.key);
        let r = self.resolved.get(k).and_then(Option::as_ref)?;
        let inst = &self.scene.instances[k];
        let world = match (inst.ground, self.ground) {
            (true, Some(g)) => g,
            _ => inst.placement(copy),
        };
        let hit = super::probe::Hit {
            t: f64::from(h.t),
            instance: k,
            copy,
            triangle: h.triangle as usize,
            bary: Vec3::from_array(h.bary),
            front: h.front,
        };
        let position = o + d * T::of(h.t);
        let pt = super::probe::point_at::<T>(
            self.scene,
            r,
            world,
            &hit,
            position,
            o,
            self.settings.single_scatter,
        );
        Some((pt, r))
    }

    /// Every light's share at `pt`, shadow rays to each (and, with `image_based`, the
    /// ambient and environment terms as the rasterizer has them); without `shares` only
    /// their sum.
    pub(super) fn light<T: Scalar>(
        &self,
        pt: &super::probe::Point<T>,
        image_based: bool,
        shares: bool,
    ) -> super::probe::Lit<T> {
        let rays = &self.rays;
        let occluded = |from: Vec3, to: Vec3| rays.occluded(&Ray::new(from, to - from, 0.0, 1.0));
        super::probe::light_point(
            self.scene,
            self.settings,
            self.cam_to_world,
            pt,
            true,
            image_based,
            shares,
            &occluded,
        )
    }

    /// The colour a ray from `o` along unit `d` sees at its hit `h`.
    pub fn shade_hit(
        &self,
        h: &realist_trace::Hit,
        o: Vec3,
        d: Vec3,
        depth: u32,
        weight: Vec3,
    ) -> Vec3 {
        let Some((pt, r)) = self.point(h, o, d) else {
            return self.miss(d);
        };
        let position = pt.position;
        if pt.unlit {
            return pt.base.truncate();
        }
        let lit = self.light(&pt, true, true);
        self.note_shadows(&lit.lights, depth, weight);
        let direct = lit
            .lights
            .iter()
            .fold(pt.emitted + lit.ambient_diffuse, |a, s| {
                a + s.diffuse + s.specular
            });
        let Some(p) = pt
            .surf
            .pbr
            .as_ref()
            .filter(|_| r.mode.mode().rays == Rays::Whitted)
        else {
            return direct + lit.ambient_specular;
        };
        let params = r.params.surface.pbr.as_ref();
        let transmission = p.transmission.map_or(0.0, |t| t.factor) * (1.0 - p.metallic);
        let mirror = p.roughness <= MIRROR_ROUGHNESS;
        if !(mirror || transmission > 0.0)
            || depth >= self.settings.ray_depth.min(super::MAX_RAY_DEPTH)
            || weight.max_element() < MIN_WEIGHT
        {
            return direct + lit.ambient_specular;
        }
        // The side the ray came from, and the geometric normal facing it.
        let n = pt.normal;
        let ng = if pt.face_normal.dot(d) < 0.0 {
            pt.face_normal
        } else {
            -pt.face_normal
        };
        let cos = (-d).dot(n).clamp(0.0, 1.0);
        let base = pt.surf.kd;
        let eps = 2e-5 * (position.abs().max_element() + self.radius);
        let above = position + ng * eps;
        let below = position - ng * eps;
        let reflected = (d - 2.0 * d.dot(n) * n).normalize_or_zero();
        // Specular reflectance at the view: the dielectric lobe's Fresnel and the metal's
        // base colour (Schlick), mixed by metalness.
        let schlick = |f0: Vec3, f90: f32| f0 + (Vec3::splat(f90) - f0) * (1.0 - cos).powi(5);
        let metal = schlick(base, 1.0);
        let mut color = direct;
        if let (true, Some(params)) = (transmission > 0.0, params) {
            let thin = p.transmission.is_some_and(|t| t.thickness <= 0.0);
            let entering = pt.front;
            let ior = params.ior.max(1.0);
            let eta = if thin || entering { 1.0 / ior } else { ior };
            // The dielectric's exact Fresnel (the textbook's §9.6.2 transparency model).
            let (fr, refracted) = fresnel_refract(d, n, cos, eta, thin);
            let f_diel = Vec3::splat(fr);
            let reflect_w = if entering || thin {
                metal * p.metallic + f_diel * (1.0 - p.metallic)
            } else {
                // Inside a volume: the bare interface.
                f_diel
            };
            if reflect_w.max_element() > 0.0 {
                let w = weight * reflect_w;
                let why = (RayKind::Reflection, reflect_w);
                color += reflect_w * self.radiance((above, reflected), depth + 1, w, None, why);
            }
            if let Some(t_dir) = refracted {
                // The base colour tints the light once, on its way in.
                let tw = if entering || thin {
                    (1.0 - fr) * transmission * base
                } else {
                    Vec3::splat(1.0 - fr)
                };
                let w = weight * tw;
                // A closed volume entered: its attenuation applies until the ray leaves.
                let medium = (!thin && entering).then_some(Medium {
                    color: params.attenuation_color,
                    distance: params.attenuation_distance,
                });
                let why = (RayKind::Refraction, tw);
                color += tw * self.radiance((below, t_dir), depth + 1, w, medium, why);
            }
            // The dielectric lobe's environment light is now traced.
            return color + lit.ambient_specular * p.metallic;
        }
        let f_diel = schlick(p.f0, p.f90);
        let reflect_w = metal * p.metallic + f_diel * (1.0 - p.metallic);
        let w = weight * reflect_w;
        let why = (RayKind::Reflection, reflect_w);
        color + reflect_w * self.radiance((above, reflected), depth + 1, w, None, why)
    }
}

/// The dielectric's reflectance for a ray along unit `d` meeting unit normal `n` (facing
/// the ray, `cos = -d·n`) from a medium `eta` = n1/n2 times the other's, and the refracted
/// direction by Snell's law; `None` beyond the critical angle (total internal reflection,
/// reflectance 1). A thin wall passes the ray on unbent.
pub(super) fn fresnel_refract<T: Scalar>(
    d: T::V,
    n: T::V,
    cos: T,
    eta: T,
    thin: bool,
) -> (T, Option<T::V>) {
    let one = T::ONE;
    let sin2_t = eta * eta * (one - cos * cos);
    if sin2_t >= one {
        return (one, None);
    }
    let cos_t = (one - sin2_t).sqrt();
    // Fresnel's equations for unpolarised light (n1 cos_i vs n2 cos_t, with n1/n2 = eta).
    let rs = (eta * cos - cos_t) / (eta * cos + cos_t);
    let rp = (cos - eta * cos_t) / (cos + eta * cos_t);
    let r = T::of(0.5) * (rs * rs + rp * rp);
    let t = if thin {
        d
    } else {
        T::normalize_or_zero(d * eta + n * (eta * cos - cos_t))
    };
    (r.clamp01(), Some(t))
}

/// Whitted's rays for the pixels that see a mirror or a transmissive surface (the others
/// keep what the rasterizer drew): a camera ray through each pixel's sample point (`jvp`,
/// the pass's jittered projection), and where it meets such a surface, its colour traced
/// to the depth and contribution limits, written over the pass's. Returns false if
/// stopped.
pub(super) fn mirrors(
    scene: &PreparedScene,
    settings: &Settings,
    target: &mut Target,
    jvp: Mat4,
    cam_to_world: Mat4,
    stop: &(dyn Fn() -> bool + Sync),
) -> bool {
    let tracer = Tracer::new(scene, settings, cam_to_world);
    if !tracer.any() {
        return true;
    }
    let (w, h) = (target.width, target.height);
    let inv = jvp.inverse();
    let fog = settings.fog.filter(|f| f.is_valid());
    let eye = cam_to_world.w_axis.truncate();
    let forward = -cam_to_world.z_axis.truncate();
    let rows: Option<Vec<Vec<(u32, Vec3)>>> = (0..h)
        .into_par_iter()
        .map(|y| {
            if stop() {
                return None;
            }
            let mut out = Vec::new();
            for x in 0..w {
                let ndc = glam::Vec2::new(
                    (x as f32 + 0.5) / w as f32 * 2.0 - 1.0,
                    1.0 - (y as f32 + 0.5) / h as f32 * 2.0,
                );
                let near = inv.project_point3(ndc.extend(1.0));
                let far = inv.project_point3(ndc.extend(0.0));
                let seg = far - near;
                let len = seg.length();
                if !(len > 0.0 && len.is_finite()) {
                    continue;
                }
                let d = seg / len;
                let Some(hit) = tracer.rays.closest(&Ray::new(near, d, 0.0, len)) else {
                    continue;
                };
                let (k, _) = super::rays::unkey(hit.key);
                if !tracer.may_trace(k) {
                    continue;
                }
                let c = tracer.shade_hit(&hit, near, d, 0, Vec3::ONE);
                let c = match &fog {
                    Some(f) => f.apply::<f32>(c, near + d * hit.t, eye, forward),
                    None => c,
                };
                out.push((x, c));
            }
            Some(out)
        })
        .collect();
    let Some(rows) = rows else {
        return false;
    };
    for (y, row) in rows.into_iter().enumerate() {
        for (x, c) in row {
            let (t, o) = target.locate(x, y as u32);
            let tile = &mut target.tiles[t];
            tile.materialize();
            tile.set_color(o, c.extend(1.0));
        }
    }
    true
}
