//! Per-frame set-up: the lights of the frame, and for every instance its visibility (bounding
//! sphere against the frustum), shading mode, material parameters and raster state. Memory
//! is kept in [`FrameData`] from frame to frame.

use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};

use super::prepare::{PreparedInstance, PreparedScene};
use super::settings::{Lights, Output, Settings};
use crate::mesh::TriMesh;
use crate::raster::{Blend, Cull, DepthCopy, DepthTest, DrawState, Stats};
use crate::scene::{AlphaMode, Light, Material, Style, TextureSlot};
use crate::shade::{DrawParams, Fog, LightSet, LitLayout, Shading, SlotParams, Surface};
use crate::texture::{Filter, Texture};

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
    pub state: DrawState,
    /// Index into [`FrameData::params`] (the draw id the shaders see).
    pub param: u32,
    pub mode: Shading,
    pub blend: bool,
    /// Distance from the eye to the bounding-sphere centre (for back-to-front sorting).
    pub distance: f32,
}

/// Per-frame memory, reused.
#[derive(Debug, Default)]
pub(super) struct FrameData {
    pub insts: Vec<FrameInst>,
    pub params: Vec<DrawParams>,
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
}

/// Calls `f` with every light of the frame and the matrix that moves it into the world
/// (`None`: it is in world space already): `scene_lights`, or the default rig attached to
/// the camera if there are none, or the custom lights of `lights`.
pub(crate) fn for_each_light(
    scene_lights: &[Light],
    lights: &Lights,
    camera_to_world: Mat4,
    mut f: impl FnMut(&Light, Option<Mat4>),
) {
    match lights {
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
/// `camera_to_world` (see [`Lights`]); shadow maps are left to the renderer.
pub fn frame_lights(
    scene_lights: &[Light],
    lights: &Lights,
    camera_to_world: Mat4,
    set: &mut LightSet,
) {
    set.clear();
    let mut index = 0;
    for_each_light(scene_lights, lights, camera_to_world, |l, m| {
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

/// How one instance is drawn under `settings`: its material parameters, mode and state.
pub(crate) struct Resolved {
    pub params: DrawParams,
    pub mode: Shading,
    pub blend: bool,
    pub state: DrawState,
}

/// A slot's texture if the mesh can sample it: the texture exists and the mesh has the UV
/// set the slot reads.
fn usable<'a>(
    scene: &'a PreparedScene,
    tri: &TriMesh,
    slot: Option<&TextureSlot>,
) -> Option<(TextureSlot, &'a Arc<Texture>)> {
    let slot = slot?;
    tri.uv_set(slot.uv_set)?;
    let texture = scene.scene().textures.get(slot.texture)?;
    Some((*slot, texture))
}

/// Resolves an instance's material (with the settings' overrides) and mode.
pub(crate) fn resolve(
    scene: &PreparedScene,
    settings: &Settings,
    inst: &PreparedInstance,
) -> Resolved {
    let tri = &scene.meshes[inst.mesh].tri;
    let m = settings
        .materials
        .as_ref()
        .and_then(|ms| ms.get(inst.material))
        .unwrap_or(&scene.materials[inst.material]);
    // `--texture IMG` stands in for a material without a base-colour texture, read from UV
    // set 0 with the default sampler.
    let fallback = settings
        .texture
        .as_ref()
        .filter(|_| tri.uv_set(0).is_some())
        .map(|t| (TextureSlot::new(usize::MAX), t));
    let base_map = usable(scene, tri, m.base_color_texture.as_ref()).or(fallback);
    let normal_map =
        usable(scene, tri, m.normal_texture.as_ref()).filter(|_| tri.tangents.is_some());
    let occlusion = usable(scene, tri, m.occlusion_texture.as_ref());
    let emissive = finite_colour(m.emissive);
    let emissive_map =
        usable(scene, tri, m.emissive_texture.as_ref()).filter(|_| emissive != Vec3::ZERO);
    let mapped =
        base_map.is_some() || normal_map.is_some() || occlusion.is_some() || emissive_map.is_some();
    let mode = match (settings.shading, inst.style) {
        (Some(m), _) => m,
        (None, Style::Wireframe) => Shading::Wireframe,
        (None, Style::Flat) => Shading::Flat,
        // A model with textures is shown with them unless a mode is forced.
        (None, Style::Inherit) if mapped => Shading::Textured,
        (None, Style::Inherit) => Shading::Phong,
    };
    let debug = matches!(mode, Shading::Normals | Shading::Depth | Shading::Uv);
    let blend = m.alpha_mode == AlphaMode::Blend && !debug && mode != Shading::Wireframe;
    let double_sided = m.double_sided || settings.double_sided;
    let mut state = DrawState {
        cull: if double_sided { Cull::None } else { Cull::Back },
        depth_write: !blend,
        blend: if blend { Blend::Alpha } else { Blend::Replace },
        flip_winding: inst.mirrored,
        subpixel_bits: settings.subpixel_bits,
        ..DrawState::opaque()
    };
    if settings.output == Output::Overdraw {
        state = DrawState {
            depth_test: DepthTest::Always,
            depth_write: false,
            blend: Blend::Add,
            ..state
        };
    }
    let per_pixel = matches!(mode, Shading::Phong | Shading::Blinn | Shading::Textured);
    let textured = mode == Shading::Textured;
    let mut layout = LitLayout {
        color: tri.colors.is_some(),
        ..LitLayout::default()
    };
    // Each slot the mode samples gets the UV channel of its (set, transform); the gloss map
    // shows in every per-pixel mode, the other maps in the textured one.
    let mut params_of = |found: Option<(TextureSlot, &Arc<Texture>)>, on: bool| {
        let (slot, texture) = found.filter(|_| on)?;
        let uv_at = layout.channel(slot.uv_set, slot.transform)?;
        let mut sampler = slot.sampler;
        if let Some(f) = settings.filter {
            sampler.filter = f;
        }
        Some(SlotParams {
            texture: Arc::clone(texture),
            sampler,
            uv_at,
            scale: slot.scale,
        })
    };
    let base_map = params_of(base_map, textured);
    let gloss = params_of(usable(scene, tri, m.specular_texture.as_ref()), per_pixel);
    let normal_map = params_of(normal_map, textured);
    let occlusion = params_of(occlusion, textured);
    let emissive_map = params_of(emissive_map, textured);
    layout.tangent = normal_map.is_some();
    let mapped = [&base_map, &gloss, &normal_map, &occlusion, &emissive_map]
        .iter()
        .any(|m| m.is_some());
    let params = DrawParams {
        base: if m.base_color.is_finite() {
            m.base_color
        } else {
            Vec4::ONE
        },
        surface: material_surface(m),
        emissive: if debug { Vec3::ZERO } else { emissive },
        base_map,
        gloss,
        normal_map,
        occlusion,
        emissive_map,
        layout,
        mapped,
        blinn: matches!(mode, Shading::Blinn | Shading::Textured),
        alpha: if debug {
            AlphaMode::Opaque
        } else {
            m.alpha_mode
        },
        double_sided,
        lights: (0, 0),
    };
    Resolved {
        params,
        mode,
        blend,
        state,
    }
}

/// A colour with every non-finite or negative channel made zero.
fn finite_colour(c: Vec3) -> Vec3 {
    let f = |v: f32| if v.is_finite() { v.max(0.0) } else { 0.0 };
    Vec3::new(f(c.x), f(c.y), f(c.z))
}

impl FrameInst {
    /// Instance `k` of mesh `mesh` placed by `world`, resolved as `r`; no parameters,
    /// vertex colours or distance yet.
    fn new(k: usize, mesh: usize, world: Mat4, view: Mat4, vp: Mat4, r: &Resolved) -> Self {
        Self {
            inst: k as u32,
            mesh: mesh as u32,
            mvp: vp * world,
            world,
            model_view: view * world,
            state: r.state,
            param: 0,
            mode: r.mode,
            blend: r.blend,
            distance: 0.0,
        }
    }
}

/// Fills `fd` for one frame: lights, visible instances and their parameters. Counts
/// objects culled by their bounding sphere into `stats`.
pub(super) fn set_up(
    fd: &mut FrameData,
    scene: &PreparedScene,
    settings: &Settings,
    view: Mat4,
    vp: Mat4,
    eye: Vec3,
    stats: &mut Stats,
) {
    frame_lights(
        &scene.scene().lights,
        &settings.lights,
        view.inverse(),
        &mut fd.lights,
    );
    fd.fog = settings.fog.filter(Fog::is_valid);
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
            (false, _) if !inst.drawable => continue,
            (false, _) => inst.world,
        };
        if tri.radius < 0.0 || !sphere_visible(&planes, world, tri.center, tri.radius) {
            if shadows && tri.radius >= 0.0 {
                let r = resolve(scene, settings, inst);
                // Drawn only into shadow maps: no parameters, no varyings.
                fd.casters
                    .push(FrameInst::new(k, inst.mesh, world, view, vp, &r));
            }
            stats.objects_culled += 1;
            stats.culled_frustum += tri.triangles.len() as u64;
            stats.triangles_in += tri.triangles.len() as u64;
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
        let (c, radius) = world_sphere(world, tri.center, tri.radius);
        r.params.lights = active_lights(&fd.lights, c, radius, &mut fd.active, stats);
        for t in r.params.maps() {
            if t.sampler.filter == Filter::Trilinear {
                // Built once (a no-op afterwards), in parallel, so no tile waits for it.
                t.texture.prepare_mips();
            }
        }
        let center = world.transform_point3(tri.center);
        fd.insts.push(FrameInst {
            param: fd.params.len() as u32,
            distance: (center - eye).length(),
            ..FrameInst::new(k, inst.mesh, world, view, vp, &r)
        });
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
