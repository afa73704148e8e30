//! `EXT_mesh_gpu_instancing`: a node's mesh drawn once per translation, rotation and scale
//! read from the node's `extensions.EXT_mesh_gpu_instancing.attributes` accessors (all of
//! the same count; a missing one is the identity part). Copy `i` is placed by
//! `node world * T_i * R_i * S_i`. The copies become [`Instance::copies`]: one mesh and one
//! matrix per copy, however many there are (a forest of a million trees is not a million
//! meshes). Attributes the extension leaves to applications (`_ID`, `_COLOR`, ...) are not
//! read.
//!
//! An unusable entry (an accessor of the wrong type or count, an attribute that is not an
//! index) is warned about and the node's mesh is drawn once at the node, as the
//! extension's fallback for viewers without it; copies with a non-finite matrix are left
//! out with a warning.
//!
//! [`Instance::copies`]: crate::scene::Instance::copies

use std::sync::Arc;

use glam::{Mat4, Quat, Vec3};
use serde_json::Value;

use super::accessor::Format;
use super::Builder;
use crate::LoadError;

/// The extension's name.
pub(super) const EXTENSION: &str = "EXT_mesh_gpu_instancing";

/// What reading a node's copies gave.
pub(super) enum Copies {
    /// The node has no (usable) extension entry: drawn once.
    Once,
    /// The copies' local matrices (possibly none).
    Many(Arc<[Mat4]>),
}

impl Builder<'_> {
    /// The copies of node `n` (named `name` in warnings). Errors are only those that stop
    /// the load (the budget, cancelling); anything else is a warning and [`Copies::Once`].
    pub(super) fn node_copies(&mut self, n: usize, name: &str) -> Result<Copies, LoadError> {
        let Some(entry) = self
            .doc
            .json
            .nodes
            .get(n)
            .and_then(|node| node.extensions.as_ref())
            .and_then(|e| e.others.get(EXTENSION))
            .cloned()
        else {
            return Ok(Copies::Once);
        };
        match self.read_copies(n, &entry) {
            Ok(Ok((copies, dropped))) => {
                if dropped > 0 {
                    self.scene.report.warnings.push(format!(
                        "node '{name}': {EXTENSION}: {dropped} of {} copies have a non-finite transform; left out",
                        copies.len() + dropped
                    ));
                }
                Ok(Copies::Many(copies.into()))
            }
            Ok(Err(why)) => {
                self.scene.report.warnings.push(format!(
                    "node '{name}': {EXTENSION} {why}; its mesh is drawn once, at the node"
                ));
                Ok(Copies::Once)
            }
            Err(e) => Err(e),
        }
    }

    /// The finite copies and how many were left out; the inner `Err` says why the entry
    /// is unusable.
    #[allow(clippy::type_complexity)]
    fn read_copies(
        &self,
        n: usize,
        entry: &Value,
    ) -> Result<Result<(Vec<Mat4>, usize), String>, LoadError> {
        let Some(attributes) = entry.get("attributes").and_then(Value::as_object) else {
            return Ok(Err("has no `attributes` object".into()));
        };
        let mut parts: [Option<(usize, Vec<f32>)>; 3] = [None, None, None];
        for (slot, (key, width)) in [("TRANSLATION", 3), ("ROTATION", 4), ("SCALE", 3)]
            .into_iter()
            .enumerate()
        {
            let Some(v) = attributes.get(key) else {
                continue;
            };
            let Some(index) = index_of(v) else {
                return Ok(Err(format!("{key} is not an accessor index ({v})")));
            };
            let used = format!("node {n} {EXTENSION} {key}");
            match self
                .doc
                .read_floats(index, &used, &[width], Format::Quantized)
            {
                Ok((_, values)) => parts[slot] = Some((index, values)),
                Err(e @ (LoadError::TooLarge { .. } | LoadError::Cancelled { .. })) => {
                    return Err(e)
                }
                Err(e) => return Ok(Err(format!("is unusable: {e}"))),
            }
        }
        let counts: Vec<(usize, usize)> = parts
            .iter()
            .zip([3, 4, 3])
            .filter_map(|(p, w)| p.as_ref().map(|(i, v)| (*i, v.len() / w)))
            .collect();
        let Some(&(_, count)) = counts.first() else {
            return Ok(Err("has none of TRANSLATION, ROTATION and SCALE".into()));
        };
        if let Some(&(i, c)) = counts.iter().find(|&&(_, c)| c != count) {
            return Ok(Err(format!(
                "has accessors of different counts (accessor {i} has {c}, not {count})"
            )));
        }
        self.doc.budget.charge(count as u64 * 64, || {
            format!("{count} copies of node {n} ({EXTENSION})")
        })?;
        let [t, r, s] = parts.map(|p| p.map(|(_, v)| v));
        let mut copies = Vec::with_capacity(count);
        let mut dropped = 0;
        for i in 0..count {
            let translation = t
                .as_ref()
                .map_or(Vec3::ZERO, |t| Vec3::from_slice(&t[3 * i..]));
            let rotation = r.as_ref().map_or(Quat::IDENTITY, |r| {
                let q = Quat::from_slice(&r[4 * i..]);
                // Quantized rotations are only nearly unit length.
                if q.length_squared() > 0.0 {
                    q.normalize()
                } else {
                    Quat::from_xyzw(f32::NAN, 0.0, 0.0, 0.0)
                }
            });
            let scale = s
                .as_ref()
                .map_or(Vec3::ONE, |s| Vec3::from_slice(&s[3 * i..]));
            let m = Mat4::from_scale_rotation_translation(scale, rotation, translation);
            if m.is_finite() {
                copies.push(m);
            } else {
                dropped += 1;
            }
        }
        Ok(Ok((copies, dropped)))
    }
}

/// An accessor index written as an integer (or an integral float, as the rest of the
/// document allows).
fn index_of(v: &Value) -> Option<usize> {
    v.as_u64()
        .or_else(|| {
            v.as_f64()
                .filter(|f| f.fract() == 0.0 && *f >= 0.0)
                .map(|f| f as u64)
        })
        .and_then(|i| usize::try_from(i).ok())
}
