//! Radiosity (the textbook's §9.6.3): the diffuse light between surfaces, solved once for
//! the whole scene and independent of the view. The surfaces are cut into patches; each
//! patch's radiosity `B = E + ρ Σ F B` (emission plus the reflected share of what every
//! other patch sends it, by the form factors `F`). Progressive refinement (Cohen et al.
//! 1988) shoots: the patch with the most unshot power sends it to every patch it sees, by
//! form factors from a hemicube (Cohen and Greenberg 1985) drawn by realist's own
//! rasterizer, one patch number per pixel, and the pixels' delta form factors summed per
//! patch.

use glam::{Mat4, Vec3};

mod direct;
mod display;
mod hemicube;
mod patches;
mod solve;
#[cfg(test)]
mod tests;

pub use direct::ENV_SAMPLES;
pub use display::SMOOTH_DEGREES;
pub use hemicube::Hemicube;
pub use solve::{solve, solve_grouped, Solved};

use direct::direct_light;
use display::{corner_radiance, display};
use patches::{cut, patches_of};
use solve::{ambient_correction, power, shots_for};

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
