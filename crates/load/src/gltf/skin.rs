//! Skins and morph targets: a primitive's `JOINTS_n` / `WEIGHTS_n` (sets 0 and 1: 4 or 8
//! influences) and morph `targets` into the mesh's [`Deform`], the mesh's and nodes'
//! morph weights, and the file's skins (joints and inverse bind matrices).
//!
//! Nothing here rejects a file: a weight that is negative or not finite counts as 0 (and is
//! reported), a vertex whose weights sum to 0 follows its first joint, a skin with a joint
//! that is not a node, too many joints or unusable inverse bind matrices is dropped (its
//! meshes are drawn unskinned), as is the skin of an instance whose mesh names a joint
//! the skin does not have. Morph targets whose accessors do not match the primitive are
//! reported and left out. Each message names the file's item.

use glam::{Mat4, Vec3};
use gltf::json::mesh::{Primitive, Semantic};
use gltf::json::validation::Checked;

use super::accessor::Format;
use super::{Builder, Doc, QUANTIZATION};
use crate::mesh::{Deform, MorphTarget};
use crate::scene::{Graph, Skin};
use crate::LoadError;

/// Most joints a skin may have (joint indices are stored in 16 bits).
pub const MAX_JOINTS: usize = 1 << 16;

/// A skin as the file writes it; read leniently, one entry at a time, so a bad skin is
/// reported and skipped rather than rejecting the file.
#[derive(serde::Deserialize)]
#[serde(rename_all = "camelCase")]
struct SkinJson {
    inverse_bind_matrices: Option<usize>,
    joints: Vec<usize>,
    name: Option<String>,
}

impl Doc<'_> {
    /// The deformation data of a primitive of `n` vertices, or `None` when it has neither
    /// skinning attributes nor morph targets. `label` names the primitive in messages.
    pub(super) fn deform(
        &self,
        prim: &Primitive,
        n: usize,
        label: &str,
        warnings: &mut Vec<String>,
    ) -> Result<Option<Deform>, LoadError> {
        let attr = |s: Semantic| prim.attributes.get(&Checked::Valid(s)).map(|i| i.value());
        let mut deform = Deform::default();
        let sets: Vec<(usize, usize)> = (0..2)
            .map_while(|s| Some((attr(Semantic::Joints(s))?, attr(Semantic::Weights(s))?)))
            .collect();
        if !sets.is_empty() {
            let k = 4 * sets.len();
            deform.influences = k;
            deform.joints = vec![0; n * k];
            deform.weights = vec![0.0; n * k];
            for (s, &(ja, wa)) in sets.iter().enumerate() {
                let (_, j) =
                    self.read_floats(ja, &format!("{label} JOINTS_{s}"), &[4], Format::Quantized)?;
                let (_, w) = self.read_floats(
                    wa,
                    &format!("{label} WEIGHTS_{s}"),
                    &[4],
                    Format::FloatOrUnorm,
                )?;
                if j.len() != n * 4 || w.len() != n * 4 {
                    warnings.push(format!(
                        "{label}: JOINTS_{s}/WEIGHTS_{s} have {}/{} elements but POSITION has {n}; not skinned",
                        j.len() / 4,
                        w.len() / 4
                    ));
                    deform.influences = 0;
                    deform.joints.clear();
                    deform.weights.clear();
                    break;
                }
                for v in 0..n {
                    for i in 0..4 {
                        // Integers below 2^16 are exact in f32; larger ones are out of
                        // range of any skin and caught when the skin is bound.
                        deform.joints[v * k + 4 * s + i] = j[v * 4 + i].clamp(0.0, 65535.0) as u16;
                        deform.weights[v * k + 4 * s + i] = w[v * 4 + i];
                    }
                }
            }
            // A set whose length did not match left no influences to normalise.
            if deform.influences > 0 {
                normalise_weights(&mut deform, label, warnings);
            }
        }
        let quantized = self.json.extensions_used.iter().any(|e| e == QUANTIZATION);
        let format = if quantized {
            Format::Quantized
        } else {
            Format::Float
        };
        for (t, target) in prim.targets.iter().flatten().enumerate() {
            let mut read = |name: &str,
                            a: Option<gltf::json::Index<gltf::json::Accessor>>|
             -> Result<Vec<Vec3>, LoadError> {
                let Some(a) = a else { return Ok(Vec::new()) };
                let (_, v) = self.read_floats(
                    a.value(),
                    &format!("{label} target {t} {name}"),
                    &[3],
                    format,
                )?;
                if v.len() != n * 3 {
                    warnings.push(format!(
                        "{label}: morph target {t} {name} has {} elements but POSITION has {n}; ignored",
                        v.len() / 3
                    ));
                    return Ok(Vec::new());
                }
                if v.iter().any(|x| !x.is_finite()) {
                    warnings.push(format!(
                        "{label}: morph target {t} {name} has non-finite values; ignored"
                    ));
                    return Ok(Vec::new());
                }
                Ok(v.chunks_exact(3).map(Vec3::from_slice).collect())
            };
            let positions = read("POSITION", target.positions)?;
            let normals = read("NORMAL", target.normals)?;
            let tangents = read("TANGENT", target.tangents)?;
            deform.targets.push(MorphTarget {
                positions,
                normals,
                tangents,
            });
        }
        let used = deform.influences > 0
            || deform.targets.iter().any(|t| {
                !(t.positions.is_empty() && t.normals.is_empty() && t.tangents.is_empty())
            });
        self.budget
            .charge(deform.bytes(), || format!("{label} skin and morph data"))?;
        Ok(used.then_some(deform))
    }
}

