//! Generated texture coordinates: a [`UvGenerator`] applied to every facet corner of a
//! [`Mesh`], with the seams a per-point map cannot handle.
//!
//! The result is a new [`Channel`] (the mesh is only read: positions, corners, facet
//! normals and, for degenerate facets, vertex normals). It is indexed per corner where a
//! vertex gets different UVs in different facets (seams, poles, box edges), with equal UVs
//! sharing one value, so that triangulation makes no more render vertices than needed; it is
//! per vertex when no vertex needs more than one UV.
//!
//! # Seams (cylindrical and spherical maps)
//!
//! The longitude jumps from 1 back to 0 on the seam; a facet across it would interpolate
//! `u` from about 1 to about 0 and smear the whole texture backwards across one strip.
//! Each facet is therefore unwrapped on its own: its corners' longitudes are cut at the
//! largest gap between them on the circle, and the corners before the cut get `u + 1`, so
//! the facet's `u` range is as short as the circle allows and may run past 1 (a REPEAT
//! sampler reads the same texels there).
//!
//! - Corners on the axis (a sphere's poles, a cone's apex) have no longitude: they take the
//!   mean `u` of the facet's other corners, so a pole triangle is not twisted.
//! - A facet whose corners span more than [`MAX_WRAP_EXTENT`] of the circle surrounds the
//!   axis (a convex facet not containing the axis subtends less than half a turn): no
//!   longitude maps it without a smear, so it is mapped as a cap, planar along the axis and
//!   seen from the side its normal faces ([`UvGenerator::cap`]), as the primitives' caps.
//!
//! # Box
//!
//! The face is chosen once per facet from the facet normal (for a degenerate facet, the sum
//! of its corner normals), so a facet never mixes two projections.
//!
//! Degenerate input (empty mesh, non-finite positions, zero-size bounds) gives finite UVs
//! and never panics. Facets are processed in parallel on large meshes; the result does not
//! depend on the number of threads.

use std::collections::HashMap;

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::{par, Channel, Facet, Mesh};
use crate::texture::{UvFrame, UvGenerator};

/// Largest share of the circle a facet's longitudes may span before it counts as a cap.
pub const MAX_WRAP_EXTENT: f32 = 0.5;

/// The frame a generated map uses by default: the bounding box of the finite positions
/// ([`UvFrame::UNIT`] if there are none).
#[must_use]
pub fn uv_frame(mesh: &Mesh) -> UvFrame {
    mesh.bounds()
        .map_or(UvFrame::UNIT, |(lo, hi)| UvFrame::from_bounds(lo, hi))
}

/// Texture coordinates for every corner of `mesh` by `generator`, fitted to its bounding
/// box ([`uv_frame`]).
#[must_use]
pub fn generate_uvs(mesh: &Mesh, generator: &UvGenerator) -> Channel<Vec2> {
    generate_uvs_in(mesh, generator, &uv_frame(mesh))
}

/// [`generate_uvs`] in a given frame (e.g. a rotated plane, or one frame shared by several
/// meshes so their maps line up).
#[must_use]
pub fn generate_uvs_in(mesh: &Mesh, generator: &UvGenerator, frame: &UvFrame) -> Channel<Vec2> {
    let mut uvs = vec![Vec2::ZERO; mesh.corners.len()];
    let ranges = par::facet_ranges(mesh.facets(), par::parts(mesh.corners.len(), 4));
    let corner_count = |r: &std::ops::Range<usize>| {
        let (first, last) = (&mesh.facets()[r.start], &mesh.facets()[r.end - 1]);
        (last.first + last.len - first.first) as usize
    };
    let pieces = par::split_lengths(&mut uvs, ranges.iter().map(corner_count));
    ranges.par_iter().zip(pieces).for_each(|(range, out)| {
        let mut scratch = Vec::new();
        let base = mesh.facets()[range.start].first;
        for facet in &mesh.facets()[range.clone()] {
            let start = (facet.first - base) as usize;
            let out = &mut out[start..start + facet.len as usize];
            facet_uvs(mesh, generator, frame, facet, out, &mut scratch);
        }
    });
    compact(mesh, generator, frame, &uvs)
}

/// The facet normal, or for a degenerate facet the sum of its corner normals.
fn facet_normal(mesh: &Mesh, facet: &Facet) -> Vec3 {
    if !facet.is_degenerate() {
        return facet.normal;
    }
    facet
        .corners()
        .map(|c| mesh.normals.at(c, mesh.corners[c]))
        .sum()
}

