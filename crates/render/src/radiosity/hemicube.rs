//! The hemicube: the form factors from a point to every patch, its five faces drawn by
//! realist's own rasterizer (one patch number per pixel) and the pixels' delta form factors summed.

use glam::{Mat4, Vec3, Vec4};

use super::Patch;
use crate::raster::{self, Batch, Cull, Draw, DrawState, FragmentShader, Stats, Target};
use crate::scene::Camera;

/// Writes the interpolated varyings (a patch number) as the colour.
struct Numbers;

impl FragmentShader for Numbers {
    fn colour_is_varyings(&self, _: u32) -> bool {
        true
    }

    fn discards(&self, _: u32) -> bool {
        false
    }

    fn shade(&self, _: &mut Batch) {}
}

/// A hemicube's faces for one patch, kept between shots.
pub struct Hemicube {
    res: u32,
    target: Target,
    clip: Vec<Vec4>,
    varyings: Vec<f32>,
    triangles: Vec<[u32; 3]>,
    /// Delta form factors of the top face's pixels and of a side face's (upper half).
    top: Vec<f32>,
    side: Vec<f32>,
    pub(super) sums: Vec<f32>,
    /// The rasterizer's memory, kept between shots.
    bins: raster::Bins,
    scratch: raster::RasterScratch,
}

impl Hemicube {
    /// A hemicube of `res` x `res` pixels on its top face (at least 8, even).
    #[must_use]
    pub fn new(res: u32) -> Self {
        let res = (res.max(8) + 1) & !1;
        let n = res as usize;
        let d = 2.0 / res as f32;
        let mut top = vec![0.0; n * n];
        let mut side = vec![0.0; n * n / 2];
        for j in 0..n {
            for i in 0..n {
                let x = -1.0 + (i as f32 + 0.5) * d;
                let y = -1.0 + (j as f32 + 0.5) * d;
                let r = x * x + y * y + 1.0;
                top[j * n + i] = d * d / (std::f32::consts::PI * r * r);
            }
        }
        // Side faces: rows from the top (z = 1, along the normal) down to the horizon.
        for j in 0..n / 2 {
            for i in 0..n {
                let x = -1.0 + (i as f32 + 0.5) * d;
                let z = 1.0 - (j as f32 + 0.5) * d;
                let r = x * x + z * z + 1.0;
                side[j * n + i] = z * d * d / (std::f32::consts::PI * r * r);
            }
        }
        Self {
            res,
            target: Target::new(res, res, Vec4::ZERO),
            clip: Vec::new(),
            varyings: Vec::new(),
            triangles: Vec::new(),
            top,
            side,
            sums: Vec::new(),
            bins: raster::Bins::default(),
            scratch: raster::RasterScratch::default(),
        }
    }

    /// The form factors from a point at `p` with unit normal `n` to every patch it sees
    /// (`F[j]`, summed over the hemicube's pixels). `near`: how far in front of the point
    /// the faces start (a patch nearer than that is not seen).
    pub fn form_factors(&mut self, patches: &[Patch], p: Vec3, n: Vec3, near: f32) -> &[f32] {
        self.sums.clear();
        self.sums.resize(patches.len(), 0.0);
        self.add_form_factors(patches, p, n, near, 0.0, 1.0);
        &self.sums
    }

