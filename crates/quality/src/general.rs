//! The general reference: any scene, rendered in f64 with heavy supersampling, as the
//! ground truth the rasterizer's lit modes are measured against (`realist bench accuracy`
//! on a loaded model).
//!
//! What it computes, per pixel: the box-filtered average, in linear light, of
//! `samples` x `samples` stratified samples at `(x + (i + 0.5) / samples,
//! y + (j + 0.5) / samples)` (y down). Each sample sees the ideal of the lit modes:
//!
//! - *visibility* in f64, written independently of `raster`: every triangle's clip-space
//!   vertices `(x, y, z, w)` become homogeneous screen vectors `V_k = ((x + w) W/2,
//!   (w - y) H/2, w)`, and the perspective-correct barycentrics at a sample `p = (px, py, 1)`
//!   are `c = M^-1 p` normalised to sum 1, with `M = [V_0 V_1 V_2]` (homogeneous
//!   rasterization). The rows of `M^-1` are the edge functions `V_1 x V_2`, `V_2 x V_0`,
//!   `V_0 x V_1`; a sample is inside when all three are >= 0 (signs taken with `det M`), and
//!   `Σ c = 1 / w`, so the nearest surface is the one with the largest `Σ c`. The near and far
//!   planes are the clip-space planes `0 <= z <= w`, tested per sample on `z / w = Σ c_k z_k`;
//!   the triangle is clipped against them in homogeneous f64 only to bound the samples to
//!   visit. A triangle crossing `w = 0` therefore needs no special case, and no clipped
//!   vertex ever carries an interpolated attribute. Samples on an edge shared by two
//!   triangles are covered exactly once: the two edge functions are exact negatives of each
//!   other in floating point, and ties go to one side by the sign of the edge's gradient;
//! - *shading* in f64: world position and unit world normals (the cofactor normal matrix,
//!   as the renderer does) interpolated with those barycentrics, the normal renormalised and
//!   flipped on back faces, then the equation of [`crate::shade::illuminate`]: ambient
//!   `g_amb K_a K_d`, Lambert, Phong `R·V` or (with `blinn`) Blinn `N·H` highlights, no
//!   specular term when `K_s = 0`, shininess clamped to 1..=2000;
//! - `K_d` = material base colour (white if not finite) x interpolated vertex colour x the
//!   base-colour texture, sampled in f64 with the texture's wrap modes and reconstruction
//!   (nearest, or bilinear on the base level for bilinear and trilinear textures) and the
//!   exact sRGB decode: the heavy supersampling does the filtering that mipmaps approximate;
//! - *alpha*: `Opaque` forces alpha 1, `Mask` discards fragments below the cutoff (before
//!   they can hide anything), `Blend` fragments in front of the opaque surface are sorted
//!   by exact depth per sample and composited back to front. The renderer approximates this
//!   last ideal by drawing blended instances sorted by the distance of their bounding
//!   spheres, each in triangle order, so interpenetrating or self-overlapping blended
//!   geometry differs from the reference by design.
//!
//! It reproduces the renderer's inputs, not its arithmetic: the camera (`opts.camera`, else
//! [`default_camera`]) with view and projection rebuilt in f64 from its fields, the scene's
//! lights or [`Light::default_rig`] when it has none, back faces culled unless the material
//! or `opts.double_sided` says double-sided, winding flipped under a mirroring world matrix,
//! instances with a non-finite world matrix or a missing mesh skipped, triangles with a
//! non-finite vertex skipped. Textures are applied exactly when the renderer would pick the
//! `textured` mode for the instance (`opts.shading` is `None` with an inherited style, or
//! `Some(Textured)`): forced Phong or Blinn draw no texture, and neither does the reference.
//!
//! Limits:
//! - every instance is drawn lit per pixel, whatever its style or `opts.shading`: the
//!   reference of wireframe, flat, Gouraud or the debug views is not this one, so compare a
//!   render with a lit mode forced (`Some(Phong)` against `blinn = false`, `Some(Blinn)` or
//!   `Some(Textured)` against `blinn = true`; the renderer's default mode on a textured
//!   instance is Blinn);
//! - the box filter over a finite sample grid is the only anti-aliasing: at 8 x 8 samples a
//!   silhouette pixel's coverage is known to 1/64, and a texture minified by more than the
//!   sample spacing aliases like any point-sampled image;
//! - memory: the image is cut into bands (whole rows, or part of a row for very wide images)
//!   of at most [`BAND_SAMPLES`] samples, each processed by one rayon task with its own depth
//!   and triangle buffers (12 bytes a sample) plus its blended fragments (48 bytes each,
//!   as many as the blended depth complexity makes); the per-band triangle lists take
//!   8 bytes per triangle and band it touches. Requests above [`MAX_TOTAL_SAMPLES`] samples
//!   (minutes of work) are refused;
//! - no shadows: every light reaches every surface facing it. Shadow maps are measured
//!   against analytic shadow outlines in `tests/lighting.rs`; turn a scene's shadows off
//!   (or expect the difference) before comparing;
//! - polygons are split into triangles by [`crate::mesh::Mesh::triangulate`], as for the
//!   renderer: the triangulation is part of the input, not of what is measured.

use std::sync::OnceLock;

use glam::{DMat3, DMat4, DVec2, DVec3, DVec4};
use rayon::prelude::*;

use super::LinearImage;
use crate::mesh::TriMesh;
use crate::microfacet;
use crate::render::{default_camera, frame_lights, Policy, Shot};
use crate::scene::{AlphaMode, Material, Scene, Slot, SlotOverride, TextureSource, UvTransform};
use crate::shade::brdf::{self, Pbr};
use crate::shade::{illuminate, maps, Fog, LightSet, Surface, SurfaceAt};
use crate::texture::{
    Domain, Filter, ProceduralTexture, SamplePoint, Sampler, Texels, Texture, Wrap,
};

/// Largest number of samples per pixel side.
pub const MAX_SAMPLES: u32 = 64;
/// Largest `width * height * samples^2`.
pub const MAX_TOTAL_SAMPLES: u64 = 1 << 31;
/// Samples per band (one rayon task): 12 MB of per-sample buffers.
pub const BAND_SAMPLES: u64 = 1 << 20;

/// Why no reference was rendered.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ReferenceError {
    #[error("samples per pixel side must be 1..={MAX_SAMPLES}, got {0}")]
    Samples(u32),
    #[error("image size {width}x{height} has no pixels")]
    EmptyImage { width: u32, height: u32 },
    #[error(
        "{width}x{height} pixels at {samples}x{samples} samples is {total} samples, above the \
         limit of {MAX_TOTAL_SAMPLES}"
    )]
    TooLarge {
        width: u32,
        height: u32,
        samples: u32,
        total: u64,
    },
    #[error("camera '{name}' is unusable: {reason}")]
    Camera { name: String, reason: &'static str },
}

/// The reference image of `scene` as [`crate::render::render`] would draw it with `opts`
/// (camera, size, background, lights, materials, textures) in a lit mode, computed
/// independently in f64 with `samples` x `samples` stratified samples per pixel,
/// box-filtered in linear light; Blinn (`N·H`) highlights if `blinn`, else Phong (`R·V`).
/// Opaque surfaces replace the background (`opts.background`, RGB); see the module docs
/// for what is reproduced and what is not. Runs on the current rayon pool; the image does
/// not depend on its thread count.
///
/// # Errors
/// If `samples` is 0 or above [`MAX_SAMPLES`], the image is empty, the request exceeds
/// [`MAX_TOTAL_SAMPLES`], or the camera has non-finite fields, `near <= 0`, `far <= near`,
/// a field of view outside (0, 180) degrees, or its eye on its target.
pub fn reference(
    scene: &Scene,
    opts: &Shot,
    samples: u32,
    blinn: bool,
) -> Result<LinearImage, ReferenceError> {
    render(scene, opts, samples, blinn, BAND_SAMPLES, ENV_SAMPLES)
}

/// Samples per lobe with which [`reference`] integrates the environment over a `pbr`
/// surface point (see [`reference_env`]). With the 4 x 4 or more samples per pixel of a
/// typical comparison, each pixel averages 16 x that many directions per lobe.
pub const ENV_SAMPLES: u32 = 128;

/// [`reference`] with the image-based lighting of `pbr` surfaces integrated with
/// `env_samples` samples per lobe, or (0) by the renderer's own split sum.
///
/// Integrated, the environment (the scene's environment plus the ambient light as a
/// uniform one) is not looked up in the prefiltered chain, the BRDF table or the nine SH
/// coefficients; at each shading sample the reference sums, over `env_samples` GGX half
/// vectors and as many cosine-distributed directions (Hammersley points turned by an
/// offset hashed from the sample position, so neighbouring samples do not share a
/// pattern), with radiance read bilinearly from the full-resolution source in f64:
/// - `∫ F D Vis L NL dω` per lobe (the specular image-based term itself, not its split);
/// - `A = ∫ (1 - w) D Vis NL dω`, `B = ∫ w D Vis NL dω` with `w = (1 - VH)⁵` (the BRDF table);
/// - `E/π = (1/π) ∫ L NL dω` (the irradiance);
///
/// and combines them as the renderer does ([`crate::shade::brdf::ibl_fresnel`]: the
/// multiple-scattering term, the diffuse term getting the energy the specular one leaves).
/// The difference to the renderer is then the split-sum approximation, the prefiltering
/// and the SH truncation, nothing else.
///
/// # Errors
/// As [`reference`].
pub fn reference_env(
    scene: &Scene,
    opts: &Shot,
    samples: u32,
    blinn: bool,
    env_samples: u32,
) -> Result<LinearImage, ReferenceError> {
    render(scene, opts, samples, blinn, BAND_SAMPLES, env_samples)
}

