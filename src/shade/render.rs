//! The renderer: camera and lights for a scene, object culling, per-instance vertex stage,
//! and the passes (opaque by mode, wireframe, then blended back to front).

use std::sync::Arc;

use glam::{Mat3, Mat4, Vec3, Vec4};
use rayon::prelude::*;

use super::lighting::{LightSet, Surface};
use super::passes::{draw_group, draw_wireframe, Ctx};
use super::shaders::DrawParams;
use super::Shading;
use crate::mesh::TriMesh;
use crate::raster::{Blend, Cull, DrawState, Framebuffer, Stats, Target};
use crate::scene::{AlphaMode, Camera, Light, Scene, Style};
use crate::texture::{Filter, Texture};

/// Per-mesh render data, built once per scene and reused for every frame.
#[derive(Clone, Debug, Default)]
pub struct Prepared {
    pub meshes: Vec<TriMesh>,
}

impl Prepared {
    /// Triangulates every mesh (in parallel).
    #[must_use]
    pub fn new(scene: &Scene) -> Self {
        Self {
            meshes: scene.meshes.par_iter().map(|m| m.triangulate()).collect(),
        }
    }
}

/// What to render.
#[derive(Clone, Debug)]
pub struct RenderOptions {
    pub width: u32,
    pub height: u32,
    /// Forces one mode on every instance; `None` = each instance's style, else Phong.
    pub shading: Option<Shading>,
    /// `None` = [`default_camera`].
    pub camera: Option<Camera>,
    /// Applied to meshes that have UVs but no base-colour texture.
    pub texture: Option<Arc<Texture>>,
    /// Linear RGBA.
    pub background: Vec4,
    /// Draw every material double-sided: no back-face culling, back faces lit from behind.
    pub double_sided: bool,
    /// Sub-pixel bits of the vertex snap (see [`DrawState::subpixel_bits`]); the default is
    /// the rasterizer's full [`crate::raster::SUBPIXEL_BITS`].
    pub subpixel_bits: u8,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            width: 1280,
            height: 720,
            shading: None,
            camera: None,
            texture: None,
            background: Vec4::new(0.018, 0.02, 0.026, 1.0),
            double_sided: false,
            subpixel_bits: crate::raster::SUBPIXEL_BITS as u8,
        }
    }
}

/// A rendered frame, still in the rasterizer's tiled form.
#[derive(Clone, Debug)]
pub struct Frame {
    pub target: Target,
    pub stats: Stats,
    /// The camera actually used.
    pub camera: Camera,
}

/// The default camera: the scene's bounding sphere framed from a three-quarter view.
#[must_use]
pub fn default_camera(scene: &Scene, aspect: f32) -> Camera {
    match scene.bounds() {
        Some((lo, hi)) => Camera::frame_box(lo, hi, aspect, 35.0, 25.0),
        None => Camera::default(),
    }
}

/// One visible instance, ready for the vertex stage.
pub(super) struct Inst<'a> {
    pub tri: &'a TriMesh,
    pub world: Mat4,
    pub normal: Mat3,
    pub mvp: Mat4,
    pub view: Mat4,
    pub state: DrawState,
    pub id: u32,
    pub mode: Shading,
    pub textured: bool,
    pub blend: bool,
    /// Distance from the eye to the bounding-sphere centre (for back-to-front sorting).
    pub distance: f32,
}

impl Frame {
    /// The row-major linear-light image.
    #[must_use]
    pub fn image(&self) -> Framebuffer {
        self.target.resolve()
    }

    /// 8-bit sRGB RGB, row-major, ready for a PNG.
    #[must_use]
    pub fn srgb8(&self) -> Vec<u8> {
        self.target.to_srgb8()
    }
}

/// Renders `scene` (whose meshes were prepared into `prepared`) on the current rayon pool.
#[must_use]
pub fn render(scene: &Scene, prepared: &Prepared, opts: &RenderOptions) -> Frame {
    let mut target = Target::new(opts.width, opts.height, opts.background);
    let (stats, camera) = render_into(&mut target, scene, prepared, opts);
    Frame {
        target,
        stats,
        camera,
    }
}

