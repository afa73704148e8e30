//! Analytic references (a sphere, a capped cylinder): ray-cast images that need no
//! rasterizer, and the matching rasterizer scenes at any tessellation.
//!
//! The reference shades the exact sphere with the lighting equation of
//! [`crate::shade::illuminate`] (same lights, material, eye) in f64 per sample. Pixels a
//! silhouette or a shading edge crosses (their four corners see different parts, dilated by
//! one pixel) take 16 x 16 samples, so coverage is exact to 1/256; pixels fully inside take
//! 4 x 4 samples of the smoothly varying shading (the box filter's midpoint error is below
//! 1e-5 for the default material); pixels fully outside are the background.

use glam::Vec3;
use rayon::prelude::*;

use super::LinearImage;
use crate::mesh::Mesh;
use crate::scene::{Camera, Instance, Light, Material, Scene, Style};
use crate::shade::{illuminate, LightSet, Surface};

/// Samples per side in silhouette pixels.
pub const EDGE_SAMPLES: u32 = 16;
/// Samples per side in interior pixels.
pub const INTERIOR_SAMPLES: u32 = 4;

/// The analytic shape of a reference scene.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Shape {
    /// Unit sphere at the origin (the textbook's latitude/longitude tessellation).
    #[default]
    Sphere,
    /// Capped cylinder of radius 1 from y = -1 to 1 (side normals radial, caps flat).
    Cylinder,
}

/// An analytic shape at the origin under a fixed camera and the default light rig.
#[derive(Clone, Debug)]
pub struct SphereSetup {
    pub shape: Shape,
    pub width: u32,
    pub height: u32,
    pub camera: Camera,
    pub lights: Vec<Light>,
    pub material: Material,
}

impl SphereSetup {
    /// The standard view: azimuth 35, elevation 25 degrees, distance 3.2, 45 degree FOV;
    /// the default light rig; grey diffuse 0.6 with a white Ks 0.4, n = 32 highlight.
    #[must_use]
    pub fn standard(width: u32, height: u32) -> Self {
        let camera = Camera::orbit(Vec3::ZERO, 35.0, 25.0, 3.2, crate::scene::DEFAULT_YFOV);
        let lights = Light::default_rig(glam::Mat3::from_mat4(camera.view().inverse()));
        let material = Material {
            specular: Vec3::splat(0.4),
            shininess: 32.0,
            ..Material::default()
        };
        Self {
            shape: Shape::Sphere,
            width,
            height,
            camera,
            lights,
            material,
        }
    }

    /// [`SphereSetup::standard`] for another shape.
    #[must_use]
    pub fn standard_shape(shape: Shape, width: u32, height: u32) -> Self {
        Self {
            shape,
            ..Self::standard(width, height)
        }
    }

    /// The rasterizer's scene: the textbook's latitude/longitude sphere (`slices` x `stacks`),
    /// or the capped cylinder with `slices` sides (`stacks` unused).
    ///
    /// # Errors
    /// If `slices` < 3 or `stacks` < 2 (or too many).
    pub fn scene(&self, slices: u32, stacks: u32) -> Result<Scene, crate::mesh::MeshError> {
        let mut mesh = match self.shape {
            Shape::Sphere => Mesh::sphere(1.0, slices, stacks)?,
            Shape::Cylinder => Mesh::cylinder(1.0, 2.0, slices, true)?,
        };
        mesh.material = Some(0);
        Ok(Scene {
            meshes: vec![mesh],
            materials: vec![self.material.clone()],
            instances: vec![Instance {
                mesh: 0,
                world: glam::Mat4::IDENTITY,
                name: "sphere".into(),
                style: Style::Inherit,
                node: None,
                skin: None,
                copies: None,
            }],
            lights: self.lights.clone(),
            ..Scene::default()
        })
    }

    /// The reference image (linear light, black background), Phong (R.V) or Blinn (N.H)
    /// highlights.
    #[must_use]
    pub fn reference(&self, blinn: bool) -> LinearImage {
        let (w, h) = (self.width, self.height);
        let rays = Rays::new(&self.camera, w, h);
        // Hit status of every pixel corner, (w + 1) x (h + 1).
        let shape = self.shape;
        let corners: Vec<u8> = (0..=h)
            .flat_map(|y| (0..=w).map(move |x| (x, y)))
            .map(|(x, y)| {
                hit(shape, &rays, f64::from(x), f64::from(y)).map_or(0, |(_, _, part)| part)
            })
            .collect();
        let cw = w as usize + 1;
        let mixed = |x: usize, y: usize| {
            let c = [
                corners[y * cw + x],
                corners[y * cw + x + 1],
                corners[(y + 1) * cw + x],
                corners[(y + 1) * cw + x + 1],
            ];
            c.iter().any(|&v| v != c[0])
        };
        let shade = Shade::new(self, blinn);
        let rgb = (0..h as usize)
            .into_par_iter()
            .flat_map_iter(|y| {
                let (rays, shade, corners) = (&rays, &shade, &corners);
                (0..w as usize).map(move |x| {
                    let edge = (y.saturating_sub(1)..=(y + 1).min(h as usize - 1)).any(|yy| {
                        (x.saturating_sub(1)..=(x + 1).min(w as usize - 1)).any(|xx| mixed(xx, yy))
                    });
                    if !edge && corners[y * cw + x] == 0 {
                        return [0.0; 3];
                    }
                    let n = if edge { EDGE_SAMPLES } else { INTERIOR_SAMPLES };
                    let mut sum = [0.0; 3];
                    for j in 0..n {
                        for i in 0..n {
                            let sx = x as f64 + (f64::from(i) + 0.5) / f64::from(n);
                            let sy = y as f64 + (f64::from(j) + 0.5) / f64::from(n);
                            if let Some((p, n, _)) = hit(shape, rays, sx, sy) {
                                let c = shade.at(p, n);
                                for k in 0..3 {
                                    sum[k] += c[k];
                                }
                            }
                        }
                    }
                    sum.map(|s| s / f64::from(n * n))
                })
            })
            .collect();
        LinearImage {
            width: w,
            height: h,
            rgb,
        }
    }
}