/// [`reference`] with a given band size in samples (tests vary it).
fn render(
    scene: &Scene,
    opts: &Shot,
    samples: u32,
    blinn: bool,
    band_samples: u64,
    env_samples: u32,
) -> Result<LinearImage, ReferenceError> {
    let (width, height) = (opts.width, opts.height);
    if samples == 0 || samples > MAX_SAMPLES {
        return Err(ReferenceError::Samples(samples));
    }
    if width == 0 || height == 0 {
        return Err(ReferenceError::EmptyImage { width, height });
    }
    let total = u64::from(width) * u64::from(height) * u64::from(samples * samples);
    if total > MAX_TOTAL_SAMPLES {
        return Err(ReferenceError::TooLarge {
            width,
            height,
            samples,
            total,
        });
    }
    let view = View::new(scene, opts, samples, blinn, env_samples)?;
    let meshes: Vec<TriMesh> = scene.meshes.par_iter().map(|m| m.triangulate()).collect();
    let insts = instances(scene, opts, &meshes, &view);

    // Bands: whole rows when a row fits the budget, else parts of one row.
    let s2 = u64::from(samples * samples);
    let band_w = (band_samples / s2).clamp(1, u64::from(width)) as u32;
    let band_h = (band_samples / (s2 * u64::from(band_w))).clamp(1, u64::from(height)) as u32;
    let (bands_x, bands_y) = (width.div_ceil(band_w), height.div_ceil(band_h));
    let bands: Vec<Rect> = (0..bands_x * bands_y)
        .map(|i| {
            let (bx, by) = (i % bands_x, i / bands_x);
            Rect {
                x0: bx * band_w,
                y0: by * band_h,
                x1: ((bx + 1) * band_w).min(width),
                y1: ((by + 1) * band_h).min(height),
            }
        })
        .collect();

    // Bin every triangle, in submission order, into the bands its sample bounds touch.
    let mut bins: Vec<Vec<(u32, u32)>> = vec![Vec::new(); bands.len()];
    for (i, inst) in insts.iter().enumerate() {
        let bounds: Vec<Option<[i64; 4]>> = (0..inst.tri.triangles.len())
            .into_par_iter()
            .with_min_len(4096)
            .map(|t| setup(&view, inst, i as u32, t as u32).map(|g| g.bounds))
            .collect();
        let s = i64::from(samples);
        for (t, b) in bounds.into_iter().enumerate() {
            let Some([x0, x1, y0, y1]) = b else {
                continue;
            };
            let (px0, px1) = ((x0 / s) as u32, (x1 / s) as u32);
            let (py0, py1) = ((y0 / s) as u32, (y1 / s) as u32);
            for by in py0 / band_h..=py1 / band_h {
                for bx in px0 / band_w..=px1 / band_w {
                    bins[(by * bands_x + bx) as usize].push((i as u32, t as u32));
                }
            }
        }
    }

    let tiles: Vec<Vec<[f64; 3]>> = bands
        .par_iter()
        .zip(bins.par_iter())
        .map(|(r, bin)| band(&view, &insts, bin, *r))
        .collect();
    let mut rgb = vec![[0.0; 3]; width as usize * height as usize];
    for (r, tile) in bands.iter().zip(tiles) {
        let w = (r.x1 - r.x0) as usize;
        for (row, y) in (r.y0..r.y1).enumerate() {
            let o = y as usize * width as usize + r.x0 as usize;
            rgb[o..o + w].copy_from_slice(&tile[row * w..(row + 1) * w]);
        }
    }
    Ok(LinearImage { width, height, rgb })
}

/// A rectangle of pixels, `x0..x1` by `y0..y1`.
#[derive(Clone, Copy, Debug)]
struct Rect {
    x0: u32,
    y0: u32,
    x1: u32,
    y1: u32,
}

/// Frame-wide data: image and sampling, camera, lights.
struct View {
    width: u32,
    height: u32,
    samples: u32,
    /// Projection x view, f64.
    vp: DMat4,
    eye: DVec3,
    /// Unit view direction (depth fog).
    forward: DVec3,
    lights: LightSet,
    /// `lights` without the ambient light and the environment: what `illuminate` sums
    /// when the environment is integrated ([`reference_env`]).
    punctual: LightSet,
    /// Samples per lobe of the integrated environment (0: the split sum).
    env_samples: u32,
    fog: Option<Fog>,
    tone: crate::render::ToneMap,
    /// `2^exposure` ([`crate::render::Settings::exposure_scale`]).
    exposure: f64,
    background: DVec3,
    blinn: bool,
}

impl View {
    fn new(
        scene: &Scene,
        opts: &Shot,
        samples: u32,
        blinn: bool,
        env_samples: u32,
    ) -> Result<Self, ReferenceError> {
        let (w, h) = (opts.width, opts.height);
        let camera = opts
            .camera
            .clone()
            .unwrap_or_else(|| default_camera(scene, w as f32 / h as f32));
        let bad = |reason| ReferenceError::Camera {
            name: camera.name.clone(),
            reason,
        };
        let (eye, target, up) = (
            camera.eye.as_dvec3(),
            camera.target.as_dvec3(),
            camera.up.as_dvec3(),
        );
        let (yfov, near, far) = (
            f64::from(camera.yfov),
            f64::from(camera.near),
            f64::from(camera.far),
        );
        if !(eye.is_finite() && target.is_finite() && up.is_finite()) {
            return Err(bad("non-finite eye, target or up"));
        }
        if camera.ortho.is_some() {
            return Err(bad(
                "orthographic cameras are not supported by the reference",
            ));
        }
        if !(near > 0.0 && far > near && far.is_finite()) {
            return Err(bad("needs 0 < near < far < infinity"));
        }
        if !(yfov > 0.0 && yfov < std::f64::consts::PI) {
            return Err(bad("vertical field of view outside (0, 180) degrees"));
        }
        // View: right-handed, looking down -Z, as `Camera::view` (same fallback for an up
        // vector along the view direction).
        let fwd = target - eye;
        if fwd.length_squared() == 0.0 {
            return Err(bad("eye and target coincide"));
        }
        let up = if fwd.cross(up).length_squared() < 1e-12 * fwd.length_squared() {
            fwd.any_orthonormal_vector()
        } else {
            up
        };
        let f = fwd.normalize();
        let s = f.cross(up).normalize();
        let u = s.cross(f);
        if !s.is_finite() {
            return Err(bad("up vector is zero"));
        }
        let view = DMat4::from_cols(
            DVec4::new(s.x, u.x, -f.x, 0.0),
            DVec4::new(s.y, u.y, -f.y, 0.0),
            DVec4::new(s.z, u.z, -f.z, 0.0),
            DVec4::new(-s.dot(eye), -u.dot(eye), f.dot(eye), 1.0),
        );
        // Projection: reversed Z, z/w = 1 at w = near and 0 at w = far, w = distance in
        // front, as `Camera::projection` (image aspect, camera's vertical field of view).
        let zoom = 1.0 / (yfov * 0.5).tan();
        let aspect = f64::from(w) / f64::from(h);
        let a = near * far / (far - near);
        let b = -near / (far - near);
        let proj = DMat4::from_cols(
            DVec4::new(zoom / aspect, 0.0, 0.0, 0.0),
            DVec4::new(0.0, zoom, 0.0, 0.0),
            DVec4::new(0.0, 0.0, -b, -1.0),
            DVec4::new(0.0, 0.0, a, 0.0),
        );
        // Camera -> world: columns right, up, backwards, eye.
        let cam_to_world = DMat4::from_cols(
            s.extend(0.0),
            u.extend(0.0),
            (-f).extend(0.0),
            eye.extend(1.0),
        )
        .as_mat4();
        let mut lights = LightSet::default();
        frame_lights(
            &scene.lights,
            &opts.settings.lights,
            cam_to_world,
            &mut lights,
        );
        lights.env = opts.settings.environment.view();
        let punctual = LightSet {
            ambient: glam::Vec3::ZERO,
            env: None,
            ..lights.clone()
        };
        Ok(Self {
            width: w,
            height: h,
            samples,
            vp: proj * view,
            eye,
            forward: f,
            lights,
            punctual,
            env_samples,
            fog: opts.settings.fog.filter(Fog::is_valid),
            tone: opts.settings.tone,
            exposure: f64::from(opts.settings.exposure_scale()),
            background: opts.settings.background.truncate().as_dvec3(),
            blinn,
        })
    }
}

/// The image-based term of a `pbr` surface point, integrated ([`reference_env`]); `at` is
/// the sample position, which seeds the offset of the point sets.
fn environment(
    view: &View,
    s: &SurfaceAt<f64>,
    pb: &Pbr<f64>,
    n: DVec3,
    v: DVec3,
    at: (f64, f64),
) -> DVec3 {
    use std::f64::consts::PI;
    let g = view.lights.ambient.as_dvec3();
    let radiance = |l: DVec3| match &view.lights.env {
        Some(env) => g + env.radiance_f64(l),
        None => g,
    };
    let count = view.env_samples;
    // A Cranley-Patterson offset from the sample position (splitmix64 of its bits).
    let mut h = at.0.to_bits() ^ at.1.to_bits().rotate_left(29) ^ 0x9E37_79B9_7F4A_7C15;
    let mut next = || {
        h = h.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = h;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        (z ^ (z >> 31)) as f64 / u64::MAX as f64
    };
    let offset = (next(), next());
    let point = |i: u32| {
        let (a, b) = microfacet::hammersley(i, count);
        ((a + offset.0).fract(), (b + offset.1).fract())
    };
    let (t, b) = n.any_orthonormal_pair();
    let world = |d: DVec3| t * d.x + b * d.y + n * d.z;
    // E/π: cosine-distributed directions, pdf NL/π.
    let mut irradiance = DVec3::ZERO;
    for i in 0..count {
        let (u1, u2) = point(i);
        let (r, phi) = (u1.sqrt(), 2.0 * PI * u2);
        irradiance += radiance(world(DVec3::new(
            r * phi.cos(),
            r * phi.sin(),
            (1.0 - u1).sqrt(),
        )));
    }
    irradiance /= f64::from(count);
    // The specular lobe: GGX half vectors, pdf(l) = D NH / (4 VH), so the weight of
    // D Vis NL is g = 4 Vis NL VH / NH.
    let nv = n.dot(v).max(1e-4);
    let alpha = microfacet::alpha::<f64>(pb.roughness);
    let (mut a, mut bias) = (0.0, 0.0);
    let (mut spec_d, mut spec_m) = (DVec3::ZERO, DVec3::ZERO);
    for i in 0..count {
        let hv = world(microfacet::sample_h(point(i), alpha));
        let vh = v.dot(hv);
        let l = hv * (2.0 * vh) - v;
        let (nl, nh) = (n.dot(l), n.dot(hv));
        if vh <= 0.0 || nl <= 0.0 || nh <= 0.0 {
            continue;
        }
        let g = 4.0 * microfacet::smith_vis::<f64>(nl, nv, alpha) * nl * vh / nh;
        let w = microfacet::schlick_weight::<f64>(vh);
        a += (1.0 - w) * g;
        bias += w * g;
        let light = radiance(l) * g;
        spec_d += microfacet::schlick::<f64>(pb.f0, pb.f90, w) * light;
        spec_m += microfacet::schlick::<f64>(s.kd, 1.0, w) * light;
    }
    let k = 1.0 / f64::from(count);
    let (a, bias, spec_d, spec_m) = (a * k, bias * k, spec_d * k, spec_m * k);
    let (d_ss, d_ms) = brdf::ibl_fresnel::<f64>(pb.f0, pb.f90, a, bias);
    let (_, m_ms) = brdf::ibl_fresnel::<f64>(s.kd, 1.0, a, bias);
    let diel = s.kd * (DVec3::ONE - d_ss - d_ms) * irradiance + spec_d + d_ms * irradiance;
    let metal = spec_m + m_ms * irradiance;
    diel * (1.0 - pb.metallic) + metal * pb.metallic
}

