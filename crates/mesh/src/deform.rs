//! Deforming a mesh per frame: morph targets, then linear blend skinning (glTF's
//! "Skins" and "Morph Targets").
//!
//! [`Deform`] is the per-vertex data a mesh carries for this (indexed by mesh vertex, like
//! [`Mesh::positions`]; loaders do not weld deformable meshes, so every vertex keeps its own
//! joints and deltas). [`deform`] writes a posed [`TriMesh`] from the rest one into buffers
//! that are reused (nothing is allocated), in parallel over vertices:
//!
//! - morphing: `p = p0 + sum_k w_k dp_k`, the same for normals and tangents (`xyz`);
//! - skinning: `M = sum_i w_i J_i` over the vertex's influences (4 or 8), `J_i` the joint's
//!   world matrix times its inverse bind matrix; positions by `M`, normals by the cofactor
//!   of `M`'s 3x3 part (correct under non-uniform scale), tangents by `M`'s 3x3 part, both
//!   renormalised; the tangent's handedness is kept;
//! - flat-shaded meshes (glTF without NORMAL) get their normals from the posed triangles;
//!   facet normals, the bounding sphere follow the posed positions.
//!
//! A vertex whose posed position is not finite (a singular or huge joint matrix) keeps its
//! rest position, so a bad frame cannot put NaN into the rasterizer.

use glam::{Mat3, Mat4, Vec3};
use rayon::prelude::*;

use super::{par, TriMesh};

/// Per-vertex skinning and morph data of a mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Deform {
    /// Influences per vertex: 0 (not skinned), 4 or 8.
    pub influences: usize,
    /// `influences` joint indices per vertex (into the skin's `joints`).
    pub joints: Vec<u16>,
    /// `influences` weights per vertex: finite, `>= 0`, summing to 1.
    pub weights: Vec<f32>,
    pub targets: Vec<MorphTarget>,
}

/// One morph target's displacements, one per vertex; an empty list means the target does
/// not move that attribute.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MorphTarget {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub tangents: Vec<Vec3>,
}

impl Deform {
    /// The largest joint index used with a non-zero weight, if the mesh is skinned.
    #[must_use]
    pub fn max_joint(&self) -> Option<u16> {
        self.joints
            .iter()
            .zip(&self.weights)
            .filter(|(_, w)| **w > 0.0)
            .map(|(j, _)| *j)
            .max()
    }

    /// Bytes held, for load budgets.
    #[must_use]
    pub fn bytes(&self) -> u64 {
        let t: usize = self
            .targets
            .iter()
            .map(|t| (t.positions.len() + t.normals.len() + t.tangents.len()) * 12)
            .sum();
        (self.joints.len() * 2 + self.weights.len() * 4 + t) as u64
    }
}

/// What one call of [`deform`] applies.
pub struct Posing<'a> {
    pub deform: &'a Deform,
    /// Mesh vertex of each render vertex (empty: the identity).
    pub vertex_of: &'a [u32],
    /// Morph weights (missing ones read as 0).
    pub weights: &'a [f32],
    /// Joint matrices (world x inverse bind), or `None` without skinning.
    pub joints: Option<&'a [Mat4]>,
    /// The mesh's normals are flat (one per facet): recompute them from the triangles.
    pub flat: bool,
}

