//! Per-frame set-up: the lights of the frame, and for every instance its visibility (bounding
//! sphere against the frustum), shading mode, material parameters and raster state. Memory
//! is kept in [`FrameData`] from frame to frame.

use std::sync::Arc;

use glam::{Mat3, Mat4, Vec3, Vec4};

use super::prepare::{PreparedInstance, PreparedScene};
use super::settings::{Lights, Output, Settings};
use crate::mesh::TriMesh;
use crate::raster::{Blend, Cull, DepthCopy, DepthTest, DrawState, Stats};
use crate::scene::{
    AlphaMode, Light, Material, Slot, SlotOverride, Style, TextureSource, UvTransform,
};
use crate::shade::mode::{Base, Pass, Rays};
use crate::shade::stages::Program;
use crate::shade::{
    DrawParams, Fog, LightSet, LitLayout, PbrParams, Shading, SlotParams, Surface, TexView,
};
use crate::simd::KernelKind;
use crate::texture::{Procedural, ProceduralTexture, Sampler};

mod material;
pub use material::*;

/// One visible instance of this frame.
#[derive(Clone, Copy, Debug)]
pub(super) struct FrameInst {
    /// Index into [`PreparedScene::instances`].
    pub inst: u32,
    pub mesh: u32,
    /// Model -> clip (without the sub-pixel jitter of a supersampling pass).
    pub mvp: Mat4,
    pub world: Mat4,
    /// Model -> camera.
    pub model_view: Mat4,
    /// Cofactor normal matrix of `world` ([`crate::prepare::normal_matrix`]).
    pub normal: Mat3,
    /// `world` mirrors (det < 0): front faces are clockwise (`state.flip_winding`).
    pub mirrored: bool,
    pub state: DrawState,
    /// Index into [`FrameData::params`] (the draw id the shaders see).
    pub param: u32,
    pub mode: Shading,
    pub blend: bool,
    /// Distance from the eye to the bounding-sphere centre (for back-to-front sorting).
    pub distance: f32,
    /// The mesh has triangles (the triangle passes skip an instance without).
    pub tris: bool,
    /// The mesh has points or lines (drawn by the strokes pass).
    pub strokes: bool,
}

/// Per-frame memory, reused.
#[derive(Debug, Default)]
pub(super) struct FrameData {
    pub insts: Vec<FrameInst>,
    pub params: Vec<DrawParams>,
    /// Each draw's shading stages, parallel to `params` (entries beyond it are stale).
    pub programs: Vec<Program>,
    pub lights: LightSet,
    /// Per instance, the indices of the sources that reach it ([`DrawParams::lights`]).
    pub active: Vec<u32>,
    /// Blended instances in drawing order.
    pub order: Vec<u32>,
    /// The frame's fog, if on and valid.
    pub fog: Option<Fog>,
    /// Shadow casters outside the view frustum (filled only when a light casts shadows).
    pub casters: Vec<FrameInst>,
    /// Wireframe's saved depth.
    pub depth: DepthCopy,
    /// [`Settings::point_size`] and [`Settings::line_width`] of the frame.
    pub point_size: f32,
    pub line_width: f32,
    /// The section caps' colour (linear RGBA), when planes cut and caps are on.
    pub cap: Option<Vec4>,
    /// World -> clip of the frame (without a supersampling pass's jitter).
    pub view_proj: Mat4,
    /// The opaque surfaces the transmissive ones see through, made by the pass that draws
    /// them (`KHR_materials_transmission`).
    pub backdrop: Option<crate::shade::Backdrop>,
}

/// Calls `f` with every light of the frame and the matrix that moves it into the world
/// (`None`: it is in world space already): `scene_lights`, or if there are none the default
/// rig attached to the camera when `rig` ([`Settings::default_rig`]), or the custom lights
/// of `lights`.
pub(crate) fn for_each_light(
    scene_lights: &[Light],
    lights: &Lights,
    rig: bool,
    camera_to_world: Mat4,
    mut f: impl FnMut(&Light, Option<Mat4>),
) {
    match lights {
        Lights::Auto if scene_lights.is_empty() && !rig => {}
        Lights::Auto if scene_lights.is_empty() => {
            let rig = Light::default_rig_array(glam::Mat3::from_mat4(camera_to_world));
            rig.iter().for_each(|l| f(l, None));
        }
        Lights::Auto => scene_lights.iter().for_each(|l| f(l, None)),
        Lights::Custom {
            lights,
            follow_camera,
        } => {
            let m = follow_camera.then_some(camera_to_world);
            lights.iter().for_each(|l| f(l, m));
        }
    }
}

