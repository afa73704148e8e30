//! Built-in environments, generated procedurally and deterministically (no files, no
//! randomness): `uniform` for furnace tests, `studio` and `sky` for looking at materials.
//!
//! Placement is given in the image's frame as azimuth (degrees from the image centre, +X,
//! toward +Z, i.e. rightward in the image) and elevation. With the default rotation
//! (`DEFAULT_ROTATION_DEG`, image centre at world +Z, the side glTF assets face and the
//! default camera sits on) azimuth 0 is behind the camera and positive azimuths are on the
//! camera's left.
//!
//! Generation (2 cores, release): studio ~5 ms, sky ~5 ms at 512×256; uniform is 64×32.

use glam::Vec3;
use rayon::prelude::*;

use super::equirect::{texel_dir, EnvImage, Plane};

/// The names of the built-in environments ([`EnvImage::builtin`]).
pub const BUILTIN_NAMES: [&str; 3] = ["uniform", "studio", "sky"];

/// Size of the studio and the sky.
const WIDTH: usize = 512;
const HEIGHT: usize = 256;

/// Unit direction at azimuth `az` and elevation `el`, in degrees (module docs).
fn direction(az: f32, el: f32) -> Vec3 {
    let (sa, ca) = libm::sincosf(az.to_radians());
    let (se, ce) = libm::sincosf(el.to_radians());
    Vec3::new(ce * ca, se, ce * sa)
}

fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// A `w×h` image whose texel `(x, y)` is `f(x, y)`, rows in parallel.
fn generate(name: &str, w: usize, h: usize, f: impl Fn(usize, usize) -> Vec3 + Sync) -> EnvImage {
    let mut rgb = vec![0.0f32; 3 * w * h];
    rgb.par_chunks_mut(3 * w).enumerate().for_each(|(y, row)| {
        for (x, t) in row.chunks_exact_mut(3).enumerate() {
            t.copy_from_slice(&f(x, y).max(Vec3::ZERO).to_array());
        }
    });
    EnvImage::from_plane(
        name,
        Plane {
            width: w,
            height: h,
            rgb,
        },
    )
}

/// The mean of `f` over `n×n` points spread evenly over texel `(x, y)` of a `w×h` image.
fn texel_mean(
    (x, y): (usize, usize),
    (w, h): (usize, usize),
    n: usize,
    f: &impl Fn(Vec3) -> Vec3,
) -> Vec3 {
    use std::f32::consts::PI;
    let mut acc = Vec3::ZERO;
    for j in 0..n {
        for i in 0..n {
            let u = (x as f32 + (i as f32 + 0.5) / n as f32) / w as f32;
            let v = (y as f32 + (j as f32 + 0.5) / n as f32) / h as f32;
            let (st, ct) = libm::sincosf(v * PI);
            let (sp, cp) = libm::sincosf((u - 0.5) * 2.0 * PI);
            acc += f(Vec3::new(st * cp, ct, st * sp));
        }
    }
    acc / (n * n) as f32
}

/// A rectangular softbox: radiance inside a rectangle of the plane tangent to the sphere at
/// `centre`, with edges smoothed over `SOFT` (in the tangent plane, ≈ 3°).
struct Softbox {
    centre: Vec3,
    right: Vec3,
    up: Vec3,
    /// Half extents in the tangent plane (tan of the half angles).
    half: (f32, f32),
    radiance: Vec3,
}

impl Softbox {
    const SOFT: f32 = 0.05;

    /// A softbox at (`az`, `el`) degrees, `w_deg`×`h_deg` across, facing the origin.
    fn new(az: f32, el: f32, w_deg: f32, h_deg: f32, radiance: Vec3) -> Self {
        let centre = direction(az, el);
        let right = Vec3::Y.cross(centre).normalize_or(Vec3::Z);
        let up = centre.cross(right);
        let half = (
            libm::tanf((w_deg * 0.5).to_radians()),
            libm::tanf((h_deg * 0.5).to_radians()),
        );
        Self {
            centre,
            right,
            up,
            half,
            radiance,
        }
    }

    fn eval(&self, d: Vec3) -> Vec3 {
        let c = d.dot(self.centre);
        if c <= 0.1 {
            return Vec3::ZERO;
        }
        let (a, b) = ((d.dot(self.right) / c).abs(), (d.dot(self.up) / c).abs());
        let s = Self::SOFT;
        let inside = (1.0 - smoothstep(self.half.0 - s, self.half.0 + s, a))
            * (1.0 - smoothstep(self.half.1 - s, self.half.1 + s, b));
        self.radiance * inside
    }
}