/// How a material's alpha is used, cutoff in f64.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Alpha {
    Opaque,
    Mask(f64),
    Blend,
}

/// One drawable instance: matrices in f64 and its material resolved.
struct Inst<'a> {
    tri: &'a TriMesh,
    world: DMat4,
    /// Cofactor of the world matrix's 3x3 part, negated for mirroring matrices.
    normal: DMat3,
    mvp: DMat4,
    flip: bool,
    cull: bool,
    base: DVec4,
    /// The material's Phong constants, as the renderer resolves them.
    surface: Surface,
    alpha: Alpha,
    /// Emitted light (linear RGB), added after lighting.
    emissive: DVec3,
    /// Base-colour texture (textured mode).
    texture: Option<RefSlot<'a>>,
    /// Gloss map (multiplies `K_s`), in the per-pixel modes the reference stands for but
    /// `pbr`.
    gloss: Option<RefSlot<'a>>,
    /// Metallic-roughness texture (`pbr`): G multiplies roughness, B metallic.
    metal_rough: Option<RefSlot<'a>>,
    /// `KHR_materials_unlit`: the base colour is the colour.
    unlit: bool,
    /// Normal map, occlusion and emissive map (textured mode).
    normal_map: Option<RefSlot<'a>>,
    occlusion: Option<RefSlot<'a>>,
    emissive_map: Option<RefSlot<'a>>,
    /// Bump map (textured mode).
    bump: Option<RefSlot<'a>>,
    /// The handedness of the world matrix (-1 mirrors the tangent frame).
    handed: f64,
}

/// Where a slot's values come from, as the reference reads them.
#[derive(Clone, Copy)]
enum RefSource<'a> {
    Image(&'a Texture),
    Procedural(&'a ProceduralTexture),
}

/// A texture slot as the reference reads it: the image or procedural texture, its sampler,
/// the UV set and the transform of its UVs, and its scalar (normal scale, occlusion
/// strength, bump height).
#[derive(Clone, Copy)]
struct RefSlot<'a> {
    source: RefSource<'a>,
    uv_set: u32,
    transform: UvTransform,
    sampler: Sampler,
    scale: f64,
}

impl RefSlot<'_> {
    /// The UV of the slot's set at corner `k` of triangle `v`, transformed (in f64).
    fn corner_uv(&self, tri: &TriMesh, v: [usize; 3], k: usize) -> DVec2 {
        let uv = tri
            .uv_set(self.uv_set)
            .and_then(|uv| uv.get(v[k]))
            .map_or(DVec2::ZERO, |u| u.as_dvec2());
        self.transform.matrix().as_dmat3().transform_point2(uv)
    }

    /// The slot's UV at barycentrics `b` of triangle `v`.
    fn uv(&self, tri: &TriMesh, v: [usize; 3], b: DVec3) -> DVec2 {
        let at = |k| self.corner_uv(tri, v, k);
        at(0) * b.x + at(1) * b.y + at(2) * b.z
    }

    /// The slot's value at barycentrics `b` of triangle `v` of `tri`: an image sampled at
    /// the UV of its set, interpolated and transformed (in f64); a procedural texture
    /// evaluated at a point (no footprint: the supersampling filters it).
    fn at(&self, tri: &TriMesh, v: [usize; 3], b: DVec3) -> DVec4 {
        match self.source {
            RefSource::Image(t) => {
                if tri.uv_set(self.uv_set).is_none() {
                    return DVec4::ONE;
                }
                sample_texture(t, self.uv(tri, v, b), self.sampler)
            }
            RefSource::Procedural(p) => p.color(&self.point(tri, v, b)).as_dvec4(),
        }
    }

    /// A procedural texture's sample point at barycentrics `b` (no footprint).
    fn point(&self, tri: &TriMesh, v: [usize; 3], b: DVec3) -> SamplePoint {
        match self.source {
            RefSource::Procedural(p) if p.domain() == Domain::Object => {
                let l = solid_corners(tri, v);
                SamplePoint::position((l[0] * b.x + l[1] * b.y + l[2] * b.z).as_vec3(), 0.0)
            }
            _ => SamplePoint::uv(self.uv(tri, v, b).as_vec2()),
        }
    }

    /// The tangent frame of triangle `v` (world corners `p`, unit normal `n`) for a mesh
    /// without tangents: [`maps::uv_tangent`] from the triangle's edges and this slot's UVs
    /// (the renderer's from the screen-space derivatives).
    fn uv_tangent(
        &self,
        tri: &TriMesh,
        v: [usize; 3],
        p: &[DVec3; 3],
        n: DVec3,
    ) -> Option<(DVec3, f64)> {
        tri.uv_set(self.uv_set)?;
        let uv = [0, 1, 2].map(|k| self.corner_uv(tri, v, k));
        let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
        maps::uv_tangent::<f64>(n, p[1] - p[0], p[2] - p[0], (d1.x, d2.x), (d1.y, d2.y))
    }

    /// The surface gradient of the bump displacement at barycentrics `b` of triangle `v`
    /// (world corners `p`, unit normal `n`): the renderer's formulas (`shade::texlab`) with
    /// the triangle's edges in place of the screen-space derivatives, in f64.
    fn bump_gradient(
        &self,
        tri: &TriMesh,
        v: [usize; 3],
        p: &[DVec3; 3],
        b: DVec3,
        n: DVec3,
    ) -> Option<DVec3> {
        let (s1, s2) = (p[1] - p[0], p[2] - p[0]);
        let uv_slope = |slope: DVec2| {
            let uv = [0, 1, 2].map(|k| self.corner_uv(tri, v, k));
            let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
            maps::uv_height_gradient::<f64>(
                n,
                s1,
                s2,
                (d1.x, d2.x),
                (d1.y, d2.y),
                (slope.x, slope.y),
                self.scale,
            )
        };
        match self.source {
            RefSource::Image(t) => {
                tri.uv_set(self.uv_set)?;
                uv_slope(image_height_slope(t, self.uv(tri, v, b), self.sampler))
            }
            RefSource::Procedural(pt) => {
                let g = pt.height_gradient(&self.point(tri, v, b)).as_dvec3();
                if pt.domain() == Domain::Uv {
                    return uv_slope(g.truncate());
                }
                let l = solid_corners(tri, v);
                let (l1, l2) = (l[1] - l[0], l[2] - l[0]);
                let sg = maps::surface_gradient::<f64>(n, s1, s2, g.dot(l1), g.dot(l2))?;
                let (ws, ls) = if l1.length_squared() >= l2.length_squared() {
                    (s1.length(), l1.length())
                } else {
                    (s2.length(), l2.length())
                };
                (ls > 0.0).then(|| sg * (self.scale * ws / ls))
            }
        }
    }
}

/// The corners of triangle `v` in the solid textures' frame (the mesh's bounding sphere is
/// the unit sphere), as the renderer's vertex stage computes them.
fn solid_corners(tri: &TriMesh, v: [usize; 3]) -> [DVec3; 3] {
    let inv = if tri.radius > 0.0 && tri.radius.is_finite() {
        1.0 / f64::from(tri.radius)
    } else {
        1.0
    };
    v.map(|k| {
        tri.positions.get(k).map_or(DVec3::ZERO, |p| {
            (p.as_dvec3() - tri.center.as_dvec3()) * inv
        })
    })
}

/// The slope per texel of a height image in f64: central differences one texel apart of its R
/// channel, read bilinearly (nearest for a nearest sampler) on the base level, as
/// `shade::texlab::image_height_slope` does.
fn image_height_slope(t: &Texture, uv: DVec2, s: Sampler) -> DVec2 {
    let filter = if s.filter == Filter::Nearest {
        Filter::Nearest
    } else {
        Filter::Bilinear
    };
    let s = Sampler { filter, ..s };
    let step = DVec2::new(
        1.0 / f64::from(t.width.max(1)),
        1.0 / f64::from(t.height.max(1)),
    );
    let h = |uv: DVec2| sample_texture(t, uv, s).x;
    let g = DVec2::new(
        (h(uv + DVec2::X * step.x) - h(uv - DVec2::X * step.x)) * 0.5,
        (h(uv + DVec2::Y * step.y) - h(uv - DVec2::Y * step.y)) * 0.5,
    );
    if g.is_finite() {
        g
    } else {
        DVec2::ZERO
    }
}

/// What draws of material `m` on mesh `tri` read in `slot`, as `render::frame::found`
/// decides it: the options' override (an image or a 2D pattern needs the UV set), else the
/// material's texture if it exists and the mesh has its UV set.
fn ref_slot<'a>(
    scene: &'a Scene,
    opts: &'a Shot,
    tri: &TriMesh,
    m: &Material,
    slot: Slot,
) -> Option<RefSlot<'a>> {
    let own = m.slot(slot);
    match opts.settings.slots.get(slot) {
        Some(SlotOverride::Off) => None,
        Some(SlotOverride::Source {
            source,
            uv_set,
            transform,
            sampler,
            scale,
        }) => {
            if source.needs_uv() {
                tri.uv_set(*uv_set)?;
            }
            Some(RefSlot {
                source: match source {
                    TextureSource::Image(t) => RefSource::Image(t),
                    TextureSource::Procedural(p) => RefSource::Procedural(p),
                },
                uv_set: *uv_set,
                transform: *transform,
                sampler: sampler.or(own.map(|t| t.sampler)).unwrap_or_default(),
                scale: f64::from(*scale),
            })
        }
        None => {
            let t = own?;
            tri.uv_set(t.uv_set)?;
            Some(RefSlot {
                source: RefSource::Image(scene.textures.get(t.texture)?),
                uv_set: t.uv_set,
                transform: t.transform,
                sampler: t.sampler,
                scale: f64::from(t.scale),
            })
        }
    }
}

