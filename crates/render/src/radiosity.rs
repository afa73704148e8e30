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
    /// The patch this element was cut from ([`solve_grouped`] shoots from those), its
    /// own index when it was not cut.
    pub group: usize,
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
            group: 0,
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
        let (sin, cos) = spin.sin_cos();
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

/// How a solution ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Solved {
    pub shots: usize,
    /// The unshot power left, as a share of the power emitted.
    pub unshot: f32,
    /// The share of the power shot that met a patch (1 in a closed room; the rest left
    /// the scene), over all shots (1 if none was shot).
    pub closure: f32,
}

fn power(c: Vec3) -> f32 {
    c.x + c.y + c.z
}

/// Progressive refinement: shoots from the patch with the most unshot power until the
/// power left unshot is below `tolerance` of what there was to shoot at the start (the
/// emission and any light already received), or after `max_shots` hemicubes (a shot
/// carrying much of the light draws four).
pub fn solve(
    patches: &mut [Patch],
    cube: &mut Hemicube,
    tolerance: f32,
    max_shots: usize,
) -> Solved {
    for (k, q) in patches.iter_mut().enumerate() {
        q.group = k;
    }
    let shooters: Vec<[Vec3; 3]> = patches.iter().map(|q| q.corners).collect();
    solve_grouped(patches, &shooters, cube, tolerance, max_shots)
}

/// [`solve`] with patches and elements (Cohen et al. 1986): light is received by the
/// elements (`elements`, each in group `group` of `shooters`) and shot from the patches
/// they were cut from, each with its elements' unshot power: shots as few as the patches,
/// shading as fine as the elements.
pub fn solve_grouped(
    elements: &mut [Patch],
    shooters: &[[Vec3; 3]],
    cube: &mut Hemicube,
    tolerance: f32,
    max_shots: usize,
) -> Solved {
    let patches = elements;
    let emitted: f32 = patches.iter().map(|q| power(q.unshot) * q.area()).sum();
    let size = patches
        .iter()
        .flat_map(|q| q.corners)
        .fold(0.0f32, |m, c| m.max(c.abs().max_element()));
    let near = 1e-4 * size.max(1e-6);
    // Per group: its elements, and its unshot power (area-weighted).
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); shooters.len()];
    for (k, q) in patches.iter().enumerate() {
        if let Some(m) = members.get_mut(q.group) {
            m.push(k);
        }
    }
    // Shots, and hemicubes drawn (the work `max_shots` bounds: a shot may draw four).
    let (mut shots, mut cubes) = (0, 0);
    let (mut sent, mut met) = (0.0f64, 0.0f64);
    loop {
        let unshot_of = |g: &[usize]| -> (Vec3, f32) {
            let (mut sum, mut area) = (Vec3::ZERO, 0.0);
            for &k in g {
                let a = patches[k].area();
                sum += patches[k].unshot * a;
                area += a;
            }
            (sum, area)
        };
        let mut best = (0usize, 0.0f32);
        let mut rest = 0.0f32;
        for (g, m) in members.iter().enumerate() {
            let (sum, _) = unshot_of(m);
            let p = power(sum);
            rest += p;
            if p > best.1 {
                best = (g, p);
            }
        }
        if cubes >= max_shots || rest <= tolerance * emitted || best.1 <= 0.0 {
            return Solved {
                shots,
                unshot: if emitted > 0.0 { rest / emitted } else { 0.0 },
                closure: if sent > 0.0 { (met / sent) as f32 } else { 1.0 },
            };
        }
        let g = best.0;
        let (sum, area) = unshot_of(&members[g]);
        let shooter = Patch::new(shooters[g], Vec3::ZERO, Vec3::ZERO);
        let n = shooter.normal();
        let shot = sum / area.max(1e-30);
        let power_area = area;
        // A shot carrying much of the light is seen from four points of its patch.
        let views = if best.1 > SPLIT_SHOTS_ABOVE * emitted {
            4
        } else {
            1
        };
        cube.form_factors_from(patches, shooters[g], n, near, views);
        let ff = std::mem::take(&mut cube.sums);
        sent += f64::from(best.1);
        met += f64::from(best.1)
            * ff.iter()
                .enumerate()
                .filter(|(j, _)| patches[*j].group != g)
                .map(|(_, &f)| f64::from(f))
                .sum::<f64>();
        for (j, &f) in ff.iter().enumerate() {
            if f <= 0.0 || patches[j].group == g {
                continue;
            }
            let aj = patches[j].area();
            if aj <= 0.0 {
                continue;
            }
            let q = &mut patches[j];
            let d = q.reflectance * shot * (f * power_area / aj);
            q.radiosity += d;
            q.unshot += d;
        }
        cube.sums = ff;
        for &k in &members[g] {
            patches[k].unshot = Vec3::ZERO;
        }
        shots += 1;
        cubes += views;
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

/// The surfaces are cut into patches (which shoot) until no side is longer than this share
/// of the scene's bounding diameter, and the patches into elements (which receive and are
/// drawn) until no side is longer than [`ELEMENT_SHARE`].
pub const PATCH_SHARE: f32 = 1.0 / 8.0;
pub const ELEMENT_SHARE: f32 = 1.0 / 16.0;
/// Cutting stops at this many elements (a larger scene keeps its triangles as they are);
/// a scene of more triangles than [`MAX_ELEMENTS`] is solved and drawn on its first ones
/// only ([`Solution::truncated`]).
pub const MAX_PATCHES: usize = 40_000;
pub const MAX_ELEMENTS: usize = 1_000_000;
/// Shots stop when they have drawn this many triangles into hemicubes in all (about four
/// seconds here): a large scene is solved coarsely (its direct light exact, the rest
/// mostly the ambient term) rather than for minutes.
pub const MAX_WORK: usize = 6_000_000;
/// Pixels per side of the hemicube's top face.
pub const HEMICUBE: u32 = 128;
/// A shot carrying more than this share of the emitted power is seen by four hemicubes
/// ([`Hemicube::form_factors_from`]).
pub const SPLIT_SHOTS_ABOVE: f32 = 1.0 / 64.0;
/// Shooting stops when the power left unshot falls below this share of the power there
/// was to shoot, or after [`MAX_SHOTS`]; what is left is spread as an ambient term (Cohen
/// et al. 1988), so the picture is right on average.
pub const TOLERANCE: f32 = 5e-2;
pub const MAX_SHOTS: usize = 20_000;
/// The first solution (on the uncut patches, to find where to cut) stops earlier.
pub const FIRST_TOLERANCE: f32 = 0.3;
/// A patch whose corners' smoothed radiosity differs from its own by more than this share
/// is cut in four for the second solution (where shadows and light change fast).
pub const REFINE_ABOVE: f32 = 0.25;

/// Cuts `t` into four by its edges' midpoints until no side is longer than `max`.
fn cut(t: [Vec3; 3], max: f32, out: &mut Vec<[Vec3; 3]>, budget: usize) {
    let [a, b, c] = t;
    let longest = (b - a).length().max((c - b).length()).max((a - c).length());
    if longest <= max || out.len() + 4 > budget || !longest.is_finite() {
        out.push(t);
        return;
    }
    let (ab, bc, ca) = ((a + b) * 0.5, (b + c) * 0.5, (c + a) * 0.5);
    for q in [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]] {
        cut(q, max, out, budget);
    }
}

