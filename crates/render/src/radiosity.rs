//! Radiosity (the textbook's §9.6.3): the diffuse light between surfaces, solved once for
//! the whole scene and independent of the view. The surfaces are cut into patches; each
//! patch's radiosity `B = E + ρ Σ F B` (emission plus the reflected share of what every
//! other patch sends it, by the form factors `F`). Progressive refinement (Cohen et al.
//! 1988) shoots: the patch with the most unshot power sends it to every patch it sees, by
//! form factors from a hemicube (Cohen and Greenberg 1985) drawn by realist's own
//! rasterizer, one patch number per pixel, and the pixels' delta form factors summed per
//! patch.

use glam::{Mat4, Vec3, Vec4};

use crate::raster::{self, Batch, Cull, Draw, DrawState, FragmentShader, Stats, Target};
use crate::scene::Camera;

/// One patch: a triangle with its reflectance, emission and radiosity (RGB, W/m² per
/// unit: a Lambertian surface of radiosity B has radiance B/π).
#[derive(Clone, Debug)]
pub struct Patch {
    pub corners: [Vec3; 3],
    pub reflectance: Vec3,
    pub emission: Vec3,
    /// Radiosity found so far.
    pub radiosity: Vec3,
    /// Radiosity received but not yet shot on.
    pub unshot: Vec3,
}

impl Patch {
    #[must_use]
    pub fn new(corners: [Vec3; 3], reflectance: Vec3, emission: Vec3) -> Self {
        Self {
            corners,
            reflectance,
            emission,
            radiosity: emission,
            unshot: emission,
        }
    }

    #[must_use]
    pub fn area(&self) -> f32 {
        let [a, b, c] = self.corners;
        0.5 * (b - a).cross(c - a).length()
    }

    #[must_use]
    pub fn centre(&self) -> Vec3 {
        (self.corners[0] + self.corners[1] + self.corners[2]) / 3.0
    }

    /// Unit normal of the counter-clockwise side (the side that emits and receives).
    #[must_use]
    pub fn normal(&self) -> Vec3 {
        let [a, b, c] = self.corners;
        (b - a).cross(c - a).normalize_or_zero()
    }
}

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
    sums: Vec<f32>,
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
        }
    }

    /// The form factors from a point at `p` with unit normal `n` to every patch it sees
    /// (`F[j]`, summed over the hemicube's pixels). `near`: how far in front of the point
    /// the faces start (a patch nearer than that is not seen).
    pub fn form_factors(&mut self, patches: &[Patch], p: Vec3, n: Vec3, near: f32) -> &[f32] {
        self.sums.clear();
        self.sums.resize(patches.len(), 0.0);
        let up = if n.cross(Vec3::Y).length_squared() > 1e-3 {
            Vec3::Y
        } else {
            Vec3::X
        };
        let t = n.cross(up).normalize();
        let b = n.cross(t);
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
            };
            let vp: Mat4 = cam.projection(1.0) * cam.view();
            self.draw(patches, vp);
            let fb = self.target.resolve();
            let n_px = self.res as usize;
            let rows = if k == 0 { n_px } else { n_px / 2 };
            for j in 0..rows {
                for i in 0..n_px {
                    let c = fb.color[j * n_px + i];
                    let id = c.x.round() as i64 - 1;
                    if id < 0 || id as usize >= patches.len() {
                        continue;
                    }
                    let w = if k == 0 {
                        self.top[j * n_px + i]
                    } else {
                        self.side[j * n_px + i]
                    };
                    self.sums[id as usize] += w;
                }
            }
        }
        &self.sums
    }

    /// Every patch into the target, its number plus one as its colour.
    fn draw(&mut self, patches: &[Patch], vp: Mat4) {
        self.clip.clear();
        self.varyings.clear();
        self.triangles.clear();
        for (k, q) in patches.iter().enumerate() {
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
        raster::draw(&mut self.target, &[draw], &Numbers, &mut stats);
    }
}

/// How a solution ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Solved {
    pub shots: usize,
    /// The unshot power left, as a share of the power emitted.
    pub unshot: f32,
}

fn power(c: Vec3) -> f32 {
    c.x + c.y + c.z
}

