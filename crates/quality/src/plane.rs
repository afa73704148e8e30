//! The textured-plane reference: a large textured floor seen at a grazing angle, filtered
//! exactly.
//!
//! The texture is taken as what its texels say it is: a picture made of constant-colour
//! squares (linear light, decoded exactly from sRGB). The plane is lit by ambient light and
//! one directional light with no highlight, so its radiance is the texel colour times one
//! constant and the exact value of a pixel is the box filter of the picture over the pixel's
//! footprint. A projective map sends every texel square to a convex quadrilateral on the
//! screen, so the reference clips each projected texel against each pixel square it touches
//! and adds colour x area: an exact box integral (to f64 rounding), with nothing sampled.
//! The plane is kept wholly in front of the camera, so no near-plane clipping is involved.
//!
//! Near the camera a texel covers a few pixels (magnification: nearest-texel sampling is
//! exact there, bilinear blurs the texel edges); towards the far edge a pixel covers
//! hundreds of texels (minification: any single sample aliases, the reference is their
//! area-weighted mean).

use std::sync::Arc;

use glam::{Vec2, Vec3, Vec4};
use rayon::prelude::*;

use super::LinearImage;
use crate::mesh::{Channel, Mesh, MeshData, NormalPolicy};
use crate::scene::{Camera, Instance, Light, Material, Scene, Style, TextureSlot};
use crate::texture::{Filter, Sampler, Texture};

/// Texels per side of the standard texture.
pub const TEXELS: u32 = 128;
/// World size of one repeat of the texture.
pub const REPEAT: f32 = 0.5;

/// A textured plane y = 0 under a fixed camera, ambient and one directional light.
#[derive(Clone, Debug)]
pub struct PlaneSetup {
    pub width: u32,
    pub height: u32,
    pub camera: Camera,
    pub lights: Vec<Light>,
    /// The texture (sRGB texels); its sampler's filter is set per render.
    pub texture: Arc<Texture>,
    /// Plane extent: x from `x.0` to `x.1`, z from `z.0` (far) to `z.1` (near).
    pub x: (f32, f32),
    pub z: (f32, f32),
}

impl PlaneSetup {
    /// The standard floor: 8 x 32 world units, the texture repeated every half unit (a texel
    /// is 1/256 unit, about one pixel at the bottom of a 1280x720 image and hundreds of
    /// texels per pixel at the far edge), seen from 1.2 units above at a distance of 1.9 to
    /// 33 units; the near edge is below the image, the far edge and the sides are visible.
    #[must_use]
    pub fn standard(width: u32, height: u32) -> Self {
        let camera = Camera {
            name: "plane".into(),
            eye: Vec3::new(0.0, 1.2, 3.0),
            target: Vec3::new(0.0, 0.0, -4.0),
            up: Vec3::Y,
            yfov: crate::scene::DEFAULT_YFOV,
            near: 0.05,
            far: 200.0,
            aspect: None,
            ortho: None,
            lens: Default::default(),
        };
        let lights = vec![
            Light::ambient(Vec3::splat(0.15)),
            Light::directional(Vec3::new(0.3, -1.0, -0.4).normalize(), Vec3::splat(0.85)),
        ];
        Self {
            width,
            height,
            camera,
            lights,
            texture: Arc::new(pattern(TEXELS)),
            x: (-4.0, 4.0),
            z: (-30.0, 2.0),
        }
    }

