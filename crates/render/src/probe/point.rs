//! A surface point as the lit shaders see it, rebuilt at one hit, and what lights it: the
//! probe's, Whitted's and the path tracer's shading, in `f32` or (the path tracer's
//! reference) `f64` ([`Scalar`]).

use glam::{Vec2, Vec3, Vec4};

use super::{Hit, LightShare};
use crate::frame::{for_each_light, Resolved};
use crate::prepare::PreparedScene;
use crate::scalar::Scalar;
use crate::scene::{LightKind, Slot, TextureSource};
use crate::settings::Settings;
use crate::shade::layer_maps::LayerTexels;
use crate::shade::{
    ambient_split, arriving, emission_seen, maps, reflect, texlab, view_terms, view_vector,
    LightSet, SlotParams, SurfaceAt,
};

/// A point of a surface as the lit shaders see it: the interpolated attributes, the maps
/// applied, the surface's parameters at the view (`v`, from the eye or a ray's origin).
pub(crate) struct Point<T: Scalar = f32> {
    pub position: T::V,
    /// Unit world normal as shaded (turned towards the viewer on a back face).
    pub normal: T::V,
    pub face_normal: T::V,
    pub front: bool,
    pub uv: Option<Vec2>,
    pub base: Vec4,
    pub surf: SurfaceAt<T>,
    pub v: T::V,
    pub occlusion: T,
    pub emitted: T::V,
    pub blinn: bool,
    pub unlit: bool,
}

