//! The pixel probe: what is seen at one pixel and how it is lit, recomputed for that pixel
//! alone. A ray through the pixel centre (the rasterizer's sample point) is cast against
//! every instance's triangles in f64 (back faces skipped where the rasterizer culls them,
//! hits outside the near/far planes ignored); the nearest hit's barycentric coordinates
//! give the interpolated normal, UV and vertex colour, which go through the shared lighting
//! model ([`crate::shade::arriving`] and [`crate::shade::reflect`], what
//! [`crate::shade::illuminate`] sums) once per light, so each light's diffuse and specular
//! share after attenuation, cone and shadow is exact and the shares add up to the shaded
//! colour. Shadows are found by a shadow ray towards the light (exact; the rendered
//! shadow map approximates it). Hits cut away by section planes are passed over, and a
//! cut's cap is the back face seen through it.

use glam::{DVec3, Vec2, Vec3, Vec4};
use rayon::prelude::*;

mod point;

pub(crate) use point::{light_point, point_at, Lit, Point};

use super::frame::resolve;
use super::prepare::PreparedScene;
use super::settings::{Settings, View};
use crate::raster::Cull;
use crate::scene::Light;
use crate::shade::mode::Rays;
use crate::shade::Shading;

/// One light's contribution at the probed point (linear RGB).
#[derive(Clone, Debug, PartialEq)]
pub struct LightShare {
    /// Position in the frame's light list (scene, rig or custom lights).
    pub index: usize,
    /// The light as it was in world space this frame.
    pub light: Light,
    /// Radiance arriving at the point after attenuation, cone or pyramid and projected
    /// image, before shadowing (zero when none does).
    pub arriving: Vec3,
    /// 1 lit, 0 in shadow: a shadow ray towards the light (the exact answer the shadow map
    /// approximates); 1 for lights without shadows.
    pub shadow: f32,
    pub diffuse: Vec3,
    pub specular: Vec3,
    /// The `pbr` BRDF's terms for this light: GGX `D`, the visibility `Vis = G / (4 NL NV)`
    /// and the Fresnel colour (zero in the Phong modes).
    pub d: f32,
    pub vis: f32,
    pub fresnel: Vec3,
    /// The sheen and clear-coat layers' own reflection of this light (included in
    /// `specular`; zero without those layers).
    pub sheen: Vec3,
    pub coat: Vec3,
}

/// What the probe found at a pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct Probe {
    /// World-space point.
    pub position: Vec3,
    /// Distance from the camera plane (camera-space depth).
    pub view_depth: f32,
    /// The depth-buffer value the rasterizer stores there (reversed-Z z/w).
    pub depth: f32,
    /// Interpolated unit world normal as shaded (turned towards the viewer on a back face).
    pub normal: Vec3,
    /// Unit normal of the triangle's plane (world, counter-clockwise side).
    pub face_normal: Vec3,
    /// The ray hit the triangle's front side.
    pub front: bool,
    pub uv: Option<Vec2>,
    /// Barycentric weights of the triangle's three render vertices.
    pub barycentric: Vec3,
    /// Index into [`Scene::instances`](crate::scene::Scene::instances).
    pub instance: usize,
    pub mesh: usize,
    /// Index into the scene's materials, or `None` for the default material.
    pub material: Option<usize>,
    /// Triangle of the prepared mesh, and the mesh facet it belongs to.
    pub triangle: usize,
    pub facet: usize,
    /// The instance's shading mode under the settings.
    pub mode: Shading,
    /// Diffuse colour and alpha at the point (material x vertex colour x texture).
    pub base: Vec4,
    /// Ambient term (never attenuated; times the occlusion map's factor).
    pub ambient: Vec3,
    /// For a `pbr` surface, the ambient term's diffuse and specular parts (the image-based
    /// lighting of the environment and the ambient light, after occlusion).
    pub image_based: Option<(Vec3, Vec3)>,
    /// Emitted light (the material's emissive colour times its emissive map).
    pub emitted: Vec3,
    pub lights: Vec<LightShare>,
    /// Fog factor f (0 clear, 1 only fog), if fog is on.
    pub fog: Option<f32>,
    /// Ambient plus every light's share, fogged: the colour per-pixel lighting gives here
    /// (Blinn's highlight for the Blinn and textured modes, Phong's otherwise). In `path`,
    /// the path tracer's estimate: the mean of the pixel's first
    /// [`PROBE_PATHS`](crate::path::PROBE_PATHS) paths, as the image shows it after as many.
    pub color: Vec3,
    /// In Whitted's model (`--shading whitted`), the pixel's ray tree as the tracer follows
    /// it: the primary ray, shadow rays, reflections and refractions, each with what it met
    /// and its share of the pixel. Empty in the other modes.
    pub rays: Vec<super::raylog::RayStep>,
}