/// Progressive refinement: shoots from the patch with the most unshot power until what is
/// left is below `tolerance` of what was emitted, or `max_shots` shots.
pub fn solve(
    patches: &mut [Patch],
    cube: &mut Hemicube,
    tolerance: f32,
    max_shots: usize,
) -> Solved {
    let emitted: f32 = patches.iter().map(|q| power(q.emission) * q.area()).sum();
    let size = patches
        .iter()
        .flat_map(|q| q.corners)
        .fold(0.0f32, |m, c| m.max(c.abs().max_element()));
    let near = 1e-4 * size.max(1e-6);
    let mut shots = 0;
    loop {
        let (i, left) = patches
            .iter()
            .enumerate()
            .map(|(k, q)| (k, power(q.unshot) * q.area()))
            .fold((0, 0.0f32), |a, b| if b.1 > a.1 { b } else { a });
        if shots >= max_shots || left <= tolerance * emitted || left <= 0.0 {
            let rest: f32 = patches.iter().map(|q| power(q.unshot) * q.area()).sum();
            return Solved {
                shots,
                unshot: if emitted > 0.0 { rest / emitted } else { 0.0 },
            };
        }
        let (p, n, area, shot) = {
            let q = &patches[i];
            (q.centre(), q.normal(), q.area(), q.unshot)
        };
        let ff = cube.form_factors(patches, p + n * near, n, near).to_vec();
        for (j, f) in ff.into_iter().enumerate() {
            if f <= 0.0 || j == i {
                continue;
            }
            let aj = patches[j].area();
            if aj <= 0.0 {
                continue;
            }
            let q = &mut patches[j];
            let d = q.reflectance * shot * (f * area / aj);
            q.radiosity += d;
            q.unshot += d;
        }
        patches[i].unshot = Vec3::ZERO;
        shots += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A square `size` wide in the plane y = `y`, cut into `n` x `n` cells of two
    /// triangles, facing `+y` (`up`) or `-y`.
    fn square(y: f32, size: f32, n: usize, up: bool, rho: f32, e: f32) -> Vec<Patch> {
        let mut out = Vec::new();
        let h = size / n as f32;
        for j in 0..n {
            for i in 0..n {
                let (x0, z0) = (-size / 2.0 + i as f32 * h, -size / 2.0 + j as f32 * h);
                let p = |a: f32, b: f32| Vec3::new(x0 + a * h, y, z0 + b * h);
                let (a, b, c, d) = (p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0), p(0.0, 1.0));
                let tris = if up {
                    [[a, d, c], [a, c, b]]
                } else {
                    [[a, b, c], [a, c, d]]
                };
                for t in tris {
                    out.push(Patch::new(t, Vec3::splat(rho), Vec3::splat(e)));
                }
            }
        }
        out
    }

    /// Two parallel, directly opposed unit squares one apart: the form factor between them
    /// is 0.199825 (Howell's catalogue, case C-11). Averaged over the first square's cells
    /// (each a hemicube at its centre), the hemicube gives it within 1 %.
    #[test]
    fn form_factor_of_parallel_squares_matches_the_closed_form() {
        let lower = square(0.0, 1.0, 8, true, 0.5, 0.0);
        let upper = square(1.0, 1.0, 4, false, 0.5, 0.0);
        let n_lower = lower.len();
        let mut all = lower;
        all.extend(upper);
        assert!(all[0].normal().y > 0.99 && all[n_lower].normal().y < -0.99);
        let mut cube = Hemicube::new(256);
        let (mut f, mut area) = (0.0f64, 0.0f64);
        for k in 0..n_lower {
            let (p, n, a) = (all[k].centre(), all[k].normal(), all[k].area());
            let ff = cube.form_factors(&all, p + n * 1e-5, n, 1e-5);
            let to_upper: f32 = ff[n_lower..].iter().sum();
            f += f64::from(to_upper) * f64::from(a);
            area += f64::from(a);
        }
        let f = f / area;
        let want = 0.199_825;
        eprintln!("parallel unit squares: hemicube {f:.5}, closed form {want}");
        assert!((f - want).abs() < 0.01 * want, "{f} against {want}");
    }

    /// A closed white room (a cube seen from inside, reflectance 0.6) with one emitting
    /// cell: every shot's form factors sum to 1 (the room is closed), and at the end the
    /// power absorbed plus the power still unshot is the power emitted.
    #[test]
    fn a_closed_room_conserves_energy() {
        let rho = 0.6;
        let mut room = Vec::new();
        for (axis, sign) in [
            (0usize, 1.0f32),
            (0, -1.0),
            (1, 1.0),
            (1, -1.0),
            (2, 1.0),
            (2, -1.0),
        ] {
            // A face of the cube [-1, 1]³ at coordinate `sign` on `axis`, facing inwards.
            for t in square(0.0, 2.0, 6, sign < 0.0, rho, 0.0) {
                let corners = t.corners.map(|c| {
                    let (u, w) = (c.x, c.z);
                    let mut v = [0.0f32; 3];
                    v[axis] = sign;
                    v[(axis + 1) % 3] = u;
                    v[(axis + 2) % 3] = w;
                    Vec3::from_array(v)
                });
                // Keep the triangle facing the room's centre.
                let mut q = Patch::new(corners, Vec3::splat(rho), Vec3::ZERO);
                if q.normal().dot(-q.centre()) < 0.0 {
                    q.corners.swap(1, 2);
                }
                room.push(q);
            }
        }
        room[5] = Patch::new(room[5].corners, Vec3::splat(rho), Vec3::splat(10.0));
        let mut cube = Hemicube::new(128);
        // Closed: the form factors from any patch sum to 1.
        for k in [0, 40, 100, 200] {
            let (p, n) = (room[k].centre(), room[k].normal());
            let sum: f32 = cube.form_factors(&room, p + n * 1e-5, n, 1e-5).iter().sum();
            assert!(
                (sum - 1.0).abs() < 5e-3,
                "patch {k}: form factors sum to {sum}"
            );
        }
        let emitted: f64 = room
            .iter()
            .map(|q| f64::from(power(q.emission) * q.area()))
            .sum();
        let solved = solve(&mut room, &mut cube, 1e-3, 2000);
        // Absorbed: (1 - ρ) of what each patch received, H = (B - E) / ρ.
        let absorbed: f64 = room
            .iter()
            .map(|q| {
                let h = (power(q.radiosity) - power(q.emission)) / rho;
                f64::from((1.0 - rho) * h * q.area())
            })
            .sum();
        let unshot: f64 = room
            .iter()
            .map(|q| f64::from(power(q.unshot) * q.area()))
            .sum();
        eprintln!(
            "closed room: {} shots, emitted {emitted:.3}, absorbed {absorbed:.3}, unshot {unshot:.4}",
            solved.shots
        );
        assert!(
            (absorbed + unshot - emitted).abs() < 0.01 * emitted,
            "absorbed {absorbed} + unshot {unshot} against emitted {emitted}"
        );
    }
}