    /// The rasterizer's scene: one quad with the texture, its filter set to `filter`.
    #[must_use]
    pub fn scene(&self, filter: Filter) -> Scene {
        let (x0, x1) = self.x;
        let (z0, z1) = self.z;
        let positions = vec![
            Vec3::new(x0, 0.0, z1),
            Vec3::new(x1, 0.0, z1),
            Vec3::new(x1, 0.0, z0),
            Vec3::new(x0, 0.0, z0),
        ];
        let uvs = positions
            .iter()
            .map(|p| Vec2::new((p.x - x0) / REPEAT, (z1 - p.z) / REPEAT))
            .collect();
        let data = MeshData {
            name: "plane".into(),
            positions,
            corners: vec![0, 1, 2, 3],
            facet_sizes: Some(vec![4]),
            normals: Some(Channel::per_vertex(vec![Vec3::Y; 4])),
            uvs: vec![Channel::per_vertex(uvs)],
            colors: None,
            tangents: None,
            material: Some(0),
        };
        let mesh = Mesh::new(data, NormalPolicy::default())
            .expect("the plane's mesh data is consistent by construction");
        let texture = (*self.texture).clone();
        Scene {
            meshes: vec![mesh],
            materials: vec![Material {
                name: "floor".into(),
                base_color: Vec4::ONE,
                base_color_texture: Some(TextureSlot {
                    sampler: Sampler {
                        filter,
                        ..Sampler::default()
                    },
                    ..TextureSlot::new(0)
                }),
                ambient: Vec3::ONE,
                specular: Vec3::ZERO,
                ..Material::default()
            }],
            textures: vec![Arc::new(texture)],
            instances: vec![Instance {
                mesh: 0,
                world: glam::Mat4::IDENTITY,
                name: "plane".into(),
                style: Style::Inherit,
                node: None,
                skin: None,
                copies: None,
            }],
            lights: self.lights.clone(),
            ..Scene::default()
        }
    }

    /// Radiance per unit albedo of the plane (normal +Y, no highlight) by the shared
    /// lighting model in f64, per channel. Constant over the plane for the standard
    /// set-up's directional lights.
    fn irradiance(&self) -> [f64; 3] {
        let set = crate::shade::LightSet::new(&self.lights);
        let surface = crate::shade::Surface {
            diffuse: Vec3::ONE,
            specular: Vec3::ZERO,
            ambient: Vec3::ONE,
            shininess: 1.0,
            pbr: None,
        };
        let surf = surface.at::<f64>(glam::DVec3::ONE);
        let c = crate::shade::illuminate::<f64>(
            &set,
            None,
            &surf,
            glam::DVec3::ZERO,
            glam::DVec3::Y,
            self.camera.eye.as_dvec3(),
            false,
        );
        c.to_array()
    }

    /// The exact reference (linear light, black background).
    #[must_use]
    pub fn reference(&self) -> LinearImage {
        let (w, h) = (self.width as usize, self.height as usize);
        let tex = &self.texture;
        let (tw, th) = (tex.width as usize, tex.height as usize);
        let k = self.irradiance();
        let albedo: Vec<[f64; 3]> = (0..th as u32)
            .flat_map(|y| (0..tw as u32).map(move |x| (x, y)))
            .map(|(x, y)| {
                let c = super::general::texel(tex, x, y);
                [c.x * k[0], c.y * k[1], c.z * k[2]]
            })
            .collect();
        // Texel grid lines over the whole plane: u columns, v rows (v grows away from the
        // near edge). Texel rows in chunks, each projecting its grid rows and accumulating
        // into its own image; the images are summed at the end.
        let nu =
            ((f64::from(self.x.1 - self.x.0) / f64::from(REPEAT)) * tw as f64).round() as usize;
        let nv =
            ((f64::from(self.z.1 - self.z.0) / f64::from(REPEAT)) * th as f64).round() as usize;
        let proj = Projector::new(&self.camera, self.width, self.height);
        let texel = f64::from(REPEAT) / tw as f64;
        let (x0, z1) = (f64::from(self.x.0), f64::from(self.z.1));
        let grid_row = |j: usize| -> Vec<[f64; 2]> {
            (0..=nu)
                .map(|i| proj.screen([x0 + i as f64 * texel, 0.0, z1 - j as f64 * texel]))
                .collect()
        };
        let chunks = rayon::current_num_threads().max(1) * 4;
        let rows_per = nv.div_ceil(chunks).max(1);
        let acc = (0..nv.div_ceil(rows_per))
            .into_par_iter()
            .map(|c| {
                let mut img = vec![[0.0f64; 4]; w * h];
                let (j0, j1) = (c * rows_per, ((c + 1) * rows_per).min(nv));
                let mut near = grid_row(j0);
                for j in j0..j1 {
                    let far = grid_row(j + 1);
                    for i in 0..nu {
                        let q = [near[i], near[i + 1], far[i + 1], far[i]];
                        let col = albedo[(j % th) * tw + (i % tw)];
                        splat(&mut img, w, h, &q, col);
                    }
                    near = far;
                }
                img
            })
            .reduce_with(|mut a, b| {
                for (x, y) in a.iter_mut().zip(&b) {
                    for k in 0..4 {
                        x[k] += y[k];
                    }
                }
                a
            })
            .unwrap_or_else(|| vec![[0.0; 4]; w * h]);
        // Black background: the uncovered part of a pixel adds nothing.
        LinearImage {
            width: self.width,
            height: self.height,
            rgb: acc.iter().map(|a| [a[0], a[1], a[2]]).collect(),
        }
    }
}