/// Radiance (B/π) at each patch corner: the area-weighted mean of the patches that share
/// that point and face within [`SMOOTH_DEGREES`] of the same way (one surface's patches
/// blend, a curved one's too; a crease keeps its edge).
fn corner_radiance(patches: &[Patch]) -> Vec<[Vec3; 3]> {
    use std::collections::HashMap;
    let size = patches
        .iter()
        .flat_map(|q| q.corners)
        .fold(1e-6f32, |m, c| m.max(c.abs().max_element()));
    let key = |v: Vec3| (v / size * 1e5).round().as_ivec3();
    let cos_max = SMOOTH_DEGREES.to_radians().cos();
    // Per point: each patch's normal, radiosity times area, and area.
    let mut at: HashMap<_, Vec<(Vec3, Vec3, f32)>> = HashMap::new();
    for t in patches {
        let (n, a) = (t.normal(), t.area());
        for c in t.corners {
            at.entry(key(c)).or_default().push((n, t.radiosity * a, a));
        }
    }
    patches
        .iter()
        .map(|t| {
            let n = t.normal();
            t.corners.map(|c| {
                let (s, a) = at.get(&key(c)).map_or((t.radiosity, 1.0), |list| {
                    list.iter()
                        .filter(|(m, _, _)| m.dot(n) >= cos_max)
                        .fold((Vec3::ZERO, 0.0), |(s, a), (_, b, w)| (s + *b, a + w))
                });
                s / a.max(1e-30) * std::f32::consts::FRAC_1_PI
            })
        })
        .collect()
}

/// Patches meeting at a corner blend their radiosity there when their normals are within
/// this angle.
pub const SMOOTH_DEGREES: f32 = 45.0;

