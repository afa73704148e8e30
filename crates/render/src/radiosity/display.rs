//! A solution as a mesh to draw: the patches' corners coloured by their smoothed radiance.

use glam::{Mat4, Vec3, Vec4};

use super::Patch;

/// Radiance (B/π) at each patch corner: the area-weighted mean of the patches that share
/// that point and face within [`SMOOTH_DEGREES`] of the same way (one surface's patches
/// blend, a curved one's too; a crease keeps its edge).
pub(super) fn corner_radiance(patches: &[Patch]) -> Vec<[Vec3; 3]> {
    use std::collections::HashMap;
    let size = patches
        .iter()
        .flat_map(|q| q.corners)
        .fold(1e-6f32, |m, c| m.max(c.abs().max_element()));
    let key = |v: Vec3| (v / size * 1e5).round().as_ivec3();
    let cos_max = libm::cosf(SMOOTH_DEGREES.to_radians());
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

/// A solved scene ready to draw: one mesh of every patch, unlit, its corners coloured by
/// their radiance.
pub(super) fn display(patches: &[Patch]) -> crate::scene::Scene {
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