/// Probes pixel (x, y) of `view` (pixel centre, y down). `None` if the ray meets nothing.
#[must_use]
pub fn probe(
    scene: &PreparedScene,
    settings: &Settings,
    view: &View,
    x: u32,
    y: u32,
) -> Option<Probe> {
    let (w, h) = (view.width.max(1), view.height.max(1));
    let cam = &view.camera;
    let view_m = cam.view();
    let vp = cam.projection(view.aspect()) * view_m;
    let inv = vp.as_dmat4().inverse();
    let ndc = glam::DVec2::new(
        (f64::from(x) + 0.5) / f64::from(w) * 2.0 - 1.0,
        1.0 - (f64::from(y) + 0.5) / f64::from(h) * 2.0,
    );
    // Reversed-Z: z = 1 on the near plane, 0 on the far plane.
    let near = inv.project_point3(ndc.extend(1.0));
    let far = inv.project_point3(ndc.extend(0.0));
    let hit = cast(scene, settings, near, far, true)?;
    let inst = &scene.instances[hit.instance];
    let r = resolve(scene, settings, inst);
    let d = &r.params;
    // The copy hit (an instanced mesh's) places it.
    let world = inst.placement(hit.copy);
    let position = (near + (far - near) * hit.t).as_vec3();
    let eye = cam.shading_eye();
    let pt = point_at::<f32>(
        scene,
        &r,
        world,
        &hit,
        position,
        eye,
        settings.single_scatter,
    );
    let shadow_ray = |from: Vec3, to: Vec3| {
        cast(scene, settings, from.as_dvec3(), to.as_dvec3(), false).is_some()
    };
    let lit = light_point(
        scene,
        settings,
        view_m.inverse(),
        &pt,
        false,
        true,
        true,
        &shadow_ray,
    );
    let Point {
        normal,
        face_normal,
        uv,
        base,
        surf,
        occlusion: _,
        emitted,
        ..
    } = pt;
    let Lit {
        lights,
        ambient_diffuse,
        ambient_specular,
        ..
    } = lit;
    let ambient = ambient_diffuse + ambient_specular;
    let image_based = surf
        .pbr
        .is_some()
        .then_some((ambient_diffuse, ambient_specular));
    let bary = hit.bary;
    let tri = &scene.meshes[inst.mesh].tri;
    let lit = lights
        .iter()
        .fold(ambient + emitted, |acc, s| acc + s.diffuse + s.specular);
    let (lit, lights) = if d.unlit {
        // KHR_materials_unlit: the base colour as it is, no light and no fog.
        (base.truncate(), Vec::new())
    } else {
        (lit, lights)
    };
    let fog = settings.fog.filter(|f| f.is_valid());
    let color = match &fog {
        Some(f) if !d.unlit => f.apply::<f32>(lit, position, eye, cam.forward()),
        _ => lit,
    };
    let fog = fog.map(|f| f.factor::<f32>(f.distance::<f32>(position, eye, cam.forward())));
    let (rays, color) = match settings.rays() {
        Rays::Whitted => (
            super::raylog::whitted_steps(scene, settings, view, x, y),
            color,
        ),
        // The path tracer's own estimate: what the image shows there after as many paths.
        Rays::Path => super::path::path_probe(scene, settings, view, x, y),
        // Rasterized (radiosity's solution too): no rays to list.
        Rays::None | Rays::Radiosity => (Vec::new(), color),
    };
    let clip = vp * position.extend(1.0);
    // The scene's mesh (a skinned instance draws a posed copy made from it).
    let (mesh_index, mesh) = scene.scene_mesh(inst)?;
    Some(Probe {
        position,
        view_depth: -view_m.transform_point3(position).z,
        depth: clip.z / clip.w,
        normal,
        face_normal,
        front: hit.front,
        uv,
        barycentric: bary,
        instance: hit.instance,
        mesh: mesh_index,
        material: mesh
            .material_in(settings.variant_index(scene.scene()))
            .filter(|&m| m < scene.scene().materials.len()),
        triangle: hit.triangle,
        facet: if hit.triangle < tri.triangles.len() {
            tri.facet_of(hit.triangle)
        } else {
            0
        },
        mode: r.mode,
        base,
        ambient,
        image_based,
        emitted,
        lights,
        fog,
        color,
        rays,
    })
}

