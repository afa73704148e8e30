//! The first bounce: every patch's irradiance from the punctual lights and the
//! environment, past shadow rays.

use glam::Vec3;

use super::Patch;

/// Environment directions per patch for its sky light.
pub const ENV_SAMPLES: u32 = 64;

/// The punctual lights' and the environment's first bounce: each patch's irradiance from every light at its
/// centre, past a shadow ray, reflected (and left to shoot on).
pub(super) fn direct_light(t: &crate::whitted::Tracer, patches: &mut [Patch]) {
    use crate::shade::{arriving, LightSet};
    use rayon::prelude::*;
    let mut set = LightSet::default();
    let mut index = 0;
    crate::frame::for_each_light(
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