    /// Adds `weight` times the form factors from `p` (unit normal `n`) to the sums, the
    /// cube turned by `spin` radians about `n`.
    fn add_form_factors(
        &mut self,
        patches: &[Patch],
        p: Vec3,
        n: Vec3,
        near: f32,
        spin: f32,
        weight: f32,
    ) {
        let up = if n.cross(Vec3::Y).length_squared() > 1e-3 {
            Vec3::Y
        } else {
            Vec3::X
        };
        let (t0, b0) = {
            let t = n.cross(up).normalize();
            (t, n.cross(t))
        };
        let (sin, cos) = libm::sincosf(spin);
        let t = t0 * cos + b0 * sin;
        let b = b0 * cos - t0 * sin;
        let far = patches
            .iter()
            .flat_map(|q| q.corners)
            .map(|c| (c - p).length())
            .fold(near * 2.0, f32::max)
            * 1.01;
        // The top face looks along n; the sides along ±t, ±b with n as their up.
        let faces = [(n, t), (t, n), (-t, n), (b, n), (-b, n)];
        for (k, (look, up)) in faces.into_iter().enumerate() {
            let cam = Camera {
                name: String::new(),
                eye: p,
                target: p + look,
                up,
                yfov: std::f32::consts::FRAC_PI_2,
                near,
                far,
                aspect: Some(1.0),
                ortho: None,
                lens: Default::default(),
            };
            let vp: Mat4 = cam.projection(1.0) * cam.view();
            self.draw(patches, vp, p, n);
            let n_px = self.res as usize;
            let rows = if k == 0 { n_px } else { n_px / 2 };
            for j in 0..rows {
                for i in 0..n_px {
                    let (t, o) = self.target.locate(i as u32, j as u32);
                    let c = self.target.tiles[t].color_at(o);
                    // (Numbers from 1; truncating x + 0.5 rounds what is not negative.)
                    let id = (c.x + 0.5) as i64 - 1;
                    if id < 0 || id as usize >= patches.len() {
                        continue;
                    }
                    let w = if k == 0 {
                        self.top[j * n_px + i]
                    } else {
                        self.side[j * n_px + i]
                    };
                    self.sums[id as usize] += w * weight;
                }
            }
        }
    }

    /// The form factors from triangle `shooter` (unit normal `n`) to every patch: from one
    /// point, its centroid, or (`views` 4) averaged over the centroids of its four
    /// midpoint-cut parts, each cube turned by a different angle about `n`, so that the
    /// pixels' aliasing on small, far elements, which one cube prints on the whole scene
    /// as streaks, averages out where a shot carries much of the light.
    pub fn form_factors_from(
        &mut self,
        patches: &[Patch],
        shooter: [Vec3; 3],
        n: Vec3,
        near: f32,
        views: usize,
    ) -> &[f32] {
        self.sums.clear();
        self.sums.resize(patches.len(), 0.0);
        let [a, b, c] = shooter;
        let centre = (a + b + c) / 3.0;
        let (ab, bc, ca) = ((a + b) * 0.5, (b + c) * 0.5, (c + a) * 0.5);
        let parts = [
            (a + ab + ca) / 3.0,
            (ab + b + bc) / 3.0,
            (ca + bc + c) / 3.0,
            (ab + bc + ca) / 3.0,
        ];
        if views >= parts.len() {
            let weight = 1.0 / parts.len() as f32;
            for (k, q) in parts.into_iter().enumerate() {
                // Quarter turns would repeat the pixel grid: spread over one quarter.
                let spin = std::f32::consts::FRAC_PI_2 * (k as f32 + 0.5) / parts.len() as f32;
                self.add_form_factors(patches, q + n * near, n, near, spin, weight);
            }
        } else {
            self.add_form_factors(patches, centre + n * near, n, near, 0.0, 1.0);
        }
        &self.sums
    }

    /// Every patch in front of the plane through `p` with normal `n` into the target, its
    /// number plus one as its colour.
    fn draw(&mut self, patches: &[Patch], vp: Mat4, p: Vec3, n: Vec3) {
        self.clip.clear();
        self.varyings.clear();
        self.triangles.clear();
        for (k, q) in patches.iter().enumerate() {
            if q.corners.iter().all(|c| (*c - p).dot(n) <= 0.0) {
                continue;
            }
            let id = (k + 1) as f32;
            let base = self.clip.len() as u32;
            for c in q.corners {
                self.clip.push(vp * c.extend(1.0));
                self.varyings.extend_from_slice(&[id, id, id]);
            }
            self.triangles.push([base, base + 1, base + 2]);
        }
        self.target.clear(Vec4::ZERO);
        let draw = Draw {
            id: 0,
            clip: &self.clip,
            varyings: &self.varyings,
            stride: 3,
            triangles: &self.triangles,
            state: DrawState {
                cull: Cull::None,
                ..DrawState::opaque()
            },
            sections: &[],
        };
        let mut stats = Stats::default();
        raster::draw_list(
            &mut self.target,
            &[draw][..],
            &Numbers,
            &mut stats,
            &mut self.bins,
            &mut self.scratch,
            &|| false,
        );
    }
}
