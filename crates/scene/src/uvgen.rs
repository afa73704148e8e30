//! Generated texture coordinates for a whole scene: a [`UvGenerator`] (the textbook's §9.5,
//! texture space from an auxiliary plane, cylinder, sphere or box) applied once after
//! loading to every mesh, as `realist render --uv` and the scene-file key `uv` ask.

use crate::mesh::{generate_uvs, Mesh};
use crate::texture::UvGenerator;

use super::{Material, Scene, Slot};

/// What [`Scene::apply_uv_generator`] did to one mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UvOutcome {
    /// UV set 0 was replaced.
    Replaced,
    /// The mesh had no UVs; set 0 was added.
    Added,
}

impl Scene {
    /// Replaces texture coordinate set 0 of every mesh by `generator`'s map, fitted to the
    /// mesh's bounding box (added when the mesh has no UVs; other sets are kept), and
    /// regenerates the tangents that depended on set 0: those of a mesh whose material reads
    /// a normal map from set 0, or that had tangents without a normal map on another set.
    /// Every mesh is listed in the report's `generated`; a mesh the map cannot cover (no
    /// finite position, or all positions at one point) is also named in a warning that
    /// starts with the report's file, and gets the finite UVs the generator gives it
    /// (`(0, 0)` where nothing is defined) rather than failing the load.
    ///
    /// Call it before [`Scene::check_texture_slots`] (the loaders do, through
    /// [`crate::load::LoadOptions::uv`]), so that the slots are checked against the new set.
    pub fn apply_uv_generator(&mut self, generator: &UvGenerator) -> Vec<UvOutcome> {
        let file = self.report.file.clone();
        let mut outcomes = Vec::with_capacity(self.meshes.len());
        for mesh in &mut self.meshes {
            if let Some(problem) = uncovered(mesh) {
                self.report.warnings.push(format!(
                    "{file}: mesh '{}' {problem} for the {generator} UV map (the textbook's \
                     §9.5); its texture coordinates are all equal",
                    mesh.name
                ));
            }
            let uvs = generate_uvs(mesh, generator);
            let outcome = if mesh.uvs.is_empty() {
                mesh.uvs.push(uvs);
                UvOutcome::Added
            } else {
                mesh.uvs[0] = uvs;
                UvOutcome::Replaced
            };
            self.report.generated.push(format!(
                "mesh '{}': TEXCOORD_0 by the {generator} map (the textbook's §9.5), {}",
                mesh.name,
                match outcome {
                    UvOutcome::Replaced => "replacing the file's",
                    UvOutcome::Added => "the file has none",
                }
            ));
            let material = mesh.material.and_then(|m| self.materials.get(m));
            if let (UvOutcome::Added, Some(m)) = (outcome, material) {
                // A slot check before this (a scene loaded first, mapped later, as the viewer
                // does) said set 0 was missing: it is there now.
                let mesh_name = &mesh.name;
                let stale: Vec<String> = Slot::ALL
                    .into_iter()
                    .filter(|&s| m.slot(s).is_some_and(|t| t.uv_set == 0))
                    .map(|s| super::missing_uv_set(mesh_name, &m.name, s, 0, 0))
                    .collect();
                self.report.warnings.retain(|w| !stale.contains(w));
            }
            if let Some(note) = retangent(mesh, material) {
                self.report.generated.push(note);
            }
            outcomes.push(outcome);
        }
        outcomes
    }
}

/// Why a map cannot spread over `mesh`, if it cannot.
fn uncovered(mesh: &Mesh) -> Option<&'static str> {
    if mesh.corners.is_empty() {
        return None; // nothing is drawn, nothing to say
    }
    match mesh.bounds() {
        None => Some("has no finite position"),
        Some((lo, hi)) if lo == hi => Some("has all its positions at one point"),
        Some(_) => None,
    }
}