/// Renders into an existing target (cleared first, resized if needed), so an interactive
/// viewer or a benchmark reuses its tile memory from frame to frame.
pub fn render_into(
    target: &mut Target,
    scene: &Scene,
    prepared: &Prepared,
    opts: &RenderOptions,
) -> (Stats, Camera) {
    let (w, h) = (opts.width.max(1), opts.height.max(1));
    if (target.width, target.height) != (w, h) {
        *target = Target::new(w, h, opts.background);
    } else {
        target.clear(opts.background);
    }
    let camera = opts
        .camera
        .clone()
        .unwrap_or_else(|| default_camera(scene, w as f32 / h as f32));
    let view = camera.view();
    let vp = camera.projection(w as f32 / h as f32) * view;
    let lights = if scene.lights.is_empty() {
        LightSet::new(&Light::default_rig(glam::Mat3::from_mat4(view.inverse())))
    } else {
        LightSet::new(&scene.lights)
    };
    let mut stats = Stats::default();
    let mut params = Vec::new();
    let mut insts = Vec::new();
    let planes = frustum_planes(vp);
    for inst in &scene.instances {
        let Some(tri) = prepared.meshes.get(inst.mesh) else {
            continue;
        };
        let Some(mesh) = scene.meshes.get(inst.mesh) else {
            continue;
        };
        if tri.triangles.is_empty() || !inst.world.is_finite() {
            continue;
        }
        if tri.radius < 0.0 || !sphere_visible(&planes, inst.world, tri.center, tri.radius) {
            stats.objects_culled += 1;
            stats.culled_frustum += tri.triangles.len() as u64;
            stats.triangles_in += tri.triangles.len() as u64;
            continue;
        }
        let material = scene.material_of(mesh);
        let texture = material
            .base_color_texture
            .and_then(|t| scene.textures.get(t.texture).cloned())
            .or_else(|| opts.texture.clone())
            .filter(|_| tri.uvs.is_some());
        let mode = match (opts.shading, inst.style) {
            (Some(m), _) => m,
            (None, Style::Wireframe) => Shading::Wireframe,
            (None, Style::Flat) => Shading::Flat,
            // A model with a texture is shown with it unless a mode is forced.
            (None, Style::Inherit) if texture.is_some() => Shading::Textured,
            (None, Style::Inherit) => Shading::Phong,
        };
        let debug = matches!(mode, Shading::Normals | Shading::Depth | Shading::Uv);
        let blend = material.alpha_mode == AlphaMode::Blend && !debug && mode != Shading::Wireframe;
        let double_sided = material.double_sided || opts.double_sided;
        let state = DrawState {
            cull: if double_sided { Cull::None } else { Cull::Back },
            depth_write: !blend,
            blend: if blend { Blend::Alpha } else { Blend::Replace },
            flip_winding: inst.world.determinant() < 0.0,
            subpixel_bits: opts.subpixel_bits,
            ..DrawState::opaque()
        };
        let m = &*material;
        params.push(DrawParams {
            base: if m.base_color.is_finite() {
                m.base_color
            } else {
                Vec4::ONE
            },
            surface: Surface {
                diffuse: Vec3::ONE,
                specular: m.specular,
                ambient: m.ambient,
                shininess: if m.shininess.is_finite() {
                    m.shininess.clamp(1.0, 2000.0)
                } else {
                    1.0
                },
            },
            texture: texture.clone(),
            alpha: if debug {
                AlphaMode::Opaque
            } else {
                m.alpha_mode
            },
            double_sided,
        });
        let center = inst.world.transform_point3(tri.center);
        insts.push(Inst {
            tri,
            world: inst.world,
            normal: normal_matrix(inst.world),
            mvp: vp * inst.world,
            view: view * inst.world,
            state,
            id: (params.len() - 1) as u32,
            mode,
            textured: mode == Shading::Textured && texture.is_some(),
            blend,
            distance: (center - camera.eye).length(),
        });
    }

    prepare_mips(&insts, &params);
    let ctx = Ctx {
        params: &params,
        lights: &lights,
        eye: camera.eye,
        camera: &camera,
    };
    let (blended, opaque): (Vec<&Inst>, Vec<&Inst>) = insts.iter().partition(|i| i.blend);
    let solid: Vec<&Inst> = opaque
        .iter()
        .copied()
        .filter(|i| i.mode != Shading::Wireframe)
        .collect();
    draw_group(target, &solid, &ctx, &mut stats);
    let wire: Vec<&Inst> = opaque
        .iter()
        .copied()
        .filter(|i| i.mode == Shading::Wireframe)
        .collect();
    draw_wireframe(target, &wire, &ctx, &mut stats);
    let mut blended = blended;
    blended.sort_by(|a, b| b.distance.total_cmp(&a.distance));
    for inst in blended {
        draw_group(target, &[inst], &ctx, &mut stats);
    }
    (stats, camera)
}

/// Builds the mip chains of the mipmapped textures drawn by textured instances (each once;
/// a no-op after the first frame), so that no tile of the fill waits for one.
fn prepare_mips(insts: &[Inst], params: &[DrawParams]) {
    let mut seen: Vec<&Arc<Texture>> = Vec::new();
    for i in insts.iter().filter(|i| i.textured) {
        if let Some(t) = &params[i.id as usize].texture {
            if t.sampler.filter == Filter::Trilinear && !seen.iter().any(|s| Arc::ptr_eq(s, t)) {
                seen.push(t);
                t.prepare_mips();
            }
        }
    }
}

/// Transforms normals of a model -> world matrix: the cofactor matrix of its 3x3 part, which
/// equals det * (M^-1)^T and stays defined for singular matrices (a flattened mesh keeps the
/// normal of its plane); the sign of the determinant keeps mirrored normals outward.
fn normal_matrix(world: Mat4) -> Mat3 {
    let m = Mat3::from_mat4(world);
    let cof = Mat3::from_cols(
        m.y_axis.cross(m.z_axis),
        m.z_axis.cross(m.x_axis),
        m.x_axis.cross(m.y_axis),
    );
    if m.determinant() < 0.0 {
        -cof
    } else {
        cof
    }
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