/// The patches of `scene` as `settings` show it: every shown instance's triangles in the
/// world (each copy), cut to the patch size, with the material's diffuse reflectance (base
/// colour times one minus metalness; textures are not read) and emission (π times the
/// emissive radiance).
fn patches_of(t: &super::whitted::Tracer) -> (Vec<Patch>, Vec<[Vec3; 3]>, bool) {
    let scene = t.scene;
    let max = 2.0 * t.radius * PATCH_SHARE;
    let fine = 2.0 * t.radius * ELEMENT_SHARE;
    let mut shooters = Vec::new();
    let mut elements = Vec::new();
    let ground = t.settings.ground.as_ref().map(|g| scene.ground_world(g));
    let mut out = Vec::new();
    let mut cut_tris = Vec::new();
    let mut truncated = false;
    for (k, inst) in scene.instances.iter().enumerate() {
        let Some(r) = t.resolved.get(k).and_then(Option::as_ref) else {
            continue;
        };
        let d = &r.params;
        let metal = d.surface.pbr.as_ref().map_or(0.0, |p| p.metallic);
        let rho = (d.base.truncate() * (1.0 - metal)).clamp(Vec3::ZERO, Vec3::splat(0.999));
        let emission = d.emissive.max(Vec3::ZERO) * std::f32::consts::PI;
        let tri = &scene.meshes[inst.mesh].tri;
        for copy in 0..inst.copy_count() {
            let world = match (inst.ground, ground) {
                (true, Some(g)) => g,
                _ => inst.placement(copy),
            };
            for tr in &tri.triangles {
                let c = tr.map(|i| {
                    tri.positions
                        .get(i as usize)
                        .map_or(Vec3::NAN, |p| world.transform_point3(*p))
                });
                if !c.iter().all(|v| v.is_finite()) {
                    continue;
                }
                if out.len() >= MAX_ELEMENTS {
                    truncated = true;
                    break;
                }
                cut_tris.clear();
                cut(
                    c,
                    max,
                    &mut cut_tris,
                    MAX_PATCHES.saturating_sub(out.len()).max(1),
                );
                for &q in &cut_tris {
                    let p = Patch::new(q, rho, emission);
                    // (Coordinates so large that the area overflows are left out.)
                    if !(p.area() > 0.0 && p.area().is_finite() && p.normal() != Vec3::ZERO) {
                        continue;
                    }
                    elements.clear();
                    cut(
                        q,
                        fine,
                        &mut elements,
                        MAX_PATCHES.saturating_sub(out.len()).max(1),
                    );
                    for &e in &elements {
                        let mut e = Patch::new(e, rho, emission);
                        e.group = shooters.len();
                        if e.area() > 0.0 && e.area().is_finite() {
                            out.push(e);
                        }
                    }
                    shooters.push(q);
                }
            }
        }
    }
    (out, shooters, truncated)
}

/// Environment directions per patch for its sky light.
pub const ENV_SAMPLES: u32 = 64;

