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
use crate::scene::{AlphaMode, Material, Scene, Slot, TextureSource, UvTransform};
use crate::shade::brdf::{self, Pbr};
use crate::shade::iridescence;
use crate::shade::layer_maps::LayerTexels;
use crate::shade::{illuminate, maps, Fog, LightSet, Surface, SurfaceAt};
use crate::texture::{Domain, Filter, SamplePoint, Sampler, Texels, Texture, Wrap};

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
        let zoom = 1.0 / libm::tan(yfov * 0.5);
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
            opts.settings.default_rig(scene),
            cam_to_world,
            &mut lights,
        );
        lights.env = opts.settings.environment.view();
        lights.single_scatter = opts.settings.single_scatter;
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
            tone: opts.settings.tone_for(scene),
            exposure: f64::from(opts.settings.exposure_scale()),
            background: opts.settings.background.truncate().as_dvec3(),
            blinn,
        })
    }
}

mod band;
mod coverage;
mod ibl;
mod instances;
#[cfg(test)]
mod tests;
mod texels;

use band::band;
use coverage::*;
use ibl::environment;
use instances::*;
pub(crate) use texels::texel;
use texels::*;