/// The nearest hit of a ray.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Hit {
    /// Ray parameter: 0 at the near plane, 1 at the far plane.
    pub t: f64,
    pub instance: usize,
    /// The copy of an instanced mesh hit (0 otherwise).
    pub copy: usize,
    pub triangle: usize,
    pub bary: Vec3,
    pub front: bool,
}

/// Casts the segment `near -> far` (world space) against every instance; with `cull` (a
/// camera ray), back faces are skipped where the rasterizer culls them and hits cut away by
/// section planes are passed over (a shadow ray sees both sides of the whole model).
pub(crate) fn cast(
    scene: &PreparedScene,
    settings: &Settings,
    near: DVec3,
    far: DVec3,
    cull: bool,
) -> Option<Hit> {
    let mut best: Option<Hit> = None;
    for (i, inst) in scene.instances.iter().enumerate() {
        if !inst.drawable || settings.hidden.contains(i) {
            continue;
        }
        let tri = &scene.meshes[inst.mesh].tri;
        // Section planes cut what the camera sees (not shadow rays: the whole model casts
        // shadows), everything but the ground; their caps are back faces.
        let sections: &[Vec4] = if inst.ground || !cull {
            &[]
        } else {
            &settings.sections.planes
        };
        let capped = !sections.is_empty() && settings.sections.cap.is_some();
        let kept = |t: f64| {
            let p = (near + (far - near) * t).as_vec3().extend(1.0);
            sections.iter().all(|l| l.dot(p) >= 0.0)
        };
        // Resolved only for an instance the segment comes near.
        let mut cull_back = None;
        for copy in 0..inst.copy_count() {
            let placed = inst.placement(copy);
            if inst.copies.is_some() {
                // A cheap world-space reject first: a forest has a million copies.
                let (c, r) = crate::frame::world_sphere(placed, tri.center, tri.radius);
                let (c, d) = (c.as_dvec3(), far - near);
                let t = ((c - near).dot(d) / d.length_squared()).clamp(0.0, 1.0);
                let reach = f64::from(r) * (1.0 + 1e-6) + 1e-9;
                let gap = (near + d * t - c).length();
                // NaN (a degenerate copy) is a miss too.
                if gap.is_nan() || gap > reach {
                    continue;
                }
            }
            let world = placed.as_dmat4();
            if world.determinant().abs() < 1e-300 {
                continue;
            }
            let inv = world.inverse();
            let (o, e) = (inv.transform_point3(near), inv.transform_point3(far));
            let d = e - o;
            // The segment must pass within the bounding sphere.
            let cen = tri.center.as_dvec3();
            let t_closest = ((cen - o).dot(d) / d.length_squared()).clamp(0.0, 1.0);
            if (o + d * t_closest - cen).length() > f64::from(tri.radius) * (1.0 + 1e-6) + 1e-9 {
                continue;
            }
            let cull_back = *cull_back.get_or_insert_with(|| {
                cull && !capped && resolve(scene, settings, inst).state.cull == Cull::Back
            });
            let limit = best.map_or(1.0, |b| b.t);
            let found = tri
                .triangles
                .par_iter()
                .enumerate()
                .with_min_len(4096)
                .filter_map(|(k, t)| {
                    let [a, b, c] = t.map(|v| tri.positions[v as usize].as_dvec3());
                    intersect(o, d, a, b, c, cull_back).map(|(t, bary, front)| (t, k, bary, front))
                })
                .filter(|h| h.0 <= limit && kept(h.0))
                .min_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
            if let Some((t, k, bary, front)) = found {
                if best.is_none_or(|b| t < b.t) {
                    best = Some(Hit {
                        t,
                        instance: i,
                        copy,
                        triangle: k,
                        bary,
                        front,
                    });
                }
            }
        }
    }
    best
}

/// Moller-Trumbore: the segment `o + t d`, t in [0, 1], against triangle (a, b, c).
/// Returns (t, barycentric weights of a, b, c, whether the front (counter-clockwise) side
/// was hit).
fn intersect(
    o: DVec3,
    d: DVec3,
    a: DVec3,
    b: DVec3,
    c: DVec3,
    cull_back: bool,
) -> Option<(f64, Vec3, bool)> {
    let (e1, e2) = (b - a, c - a);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    // det = e1 . (d x e2) = -d . (e1 x e2): positive when the ray runs against the face
    // normal, i.e. it sees the front.
    let front = det > 0.0;
    if cull_back && !front {
        return None;
    }
    let inv = 1.0 / det;
    let s = o - a;
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = d.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(q) * inv;
    (0.0..=1.0).contains(&t).then(|| {
        (
            t,
            Vec3::new((1.0 - u - v) as f32, u as f32, v as f32),
            front,
        )
    })
}