/// The punctual lights' and the environment's first bounce: each patch's irradiance from every light at its
/// centre, past a shadow ray, reflected (and left to shoot on).
fn direct_light(t: &super::whitted::Tracer, patches: &mut [Patch]) {
    use crate::shade::{arriving, LightSet};
    use rayon::prelude::*;
    let mut set = LightSet::default();
    let mut index = 0;
    super::frame::for_each_light(
        t.scene.lights(),
        &t.settings.lights,
        t.settings.default_rig(t.scene.scene()),
        t.cam_to_world,
        |l, m| {
            set.push(l, m, index);
            index += 1;
        },
    );
    let ambient = set.ambient;
    let rays = &t.rays;
    let eps = 1e-5 * t.radius.max(1e-6);
    let env = t.env.as_ref();
    patches.par_iter_mut().enumerate().for_each(|(k, q)| {
        let (p, n) = (q.centre(), q.normal());
        // The ambient light reaches everything, unshadowed (as in the rasterizer).
        let mut h = ambient;
        // The environment: directions drawn in proportion to its radiance, past shadow
        // rays (the sky a patch sees), estimating its irradiance.
        if let Some(env) = env {
            let mut seed = (k as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ 0x5851_f42d_4c95_7f2d;
            let mut next = || {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                (seed >> 40) as f32 / (1u64 << 24) as f32
            };
            let mut sum = Vec3::ZERO;
            for _ in 0..ENV_SAMPLES {
                let (d, le, pdf) = env.sample(next(), next());
                let cos = n.dot(d);
                if cos > 0.0
                    && pdf > 0.0
                    && !rays.occluded(&realist_trace::Ray::new(p + n * eps, d, 0.0, f32::INFINITY))
                {
                    sum += le * (cos / pdf);
                }
            }
            h += sum / ENV_SAMPLES as f32;
        }
        for s in &set.sources {
            let Some((dir, rad, _)) = arriving::<f32>(s, p) else {
                continue;
            };
            let cos = n.dot(dir);
            if cos <= 0.0 || rad == Vec3::ZERO {
                continue;
            }
            let from = p + n * eps;
            let ray = match s.kind {
                crate::scene::LightKind::Directional => {
                    realist_trace::Ray::new(from, dir, 0.0, f32::INFINITY)
                }
                _ => realist_trace::Ray::new(from, s.position - from, 0.0, 1.0),
            };
            if !rays.occluded(&ray) {
                h += rad * cos;
            }
        }
        let b = q.reflectance * h;
        q.radiosity += b;
        q.unshot += b;
    });
}

/// The shots [`MAX_WORK`] allows for `elements` (each shot draws them all).
fn shots_for(elements: usize) -> usize {
    (MAX_WORK / elements.max(1)).clamp(1, MAX_SHOTS)
}

/// Cohen's ambient term for the power still unshot: spread evenly over the scene's area
/// and reflected on by the mean reflectance `ρ̄` (a geometric series, `1 / (1 - ρ̄)`), each
/// patch adds its reflectance times it. Cohen's room is closed; here the share of the
/// power shot that met a patch (`closure`, measured by the shots) scales what comes back,
/// `c / (1 - ρ̄ c)`, so an open scene (a model under the sky) is not brightened by light
/// that would have left it. Leaves `unshot` as it was.
fn ambient_correction(patches: &mut [Patch], closure: f32) {
    let area: f32 = patches.iter().map(Patch::area).sum();
    if area <= 0.0 {
        return;
    }
    let unshot = patches
        .iter()
        .fold(Vec3::ZERO, |a, q| a + q.unshot * q.area())
        / area;
    let rho = patches
        .iter()
        .fold(Vec3::ZERO, |a, q| a + q.reflectance * q.area())
        / area;
    let c = closure.clamp(0.0, 1.0);
    let ambient = unshot * c / (Vec3::ONE - rho * c).max(Vec3::splat(1e-3));
    for q in patches {
        q.radiosity += q.reflectance * ambient;
    }
}

/// A solved scene ready to draw: one mesh of every patch, unlit, its corners coloured by
/// their radiance.
fn display(patches: &[Patch]) -> crate::scene::Scene {
    use crate::mesh::{Channel, Mesh, MeshData, NormalPolicy};
    use crate::scene::{Instance, Material, PbrMaterial, Scene, Style};
    let colours = corner_radiance(patches);
    let mut positions = Vec::with_capacity(patches.len() * 3);
    let mut colors = Vec::with_capacity(patches.len() * 3);
    for (p, c) in patches.iter().zip(&colours) {
        positions.extend_from_slice(&p.corners);
        // A value that overflowed shows black rather than poisoning the frame.
        colors.extend(c.iter().map(|v| {
            if v.is_finite() {
                v.extend(1.0)
            } else {
                Vec4::new(0.0, 0.0, 0.0, 1.0)
            }
        }));
    }
    let corners = (0..positions.len() as u32).collect();
    let normals = patches
        .iter()
        .flat_map(|p| [p.normal(); 3])
        .collect::<Vec<_>>();
    let data = MeshData {
        name: "radiosity".into(),
        positions,
        corners,
        normals: Some(Channel::per_vertex(normals)),
        colors: Some(Channel::per_vertex(colors)),
        material: Some(0),
        ..MeshData::default()
    };
    let mut scene = Scene::default();
    if let Ok(mesh) = Mesh::new(data, NormalPolicy::default()) {
        scene.meshes.push(mesh);
        scene.materials.push(Material {
            name: "radiosity".into(),
            base_color: Vec4::ONE,
            double_sided: true,
            pbr: Some(PbrMaterial {
                unlit: true,
                ..PbrMaterial::default()
            }),
            ..Material::default()
        });
        scene.instances.push(Instance {
            mesh: 0,
            world: Mat4::IDENTITY,
            name: "radiosity".into(),
            style: Style::Inherit,
            node: None,
            skin: None,
            copies: None,
        });
    }
    scene
}

/// What a solution was made for.
#[derive(Clone, Debug, PartialEq)]
struct Key {
    ground: Option<Mat4>,
    hidden: super::settings::Hidden,
    lights: super::settings::Lights,
    pose: u64,
}

/// The solution a prepared scene keeps; a clone starts empty.
#[derive(Debug, Default)]
pub(crate) struct Cache(std::sync::Mutex<Option<(Key, std::sync::Arc<Solution>)>>);

impl Clone for Cache {
    fn clone(&self) -> Self {
        Self::default()
    }
}

/// A solved scene: its patches' radiosity drawn as a mesh.
#[derive(Debug)]
pub struct Solution {
    pub scene: super::PreparedScene,
    pub patches: usize,
    pub shots: usize,
    /// Unshot power left, as a share of what was emitted and reflected first.
    pub unshot: f32,
    /// The scene had more triangles than [`MAX_ELEMENTS`]: its first ones only.
    pub truncated: bool,
}

impl super::PreparedScene {
    /// The radiosity solution of the scene as `settings` show it (solved on first use and
    /// kept until the shown instances, the ground, the lights or the pose change): two
    /// solutions, the second on patches cut where the first changes fast.
    #[must_use]
    pub fn radiosity(&self, settings: &super::Settings) -> std::sync::Arc<Solution> {
        let key = Key {
            ground: settings.ground.as_ref().map(|g| self.ground_world(g)),
            hidden: settings.hidden.clone(),
            lights: settings.lights.clone(),
            pose: self.rays.pose(),
        };
        let mut c = self
            .radiosity
            .0
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some((k, s)) = &*c {
            if *k == key {
                return std::sync::Arc::clone(s);
            }
        }
        let t = super::whitted::Tracer::new(self, settings, Mat4::IDENTITY);
        let (mut patches, shooters, truncated) = patches_of(&t);
        let mut cube = Hemicube::new(HEMICUBE);
        direct_light(&t, &mut patches);
        let shots = shots_for(patches.len());
        let first = solve_grouped(&mut patches, &shooters, &mut cube, FIRST_TOLERANCE, shots);
        // Adaptive subdivision: cut where the smoothed corners disagree with the patch.
        let corners = corner_radiance(&patches);
        let mut refined = Vec::with_capacity(patches.len());
        let min = 2.0 * t.radius * ELEMENT_SHARE / 4.0;
        let mut cut_any = false;
        for (q, c) in patches.iter().zip(&corners) {
            let g = q.group;
            let b = power(q.radiosity) * std::f32::consts::FRAC_1_PI;
            let off = c.iter().map(|v| (power(*v) - b).abs()).fold(0.0, f32::max);
            let longest = (q.corners[1] - q.corners[0])
                .length()
                .max((q.corners[2] - q.corners[1]).length());
            if off > REFINE_ABOVE * (b + 1e-3) && longest > min && refined.len() + 4 <= MAX_PATCHES
            {
                let mut parts = Vec::new();
                cut(q.corners, longest * 0.6, &mut parts, 4);
                for p in parts {
                    let mut e = Patch::new(p, q.reflectance, q.emission);
                    e.group = g;
                    refined.push(e);
                }
                cut_any = true;
            } else {
                let mut e = Patch::new(q.corners, q.reflectance, q.emission);
                e.group = g;
                refined.push(e);
            }
        }
        let solved = if cut_any && patches.len() < MAX_PATCHES {
            patches = refined;
            direct_light(&t, &mut patches);
            let shots = shots_for(patches.len());
            solve_grouped(&mut patches, &shooters, &mut cube, TOLERANCE, shots)
        } else {
            // Nothing to cut (or no room to): the first solution goes on.
            let shots = shots_for(patches.len()).saturating_sub(first.shots).max(1);
            let more = solve_grouped(&mut patches, &shooters, &mut cube, TOLERANCE, shots);
            Solved {
                shots: first.shots + more.shots,
                closure: if more.shots > 0 {
                    more.closure
                } else {
                    first.closure
                },
                ..more
            }
        };
        ambient_correction(&mut patches, solved.closure);
        if std::env::var_os("REALIST_RADIOSITY").is_some() {
            eprintln!(
                "radiosity: {} patches, first {first:?}, then {solved:?}",
                patches.len()
            );
        }
        let solution = std::sync::Arc::new(Solution {
            scene: super::PreparedScene::new(display(&patches)),
            patches: patches.len(),
            shots: solved.shots,
            unshot: solved.unshot,
            truncated,
        });
        *c = Some((key, std::sync::Arc::clone(&solution)));
        solution
    }
}
