//! Progressive refinement: the shots from the patch with the most unshot power, the shot
//! budget, and Cohen's ambient term for what is left unshot.

use glam::Vec3;

use super::{Hemicube, Patch, MAX_SHOTS, MAX_WORK, SPLIT_SHOTS_ABOVE};

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

pub(super) fn power(c: Vec3) -> f32 {
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

/// The shots [`MAX_WORK`] allows for `elements` (each shot draws them all).
pub(super) fn shots_for(elements: usize) -> usize {
    (MAX_WORK / elements.max(1)).clamp(1, MAX_SHOTS)
}

/// Cohen's ambient term for the power still unshot: spread evenly over the scene's area
/// and reflected on by the mean reflectance `ρ̄` (a geometric series, `1 / (1 - ρ̄)`), each
/// patch adds its reflectance times it. Cohen's room is closed; here the share of the
/// power shot that met a patch (`closure`, measured by the shots) scales what comes back,
/// `c / (1 - ρ̄ c)`, so an open scene (a model under the sky) is not brightened by light
/// that would have left it. Leaves `unshot` as it was.
pub(super) fn ambient_correction(patches: &mut [Patch], closure: f32) {
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