/// Fills `set` (cleared first) with the lights of a frame whose camera-to-world matrix is
/// `camera_to_world` (see [`Lights`]; `rig`: [`Settings::default_rig`]); shadow maps are
/// left to the renderer.
pub fn frame_lights(
    scene_lights: &[Light],
    lights: &Lights,
    rig: bool,
    camera_to_world: Mat4,
    set: &mut LightSet,
) {
    set.clear();
    let mut index = 0;
    for_each_light(scene_lights, lights, rig, camera_to_world, |l, m| {
        set.push(l, m, index);
        index += 1;
    });
}

/// The Phong constants the renderer uses for material `m` (shininess clamped to 1..=2000,
/// 1 if not finite; non-finite colours become zero).
#[must_use]
pub fn material_surface(m: &Material) -> Surface {
    let fin = |v: Vec3| if v.is_finite() { v } else { Vec3::ZERO };
    Surface {
        diffuse: Vec3::ONE,
        specular: fin(m.specular),
        ambient: fin(m.ambient),
        shininess: if m.shininess.is_finite() {
            m.shininess.clamp(1.0, 2000.0)
        } else {
            1.0
        },
        pbr: None,
    }
}

/// The reflection constants of material `m` in the `pbr` mode: [`material_surface`] with
/// the metallic-roughness parameters (factors clamped to [0, 1], 1 if not finite, as glTF's
/// defaults). A material not authored that way (an OBJ forced into `pbr`) is a dielectric
/// whose roughness matches its Phong exponent (`n = 2 / α² - 2`, the inverse of
/// `phong_from_pbr` in the glTF loader).
#[must_use]
pub fn pbr_surface(m: &Material) -> Surface {
    // A factor in [0, 1], `default` if not finite; a number at least `lo`, likewise; a
    // colour in [0, 1] per channel, likewise.
    let unit = |v: f32, default: f32| {
        if v.is_finite() {
            v.clamp(0.0, 1.0)
        } else {
            default
        }
    };
    let at_least = |v: f32, lo: f32, default: f32| if v.is_finite() { v.max(lo) } else { default };
    let colour = |c: Vec3, default: Vec3| {
        if c.is_finite() {
            c.clamp(Vec3::ZERO, Vec3::ONE)
        } else {
            default
        }
    };
    let params = match &m.pbr {
        Some(p) => {
            let (f0, f90) = p.dielectric_fresnel();
            // The layers' factors: 0 (no layer) if not finite.
            let layer = |v: f32| unit(v, 0.0);
            PbrParams {
                metallic: unit(m.metallic, 1.0),
                roughness: unit(m.roughness, 1.0),
                f0,
                f90,
                f0_tint: p.f0_tint(),
                clearcoat: layer(p.clearcoat),
                clearcoat_roughness: layer(p.clearcoat_roughness),
                sheen_color: colour(p.sheen_color, Vec3::ZERO),
                sheen_roughness: layer(p.sheen_roughness),
                iridescence: layer(p.iridescence),
                iridescence_ior: at_least(p.iridescence_ior, 1.0, 1.3),
                iridescence_thickness: p.iridescence_thickness.map(|d| at_least(d, 0.0, 0.0)),
                anisotropy: layer(p.anisotropy),
                anisotropy_rotation: at_least(p.anisotropy_rotation, f32::MIN, 0.0),
                transmission: layer(p.transmission),
                thickness: at_least(p.thickness, 0.0, 0.0),
                attenuation_distance: if p.attenuation_distance > 0.0 {
                    p.attenuation_distance
                } else {
                    f32::INFINITY
                },
                attenuation_color: colour(p.attenuation_color, Vec3::ONE),
                dispersion: at_least(p.dispersion, 0.0, 0.0),
                ior: at_least(p.ior, 0.0, 1.5),
                diffuse_transmission: layer(p.diffuse_transmission),
                diffuse_transmission_color: colour(p.diffuse_transmission_color, Vec3::ONE),
            }
        }
        None => {
            let n = material_surface(m).shininess;
            PbrParams {
                metallic: unit(m.metallic, 0.0),
                roughness: (2.0 / (n + 2.0)).sqrt().sqrt(),
                ..PbrParams::default()
            }
        }
    };
    Surface {
        pbr: Some(params),
        ..material_surface(m)
    }
}