fn instances<'a>(
    scene: &'a Scene,
    opts: &'a Shot,
    meshes: &'a [TriMesh],
    view: &View,
) -> Vec<Inst<'a>> {
    let mut out = Vec::new();
    for inst in &scene.instances {
        let (Some(tri), Some(mesh)) = (meshes.get(inst.mesh), scene.meshes.get(inst.mesh)) else {
            continue;
        };
        if tri.triangles.is_empty() || !inst.world.is_finite() {
            continue;
        }
        let m = scene.material_of(mesh);
        // The renderer's choice of maps (`render::frame::resolve`): a slot is read when its
        // texture exists and the mesh has its UV set (a normal map on a mesh without
        // tangents takes its frame from the triangle's edges and UVs); the
        // textured mode (chosen by default when any map is usable) reads every map, the
        // other per-pixel modes only the gloss map.
        let usable = |slot: Slot| ref_slot(scene, opts, tri, &m, slot);
        let emissive = crate::render::material_emission(&m).as_dvec3();
        let base_map = usable(Slot::BaseColor);
        let normal = usable(Slot::Normal);
        let occlusion = usable(Slot::Occlusion);
        let emissive_map = usable(Slot::Emissive).filter(|_| emissive != DVec3::ZERO);
        let bump = usable(Slot::Bump);
        let mapped = base_map.is_some()
            || normal.is_some()
            || occlusion.is_some()
            || emissive_map.is_some()
            || bump.is_some();
        let policy = Policy::new(opts.settings.shading, inst.style, &m, mapped);
        let textured = policy.textured;
        let textured_only = |s: Option<RefSlot<'a>>| s.filter(|_| textured);
        let world = inst.world.as_dmat4();
        let det = world.determinant();
        out.push(Inst {
            tri,
            world,
            normal: crate::geom::normal_matrix_f64(DMat3::from_mat4(world)),
            mvp: view.vp * world,
            flip: det < 0.0,
            cull: !(m.double_sided || opts.settings.double_sided),
            base: policy.base.as_dvec4(),
            surface: policy.surface,
            unlit: policy.unlit,
            alpha: match m.alpha_mode {
                AlphaMode::Opaque => Alpha::Opaque,
                AlphaMode::Mask(c) => Alpha::Mask(f64::from(c)),
                AlphaMode::Blend => Alpha::Blend,
            },
            emissive,
            texture: textured_only(base_map),
            gloss: usable(Slot::Specular).filter(|_| !policy.pbr),
            metal_rough: usable(Slot::MetallicRoughness).filter(|_| policy.pbr),
            normal_map: textured_only(normal),
            occlusion: textured_only(occlusion),
            emissive_map: textured_only(emissive_map),
            bump: textured_only(bump),
            handed: if det < 0.0 { -1.0 } else { 1.0 },
        });
    }
    out
}

/// A triangle ready for sampling: homogeneous edge functions over sample positions in
/// pixels, and the inclusive sample bounds of its visible part.
#[derive(Clone, Copy, Debug)]
struct Setup {
    inst: u32,
    /// Render-vertex indices.
    v: [u32; 3],
    /// `V_1 x V_2`, `V_2 x V_0`, `V_0 x V_1` as (a, b, c): `e(p) = a px + b py + c`.
    e: [DVec3; 3],
    /// `1 / det M`; `c_k = e_k(p) / det`.
    inv_det: f64,
    /// Sign of `det M`: a sample is inside when `sign * e_k(p) >= 0` for all k.
    sign: f64,
    /// Whether a sample with `e_k(p) == 0` exactly belongs to this triangle.
    tie: [bool; 3],
    /// `z / w` as a function of the sample position, if a vertex lies outside the near or
    /// far plane (else every inside sample is between them).
    depth: Option<DVec3>,
    front: bool,
    /// Inclusive sample index bounds `[x0, x1, y0, y1]` within the image.
    bounds: [i64; 4],
}

/// Sets up triangle `t` of instance `inst` (index `i`); `None` if it is degenerate, has a
/// non-finite vertex, is culled, or covers no sample of the image.
fn setup(view: &View, inst: &Inst, i: u32, t: u32) -> Option<Setup> {
    let tri = inst.tri;
    let v = *tri.triangles.get(t as usize)?;
    let mut clip = [DVec4::ZERO; 3];
    for k in 0..3 {
        let p = tri.positions.get(v[k] as usize)?.as_dvec3();
        clip[k] = inst.mvp * p.extend(1.0);
        if !clip[k].is_finite() {
            return None;
        }
    }
    let (hw, hh) = (f64::from(view.width) * 0.5, f64::from(view.height) * 0.5);
    let hv = clip.map(|c| DVec3::new((c.x + c.w) * hw, (c.w - c.y) * hh, c.w));
    let e = [hv[1].cross(hv[2]), hv[2].cross(hv[0]), hv[0].cross(hv[1])];
    let det = hv[0].dot(e[0]);
    if det == 0.0 || !det.is_finite() || !e.iter().all(|e| e.is_finite()) {
        return None;
    }
    // det < 0: counter-clockwise in normalised device coordinates (y up), the front.
    let front = (det < 0.0) != inst.flip;
    if inst.cull && !front {
        return None;
    }
    let sign = det.signum();
    let tie = e.map(|e| {
        let (a, b) = (sign * e.x, sign * e.y);
        a > 0.0 || (a == 0.0 && b > 0.0)
    });
    // The part between the near and far planes, clipped in homogeneous space, bounds the
    // samples to visit; the per-sample test decides coverage exactly.
    let crosses = clip.iter().any(|c| c.z < 0.0 || c.z > c.w);
    let poly = if crosses {
        clip_near_far(&clip)
    } else {
        clip.to_vec()
    };
    if poly.len() < 3 {
        return None;
    }
    let depth = crosses.then(|| (e[0] * clip[0].z + e[1] * clip[1].z + e[2] * clip[2].z) / det);
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for c in &poly {
        if c.w <= 0.0 {
            // Rounding of a clipped vertex: fall back to the whole image.
            lo = DVec2::splat(f64::NEG_INFINITY);
            hi = DVec2::splat(f64::INFINITY);
            break;
        }
        let p = DVec2::new((c.x / c.w + 1.0) * hw, (1.0 - c.y / c.w) * hh);
        lo = lo.min(p);
        hi = hi.max(p);
    }
    // Sample j sits at (j + 0.5) / s; keep a margin for the rounding of clipped vertices.
    let s = f64::from(view.samples);
    // First (`lower`) or last sample index at or inside pixel coordinate p.
    let index = |p: f64, lower: bool| {
        let margin = 1e-6 + 1e-12 * p.abs() * s;
        let x = p * s - 0.5;
        let x = if lower { x - margin } else { x + margin }.clamp(-1e15, 1e15);
        (if lower { x.ceil() } else { x.floor() }) as i64
    };
    let (sw, sh) = (
        i64::from(view.width * view.samples),
        i64::from(view.height * view.samples),
    );
    let bounds = [
        index(lo.x, true).max(0),
        index(hi.x, false).min(sw - 1),
        index(lo.y, true).max(0),
        index(hi.y, false).min(sh - 1),
    ];
    if bounds[0] > bounds[1] || bounds[2] > bounds[3] {
        return None;
    }
    Some(Setup {
        inst: i,
        v,
        e,
        inv_det: 1.0 / det,
        sign,
        tie,
        depth,
        front,
        bounds,
    })
}

/// Sutherland-Hodgman against the near (`z <= w`) and far (`z >= 0`) planes, intersections
/// computed from the inside vertex.
fn clip_near_far(tri: &[DVec4; 3]) -> Vec<DVec4> {
    let mut poly = tri.to_vec();
    let planes: [fn(DVec4) -> f64; 2] = [|c| c.w - c.z, |c| c.z];
    for d in planes {
        let mut out = Vec::with_capacity(poly.len() + 1);
        crate::geom::clip_polygon(
            &poly,
            |p| d(*p) >= 0.0,
            |&i, &o| i + (o - i) * crate::geom::crossing(d(i), d(o)),
            &mut out,
        );
        poly = out;
        if poly.len() < 3 {
            return Vec::new();
        }
    }
    poly
}

/// Position of sample index `j` in pixels.
#[inline]
fn sample_pos(j: i64, s: f64) -> f64 {
    (j as f64 + 0.5) / s
}

/// Calls `f(sx, sy, 1/w, px, py)` for every sample inside `g` within `x0..=x1`, `y0..=y1`
/// (sample indices), in row order.
#[inline]
fn cover(
    g: &Setup,
    s: f64,
    [x0, x1, y0, y1]: [i64; 4],
    mut f: impl FnMut(i64, i64, f64, f64, f64),
) {
    let inside = |v: f64, k: usize| {
        let v = v * g.sign;
        v > 0.0 || (v == 0.0 && g.tie[k])
    };
    for sy in y0..=y1 {
        let py = sample_pos(sy, s);
        let r = g.e.map(|e| e.y * py + e.z);
        for sx in x0..=x1 {
            let px = sample_pos(sx, s);
            let v = [
                g.e[0].x * px + r[0],
                g.e[1].x * px + r[1],
                g.e[2].x * px + r[2],
            ];
            if !(inside(v[0], 0) && inside(v[1], 1) && inside(v[2], 2)) {
                continue;
            }
            if let Some(z) = g.depth {
                let z = z.x * px + z.y * py + z.z;
                if !(0.0..=1.0).contains(&z) {
                    continue;
                }
            }
            f(sx, sy, (v[0] + v[1] + v[2]) * g.inv_det, px, py);
        }
    }
}

/// A set-up triangle with its world-space vertices, ready to shade.
struct Tri {
    g: Setup,
    p: [DVec3; 3],
    /// Unit world normals (zero where the transformed normal vanishes).
    n: [DVec3; 3],
}

impl Tri {
    fn new(g: Setup, inst: &Inst) -> Self {
        let (tri, v) = (inst.tri, g.v);
        Self {
            g,
            p: v.map(|k| {
                inst.world
                    .transform_point3(tri.positions[k as usize].as_dvec3())
            }),
            n: v.map(|k| {
                let n = tri.normals.get(k as usize).copied().unwrap_or_default();
                (inst.normal * n.as_dvec3()).normalize_or_zero()
            }),
        }
    }

    /// Perspective-correct barycentrics at sample position (px, py).
    #[inline]
    fn bary(&self, px: f64, py: f64) -> DVec3 {
        let c = DVec3::from_array(
            self.g
                .e
                .map(|e| (e.x * px + e.y * py + e.z) * self.g.inv_det),
        );
        c / (c.x + c.y + c.z)
    }