/// Writes the posed form of `rest` into `out` (which must have been cloned from `rest`)
/// and returns the axis-aligned bounds of its finite positions.
pub fn deform(rest: &TriMesh, out: &mut TriMesh, p: &Posing) -> Option<(Vec3, Vec3)> {
    let n = rest.positions.len().min(out.positions.len());
    let source = |r: usize| p.vertex_of.get(r).map_or(r, |&v| v as usize);
    let blended = |v: usize| -> Option<Mat4> {
        let joints = p.joints?;
        let k = p.deform.influences;
        if k == 0 {
            return None;
        }
        let (js, ws) = (
            p.deform.joints.get(v * k..(v + 1) * k)?,
            p.deform.weights.get(v * k..(v + 1) * k)?,
        );
        let mut m = Mat4::ZERO;
        for (&j, &w) in js.iter().zip(ws) {
            if w != 0.0 {
                m += *joints.get(j as usize)? * w;
            }
        }
        Some(m)
    };
    let morph = |v: usize, base: Vec3, pick: fn(&MorphTarget) -> &Vec<Vec3>| {
        let mut x = base;
        for (t, &w) in p.deform.targets.iter().zip(p.weights) {
            if w != 0.0 {
                if let Some(d) = pick(t).get(v) {
                    x += *d * w;
                }
            }
        }
        x
    };
    let (rest_p, rest_n) = (&rest.positions[..n], &rest.normals[..n]);
    out.positions[..n]
        .par_iter_mut()
        .zip(out.normals[..n].par_iter_mut())
        .enumerate()
        .with_min_len(par::MIN_ITEMS / 4)
        .for_each(|(r, (pos, nrm))| {
            let v = source(r);
            let mut x = morph(v, rest_p[r], |t| &t.positions);
            let mut m = rest_n[r];
            if !p.flat {
                m = morph(v, m, |t| &t.normals);
            }
            if let Some(mat) = blended(v) {
                x = mat.transform_point3(x);
                m = cofactor(Mat3::from_mat4(mat)) * m;
            }
            *pos = if x.is_finite() { x } else { rest_p[r] };
            *nrm = m.try_normalize().unwrap_or(rest_n[r]);
        });
    if let (Some(rt), Some(ot)) = (&rest.tangents, &mut out.tangents) {
        let n = n.min(rt.len()).min(ot.len());
        ot[..n]
            .par_iter_mut()
            .enumerate()
            .with_min_len(par::MIN_ITEMS / 4)
            .for_each(|(r, tan)| {
                let v = source(r);
                let t0 = rt[r];
                let mut x = morph(v, t0.truncate(), |t| &t.tangents);
                if let Some(mat) = blended(v) {
                    x = Mat3::from_mat4(mat) * x;
                }
                *tan = x.try_normalize().map_or(t0, |x| x.extend(t0.w));
            });
    }
    refresh_facets(out, p.flat)
}

/// Facet normals (and, for a flat-shaded mesh, vertex normals) and the bounding sphere
/// from the current positions, a facet's normal from its first triangle as
/// [`Mesh::new`](super::Mesh::new) computes it. A mesh of triangles (every glTF mesh) stores
/// no facet normals ([`TriMesh::facet_normal`] computes them from the posed positions); the
/// flat vertex normals of a mesh without NORMAL are written serially.
fn refresh_facets(out: &mut TriMesh, flat: bool) -> Option<(Vec3, Vec3)> {
    let positions = &out.positions;
    let normal_of = |t: &[u32; 3]| super::build::newell(positions, t).0;
    let one_to_one = out.triangle_facets.is_empty();
    if !one_to_one {
        let mut last = u32::MAX;
        for (t, &f) in out.triangles.iter().zip(&out.triangle_facets) {
            if f != last {
                if let Some(slot) = out.facet_normals.get_mut(f as usize) {
                    *slot = normal_of(t);
                }
                last = f;
            }
        }
    }
    if flat {
        for (k, t) in out.triangles.iter().enumerate() {
            let n = if one_to_one {
                normal_of(t)
            } else {
                let f = out.triangle_facets.get(k).copied().unwrap_or(u32::MAX);
                out.facet_normals
                    .get(f as usize)
                    .copied()
                    .unwrap_or(Vec3::ZERO)
            };
            if n != Vec3::ZERO {
                for k in t {
                    out.normals[*k as usize] = n;
                }
            }
        }
    }
    let sphere = sphere(&out.positions);
    let (center, radius) = sphere.map_or((Vec3::ZERO, -1.0), |(c, r, _)| (c, r));
    out.center = center;
    out.radius = radius;
    sphere.map(|(_, _, b)| b)
}

/// [`super::bounding_sphere_of`], in parallel (the same centre and radius), and the box
/// its centre is the middle of.
fn sphere(positions: &[Vec3]) -> Option<(Vec3, f32, (Vec3, Vec3))> {
    let finite = || {
        positions
            .par_iter()
            .with_min_len(par::MIN_ITEMS)
            .filter(|p| p.is_finite())
    };
    let (lo, hi) = finite().map(|&p| (p, p)).reduce(
        || (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |a, b| (a.0.min(b.0), a.1.max(b.1)),
    );
    if lo.x > hi.x {
        return None;
    }
    let centre = (lo + hi) * 0.5;
    let r2 = finite()
        .map(|&p| p.distance_squared(centre))
        .reduce(|| 0.0, f32::max);
    Some((centre, r2.sqrt(), (lo, hi)))
}

/// The cofactor matrix of `m` (`det(m) * m^-T`), the normal matrix: see
/// [`crate::geom::normal_matrix`].
pub use crate::geom::normal_matrix as cofactor;