/// The world-space bounding sphere of an instance (centre, radius; radius scaled by the
/// world matrix's largest axis scale).
pub(crate) fn world_sphere(world: Mat4, center: Vec3, radius: f32) -> (Vec3, f32) {
    let s = world
        .x_axis
        .truncate()
        .length()
        .max(world.y_axis.truncate().length())
        .max(world.z_axis.truncate().length());
    (world.transform_point3(center), radius * s)
}

/// Appends to `active` the sources of `lights` that can reach the sphere, returning the
/// range; counts the others in `stats`.
pub(crate) fn active_lights(
    lights: &LightSet,
    center: Vec3,
    radius: f32,
    active: &mut Vec<u32>,
    stats: &mut Stats,
) -> (u32, u32) {
    let start = active.len() as u32;
    for (i, s) in lights.sources.iter().enumerate() {
        if s.reaches(center, radius) {
            active.push(i as u32);
        } else {
            stats.lights_skipped += 1;
        }
    }
    (start, active.len() as u32)
}

/// How an instance is drawn and what its material gives the shaders: decided here once,
/// for the renderer ([`resolve`]) and the f64 reference ([`crate::quality`]).
#[derive(Clone, Copy, Debug)]
pub struct Policy {
    pub mode: Shading,
    /// The mode reads every map: textured, the tangent-normals view (which shows what the
    /// normal and bump maps do) and `pbr`. The other per-pixel modes read the gloss map
    /// only.
    pub textured: bool,
    pub pbr: bool,
    /// The base colour (RGBA, linear): the material's, its glTF base colour in `pbr`, white
    /// for the UV checker (whose grid replaces it).
    pub base: Vec4,
    pub surface: Surface,
    /// `KHR_materials_unlit` in `pbr`.
    pub unlit: bool,
}

impl Policy {
    /// The policy for material `m` drawn with style `style` when the settings force
    /// `shading` (or not), `mapped` telling whether any map of the textured mode is usable
    /// on the mesh: a forced mode wins, then the style; glTF materials are drawn as
    /// authored (`pbr`), a model with usable textures textured, anything else Phong.
    pub fn new(shading: Option<Shading>, style: Style, m: &Material, mapped: bool) -> Self {
        let mode = match (shading, style) {
            (Some(m), _) => m,
            (None, Style::Wireframe) => Shading::Wireframe,
            (None, Style::Flat) => Shading::Flat,
            (None, Style::Inherit) if m.pbr.is_some() => Shading::Pbr,
            (None, Style::Inherit) if mapped => Shading::Textured,
            (None, Style::Inherit) => Shading::Phong,
        };
        let pbr = mode.mode().base == Base::Pbr;
        let finite_or_white = |c: Vec4| if c.is_finite() { c } else { Vec4::ONE };
        Self {
            mode,
            textured: mode.mode().maps,
            pbr,
            base: match mode.mode().base {
                Base::UvGrid => Vec4::ONE,
                Base::Pbr => finite_or_white(m.base_color),
                Base::Material => finite_or_white(phong_base(m)),
            },
            surface: if pbr {
                pbr_surface(m)
            } else {
                material_surface(m)
            },
            unlit: pbr && m.pbr.is_some_and(|p| p.unlit),
        }
    }
}