    /// Base colour (material x vertex colour x texture) at barycentrics `b`.
    fn base(&self, inst: &Inst, b: DVec3) -> DVec4 {
        let v = self.g.v.map(|k| k as usize);
        let mut base = inst.base;
        if let Some(c) = &inst.tri.colors {
            let at = |k: usize| c.get(v[k]).map_or(DVec4::ONE, |c| c.as_dvec4());
            base *= at(0) * b.x + at(1) * b.y + at(2) * b.z;
        }
        if let Some(t) = &inst.texture {
            base *= t.at(inst.tri, v, b);
        }
        base
    }

    /// The fragment at sample position (px, py): linear RGB and alpha, or `None` if the
    /// alpha test discards it.
    fn shade(&self, view: &View, inst: &Inst, px: f64, py: f64) -> Option<DVec4> {
        let b = self.bary(px, py);
        let base = self.base(inst, b);
        let alpha = match inst.alpha {
            Alpha::Opaque => 1.0,
            Alpha::Mask(cutoff) if base.w >= cutoff => 1.0,
            Alpha::Mask(_) => return None,
            Alpha::Blend => base.w,
        };
        let p = self.p[0] * b.x + self.p[1] * b.y + self.p[2] * b.z;
        let mut n = (self.n[0] * b.x + self.n[1] * b.y + self.n[2] * b.z).normalize_or_zero();
        let v = self.g.v.map(|k| k as usize);
        if let Some(map) = &inst.normal_map {
            let frame = match &inst.tri.tangents {
                Some(ts) => {
                    let at = |k: usize| ts.get(v[k]).map_or(DVec4::X, |t| t.as_dvec4());
                    let t4 = at(0) * b.x + at(1) * b.y + at(2) * b.z;
                    let t = (DMat3::from_mat4(inst.world) * t4.truncate()).normalize_or_zero();
                    Some((t, t4.w * inst.handed))
                }
                None => map.uv_tangent(inst.tri, v, &self.p, n),
            };
            if let Some((t, w)) = frame {
                let c = map.at(inst.tri, v, b).truncate().to_array();
                n = maps::perturb::<f64>(n, t, w, c, map.scale);
            }
        }
        if let Some(bm) = &inst.bump {
            if let Some(g) = bm.bump_gradient(inst.tri, v, &self.p, b, n) {
                n = maps::bump::<f64>(n, g);
            }
        }
        if !self.g.front {
            n = -n;
        }
        if inst.unlit {
            return Some(base.truncate().extend(alpha));
        }
        let mut surf = inst.surface.at::<f64>(base.truncate());
        if let Some(g) = &inst.gloss {
            surf.ks *= g.at(inst.tri, v, b).truncate();
        }
        if let (Some(mr), Some(p)) = (&inst.metal_rough, &mut surf.pbr) {
            let t = mr.at(inst.tri, v, b);
            p.roughness *= t.y;
            p.metallic *= t.z;
        }
        if let Some(o) = &inst.occlusion {
            // On the ambient (or image-based) term only.
            surf.occlusion = Some(maps::occlusion(o.at(inst.tri, v, b).x, o.scale));
        }
        let mut c = match &surf.pbr {
            Some(pb) if view.env_samples > 0 => {
                let lit = illuminate::<f64>(&view.punctual, None, &surf, p, n, view.eye, false);
                let v = (view.eye - p).normalize_or_zero();
                let env = environment(view, &surf, pb, n, v, (px, py));
                lit + surf.occlusion.map_or(env, |ao| env * ao)
            }
            _ => illuminate::<f64>(&view.lights, None, &surf, p, n, view.eye, view.blinn),
        };
        c += match &inst.emissive_map {
            Some(m) => inst.emissive * m.at(inst.tri, v, b).truncate(),
            None => inst.emissive,
        };
        if let Some(fog) = &view.fog {
            c = fog.apply::<f64>(c, p, view.eye, view.forward);
        }
        Some(c.extend(alpha))
    }

    /// Whether the alpha test keeps the fragment at (px, py).
    fn kept(&self, inst: &Inst, px: f64, py: f64) -> bool {
        match inst.alpha {
            Alpha::Mask(cutoff) => self.base(inst, self.bary(px, py)).w >= cutoff,
            _ => true,
        }
    }
}

/// Exact sRGB decoding of the 256 byte values, in f64.
fn srgb_table() -> &'static [f64; 256] {
    static TABLE: OnceLock<[f64; 256]> = OnceLock::new();
    TABLE.get_or_init(|| std::array::from_fn(|i| crate::color::srgb_decode(i as f64 / 255.0)))
}

/// Texel (x, y) in linear light, 8-bit sRGB decoded exactly in f64; transparent black
/// outside the texel array.
pub(crate) fn texel(t: &Texture, x: u32, y: u32) -> DVec4 {
    if x >= t.width || y >= t.height {
        return DVec4::ZERO;
    }
    let i = y as usize * t.width as usize + x as usize;
    match &t.texels {
        Texels::Srgb8(p) => {
            let (p, lin) = (p[i], srgb_table());
            DVec4::new(
                lin[p[0] as usize],
                lin[p[1] as usize],
                lin[p[2] as usize],
                f64::from(p[3]) / 255.0,
            )
        }
        Texels::Linear8(p) => DVec4::from_array(p[i].map(f64::from)) / 255.0,
        Texels::Linear16(p) => DVec4::from_array(p[i].map(f64::from)) / 65535.0,
        Texels::Float(p) => DVec4::from_array(p[i].map(f64::from)),
    }
}

fn fetch(t: &Texture, x: u32, y: u32) -> DVec4 {
    texel(t, x, y)
}

/// `Texture::sample_with` in f64: same UV convention (origin at the top-left texel corner,
/// texel centres at half-integers), wrap modes and filter; non-finite UVs read (0, 0).
fn sample_texture(t: &Texture, uv: DVec2, s: Sampler) -> DVec4 {
    if t.width == 0 || t.height == 0 {
        return DVec4::ONE;
    }
    let uv = if uv.is_finite() { uv } else { DVec2::ZERO };
    let (u, v) = (reduce(uv.x, s.wrap_u), reduce(uv.y, s.wrap_v));
    let (w, h) = (f64::from(t.width), f64::from(t.height));
    match s.filter {
        Filter::Nearest => fetch(
            t,
            wrap_index((u * w).floor(), t.width, s.wrap_u),
            wrap_index((v * h).floor(), t.height, s.wrap_v),
        ),
        // Mipmapping (and anisotropic filtering) approximates the footprint filter that the
        // supersampling computes here, so the ideal of a mipmapped texture is its base
        // level, read bilinearly.
        Filter::Bilinear | Filter::Trilinear | Filter::Anisotropic(_) => {
            let (fx, fy) = (u * w - 0.5, v * h - 0.5);
            let (x0, y0) = (fx.floor(), fy.floor());
            let (tx, ty) = (fx - x0, fy - y0);
            let xs = [x0, x0 + 1.0].map(|x| wrap_index(x, t.width, s.wrap_u));
            let ys = [y0, y0 + 1.0].map(|y| wrap_index(y, t.height, s.wrap_v));
            let top = fetch(t, xs[0], ys[0]).lerp(fetch(t, xs[1], ys[0]), tx);
            let bottom = fetch(t, xs[0], ys[1]).lerp(fetch(t, xs[1], ys[1]), tx);
            top.lerp(bottom, ty)
        }
    }
}

/// Removes whole wrap periods (see `texture::reduce`).
fn reduce(t: f64, wrap: Wrap) -> f64 {
    match wrap {
        Wrap::Repeat => t - t.floor(),
        Wrap::MirroredRepeat => t.rem_euclid(2.0),
        Wrap::ClampToEdge => t.clamp(-1.0, 2.0),
    }
}

/// Folds an integer texel coordinate into 0..n.
fn wrap_index(i: f64, n: u32, wrap: Wrap) -> u32 {
    let nf = f64::from(n);
    match wrap {
        Wrap::ClampToEdge => i.clamp(0.0, nf - 1.0) as u32,
        Wrap::Repeat => (i.rem_euclid(nf) as u32).min(n - 1),
        Wrap::MirroredRepeat => {
            let m = i.rem_euclid(2.0 * nf);
            let m = if m >= nf { 2.0 * nf - 1.0 - m } else { m };
            (m.max(0.0) as u32).min(n - 1)
        }
    }
}