/// Weights made finite, non-negative and summing to 1 per vertex; a vertex with no weight
/// left follows its first joint. Counts of what was changed go to `warnings`.
fn normalise_weights(d: &mut Deform, label: &str, warnings: &mut Vec<String>) {
    let k = d.influences;
    if k == 0 {
        return;
    }
    let (mut bad, mut empty) = (0usize, 0usize);
    for w in d.weights.chunks_exact_mut(k) {
        for x in w.iter_mut() {
            if !(x.is_finite() && *x >= 0.0) {
                *x = 0.0;
                bad += 1;
            }
        }
        let sum: f32 = w.iter().sum();
        if sum > 0.0 && sum.is_finite() {
            w.iter_mut().for_each(|x| *x /= sum);
        } else {
            w.fill(0.0);
            w[0] = 1.0;
            empty += 1;
        }
    }
    if bad > 0 {
        warnings.push(format!(
            "{label}: {bad} negative or non-finite skin weight(s) read as 0"
        ));
    }
    if empty > 0 {
        warnings.push(format!(
            "{label}: {empty} vertex(es) have no skin weight; they follow their first joint"
        ));
    }
}

impl Builder<'_> {
    /// Reads the file's skins into [`crate::scene::Scene::skins`] (one per file skin, in
    /// order; an unusable one is kept empty and reported) and unbinds instances whose skin
    /// is unusable or too small for their mesh's joint indices.
    pub(super) fn skins(&mut self, values: &[serde_json::Value]) -> Result<(), LoadError> {
        let count = self.scene.graph.nodes.len();
        for (i, value) in values.iter().enumerate() {
            let mut value = value.clone();
            super::schema::normalise(&mut value);
            let skin = match serde_json::from_value::<SkinJson>(value) {
                Ok(s) => self.skin(i, s, count)?,
                Err(e) => Err(format!("is malformed ({e})")),
            };
            let skin = skin.unwrap_or_else(|why| {
                self.scene
                    .report
                    .warnings
                    .push(format!("skin {i} {why}; its meshes are drawn unskinned"));
                Skin {
                    name: format!("skin {i}"),
                    joints: Vec::new(),
                    inverse_bind: Vec::new(),
                }
            });
            self.scene.skins.push(skin);
        }
        let mut unbound = Vec::new();
        for inst in &mut self.scene.instances {
            let Some(s) = inst.skin else { continue };
            let joints = self.scene.skins.get(s).map_or(0, |s| s.joints.len());
            let used = self.scene.meshes[inst.mesh]
                .deform
                .as_ref()
                .and_then(|d| d.max_joint());
            let fits = joints > 0 && used.is_none_or(|j| usize::from(j) < joints);
            if !fits {
                if joints > 0 {
                    unbound.push(format!(
                        "node '{}': its mesh uses joint {} but skin {s} has {joints} joints; drawn unskinned",
                        inst.name,
                        used.unwrap_or(0)
                    ));
                }
                inst.skin = None;
            }
        }
        self.scene.report.warnings.extend(unbound);
        Ok(())
    }

    fn skin(&self, i: usize, s: SkinJson, count: usize) -> Result<Result<Skin, String>, LoadError> {
        if s.joints.is_empty() {
            return Ok(Err("has no joints".into()));
        }
        if s.joints.len() > MAX_JOINTS {
            return Ok(Err(format!(
                "has {} joints, more than {MAX_JOINTS}",
                s.joints.len()
            )));
        }
        if let Some(&bad) = s.joints.iter().find(|&&j| j >= count) {
            return Ok(Err(format!(
                "names joint node {bad}, but there are only {count} nodes"
            )));
        }
        let graph = &self.scene.graph;
        if let Some(&bad) = s.joints.iter().find(|&&j| !graph.order.contains(&j)) {
            return Ok(Err(format!(
                "joint node {bad} is not in the node tree (a cycle)"
            )));
        }
        let inverse_bind = match s.inverse_bind_matrices {
            None => vec![Mat4::IDENTITY; s.joints.len()],
            Some(a) => {
                let used = format!("skin {i} inverseBindMatrices");
                let (_, m) = match self.doc.read_floats(a, &used, &[16], Format::Float) {
                    Ok(m) => m,
                    Err(e @ (LoadError::TooLarge { .. } | LoadError::Cancelled { .. })) => {
                        return Err(e)
                    }
                    Err(e) => return Ok(Err(format!("has unusable inverse bind matrices: {e}"))),
                };
                if m.len() / 16 < s.joints.len() {
                    return Ok(Err(format!(
                        "has {} inverse bind matrices for {} joints",
                        m.len() / 16,
                        s.joints.len()
                    )));
                }
                if m.iter().any(|x| !x.is_finite()) {
                    return Ok(Err("has non-finite inverse bind matrices".into()));
                }
                m.chunks_exact(16)
                    .take(s.joints.len())
                    .map(Mat4::from_cols_slice)
                    .collect()
            }
        };
        Ok(Ok(Skin {
            name: s.name.unwrap_or_else(|| format!("skin {i}")),
            joints: s.joints,
            inverse_bind,
        }))
    }

    /// The rest morph weights of every node with a mesh that has morph targets: the
    /// node's `weights`, else the mesh's, else zeros, fitted to the number of targets.
    pub(super) fn morph_weights(&mut self, graph: &mut Graph) {
        let json = &self.doc.json;
        for (n, node) in json.nodes.iter().enumerate() {
            let Some(m) = node.mesh.map(|m| m.value()) else {
                continue;
            };
            let Some(mesh) = json.meshes.get(m) else {
                continue;
            };
            let targets = mesh
                .primitives
                .iter()
                .map(|p| p.targets.as_ref().map_or(0, Vec::len))
                .max()
                .unwrap_or(0);
            if targets == 0 {
                continue;
            }
            let given = node.weights.as_ref().or(mesh.weights.as_ref());
            let mut w = given.cloned().unwrap_or_default();
            if given.is_some() && w.len() != targets {
                self.scene.report.warnings.push(format!(
                    "node {n}: {} morph weight(s) for {targets} target(s); the rest read as 0",
                    w.len()
                ));
            }
            w.resize(targets, 0.0);
            w.iter_mut()
                .filter(|x| !x.is_finite())
                .for_each(|x| *x = 0.0);
            if let Some(g) = graph.nodes.get_mut(n) {
                g.weights = w;
            }
        }
    }
}