/// Regenerates the tangents of `mesh` that followed UV set 0 (see
/// [`Scene::apply_uv_generator`]); the report line, if it did.
fn retangent(mesh: &mut Mesh, material: Option<&Material>) -> Option<String> {
    let normal_set = material
        .and_then(|m| m.normal_texture.as_ref())
        .map(|n| n.uv_set);
    let set = match normal_set {
        Some(0) => 0,
        Some(_) => return None, // the normal map's own set did not change
        None if mesh.tangents.is_some() => 0,
        None => return None,
    };
    mesh.generate_tangents(set).ok()?;
    Some(format!(
        "mesh '{}': MikkTSpace tangents from the generated TEXCOORD_0{}",
        mesh.name,
        match material {
            Some(m) if normal_set.is_some() => format!(" (normal map of material '{}')", m.name),
            _ => String::new(),
        }
    ))
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3, Vec4};

    use super::*;
    use crate::mesh::{Channel, MeshData, NormalPolicy};
    use crate::texture::Axis;
    use crate::{Instance, Style, TextureSlot};

    fn scene_of(data: MeshData, material: Material) -> Scene {
        let mut mesh = Mesh::new(data, NormalPolicy::default()).unwrap();
        mesh.material = Some(0);
        let mut scene = Scene {
            meshes: vec![mesh],
            materials: vec![material],
            ..Scene::default()
        };
        scene.instances.push(Instance {
            mesh: 0,
            world: glam::Mat4::IDENTITY,
            name: "quad".into(),
            style: Style::Inherit,
            node: None,
            skin: None,
            copies: None,
        });
        scene.report.file = "dir/model.gltf".into();
        scene
    }

    fn quad(positions: [Vec3; 4]) -> MeshData {
        MeshData {
            name: "quad".into(),
            positions: positions.to_vec(),
            corners: vec![0, 1, 2, 0, 2, 3],
            ..MeshData::default()
        }
    }

    const SQUARE: [Vec3; 4] = [
        Vec3::new(-1.0, -1.0, 0.0),
        Vec3::new(1.0, -1.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(-1.0, 1.0, 0.0),
    ];

    #[test]
    fn set_0_is_replaced_and_other_sets_kept() {
        let mut data = quad(SQUARE);
        let first = Channel::per_vertex(vec![Vec2::splat(9.0); 4]);
        let second = Channel::per_vertex(vec![Vec2::splat(0.25); 4]);
        data.uvs = vec![first, second.clone()];
        let mut scene = scene_of(data, Material::default());
        let g = UvGenerator::Planar { axis: Axis::Z };
        assert_eq!(scene.apply_uv_generator(&g), vec![UvOutcome::Replaced]);
        let mesh = &scene.meshes[0];
        assert_eq!(mesh.uvs.len(), 2);
        assert_eq!(mesh.uvs[1], second);
        // planar:z: u left to right, v top to bottom over the square.
        assert_eq!(mesh.uvs[0].values[0], Vec2::new(0.0, 1.0));
        assert_eq!(mesh.uvs[0].values[2], Vec2::new(1.0, 0.0));
        assert_eq!(
            scene.report.generated.len(),
            1,
            "{:?}",
            scene.report.generated
        );
        assert!(scene.report.generated[0].contains("replacing the file's"));
        assert!(scene.report.warnings.is_empty());
    }

    #[test]
    fn tangents_follow_the_new_set_0() {
        // A normal map on set 0, and tangents from the file along +y (for the old UVs).
        let mut data = quad(SQUARE);
        data.uvs = vec![Channel::per_vertex(vec![Vec2::ZERO; 4])];
        data.tangents = Some(Channel::per_vertex(vec![Vec4::new(0.0, 1.0, 0.0, 1.0); 4]));
        let material = Material {
            normal_texture: Some(TextureSlot::new(0)),
            ..Material::default()
        };
        let mut scene = scene_of(data, material);
        scene.apply_uv_generator(&UvGenerator::Planar { axis: Axis::Z });
        let t = scene.meshes[0].tangents.as_ref().unwrap();
        for c in 0..6 {
            let v = scene.meshes[0].corners[c];
            assert!(
                (t.at(c, v).truncate() - Vec3::X).length() < 1e-5,
                "u runs along +x"
            );
        }
        assert!(
            scene
                .report
                .generated
                .iter()
                .any(|g| g.contains("MikkTSpace")),
            "{:?}",
            scene.report.generated
        );
        // A normal map on set 1 keeps its tangents.
        let mut data = quad(SQUARE);
        data.uvs = vec![Channel::per_vertex(vec![Vec2::ZERO; 4]); 2];
        data.tangents = Some(Channel::per_vertex(vec![Vec4::new(0.0, 1.0, 0.0, 1.0); 4]));
        let mut slot = TextureSlot::new(0);
        slot.uv_set = 1;
        let material = Material {
            normal_texture: Some(slot),
            ..Material::default()
        };
        let mut scene = scene_of(data, material);
        scene.apply_uv_generator(&UvGenerator::Box);
        let t = scene.meshes[0].tangents.as_ref().unwrap();
        assert_eq!(t.values[0], Vec4::new(0.0, 1.0, 0.0, 1.0));
    }

    #[test]
    fn mapping_after_the_slot_check_drops_its_missing_set_0_warning() {
        // Loaded without UVs (the check warns), mapped afterwards (as the viewer does).
        let material = Material {
            name: "m".into(),
            base_color_texture: Some(TextureSlot::new(0)),
            ..Material::default()
        };
        let mut scene = scene_of(quad(SQUARE), material);
        scene.check_texture_slots();
        assert_eq!(
            scene.report.warnings.len(),
            1,
            "{:?}",
            scene.report.warnings
        );
        assert!(scene.report.warnings[0].contains("TEXCOORD_0"));
        scene.report.warnings.push("another warning".into());
        let g = UvGenerator::Spherical { axis: Axis::Y };
        assert_eq!(scene.apply_uv_generator(&g), vec![UvOutcome::Added]);
        assert_eq!(scene.report.warnings, ["another warning"]);
    }

    #[test]
    fn a_mesh_without_extent_warns_naming_the_file() {
        for (positions, problem) in [
            ([Vec3::NAN; 4], "has no finite position"),
            ([Vec3::ONE; 4], "all its positions at one point"),
        ] {
            let mut scene = scene_of(quad(positions), Material::default());
            for g in UvGenerator::PRESETS {
                scene.report.warnings.clear();
                assert_eq!(scene.apply_uv_generator(&g), vec![UvOutcome::Added]);
                let w = &scene.report.warnings;
                assert_eq!(w.len(), 1, "{w:?}");
                assert!(
                    w[0].starts_with("dir/model.gltf: mesh 'quad' ")
                        && w[0].contains(problem)
                        && w[0].contains(&g.to_string())
                        && w[0].contains("§9.5"),
                    "{}",
                    w[0]
                );
                assert!(scene.meshes[0].uvs[0]
                    .values
                    .iter()
                    .all(|uv| uv.is_finite()));
                scene.meshes[0].uvs.clear();
            }
        }
    }
}