impl FrameInst {
    /// Instance `k` placed by `world`, resolved as `r`; no parameters, vertex colours or
    /// distance yet. A copy of an instanced mesh (`copy`) has its own normal matrix and
    /// winding; otherwise the instance's are used.
    fn new(
        k: usize,
        inst: &PreparedInstance,
        world: Mat4,
        view: Mat4,
        vp: Mat4,
        r: &Resolved,
        copy: bool,
    ) -> Self {
        let (normal, mirrored) = if copy {
            (
                crate::prepare::normal_matrix(world),
                world.determinant() < 0.0,
            )
        } else {
            (inst.normal, inst.mirrored)
        };
        Self {
            inst: k as u32,
            mesh: inst.mesh as u32,
            mvp: vp * world,
            world,
            model_view: view * world,
            normal,
            mirrored,
            state: DrawState {
                flip_winding: mirrored,
                ..r.state
            },
            param: 0,
            mode: r.mode,
            blend: r.blend,
            distance: 0.0,
            tris: true,
            strokes: false,
        }
    }
}

/// Fills `fd` for one frame: lights, visible instances and their parameters. Counts
/// objects culled by their bounding sphere into `stats`. Builds each draw's shading stages for
/// `kernel`.
#[allow(clippy::too_many_arguments)]
pub(super) fn set_up(
    fd: &mut FrameData,
    scene: &PreparedScene,
    settings: &Settings,
    view: Mat4,
    vp: Mat4,
    eye: Vec3,
    kernel: KernelKind,
    stats: &mut Stats,
) {
    frame_lights(
        scene.lights(),
        &settings.lights,
        settings.default_rig(scene.scene()),
        view.inverse(),
        &mut fd.lights,
    );
    fd.lights.single_scatter = settings.single_scatter;
    if settings.rays() == Rays::Whitted {
        // Whitted's model sends a shadow ray to every light (the textbook's §9.6.1).
        for s in &mut fd.lights.sources {
            s.casts = s.kind.can_shadow();
        }
    }
    fd.fog = settings.fog.filter(Fog::is_valid);
    fd.cap = settings
        .sections
        .cap
        .filter(|c| !settings.sections.is_empty() && c.is_finite())
        .map(|c| c.clamp(Vec3::ZERO, Vec3::ONE).extend(1.0));
    fd.point_size = settings.point_size;
    fd.line_width = settings.line_width;
    fd.view_proj = vp;
    fd.backdrop = None;
    let shadows = settings.output == Output::Shaded && fd.lights.sources.iter().any(|s| s.casts);
    fd.casters.clear();
    fd.insts.clear();
    fd.params.clear();
    fd.active.clear();
    let planes = frustum_planes(vp);
    for (k, inst) in scene.instances.iter().enumerate() {
        let tri = &scene.meshes[inst.mesh].tri;
        let world = match (inst.ground, &settings.ground) {
            (true, Some(g)) => scene.ground_world(g),
            (true, None) => continue,
            (false, _) if !inst.drawable || settings.hidden.contains(k) => continue,
            (false, _) => inst.world,
        };
        let (center, radius) = match &inst.copies {
            Some(c) => c.all,
            None => (tri.center, tri.radius),
        };
        if radius < 0.0 || !sphere_visible(&planes, world, center, radius) {
            if shadows && radius >= 0.0 {
                let r = resolve(scene, settings, inst);
                // Drawn only into shadow maps: no parameters, no varyings.
                for c in 0..inst.copy_count() {
                    let placed = inst.placement(c);
                    let copy = inst.copies.is_some();
                    fd.casters
                        .push(FrameInst::new(k, inst, placed, view, vp, &r, copy));
                }
            }
            let copies = inst.copy_count() as u64;
            stats.objects_culled += copies;
            stats.culled_frustum += tri.triangles.len() as u64 * copies;
            stats.triangles_in += tri.triangles.len() as u64 * copies;
            continue;
        }
        let mut r = resolve(scene, settings, inst);
        if let (true, Some(g)) = (inst.ground, &settings.ground) {
            let c = if g.color.is_finite() {
                g.color
            } else {
                Vec3::splat(0.5)
            };
            r.params.base = c.extend(1.0);
        }
        let (c, radius) = world_sphere(world, center, radius);
        r.params.lights = active_lights(&fd.lights, c, radius, &mut fd.active, stats);
        for t in r.params.maps() {
            let mipmapped = t.sampler.filter.mipmapped();
            if let (true, TextureSource::Image(texture)) = (mipmapped, &t.source) {
                // Built once (a no-op afterwards), in parallel, so no tile waits for it.
                texture.prepare_mips();
            }
        }
        let param = fd.params.len() as u32;
        let one = |placed: Mat4, copy: bool| FrameInst {
            param,
            distance: (placed.transform_point3(tri.center) - eye).length(),
            tris: !tri.triangles.is_empty(),
            strokes: !tri.points.is_empty() || !tri.lines.is_empty(),
            ..FrameInst::new(k, inst, placed, view, vp, &r, copy)
        };
        match &inst.copies {
            None => fd.insts.push(one(world, false)),
            Some(copies) => {
                // Each copy against the frustum in the instance's frame (where its sphere
                // is), one shared parameter block.
                let mt = world.transpose();
                let local = planes.map(|p| {
                    let q = mt * p;
                    (q, q.truncate().length())
                });
                let triangles = tri.triangles.len() as u64;
                for (m, s) in copies.matrices.iter().zip(copies.spheres.iter()) {
                    let visible = local
                        .iter()
                        .all(|(q, len)| q.truncate().dot(s.truncate()) + q.w >= -s.w * len);
                    let placed = world * *m;
                    if visible {
                        fd.insts.push(one(placed, true));
                    } else {
                        if shadows {
                            fd.casters
                                .push(FrameInst::new(k, inst, placed, view, vp, &r, true));
                        }
                        stats.objects_culled += 1;
                        stats.culled_frustum += triangles;
                        stats.triangles_in += triangles;
                    }
                }
            }
        }
        fd.params.push(r.params);
    }
    fd.order.clear();
    fd.order.extend(
        fd.insts
            .iter()
            .enumerate()
            .filter(|(_, i)| i.blend && settings.output == Output::Shaded)
            .map(|(k, _)| k as u32),
    );
    // The environment only when something reads it (a `pbr` draw, or the background): the
    // built-in studio is prefiltered on first use (about 0.2 s), which a Phong render of
    // an OBJ must not pay.
    let wanted = settings.env_background.is_some() && settings.output == Output::Shaded
        || fd
            .params
            .iter()
            .any(|p| p.surface.pbr.is_some() && !p.unlit);
    fd.lights.env = if wanted {
        settings.environment.view()
    } else {
        None
    };
    if fd.programs.len() < fd.params.len() {
        fd.programs.resize_with(fd.params.len(), Program::default);
    }
    let fog = fd.fog.is_some();
    for (prog, d) in fd.programs.iter_mut().zip(&fd.params) {
        prog.build(d, d.active(&fd.active), fog, kernel);
    }
    let insts = &fd.insts;
    // Back to front; unstable sort allocates nothing, ties broken by instance order.
    fd.order.sort_unstable_by(|&a, &b| {
        let (a, b) = (&insts[a as usize], &insts[b as usize]);
        b.distance.total_cmp(&a.distance).then(a.inst.cmp(&b.inst))
    });
}

/// Whether a model-space bounding sphere may be inside the frustum. The planes are taken to
/// model space (p' = M^T p), where the sphere is exact, so shear and non-uniform scale in the
/// world matrix cannot make a visible object disappear.
fn sphere_visible(planes: &[Vec4; 6], world: Mat4, center: Vec3, radius: f32) -> bool {
    let mt = world.transpose();
    planes.iter().all(|p| {
        let q = mt * *p;
        q.truncate().dot(center) + q.w >= -radius * q.truncate().length()
    })
}

/// The six frustum planes (a, b, c, d) with a·x + d >= 0 inside, normalised, from a
/// view-projection matrix in this crate's clip convention (0 <= z <= w).
fn frustum_planes(vp: Mat4) -> [Vec4; 6] {
    let (r0, r1, r2, r3) = (vp.row(0), vp.row(1), vp.row(2), vp.row(3));
    [r3 + r0, r3 - r0, r3 + r1, r3 - r1, r3 - r2, r2].map(|p| {
        let l = p.truncate().length();
        if l > 0.0 && l.is_finite() {
            p / l
        } else {
            Vec4::new(0.0, 0.0, 0.0, 1.0)
        }
    })
}