impl EnvImage {
    /// Radiance `c` in every direction (64×32 texels; negative or NaN channels become 0).
    /// Irradiance is π·c everywhere, every prefiltered level is c.
    #[must_use]
    pub fn uniform(c: Vec3) -> Self {
        let c = Vec3::from_array(c.to_array().map(|x| if x > 0.0 { x } else { 0.0 }));
        generate("uniform", 64, 32, |_, _| c)
    }

    /// A neutral photo studio (512×256): a warm key softbox (radiance ≈ 6, 40°×30°, azimuth
    /// 45°, elevation 30°), a fill (2, 30°×45°, -60°, 15°), a tall rim strip behind (4,
    /// 12°×50°, 160°, 30°) and an overhead panel (1.5, 60°×25°, 0°, 75°), on grey walls
    /// 0.3 at the horizon to 0.45 at the zenith and a darker floor (0.15 to 0.08). Nothing
    /// is black; metal spheres show the boxes as readable highlights.
    #[must_use]
    pub fn studio() -> Self {
        let boxes = [
            Softbox::new(45.0, 30.0, 40.0, 30.0, Vec3::new(6.0, 5.8, 5.4)),
            Softbox::new(-60.0, 15.0, 30.0, 45.0, Vec3::splat(2.0)),
            Softbox::new(160.0, 30.0, 12.0, 50.0, Vec3::splat(4.0)),
            Softbox::new(0.0, 75.0, 60.0, 25.0, Vec3::splat(1.5)),
        ];
        let f = |d: Vec3| {
            let wall = 0.3 + 0.15 * d.y.max(0.0);
            let floor = 0.08 + 0.07 * (1.0 + d.y.min(0.0));
            let room = floor + (wall - floor) * smoothstep(-0.03, 0.03, d.y);
            let lights: Vec3 = boxes.iter().map(|b| b.eval(d)).sum();
            Vec3::splat(room) + lights
        };
        generate("studio", WIDTH, HEIGHT, |x, y| {
            texel_mean((x, y), (WIDTH, HEIGHT), 2, &f)
        })
    }

    /// A clear daylight sky (512×256): blue at the zenith (≈ 0.2, 0.35, 0.8) brightening to
    /// a pale horizon (≈ 0.85, 0.9, 1.0), a warm sun disk 2.5° across (radiance ≈ 6000, so
    /// ≈ 9 lux-like units of irradiance, about three times the sky's) at azimuth 30°,
    /// elevation 40°, with a glow around it, and brownish-grey ground below the horizon.
    /// Texels within 4° of the sun are averaged over 8×8 points so the disk's flux does not
    /// depend on where its edge falls.
    #[must_use]
    pub fn sky() -> Self {
        let sun = direction(30.0, 40.0);
        let sun_radius = 1.25f32.to_radians();
        let sun_colour = Vec3::new(1.0, 0.92, 0.8) * 6000.0;
        let glow = Vec3::new(1.0, 0.85, 0.6);
        let zenith = Vec3::new(0.2, 0.35, 0.8);
        let horizon = Vec3::new(0.85, 0.9, 1.0);
        let ground_near = Vec3::new(0.22, 0.19, 0.16);
        let ground_far = Vec3::new(0.12, 0.10, 0.08);
        let f = |d: Vec3| {
            let angle = libm::acosf(d.dot(sun).clamp(-1.0, 1.0));
            let air = horizon.lerp(zenith, d.y.max(0.0).sqrt())
                + glow * (2.0 * libm::expf(-angle / 0.06) + 0.4 * libm::expf(-angle / 0.35));
            let disk = 1.0 - smoothstep(sun_radius * 0.9, sun_radius * 1.1, angle);
            let sky = air + sun_colour * disk;
            let ground = ground_near.lerp(ground_far, (-d.y).max(0.0).sqrt());
            ground.lerp(sky, smoothstep(-0.02, 0.005, d.y))
        };
        let near_sun = libm::cosf(4f32.to_radians());
        generate("sky", WIDTH, HEIGHT, |x, y| {
            let n = if texel_dir(x, y, WIDTH, HEIGHT).dot(sun) > near_sun {
                8
            } else {
                1
            };
            texel_mean((x, y), (WIDTH, HEIGHT), n, &f)
        })
    }

    /// The built-in environment called `name` ([`BUILTIN_NAMES`]; `"uniform"` is radiance 1).
    #[must_use]
    pub fn builtin(name: &str) -> Option<Self> {
        match name {
            "uniform" => Some(Self::uniform(Vec3::ONE)),
            "studio" => Some(Self::studio()),
            "sky" => Some(Self::sky()),
            _ => None,
        }
    }
}