/// The plane's four corners on the screen (pixels, y down) and the part of its area that
/// lies inside the image: what the reference's coverage must add up to.
#[must_use]
pub fn visible_area(setup: &PlaneSetup) -> f64 {
    let p = Projector::new(&setup.camera, setup.width, setup.height);
    let (x0, x1) = (f64::from(setup.x.0), f64::from(setup.x.1));
    let (z0, z1) = (f64::from(setup.z.0), f64::from(setup.z.1));
    let q = [
        p.screen([x0, 0.0, z1]),
        p.screen([x1, 0.0, z1]),
        p.screen([x1, 0.0, z0]),
        p.screen([x0, 0.0, z0]),
    ];
    rect_area(
        &q,
        [0.0, 0.0, f64::from(setup.width), f64::from(setup.height)],
    )
}

/// The standard texture: a chequerboard of 16-texel squares in a light and a dark colour,
/// crossed every 8 texels by one-texel lines in a saturated red: large flat areas, hard
/// edges and thin lines, all of which alias when minified.
#[must_use]
pub fn pattern(size: u32) -> Texture {
    let light = [226, 221, 204, 255];
    let dark = [52, 66, 98, 255];
    let line = [205, 52, 38, 255];
    let texels = (0..size * size)
        .map(|i| {
            let (x, y) = (i % size, i / size);
            if x % 8 == 7 || y % 8 == 7 {
                line
            } else if (x / 16 + y / 16) % 2 == 0 {
                light
            } else {
                dark
            }
        })
        .collect();
    Texture::new("plane-pattern", size, size, texels, true)
        .expect("the pattern has size x size texels")
}

/// World -> screen pixels in f64 (x right, y down), as the rasterizer's projection maps
/// them.
struct Projector {
    eye: [f64; 3],
    right: [f64; 3],
    up: [f64; 3],
    forward: [f64; 3],
    /// Pixels per unit of tangent, horizontally and vertically.
    fx: f64,
    fy: f64,
    cx: f64,
    cy: f64,
}

impl Projector {
    fn new(cam: &Camera, w: u32, h: u32) -> Self {
        let eye = cam.eye.as_dvec3();
        let forward = (cam.target.as_dvec3() - eye).normalize();
        let right = forward.cross(cam.up.as_dvec3()).normalize();
        let up = right.cross(forward);
        let t = 1.0 / f64::from(cam.zoom());
        let (wf, hf) = (f64::from(w), f64::from(h));
        Self {
            eye: eye.to_array(),
            right: right.to_array(),
            up: up.to_array(),
            forward: forward.to_array(),
            fx: wf / 2.0 / (t * wf / hf),
            fy: hf / 2.0 / t,
            cx: wf / 2.0,
            cy: hf / 2.0,
        }
    }

    fn screen(&self, p: [f64; 3]) -> [f64; 2] {
        let d = [p[0] - self.eye[0], p[1] - self.eye[1], p[2] - self.eye[2]];
        let dot = |a: [f64; 3]| a[0] * d[0] + a[1] * d[1] + a[2] * d[2];
        let z = dot(self.forward);
        [
            self.cx + self.fx * dot(self.right) / z,
            self.cy - self.fy * dot(self.up) / z,
        ]
    }
}