/// Renders one band: visibility of opaque and masked triangles, shading of the nearest,
/// blended fragments composited in depth order, box filter. Returns the band's pixels,
/// row-major.
fn band(view: &View, insts: &[Inst], bin: &[(u32, u32)], r: Rect) -> Vec<[f64; 3]> {
    let s = view.samples;
    let sf = f64::from(s);
    let (sx0, sy0) = (i64::from(r.x0 * s), i64::from(r.y0 * s));
    let (sw, sh) = (((r.x1 - r.x0) * s) as usize, ((r.y1 - r.y0) * s) as usize);
    let clamp = |b: [i64; 4]| {
        [
            b[0].max(sx0),
            b[1].min(sx0 + sw as i64 - 1),
            b[2].max(sy0),
            b[3].min(sy0 + sh as i64 - 1),
        ]
    };
    let slot = |sx: i64, sy: i64| (sy - sy0) as usize * sw + (sx - sx0) as usize;
    // 1 / w of the nearest opaque fragment (0: none) and its triangle in `tris`.
    let mut depth = vec![0.0f64; sw * sh];
    let mut id = vec![u32::MAX; sw * sh];
    let mut tris: Vec<Tri> = Vec::new();
    let mut blended: Vec<Tri> = Vec::new();
    for &(i, t) in bin {
        let inst = &insts[i as usize];
        let Some(g) = setup(view, inst, i, t) else {
            continue;
        };
        let b = clamp(g.bounds);
        if b[0] > b[1] || b[2] > b[3] {
            continue;
        }
        let tri = Tri::new(Setup { bounds: b, ..g }, inst);
        if inst.alpha == Alpha::Blend {
            blended.push(tri);
            continue;
        }
        let k = tris.len() as u32;
        cover(&tri.g, sf, b, |sx, sy, inv_w, px, py| {
            let o = slot(sx, sy);
            // Nearest wins; on an exact tie the first drawn stays.
            if inv_w > depth[o] && tri.kept(inst, px, py) {
                depth[o] = inv_w;
                id[o] = k;
            }
        });
        tris.push(tri);
    }
    // Blended fragments in front of the opaque surface: (slot, 1/w, draw order, colour),
    // per sample farthest (smallest 1/w) first, equal depths in draw order.
    let mut frags: Vec<(u32, f64, u32, DVec4)> = Vec::new();
    for (seq, tri) in blended.iter().enumerate() {
        let inst = &insts[tri.g.inst as usize];
        cover(&tri.g, sf, tri.g.bounds, |sx, sy, inv_w, px, py| {
            let o = slot(sx, sy);
            if inv_w > depth[o] {
                if let Some(c) = tri.shade(view, inst, px, py) {
                    frags.push((o as u32, inv_w, seq as u32, c));
                }
            }
        });
    }
    frags.sort_unstable_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)).then(a.2.cmp(&b.2)));
    // Shade the nearest opaque fragment of every sample, composite the blended ones over
    // it, and box-filter into the band's pixels.
    let (pw, ph) = ((r.x1 - r.x0) as usize, (r.y1 - r.y0) as usize);
    let su = s as usize;
    let mut sum = vec![DVec3::ZERO; pw * ph];
    let mut next = frags.iter().peekable();
    for (o, &k) in id.iter().enumerate() {
        let (sx, sy) = (o % sw, o / sw);
        let mut c = match tris.get(k as usize) {
            None => view.background,
            Some(tri) => {
                let (px, py) = (
                    sample_pos(sx as i64 + sx0, sf),
                    sample_pos(sy as i64 + sy0, sf),
                );
                tri.shade(view, &insts[tri.g.inst as usize], px, py)
                    .map_or(view.background, |c| c.truncate())
            }
        };
        while let Some(&&(_, _, _, f)) = next.peek().filter(|f| f.0 as usize == o) {
            let a = f.w.clamp(0.0, 1.0);
            c = f.truncate() * a + c * (1.0 - a);
            next.next();
        }
        c *= view.exposure;
        if view.tone != crate::render::ToneMap::Clamp {
            c = view
                .tone
                .apply(c.as_vec3().extend(1.0))
                .truncate()
                .as_dvec3();
        }
        sum[(sy / su) * pw + sx / su] += c;
    }
    let n = f64::from(s * s);
    sum.into_iter().map(|c| (c / n).to_array()).collect()
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use glam::{Mat4, Vec2, Vec3, Vec4};

    use crate::scene::{Style, TextureSlot};
    use crate::shade::Shading;

    use super::*;
    use crate::mesh::{Channel, Mesh, MeshData, NormalPolicy};
    use crate::render::{self, PreparedScene, Settings};
    use crate::scene::{Camera, Instance, Light, Material};
    use crate::sphere::SphereSetup;
    use crate::texture::Sampler;
    use crate::{compare, metrics::DEFAULT_DE_THRESHOLD, Metrics};

    /// The rasterizer at `ss` x `ss` supersampling, box-filtered: its samples sit exactly
    /// where [`reference`] with `samples = ss` puts them.
    fn raster(scene: &Scene, opts: &Shot, ss: u32) -> LinearImage {
        let big = Shot {
            width: opts.width * ss,
            height: opts.height * ss,
            ..opts.clone()
        };
        let frame = render::render(&PreparedScene::new(scene.clone()), &big);
        LinearImage::from_framebuffer(&frame.image()).downsample(ss)
    }

    fn de(test: &LinearImage, reference: &LinearImage) -> Metrics {
        compare(test, reference, DEFAULT_DE_THRESHOLD)
    }

    fn black(width: u32, height: u32, camera: Option<Camera>) -> Shot {
        Shot {
            width,
            height,
            camera,
            settings: Settings {
                background: Vec4::new(0.0, 0.0, 0.0, 1.0),
                ..Settings::default()
            },
        }
    }

    /// A one-facet quad (corners counter-clockwise from the front), optional UVs and
    /// vertex colours.
    fn quad(p: [Vec3; 4], uv: Option<[Vec2; 4]>, color: Option<[Vec4; 4]>, mat: usize) -> Mesh {
        Mesh::new(
            MeshData {
                name: "quad".into(),
                positions: p.to_vec(),
                corners: vec![0, 1, 2, 3],
                facet_sizes: Some(vec![4]),
                normals: None,
                uvs: uv
                    .map(|u| Channel::per_vertex(u.to_vec()))
                    .into_iter()
                    .collect(),
                colors: color.map(|c| Channel::per_vertex(c.to_vec())),
                tangents: None,
                material: Some(mat),
            },
            NormalPolicy::default(),
        )
        .unwrap()
    }

    /// An axis-aligned square facing +Z at depth `z`, half size `r`.
    fn square(z: f32, r: f32, color: Option<[Vec4; 4]>, mat: usize) -> Mesh {
        quad(
            [
                Vec3::new(-r, -r, z),
                Vec3::new(r, -r, z),
                Vec3::new(r, r, z),
                Vec3::new(-r, r, z),
            ],
            None,
            color,
            mat,
        )
    }

    fn place(scene: &mut Scene, mesh: Mesh, world: Mat4) {
        scene.instances.push(Instance {
            mesh: scene.meshes.len(),
            world,
            name: mesh.name.clone(),
            style: Style::Inherit,
            node: None,
            skin: None,
        });
        scene.meshes.push(mesh);
    }

    /// Plain diffuse material lit by ambient light only: every pixel's colour is `kd`.
    fn flat_material(kd: Vec3, alpha: f32, mode: AlphaMode) -> Material {
        Material {
            base_color: kd.extend(alpha),
            specular: Vec3::ZERO,
            alpha_mode: mode,
            ..Material::default()
        }
    }

    /// Equal up to the f32 rounding of the inputs.
    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        (0..3).all(|k| (a[k] - b[k]).abs() < 1e-6)
    }

    #[test]
    fn tessellated_sphere_matches_the_analytic_sphere() {
        let setup = SphereSetup::standard(320, 180);
        let opts = Shot {
            settings: Settings {
                shading: Some(Shading::Phong),
                ..black(320, 180, Some(setup.camera.clone())).settings
            },
            ..black(320, 180, Some(setup.camera.clone()))
        };
        let analytic = setup.reference(false);
        let fine = reference(&setup.scene(256, 128).unwrap(), &opts, 8, false).unwrap();
        let coarse = reference(&setup.scene(16, 8).unwrap(), &opts, 8, false).unwrap();
        let (fine, coarse) = (de(&fine, &analytic), de(&coarse, &analytic));
        // Measured: mean 0.0041, p95 0.0035. Two things are left, neither the reference's
        // fault: silhouette pixels are resolved to 1/64 of coverage here and to 1/256 by the
        // analytic reference (at 16 x 16 samples the mean drops to 0.0019), and the
        // interpolated normals of a 256 x 128 mesh are not the sphere's (the p95, which
        // 16 x 16 samples leave unchanged). A 16 x 8 mesh shows what a real error is.
        assert!(fine.mean_de2000 < 0.01, "{fine:?}");
        assert!(coarse.mean_de2000 > 0.3, "{coarse:?}");
        // Both residues vanish together: a 1024 x 512 mesh at the analytic reference's own
        // edge sampling agrees to a mean of 1e-4 (measured 0.00009).
        let opts = Shot {
            settings: Settings {
                shading: Some(Shading::Phong),
                ..black(320, 180, Some(setup.camera.clone())).settings
            },
            ..black(320, 180, Some(setup.camera.clone()))
        };
        let finest = reference(&setup.scene(1024, 512).unwrap(), &opts, 16, false).unwrap();
        let finest = de(&finest, &analytic);
        assert!(
            finest.mean_de2000 < 5e-4 && finest.over_threshold == 0,
            "{finest:?}"
        );
    }

    /// The demo scene, every instance forced to `mode`, with its own camera.
    /// Its spotlight's shadow is turned off: the reference draws no shadows.
    fn demo(mode: Shading, width: u32, height: u32) -> (Scene, Shot) {
        let mut scene = crate::scene::demo();
        scene.lights.iter_mut().for_each(|l| l.shadow = false);
        let opts = Shot {
            settings: Settings {
                shading: Some(mode),
                ..black(width, height, Some(scene.cameras[0].clone())).settings
            },
            ..black(width, height, Some(scene.cameras[0].clone()))
        };
        (scene, opts)
    }

    #[test]
    fn rasterizer_agrees_on_the_demo_scene_and_a_wrong_reference_does_not() {
        let (scene, opts) = demo(Shading::Phong, 320, 180);
        let ras = raster(&scene, &opts, 4);
        let same = de(&ras, &reference(&scene, &opts, 4, false).unwrap());
        let dense = de(&ras, &reference(&scene, &opts, 8, false).unwrap());
        let blinn = de(&ras, &reference(&scene, &opts, 4, true).unwrap());
        let mut dark = scene.clone();
        dark.lights
            .retain(|l| l.kind == crate::scene::LightKind::Ambient);
        let unlit = de(&ras, &reference(&dark, &opts, 4, false).unwrap());
        // Same sample positions (the rasterizer's 4x image box-filtered, the reference at
        // 4 x 4): only arithmetic differs. Measured mean 8e-5, 2 pixels above 1: samples
        // within 1e-3 pixel of a silhouette edge, which the rasterizer's 1/256-pixel vertex
        // snapping moves across the sample. The tolerance allows about 100 such pixels.
        assert!(
            same.mean_de2000 < 2e-3 && same.over_threshold < 30,
            "{same:?}"
        );
        // Teeth: Blinn highlights on these Phong spheres (n = 40, Ks up to 0.6) measure
        // 0.15; without the two point lights 7.
        assert!(blinn.mean_de2000 > 0.05, "{blinn:?}");
        assert!(unlit.mean_de2000 > 1.0, "{unlit:?}");
        // The rasterizer's own error at 4x4 supersampling against the converged reference
        // (8 x 8): measured 0.016, all of it in silhouette pixels.
        assert!(
            dense.mean_de2000 < 0.05 && dense.p95_de2000 < 0.01,
            "{dense:?}"
        );
    }

    /// A checkered sphere (material texture, repeat), a mirrored and stretched copy of it,
    /// and a vertex-coloured quad whose UVs run over -1..2 (a grid with mirrored repeat);
    /// default camera and light rig.
    fn textured() -> (Scene, Shot) {
        let mut scene = Scene::default();
        let checker = Texture::checker(64, 8, [230, 40, 30, 255], [40, 90, 220, 255]);
        scene.textures.push(Arc::new(checker));
        let grid = Texture::checker(16, 4, [250, 250, 250, 255], [20, 120, 60, 255]);
        scene.textures.push(Arc::new(grid));
        scene.materials.push(Material {
            base_color_texture: Some(TextureSlot {
                sampler: Sampler {
                    wrap_u: Wrap::Repeat,
                    wrap_v: Wrap::Repeat,
                    filter: Filter::Bilinear,
                },
                ..TextureSlot::new(0)
            }),
            specular: Vec3::splat(0.5),
            shininess: 60.0,
            ..Material::default()
        });
        scene.materials.push(Material {
            base_color: Vec4::new(1.0, 1.0, 1.0, 1.0),
            base_color_texture: Some(TextureSlot {
                sampler: Sampler {
                    wrap_u: Wrap::MirroredRepeat,
                    wrap_v: Wrap::MirroredRepeat,
                    filter: Filter::Bilinear,
                },
                ..TextureSlot::new(1)
            }),
            double_sided: true,
            ..Material::default()
        });
        let mut sphere = Mesh::sphere(1.0, 48, 24).unwrap();
        sphere.material = Some(0);
        place(
            &mut scene,
            sphere.clone(),
            Mat4::from_translation(Vec3::new(-1.2, 0.0, 0.0)),
        );
        place(
            &mut scene,
            sphere,
            Mat4::from_translation(Vec3::new(1.3, 0.2, 0.0))
                * Mat4::from_scale(Vec3::new(-0.8, 1.3, 0.8)),
        );
        let c = |r: f32, g: f32, b: f32| Vec4::new(r, g, b, 1.0);
        place(
            &mut scene,
            quad(
                [
                    Vec3::new(-3.0, -1.5, -1.5),
                    Vec3::new(3.0, -1.5, -1.5),
                    Vec3::new(3.0, 1.8, -2.0),
                    Vec3::new(-3.0, 1.8, -2.0),
                ],
                Some([
                    Vec2::new(-1.0, 2.0),
                    Vec2::new(2.0, 2.0),
                    Vec2::new(2.0, -1.0),
                    Vec2::new(-1.0, -1.0),
                ]),
                Some([
                    c(1.0, 1.0, 1.0),
                    c(1.0, 0.5, 0.5),
                    c(0.5, 1.0, 0.5),
                    c(0.6, 0.6, 1.0),
                ]),
                1,
            ),
            Mat4::IDENTITY,
        );
        let opts = black(320, 180, None);
        (scene, opts)
    }

    #[test]
    fn rasterizer_agrees_on_a_textured_scene_and_a_wrong_reference_does_not() {
        let (scene, opts) = textured();
        // No mode forced: textured instances are drawn in the textured mode (Blinn).
        let ras = raster(&scene, &opts, 4);
        let same = de(&ras, &reference(&scene, &opts, 4, true).unwrap());
        let dense = de(&ras, &reference(&scene, &opts, 8, true).unwrap());
        let plain = Shot {
            settings: Settings {
                shading: Some(Shading::Blinn),
                ..opts.clone().settings
            },
            ..opts.clone()
        };
        let untextured = de(&ras, &reference(&scene, &plain, 4, true).unwrap());
        let phong = de(&ras, &reference(&scene, &opts, 4, false).unwrap());
        // As on the demo scene (measured mean 3e-4, 1 pixel above 1): f32 against f64,
        // vertex snapping; texture filtering adds the f32 bilinear weights.
        assert!(
            same.mean_de2000 < 2e-3 && same.over_threshold < 30,
            "{same:?}"
        );
        // Teeth: the reference without textures (measured 4.1), or with Phong highlights
        // where the textured mode uses Blinn (measured 0.35).
        assert!(untextured.mean_de2000 > 1.0, "{untextured:?}");
        assert!(phong.mean_de2000 > 0.1, "{phong:?}");
        // Measured 0.018 at 4x4 against 8 x 8: silhouettes and the chequer edges.
        assert!(dense.mean_de2000 < 0.05, "{dense:?}");
    }

    #[test]
    fn gloss_map_modulates_the_highlight_as_in_the_reference() {
        // A matte blue sphere whose highlight is masked by a chequered gloss map (003 §7).
        let mut scene = Scene::default();
        let gloss = Texture::checker(64, 8, [255, 255, 255, 255], [0, 0, 0, 255]);
        scene.textures.push(Arc::new(gloss));
        scene.materials.push(Material {
            base_color: Vec4::new(0.1, 0.15, 0.5, 1.0),
            specular: Vec3::ONE,
            specular_texture: Some(TextureSlot {
                sampler: Sampler {
                    wrap_u: Wrap::Repeat,
                    wrap_v: Wrap::Repeat,
                    filter: Filter::Bilinear,
                },
                ..TextureSlot::new(0)
            }),
            shininess: 20.0,
            ..Material::default()
        });
        let mut sphere = Mesh::sphere(1.0, 48, 24).unwrap();
        sphere.material = Some(0);
        place(&mut scene, sphere, Mat4::IDENTITY);
        let opts = Shot {
            settings: Settings {
                shading: Some(Shading::Phong),
                ..black(160, 120, None).settings
            },
            ..black(160, 120, None)
        };
        let ras = raster(&scene, &opts, 4);
        let same = de(&ras, &reference(&scene, &opts, 4, false).unwrap());
        let mut plain = scene.clone();
        plain.materials[0].specular_texture = None;
        let ungloss = de(&ras, &reference(&plain, &opts, 4, false).unwrap());
        let unmapped = de(&raster(&plain, &opts, 4), &ras);
        assert!(
            same.mean_de2000 < 2e-3 && same.over_threshold < 30,
            "{same:?}"
        );
        // Teeth: the gloss map must change the picture, and the reference must see it.
        // Measured 0.32 for both (the masked highlight is a small part of the image).
        assert!(unmapped.mean_de2000 > 0.15, "{unmapped:?}");
        assert!(ungloss.mean_de2000 > 0.15, "{ungloss:?}");
    }

    /// Camera at the origin looking down -Z, 45 degree field of view.
    fn forward(near: f32, far: f32) -> Camera {
        Camera {
            eye: Vec3::ZERO,
            target: -Vec3::Z,
            near,
            far,
            ..Camera::default()
        }
    }

    #[test]
    fn floor_through_the_eye_plane_is_clipped_at_near_and_far() {
        // A floor at y = -1 from 50 behind the eye to 1000 in front: its triangles cross
        // w = 0. Ambient light only, so covered samples are exactly 0.5 * 0.6 = 0.3. The
        // camera is rolled by 20 degrees so that the near and far lines cross the image
        // diagonally and the bounds of the clipped polygon alone cannot cut them.
        let mut scene = Scene::default();
        scene
            .materials
            .push(flat_material(Vec3::splat(0.6), 1.0, AlphaMode::Opaque));
        let floor = quad(
            [
                Vec3::new(-1000.0, -1.0, 50.0),
                Vec3::new(1000.0, -1.0, 50.0),
                Vec3::new(1000.0, -1.0, -1000.0),
                Vec3::new(-1000.0, -1.0, -1000.0),
            ],
            None,
            None,
            0,
        );
        place(&mut scene, floor, Mat4::IDENTITY);
        scene.lights = vec![Light::ambient(Vec3::splat(0.5))];
        let (w, h, s) = (64u32, 90u32, 8u32);
        let (near, far) = (5.0f32, 300.0f32);
        let roll = 20f32.to_radians();
        let camera = Camera {
            up: Vec3::new(roll.sin(), roll.cos(), 0.0),
            ..forward(near, far)
        };
        // Expected: the view distance where each sample's ray meets the floor.
        let f = DVec3::NEG_Z;
        let right = f.cross(camera.up.as_dvec3()).normalize();
        let up = right.cross(f);
        let t = (f64::from(camera.yfov) / 2.0).tan();
        let opts = black(w, h, Some(camera));
        let img = reference(&scene, &opts, s, false).unwrap();
        let (mut near_cut, mut far_cut) = (0, 0);
        for y in 0..h {
            for x in 0..w {
                let mut covered = 0;
                for j in 0..s {
                    for i in 0..s {
                        let px = f64::from(x) + (f64::from(i) + 0.5) / f64::from(s);
                        let py = f64::from(y) + (f64::from(j) + 0.5) / f64::from(s);
                        let nx = (2.0 * px / f64::from(w) - 1.0) * t * f64::from(w) / f64::from(h);
                        let ny = (1.0 - 2.0 * py / f64::from(h)) * t;
                        let dir = f + right * nx + up * ny;
                        // Distance in front of the eye (w) of the floor point on this ray.
                        let d = -1.0 / dir.y;
                        if dir.y < 0.0 && d < f64::from(near) {
                            near_cut += 1;
                        } else if dir.y < 0.0 && d > f64::from(far) {
                            far_cut += 1;
                        } else if dir.y < 0.0 {
                            covered += 1;
                        }
                    }
                }
                let want = 0.3 * f64::from(covered) / f64::from(s * s);
                let got = img.rgb[(y * w + x) as usize];
                assert!(close(got, [want; 3]), "({x}, {y}): {got:?}, want {want}");
            }
        }
        // Both planes cut something away.
        assert!(near_cut > 1000 && far_cut > 1000, "{near_cut} {far_cut}");
        // The rasterizer draws the same thing.
        let m = de(
            &raster(&scene, &opts, 4),
            &reference(&scene, &opts, 4, false).unwrap(),
        );
        assert!(m.mean_de2000 < 1e-3, "{m:?}");
    }

    #[test]
    fn non_finite_input_empty_scenes_and_bad_requests() {
        let opts = black(40, 30, Some(Camera::default()));
        let background = [0.25, 0.5, 0.75];
        let opts = Shot {
            settings: Settings {
                background: Vec4::new(0.25, 0.5, 0.75, 1.0),
                ..opts.settings.clone()
            },
            ..opts
        };
        // Empty scene, with and without the default camera.
        for camera in [None, Some(Camera::default())] {
            let o = Shot {
                camera,
                ..opts.clone()
            };
            let img = reference(&Scene::default(), &o, 3, false).unwrap();
            assert!(img.rgb.iter().all(|&c| c == background));
        }
        // A triangle with a NaN corner next to a good one, an instance with a NaN matrix,
        // one with a missing mesh: only the good triangle is drawn.
        let mut scene = Scene::default();
        scene
            .materials
            .push(flat_material(Vec3::ONE, 1.0, AlphaMode::Opaque));
        scene.lights = vec![Light::ambient(Vec3::ONE)];
        let mesh = Mesh::new(
            MeshData {
                name: "nan".into(),
                positions: vec![
                    Vec3::new(-1.0, -1.0, 0.0),
                    Vec3::new(0.0, -1.0, 0.0),
                    Vec3::new(-1.0, 1.0, 0.0),
                    Vec3::new(1.0, -1.0, 0.0),
                    Vec3::new(1.0, 1.0, f32::NAN),
                    Vec3::new(f32::INFINITY, 0.0, 0.0),
                ],
                corners: vec![0, 1, 2, 1, 3, 4, 3, 5, 4],
                material: Some(0),
                ..MeshData::default()
            },
            NormalPolicy::default(),
        )
        .unwrap();
        place(&mut scene, mesh.clone(), Mat4::IDENTITY);
        place(
            &mut scene,
            mesh,
            Mat4::from_scale(Vec3::new(1.0, f32::NAN, 1.0)),
        );
        scene.instances.push(Instance {
            mesh: 99,
            world: Mat4::IDENTITY,
            name: "missing".into(),
            style: Style::Inherit,
            node: None,
            skin: None,
        });
        let img = reference(&scene, &opts, 4, false).unwrap();
        // Camera at z = 3, 45 degrees: the plane z = 0 spans +-1.243 vertically, so the
        // good triangle's interior around (-0.7, -0.6) is at pixel (9, 22); (30, 10) is
        // where the NaN triangles would be.
        assert_eq!(img.rgb[22 * 40 + 9], [1.0; 3]);
        assert_eq!(img.rgb[10 * 40 + 30], background);
        assert!(img.rgb.iter().all(|c| c.iter().all(|v| v.is_finite())));
        let _ = raster(&scene, &opts, 2);
        // Refused requests.
        let bad = |o: &Shot, s: u32| reference(&scene, o, s, false).unwrap_err();
        assert_eq!(bad(&opts, 0), ReferenceError::Samples(0));
        assert_eq!(bad(&opts, 65), ReferenceError::Samples(65));
        let huge = Shot {
            width: 8192,
            height: 8192,
            ..opts.clone()
        };
        assert!(
            matches!(bad(&huge, 8), ReferenceError::TooLarge { total, .. } if total == 1 << 32)
        );
        let empty = Shot {
            width: 0,
            ..opts.clone()
        };
        assert!(matches!(bad(&empty, 1), ReferenceError::EmptyImage { .. }));
        for camera in [
            Camera {
                near: 0.0,
                ..Camera::default()
            },
            Camera {
                far: 0.05,
                ..Camera::default()
            },
            Camera {
                eye: Vec3::ZERO,
                ..Camera::default()
            },
            Camera {
                yfov: f32::NAN,
                ..Camera::default()
            },
        ] {
            let o = Shot {
                camera: Some(camera),
                ..opts.clone()
            };
            let e = bad(&o, 1);
            assert!(matches!(e, ReferenceError::Camera { .. }), "{e}");
        }
    }

    #[test]
    fn back_faces_culled_or_lit_from_behind() {
        // A square facing +Z seen from behind (camera at z = -3), lit along +Z from the
        // camera's side: only its back can be lit, with N.L = 1.
        let mut scene = Scene::default();
        let mut mat = flat_material(Vec3::splat(0.5), 1.0, AlphaMode::Opaque);
        scene.materials.push(mat.clone());
        place(&mut scene, square(0.0, 1.0, None, 0), Mat4::IDENTITY);
        scene.lights = vec![
            Light::directional(Vec3::Z, Vec3::splat(0.8)),
            Light::ambient(Vec3::splat(0.1)),
        ];
        let camera = Camera {
            eye: Vec3::new(0.0, 0.0, -3.0),
            ..Camera::default()
        };
        let opts = black(32, 32, Some(camera));
        let centre = |scene: &Scene, opts: &Shot| {
            reference(scene, opts, 2, false).unwrap().rgb[16 * 32 + 16]
        };
        assert_eq!(centre(&scene, &opts), [0.0; 3], "culled");
        let want = [0.1 * 0.5 + 0.8 * 0.5; 3];
        let both = Shot {
            settings: Settings {
                double_sided: true,
                ..opts.clone().settings
            },
            ..opts.clone()
        };
        assert!(close(centre(&scene, &both), want));
        mat.double_sided = true;
        scene.materials[0] = mat;
        assert!(close(centre(&scene, &opts), want));
        // A mirroring world matrix makes the same square front-facing from behind.
        scene.materials[0].double_sided = false;
        scene.instances[0].world = Mat4::from_scale(Vec3::new(1.0, 1.0, -1.0));
        assert!(close(centre(&scene, &opts), want));
        let m = de(
            &raster(&scene, &opts, 2),
            &reference(&scene, &opts, 2, false).unwrap(),
        );
        assert!(m.mean_de2000 < 1e-3, "{m:?}");
    }

    #[test]
    fn alpha_mask_discards_and_blending_follows_depth() {
        // Head-on: camera at z = 3. Back: an opaque red square at z = -1. Front: a masked
        // white square whose vertex alpha runs 0 -> 1 from left to right (cutoff 0.5), so
        // its left half is cut away and shows the red one behind it. Ambient light 1.
        let mut scene = Scene {
            lights: vec![Light::ambient(Vec3::ONE)],
            materials: vec![
                flat_material(Vec3::X, 1.0, AlphaMode::Opaque),
                flat_material(Vec3::splat(0.5), 1.0, AlphaMode::Mask(0.5)),
            ],
            ..Scene::default()
        };
        let ramp = [0.0, 1.0, 1.0, 0.0].map(|a| Vec4::new(1.0, 1.0, 1.0, a));
        place(&mut scene, square(-1.0, 10.0, None, 0), Mat4::IDENTITY);
        place(&mut scene, square(0.0, 5.0, Some(ramp), 1), Mat4::IDENTITY);
        let (w, h) = (40u32, 20u32);
        let opts = black(w, h, Some(Camera::default()));
        let img = reference(&scene, &opts, 4, false).unwrap();
        for y in 0..h {
            for x in 0..w {
                let c = img.rgb[(y * w + x) as usize];
                if x < w / 2 - 1 {
                    assert_eq!(c, [1.0, 0.0, 0.0], "({x}, {y})");
                } else if x > w / 2 {
                    assert!(close(c, [0.5; 3]), "({x}, {y}) {c:?}");
                }
            }
        }
        let m = de(
            &raster(&scene, &opts, 4),
            &reference(&scene, &opts, 4, false).unwrap(),
        );
        assert!(m.mean_de2000 < 1e-3, "{m:?}");

        // Blend: green at z = 0 and blue at z = -0.5, both alpha 0.5, over the red square,
        // listed near first. Per sample: red, then blue, then green over it.
        scene.materials = vec![
            flat_material(Vec3::X, 1.0, AlphaMode::Opaque),
            flat_material(Vec3::Y, 0.5, AlphaMode::Blend),
            flat_material(Vec3::Z, 0.5, AlphaMode::Blend),
        ];
        scene.meshes.truncate(1);
        scene.instances.truncate(1);
        place(&mut scene, square(0.0, 5.0, None, 1), Mat4::IDENTITY);
        place(&mut scene, square(-0.5, 5.0, None, 2), Mat4::IDENTITY);
        let img = reference(&scene, &opts, 2, false).unwrap();
        assert!(close(img.rgb[10 * w as usize + 20], [0.25, 0.5, 0.25]));
        let m = de(&raster(&scene, &opts, 2), &img);
        assert!(m.mean_de2000 < 1e-3, "{m:?}");
    }

    #[test]
    fn shared_edges_are_covered_exactly_once() {
        // Two blended triangles of a square, alpha 0.5 over black, head-on into a square
        // image: their shared diagonal projects to x = y exactly, through the samples with
        // i = j of the diagonal pixels, where both edge functions are exactly 0. Covered
        // once, every sample is 0.5; twice, 0.75; never, 0.
        let r = 2.0;
        let mut scene = Scene {
            lights: vec![Light::ambient(Vec3::ONE)],
            materials: vec![flat_material(Vec3::ONE, 0.5, AlphaMode::Blend)],
            ..Scene::default()
        };
        let mesh = Mesh::new(
            MeshData {
                name: "two triangles".into(),
                positions: vec![
                    Vec3::new(-r, -r, 0.0),
                    Vec3::new(r, -r, 0.0),
                    Vec3::new(r, r, 0.0),
                    Vec3::new(-r, r, 0.0),
                ],
                corners: vec![0, 1, 3, 1, 2, 3],
                material: Some(0),
                ..MeshData::default()
            },
            NormalPolicy::default(),
        )
        .unwrap();
        place(&mut scene, mesh, Mat4::IDENTITY);
        let opts = black(24, 24, Some(Camera::default()));
        let img = reference(&scene, &opts, 4, false).unwrap();
        assert!(
            img.rgb.iter().all(|&c| close(c, [0.5; 3])),
            "{:?}",
            img.rgb[0]
        );
        let ras = raster(&scene, &opts, 4);
        assert!(
            ras.rgb.iter().all(|&c| close(c, [0.5; 3])),
            "the rasterizer too"
        );
    }

    #[test]
    fn bands_and_threads_do_not_change_the_image() {
        let (mut scene, opts) = textured();
        // Add a masked and a blended square in front of everything.
        scene
            .materials
            .push(flat_material(Vec3::Y, 0.4, AlphaMode::Blend));
        scene
            .materials
            .push(flat_material(Vec3::X, 1.0, AlphaMode::Mask(0.5)));
        let ramp = [0.0, 1.0, 1.0, 0.0].map(|a| Vec4::new(1.0, 1.0, 1.0, a));
        place(&mut scene, square(0.8, 0.9, None, 2), Mat4::IDENTITY);
        place(
            &mut scene,
            square(0.5, 0.6, Some(ramp), 3),
            Mat4::from_translation(Vec3::X),
        );
        let opts = Shot {
            width: 61,
            height: 37,
            ..opts
        };
        let s = 3;
        let base = render(&scene, &opts, s, true, BAND_SAMPLES, ENV_SAMPLES).unwrap();
        // Sanity: both extras show.
        let m = de(&raster(&scene, &opts, 3), &base);
        assert!(m.mean_de2000 < 2e-3, "{m:?}");
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        assert_eq!(
            one.install(|| reference(&scene, &opts, s, true)).unwrap(),
            base
        );
        // One pixel per band, five pixels, part of a row, seven rows.
        for band in [1, 9 * 5, 9 * 50, 9 * 61 * 7] {
            assert_eq!(
                render(&scene, &opts, s, true, band, ENV_SAMPLES).unwrap(),
                base,
                "band {band}"
            );
        }
    }
}