type V3 = [f64; 3];

fn v3(v: Vec3) -> V3 {
    [f64::from(v.x), f64::from(v.y), f64::from(v.z)]
}
fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn add_scaled(a: V3, b: V3, s: f64) -> V3 {
    [a[0] + b[0] * s, a[1] + b[1] * s, a[2] + b[2] * s]
}
fn normalize(a: V3) -> V3 {
    let l = dot(a, a).sqrt();
    if l > 0.0 {
        a.map(|v| v / l)
    } else {
        a
    }
}
fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Primary rays of the camera, in f64: pixel (x, y) with y down, as the rasterizer's
/// projection maps them.
struct Rays {
    eye: V3,
    forward: V3,
    right: V3,
    up: V3,
    width: f64,
    height: f64,
    /// tan(fov / 2).
    t: f64,
    aspect: f64,
}

impl Rays {
    fn new(cam: &Camera, w: u32, h: u32) -> Self {
        let eye = v3(cam.eye);
        let forward = normalize(sub(v3(cam.target), eye));
        let right = normalize(cross(forward, v3(cam.up)));
        let up = cross(right, forward);
        Self {
            eye,
            forward,
            right,
            up,
            width: f64::from(w),
            height: f64::from(h),
            t: 1.0 / f64::from(cam.zoom()),
            aspect: f64::from(w) / f64::from(h),
        }
    }

    fn dir(&self, x: f64, y: f64) -> V3 {
        let nx = 2.0 * x / self.width - 1.0;
        let ny = 1.0 - 2.0 * y / self.height;
        let d = add_scaled(self.forward, self.right, nx * self.aspect * self.t);
        add_scaled(d, self.up, ny * self.t)
    }
}

/// The nearest hit of the ray through (x, y) with `shape`: point, unit normal, and which
/// part was hit (1 = sphere or cylinder side, 2 = top cap, 3 = bottom cap), so that pixels
/// whose corners see different parts (shading edges) are supersampled like silhouettes.
fn hit(shape: Shape, r: &Rays, x: f64, y: f64) -> Option<(V3, V3, u8)> {
    let d = r.dir(x, y);
    match shape {
        Shape::Sphere => {
            let (a, b, c) = (dot(d, d), 2.0 * dot(r.eye, d), dot(r.eye, r.eye) - 1.0);
            let disc = b * b - 4.0 * a * c;
            if disc < 0.0 {
                return None;
            }
            let t = (-b - disc.sqrt()) / (2.0 * a);
            (t > 0.0).then(|| {
                let p = add_scaled(r.eye, d, t);
                (p, normalize(p), 1)
            })
        }
        Shape::Cylinder => {
            let mut best: Option<(f64, V3, u8)> = None;
            let mut take = |t: f64, n: V3, part: u8| {
                if t > 0.0 && best.is_none_or(|(bt, _, _)| t < bt) {
                    best = Some((t, n, part));
                }
            };
            // Side: x^2 + z^2 = 1 with |y| <= 1.
            let (e, o) = (r.eye, d);
            let a = o[0] * o[0] + o[2] * o[2];
            let b = 2.0 * (e[0] * o[0] + e[2] * o[2]);
            let c = e[0] * e[0] + e[2] * e[2] - 1.0;
            let disc = b * b - 4.0 * a * c;
            if a > 0.0 && disc >= 0.0 {
                for t in [
                    (-b - disc.sqrt()) / (2.0 * a),
                    (-b + disc.sqrt()) / (2.0 * a),
                ] {
                    let p = add_scaled(e, o, t);
                    if p[1].abs() <= 1.0 {
                        take(t, normalize([p[0], 0.0, p[2]]), 1);
                    }
                }
            }
            // Caps: y = +-1 with x^2 + z^2 <= 1.
            if o[1] != 0.0 {
                for (cap, n, part) in [(1.0, [0.0, 1.0, 0.0], 2u8), (-1.0, [0.0, -1.0, 0.0], 3)] {
                    let t = (cap - e[1]) / o[1];
                    let p = add_scaled(e, o, t);
                    if p[0] * p[0] + p[2] * p[2] <= 1.0 {
                        take(t, n, part);
                    }
                }
            }
            best.map(|(t, n, part)| (add_scaled(e, o, t), n, part))
        }
    }
}

/// The lighting equation in f64 (see [`crate::shade::illuminate`]).
/// The shared lighting model ([`crate::shade::illuminate`]) in f64 at the sphere's points.
struct Shade {
    lights: LightSet,
    surface: Surface,
    kd: glam::DVec3,
    eye: glam::DVec3,
    blinn: bool,
}

impl Shade {
    fn new(s: &SphereSetup, blinn: bool) -> Self {
        Self {
            lights: LightSet::new(&s.lights),
            surface: crate::render::material_surface(&s.material),
            kd: s.material.base_color.truncate().as_dvec3(),
            eye: s.camera.eye.as_dvec3(),
            blinn,
        }
    }

    fn at(&self, p: V3, n: V3) -> V3 {
        let surf = self.surface.at::<f64>(self.kd);
        let c = illuminate::<f64>(
            &self.lights,
            None,
            &surf,
            glam::DVec3::from_array(p),
            glam::DVec3::from_array(n),
            self.eye,
            self.blinn,
        );
        c.to_array()
    }
}