/// The UVs of one facet's corners into `out` (one per corner).
fn facet_uvs(
    mesh: &Mesh,
    generator: &UvGenerator,
    frame: &UvFrame,
    facet: &Facet,
    out: &mut [Vec2],
    scratch: &mut Vec<(f32, usize)>,
) {
    let ring = &mesh.corners[facet.corners()];
    let position = |k: usize| mesh.positions[ring[k] as usize];
    match generator {
        UvGenerator::Planar { .. } | UvGenerator::Box => {
            let n = match generator {
                UvGenerator::Box => facet_normal(mesh, facet),
                _ => Vec3::ZERO,
            };
            for (k, uv) in out.iter_mut().enumerate() {
                *uv = generator.map(frame, position(k), n);
            }
        }
        UvGenerator::Cylindrical { .. } | UvGenerator::Spherical { .. } => {
            scratch.clear();
            for (k, uv) in out.iter_mut().enumerate() {
                let m = generator.map_point(frame, position(k), Vec3::ZERO);
                *uv = m.uv;
                if !m.on_axis {
                    scratch.push((m.uv.x, k));
                }
            }
            if !unwrap(scratch) {
                let n = facet_normal(mesh, facet);
                for (k, uv) in out.iter_mut().enumerate() {
                    *uv = generator.cap(frame, position(k), n);
                }
                return;
            }
            let Some(mean) = mean_u(scratch) else {
                return; // every corner on the axis: u stays 0
            };
            for uv in out.iter_mut() {
                uv.x = mean;
            }
            for &(u, k) in scratch.iter() {
                out[k].x = u;
            }
        }
    }
}

/// Cuts the longitudes `(u, corner)` at their largest gap on the circle, adding 1 to those
/// before the cut. False if they span more than [`MAX_WRAP_EXTENT`] (a cap).
fn unwrap(us: &mut [(f32, usize)]) -> bool {
    if us.is_empty() {
        return true;
    }
    us.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let last = us.len() - 1;
    // The gap across the seam first, so that on a tie nothing is shifted.
    let (mut gap, mut cut) = (us[0].0 + 1.0 - us[last].0, None);
    for i in 0..last {
        let g = us[i + 1].0 - us[i].0;
        if g > gap {
            (gap, cut) = (g, Some(i));
        }
    }
    if 1.0 - gap > MAX_WRAP_EXTENT {
        return false;
    }
    if let Some(i) = cut {
        for entry in &mut us[..=i] {
            entry.0 += 1.0;
        }
    }
    true
}

/// The mean of the unwrapped longitudes, `None` if there are none.
fn mean_u(us: &[(f32, usize)]) -> Option<f32> {
    (!us.is_empty()).then(|| us.iter().map(|e| e.0).sum::<f32>() / us.len() as f32)
}

/// A hashable key of a UV (`-0.0` and `0.0` alike).
fn key(uv: Vec2) -> [u32; 2] {
    [(uv.x + 0.0).to_bits(), (uv.y + 0.0).to_bits()]
}

/// Per-corner UVs as a channel: per vertex if every vertex has one UV, else per corner with
/// equal UVs sharing a value (in order of first use).
fn compact(mesh: &Mesh, generator: &UvGenerator, frame: &UvFrame, uvs: &[Vec2]) -> Channel<Vec2> {
    let mut at_vertex: Vec<Option<Vec2>> = vec![None; mesh.positions.len()];
    let one_per_vertex = mesh.corners.iter().zip(uvs).all(|(&v, &uv)| {
        let slot = &mut at_vertex[v as usize];
        key(*slot.get_or_insert(uv)) == key(uv)
    });
    if one_per_vertex {
        let values = at_vertex
            .iter()
            .zip(&mesh.positions)
            .map(|(uv, &p)| uv.unwrap_or_else(|| generator.map(frame, p, Vec3::ZERO)))
            .collect();
        return Channel::per_vertex(values);
    }
    let mut index: HashMap<[u32; 2], u32> = HashMap::new();
    let mut values = Vec::new();
    let indices = uvs
        .iter()
        .map(|&uv| {
            *index.entry(key(uv)).or_insert_with(|| {
                values.push(uv);
                // Corners < u32::MAX (a mesh invariant), so values are too.
                (values.len() - 1) as u32
            })
        })
        .collect();
    Channel {
        values,
        indices: Some(indices),
    }
}

#[cfg(test)]
mod tests;
