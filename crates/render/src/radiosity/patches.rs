//! The scene's surfaces cut into patches (which shoot) and elements (which receive), with
//! each material's diffuse reflectance and emission.

use glam::Vec3;

use super::{Patch, ELEMENT_SHARE, MAX_ELEMENTS, MAX_PATCHES, PATCH_SHARE};

/// Cuts `t` into four by its edges' midpoints until no side is longer than `max`.
pub(super) fn cut(t: [Vec3; 3], max: f32, out: &mut Vec<[Vec3; 3]>, budget: usize) {
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

/// The patches of `scene` as `settings` show it: every shown instance's triangles in the
/// world (each copy), cut to the patch size, with the material's diffuse reflectance (base
/// colour times one minus metalness; textures are not read) and emission (π times the
/// emissive radiance).
pub(super) fn patches_of(t: &crate::whitted::Tracer) -> (Vec<Patch>, Vec<[Vec3; 3]>, bool) {
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