/// Adds `col` x (area of the convex quad `q` inside each pixel) to `img` (RGB + coverage).
fn splat(img: &mut [[f64; 4]], w: usize, h: usize, q: &[[f64; 2]; 4], col: [f64; 3]) {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in q {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    if !(lo[0] < w as f64 && lo[1] < h as f64 && hi[0] > 0.0 && hi[1] > 0.0) {
        return;
    }
    let px0 = lo[0].floor().max(0.0) as usize;
    let py0 = lo[1].floor().max(0.0) as usize;
    let px1 = (hi[0].ceil() as usize).min(w);
    let py1 = (hi[1].ceil() as usize).min(h);
    let mut add = |x: usize, y: usize, a: f64| {
        let p = &mut img[y * w + x];
        p[0] += col[0] * a;
        p[1] += col[1] * a;
        p[2] += col[2] * a;
        p[3] += a;
    };
    if px1 - px0 == 1 && py1 - py0 == 1 {
        // Wholly inside one pixel (most minified texels).
        add(px0, py0, polygon_area(q));
        return;
    }
    for y in py0..py1 {
        for x in px0..px1 {
            let a = clipped_area(q, x as f64, y as f64);
            if a > 0.0 {
                add(x, y, a);
            }
        }
    }
}

/// Absolute area of a polygon (shoelace).
fn polygon_area(p: &[[f64; 2]]) -> f64 {
    let mut s = 0.0;
    for i in 0..p.len() {
        let (a, b) = (p[i], p[(i + 1) % p.len()]);
        s += a[0] * b[1] - a[1] * b[0];
    }
    0.5 * s.abs()
}

/// Area of the convex quad `q` inside the pixel square [x, x+1] x [y, y+1].
fn clipped_area(q: &[[f64; 2]; 4], x: f64, y: f64) -> f64 {
    rect_area(q, [x, y, x + 1.0, y + 1.0])
}

/// Area of the convex polygon `q` inside the rectangle [r0, r2] x [r1, r3]
/// (Sutherland-Hodgman against the four sides).
fn rect_area(q: &[[f64; 2]], r: [f64; 4]) -> f64 {
    let mut poly: Vec<[f64; 2]> = q.to_vec();
    // (axis, bound, keep the side >= bound)
    for (axis, bound, above) in [
        (0, r[0], true),
        (0, r[2], false),
        (1, r[1], true),
        (1, r[3], false),
    ] {
        if poly.is_empty() {
            return 0.0;
        }
        let inside = |p: &[f64; 2]| {
            if above {
                p[axis] >= bound
            } else {
                p[axis] <= bound
            }
        };
        let mut out = Vec::with_capacity(poly.len() + 2);
        let cut = |i: &[f64; 2], o: &[f64; 2]| {
            let t = (bound - i[axis]) / (o[axis] - i[axis]);
            let mut p = [i[0] + (o[0] - i[0]) * t, i[1] + (o[1] - i[1]) * t];
            p[axis] = bound;
            p
        };
        crate::geom::clip_polygon(&poly, inside, cut, &mut out);
        poly = out;
    }
    if poly.len() < 3 {
        0.0
    } else {
        polygon_area(&poly)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clipping_areas() {
        let sq = [[0.25, 0.25], [1.75, 0.25], [1.75, 1.75], [0.25, 1.75]];
        assert!((clipped_area(&sq, 0.0, 0.0) - 0.5625).abs() < 1e-15);
        assert!((clipped_area(&sq, 1.0, 0.0) - 0.5625).abs() < 1e-15);
        assert!((clipped_area(&sq, 1.0, 1.0) - 0.5625).abs() < 1e-15);
        assert_eq!(clipped_area(&sq, 2.0, 0.0), 0.0);
        // A diamond over four pixels splits its area 2 into quarters.
        let d = [[1.0, 0.0], [2.0, 1.0], [1.0, 2.0], [0.0, 1.0]];
        let parts: Vec<f64> = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
            .iter()
            .map(|&(x, y)| clipped_area(&d, x, y))
            .collect();
        assert!(parts.iter().all(|a| (a - 0.5).abs() < 1e-15), "{parts:?}");
        assert!((polygon_area(&d) - 2.0).abs() < 1e-15);
    }
}
