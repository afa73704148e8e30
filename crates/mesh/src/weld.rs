//! Welding: one vertex per distinct position.
//!
//! glTF (and many exporters) split a vertex wherever any attribute differs, so a UV seam or a
//! crease cuts the surface into pieces that only touch. [`MeshData::weld_positions`] restores
//! the true topology: bitwise-identical positions become one vertex (the first occurrence
//! keeps its place in the order, so the result depends on the data only; the hash map is only
//! looked up, never iterated). Attributes lose nothing: a per-vertex channel whose merged
//! vertices all carried the same value stays per vertex; otherwise it becomes per corner, its
//! indices pointing at the old per-vertex values. Per-corner channels are untouched.
//! Vertices no corner uses (e.g. those of faces dropped for NaN positions) are dropped.

use std::collections::HashMap;

use glam::Vec3;

use super::{Channel, MeshData};

impl MeshData {
    /// Merges bitwise-identical positions into one vertex (see the module docs). Data with an
    /// out-of-range corner or a per-vertex channel of the wrong length is returned unchanged,
    /// so that [`Mesh::new`](super::Mesh::new) reports the error.
    #[must_use]
    pub fn weld_positions(mut self) -> MeshData {
        let old_count = self.positions.len();
        let malformed = self.corners.iter().any(|&v| v as usize >= old_count)
            || !per_vertex_fits(self.normals.as_ref(), old_count)
            || !self
                .uvs
                .iter()
                .all(|ch| per_vertex_fits(Some(ch), old_count))
            || !per_vertex_fits(self.tangents.as_ref(), old_count)
            || !per_vertex_fits(self.colors.as_ref(), old_count);
        if malformed || old_count > u32::MAX as usize {
            return self;
        }
        let mut used = vec![false; old_count];
        for &v in &self.corners {
            used[v as usize] = true;
        }
        let (remap, positions) = distinct_positions(&self.positions, &used);
        if positions.len() == old_count {
            return self;
        }
        self.normals = self
            .normals
            .map(|ch| weld_channel(ch, &remap, positions.len(), &self.corners));
        self.uvs = std::mem::take(&mut self.uvs)
            .into_iter()
            .map(|ch| weld_channel(ch, &remap, positions.len(), &self.corners))
            .collect();
        self.tangents = self
            .tangents
            .map(|ch| weld_channel(ch, &remap, positions.len(), &self.corners));
        self.colors = self
            .colors
            .map(|ch| weld_channel(ch, &remap, positions.len(), &self.corners));
        for v in &mut self.corners {
            *v = remap[*v as usize];
        }
        self.positions = positions;
        self
    }
}

fn per_vertex_fits<T>(ch: Option<&Channel<T>>, vertices: usize) -> bool {
    ch.is_none_or(|ch| ch.indices.is_some() || ch.values.len() == vertices)
}

/// The new index of every old vertex ([`UNUSED`] for vertices no corner uses), and the
/// distinct used positions in order of first occurrence.
fn distinct_positions(old: &[Vec3], used: &[bool]) -> (Vec<u32>, Vec<Vec3>) {
    let mut seen: HashMap<[u32; 3], u32> = HashMap::with_capacity(old.len());
    let mut positions = Vec::with_capacity(old.len());
    let remap = old
        .iter()
        .zip(used)
        .map(|(p, &used)| {
            if !used {
                return UNUSED;
            }
            let key = [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
            *seen.entry(key).or_insert_with(|| {
                positions.push(*p);
                (positions.len() - 1) as u32
            })
        })
        .collect();
    (remap, positions)
}

/// The remap entry of a vertex no corner uses: it is dropped.
const UNUSED: u32 = u32::MAX;

/// A channel re-keyed for the welded vertices (see the module docs).
fn weld_channel<T: Copy + PartialEq>(
    ch: Channel<T>,
    remap: &[u32],
    new_count: usize,
    old_corners: &[u32],
) -> Channel<T> {
    if ch.indices.is_some() {
        return ch;
    }
    // The first old vertex of every new vertex.
    let mut first = vec![u32::MAX; new_count];
    for (old, &new) in remap.iter().enumerate().filter(|(_, &new)| new != UNUSED) {
        if first[new as usize] == u32::MAX {
            first[new as usize] = old as u32;
        }
    }
    let consistent = remap
        .iter()
        .enumerate()
        .filter(|(_, &new)| new != UNUSED)
        .all(|(old, &new)| ch.values[old] == ch.values[first[new as usize] as usize]);
    if consistent {
        Channel::per_vertex(first.iter().map(|&old| ch.values[old as usize]).collect())
    } else {
        Channel {
            values: ch.values,
            indices: Some(old_corners.to_vec()),
        }
    }
}