/// The surface of `r` (an instance's resolved material) at `hit` (of the mesh placed by
/// `world`), at world `position`, seen from `eye`. The mesh's vertices, the placement and
/// the texels are `f32`; they widen to `T` before they are combined.
#[allow(clippy::too_many_arguments)]
pub(crate) fn point_at<T: Scalar>(
    scene: &PreparedScene,
    r: &Resolved,
    world: glam::Mat4,
    hit: &Hit,
    position: T::V,
    eye: T::V,
    single_scatter: bool,
) -> Point<T> {
    let tri = &scene.meshes[scene.instances[hit.instance].mesh].tri;
    let normal_m = crate::prepare::normal_matrix(world);
    let mirrored = world.determinant() < 0.0;
    let [a, b, c] = tri.triangles[hit.triangle].map(|k| k as usize);
    let bary = hit.bary;
    let (wa, wb, wc) = (T::of(bary.x), T::of(bary.y), T::of(bary.z));
    let mix3 = |v: &[Vec3]| T::vec(v[a]) * wa + T::vec(v[b]) * wb + T::vec(v[c]) * wc;
    let mut normal = T::normalize_or_zero(T::mat3(normal_m, mix3(&tri.normals)));
    // Before the maps: the clear coat's normal when the base is normal- or bump-mapped.
    let mut geometric = normal;
    let corner = |k: usize| T::vec(tri.positions[k]);
    let face = T::cross(corner(b) - corner(a), corner(c) - corner(a));
    let face_normal = T::normalize_or_zero(T::mat3(normal_m, face));
    let uv = tri
        .uv_set(0)
        .map(|u| u[a] * bary.x + u[b] * bary.y + u[c] * bary.z);
    // Each slot at its own UV channel (set and transform), as the shader reads it.
    let d = &r.params;
    let uv_of = |t: &SlotParams, k: Option<usize>| {
        let ch = d.layout.channel_at(t.uv_at);
        let at = tri.uv_set(ch.set).map_or(Vec2::ZERO, |u| match k {
            Some(k) => u[k],
            None => u[a] * bary.x + u[b] * bary.y + u[c] * bary.z,
        });
        ch.transform.apply(at)
    };
    // The UV edges of a slot's triangle, as the maps' functions take them.
    let uv_edges = |t: &SlotParams| {
        let uv = [a, b, c].map(|k| uv_of(t, Some(k)));
        let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
        ((T::of(d1.x), T::of(d2.x)), (T::of(d1.y), T::of(d2.y)))
    };
    // Solid textures' frame, as the vertex stage writes it.
    let inv_radius = if tri.radius > 0.0 {
        1.0 / tri.radius
    } else {
        1.0
    };
    let local = |k: usize| (tri.positions[k] - tri.center) * inv_radius;
    let object = local(a) * bary.x + local(b) * bary.y + local(c) * bary.z;
    let point = |t: &SlotParams, p: &crate::texture::ProceduralTexture| match p.domain() {
        crate::texture::Domain::Uv => crate::texture::SamplePoint::uv(uv_of(t, None)),
        crate::texture::Domain::Object => crate::texture::SamplePoint::position(object, 0.0),
    };
    // Point samples: the probe reports the texture at the hit, not over a footprint.
    let sample = |t: &SlotParams| match &t.source {
        TextureSource::Image(tex) => tex.sample_with(uv_of(t, None), t.sampler),
        TextureSource::Procedural(p) => p.color(&point(t, p)),
    };
    // The triangle's world edges from its first corner.
    let world_edges = || {
        let w = [a, b, c].map(|k| T::point(world, tri.positions[k]));
        (w[1] - w[0], w[2] - w[0])
    };
    // The interpolated tangent in the world and its handedness.
    let tangent = |ts: &[Vec4]| {
        let t4 = ts[a] * bary.x + ts[b] * bary.y + ts[c] * bary.z;
        let m3 = glam::Mat3::from_mat4(world);
        let handed = if mirrored { -1.0 } else { 1.0 };
        (T::mat3(m3, T::vec(t4.truncate())), T::of(t4.w * handed))
    };
    // A tangent-space normal map applied to `n` (the base's or the clear coat's).
    let normal_mapped = |map: &SlotParams, n: T::V| {
        let frame = match &tri.tangents {
            Some(ts) => {
                let (t, w) = tangent(ts);
                Some((T::normalize_or_zero(t), w))
            }
            // No tangents: the frame from the triangle's world edges and UVs (the shader
            // takes it from the screen-space derivatives).
            None => {
                let (s1, s2) = world_edges();
                let (du, dv) = uv_edges(map);
                maps::uv_tangent::<T>(n, s1, s2, du, dv)
            }
        };
        match frame {
            Some((t, w)) => {
                let texel = sample(map).truncate().to_array().map(T::of);
                maps::perturb::<T>(n, t, w, texel, T::of(map.scale))
            }
            None => n,
        }
    };
    if let Some(map) = &d.normal_map {
        normal = normal_mapped(map, normal);
    }
    if let Some(bm) = &d.bump {
        // The shader's surface gradient with the triangle's world edges in place of the
        // screen-space derivatives (as the f64 reference does).
        let (s1, s2) = world_edges();
        let uv_slope = |slope: Vec2| {
            let (du, dv) = uv_edges(bm);
            maps::uv_height_gradient::<T>(
                normal,
                s1,
                s2,
                du,
                dv,
                (T::of(slope.x), T::of(slope.y)),
                T::of(bm.scale),
            )
        };
        let g = match &bm.source {
            TextureSource::Image(tex) => {
                uv_slope(texlab::image_height_slope(tex, uv_of(bm, None), bm.sampler))
            }
            TextureSource::Procedural(p) => {
                let g = p.height_gradient(&point(bm, p));
                match p.domain() {
                    crate::texture::Domain::Uv => uv_slope(g.truncate()),
                    crate::texture::Domain::Object => texlab::solid_height_gradient::<T>(
                        normal,
                        (s1, s2),
                        (T::vec(local(b) - local(a)), T::vec(local(c) - local(a))),
                        T::vec(g),
                        T::of(bm.scale),
                    ),
                }
            }
        };
        if let Some(g) = g {
            normal = maps::bump::<T>(normal, g);
        }
    }
    // The clear coat's own normal map, over the interpolated normal.
    let coat_map = d.layer_map(Slot::ClearcoatNormal);
    if let Some(map) = coat_map {
        geometric = normal_mapped(map, geometric);
    }
    if !hit.front {
        normal = -normal;
        geometric = -geometric;
    }
    let mut base = d.base;
    if let Some(col) = &tri.colors {
        base *= col[a] * bary.x + col[b] * bary.y + col[c] * bary.z;
    }
    if let Some(t) = &d.base_map {
        base *= sample(t);
    }
    let blinn = d.blinn;
    let mut surf = d.surface.at::<T>(T::vec(base.truncate()));
    if let Some(g) = &d.gloss {
        surf.ks = surf.ks * T::vec(sample(g).truncate());
    }
    if let (Some(mr), Some(p)) = (&d.metal_rough, &mut surf.pbr) {
        let t = sample(mr);
        p.roughness = p.roughness * T::of(t.y);
        p.metallic = p.metallic * T::of(t.z);
    }
    if let (Some(p), Some(params)) = (&mut surf.pbr, &d.surface.pbr) {
        let mut texels = LayerTexels::<T>::default();
        for (slot, t) in Slot::LAYERS.iter().zip(&d.layer_maps) {
            if let Some(t) = t {
                texels.read(*slot, sample(t).to_array().map(T::of));
            }
        }
        texels.apply(params, p);
        // Anisotropy, in the frame of the mesh's tangents (as the shader reads them), about
        // the normal before it turned to the side seen (the direction's line is the same).
        let unturned = if hit.front { normal } else { -normal };
        if let (Some(ts), true) = (&tri.tangents, d.layout.tangent_at().is_some()) {
            let (t, w) = tangent(ts);
            p.anisotropy = texels.anisotropy(params, unturned, t, w);
        }
    }
    let occlusion = d.occlusion.as_ref().map_or(T::ONE, |o| {
        maps::occlusion::<T>(T::of(sample(o).x), T::of(o.scale))
    });
    let emitted = match &d.emissive_map {
        Some(m) => T::vec(d.emissive) * T::vec(sample(m).truncate()),
        None => T::vec(d.emissive),
    };
    let v = view_vector(&surf, position, eye);
    if let (Some(y), true) = (
        surf.pbr.as_mut().and_then(|p| p.layers.as_mut()),
        d.normal_map.is_some() || d.bump.is_some() || coat_map.is_some(),
    ) {
        y.coat_normal = Some(geometric);
    }
    // The punctual lights' multiple-scattering compensation and the layers' values at the
    // view, as the shaders have them.
    view_terms(&mut surf, normal, v, single_scatter);
    let emitted = emission_seen(&surf, emitted);
    Point {
        position,
        normal,
        face_normal,
        front: hit.front,
        uv,
        base,
        surf,
        v,
        occlusion,
        emitted,
        blinn,
        unlit: d.unlit,
    }
}

