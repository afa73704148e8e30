//! Generated texture coordinates for a whole scene: a [`UvGenerator`] (the textbook's §9.5,
//! texture space from an auxiliary plane, cylinder, sphere or box) applied once after
//! loading to every mesh, as `realist render --uv` and the scene-file key `uv` ask.

use crate::mesh::{generate_uvs, Mesh};
use crate::texture::UvGenerator;

use super::{Material, Scene};

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