/// What lights a [`Point`]: each light's share (as the probe lists it, in `f32`), their
/// sum in `T`, and the ambient light's (and for pbr the environment's) diffuse and
/// specular parts, after occlusion.
pub(crate) struct Lit<T: Scalar = f32> {
    pub lights: Vec<LightShare>,
    /// The lights' diffuse and specular shares summed.
    pub direct: T::V,
    pub ambient_diffuse: T::V,
    pub ambient_specular: T::V,
}

/// Lights `pt` with the frame's lights (`cam_to_world` places camera-attached ones).
/// `occluded(from, to)` answers a shadow ray, asked for lights that cast shadows, or for
/// `every` light that can (Whitted's model). Without `image_based` the ambient and
/// environment terms are left at zero (a path tracer samples them itself). Without
/// `shares` only their sum is made (each share clones its light).
#[allow(clippy::too_many_arguments)]
pub(crate) fn light_point<T: Scalar>(
    scene: &PreparedScene,
    settings: &Settings,
    cam_to_world: glam::Mat4,
    pt: &Point<T>,
    every: bool,
    image_based: bool,
    shares: bool,
    occluded: &dyn Fn(Vec3, Vec3) -> bool,
) -> Lit<T> {
    let mut set = LightSet::default();
    let (position, normal, v, blinn) = (pt.position, pt.normal, pt.v, pt.blinn);
    let surf = &pt.surf;
    let zero = T::splat(T::ZERO);
    let mut ambient_light = Vec3::ZERO;
    let mut lights = Vec::new();
    let mut direct = zero;
    let mut index = 0;
    let (center, radius) = scene.bounding_sphere();
    let rig = settings.default_rig(scene.scene());
    for_each_light(
        scene.lights(),
        &settings.lights,
        rig,
        cam_to_world,
        |l, m| {
            set.clear();
            set.push(l, m, index);
            index += 1;
            if l.kind == LightKind::Ambient {
                ambient_light += set.ambient;
                return;
            }
            let Some(src) = set.sources.first() else {
                return;
            };
            let (dir, rad, _) = arriving::<T>(src, position).unwrap_or((zero, zero, false));
            let arriving = rad;
            // A clear coat with its own normal can see the light where the mapped base
            // cannot (as `contribution` has it).
            let coat = surf
                .pbr
                .as_ref()
                .and_then(|p| p.layers.as_ref()?.coat_normal);
            let facing =
                T::dot(normal, dir) > T::ZERO || coat.is_some_and(|nc| T::dot(nc, dir) > T::ZERO);
            let lit = facing && !T::is_zero(rad);
            // Light from behind through a translucent base (as `contribution` has it).
            let translucent = surf.pbr.as_ref().is_some_and(|p| p.translucency.is_some());
            let back = translucent && T::dot(normal, dir) < T::ZERO && !T::is_zero(rad);
            let shadow = if (lit || back) && (l.shadow || every) && l.kind.can_shadow() {
                let to = match l.kind {
                    LightKind::Directional => {
                        position
                            + dir * (T::of(4.0 * radius) + T::length(position - T::vec(center)))
                    }
                    _ => T::vec(src.position),
                };
                let side = if back { -normal } else { normal };
                let from = position + side * T::of(1e-4 * radius.max(1e-3));
                if occluded(T::to_vec3(from), T::to_vec3(to)) {
                    0.0
                } else {
                    1.0
                }
            } else {
                1.0
            };
            let ndl = if coat.is_some() {
                T::dot(normal, dir).max(T::ZERO)
            } else {
                T::dot(normal, dir)
            };
            let terms = reflect(surf, normal, dir, v, lit, ndl, back, blinn);
            let s = T::of(shadow);
            let (diffuse, specular) = (terms.diffuse * rad * s, terms.specular * rad * s);
            direct = direct + diffuse + specular;
            if !shares {
                return;
            }
            let light = m.map_or_else(|| l.clone(), |m| l.transformed(m));
            lights.push(LightShare {
                index: src.index,
                light,
                arriving: T::to_vec3(arriving),
                shadow,
                diffuse: T::to_vec3(diffuse),
                specular: T::to_vec3(specular),
                d: T::to_f64(terms.d) as f32,
                vis: T::to_f64(terms.vis) as f32,
                fresnel: T::to_vec3(terms.fresnel),
                sheen: T::to_vec3(terms.sheen * rad * s),
                coat: T::to_vec3(terms.coat * rad * s),
            });
        },
    );
    // The ambient light, and for pbr the environment, as the renderer reflects them.
    set.clear();
    set.ambient = ambient_light;
    set.env = settings.environment.view();
    let (ambient_diffuse, ambient_specular) = if image_based {
        ambient_split::<T>(&set, surf, normal, v)
    } else {
        (zero, zero)
    };
    Lit {
        lights,
        direct,
        ambient_diffuse: ambient_diffuse * pt.occlusion,
        ambient_specular: ambient_specular * pt.occlusion,
    }
}
