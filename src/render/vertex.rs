//! The vertex stage: per-vertex (or, for flat shading, per-facet) work that appends the
//! varyings of each mode to a group's buffer. Runs in parallel over vertices; allocates
//! nothing when the buffers have the capacity.

use glam::{Vec2, Vec3, Vec4};
use rayon::prelude::*;

use super::frame::FrameInst;
use super::prepare::{PreparedMesh, PreparedScene};
use crate::shade::{illuminate, Debug, DrawParams, LightSet, LitVarying, Surface};

const MIN_LEN: usize = 4096;

/// What the lit vertex functions share.
pub(super) struct Lit<'a> {
    pub scene: &'a PreparedScene,
    pub params: &'a [DrawParams],
    pub lights: &'a LightSet,
    pub eye: Vec3,
}

/// Appends `f(0), f(1), ..., f(n - 1)`, computed in parallel, to `out` (in place: the range
/// is indexed, so rayon writes into the reserved capacity).
fn per_item<T: Send>(out: &mut Vec<T>, n: usize, f: impl Fn(usize) -> T + Sync + Send) {
    out.par_extend((0..n).into_par_iter().with_min_len(MIN_LEN).map(f));
}

/// World position and unit world normal of render vertex `k`.
#[inline]
fn world(scene: &PreparedScene, fi: &FrameInst, mesh: &PreparedMesh, k: usize) -> (Vec3, Vec3) {
    let normal = scene.instances[fi.inst as usize].normal;
    let p = fi.world.transform_point3(mesh.tri.positions[k]);
    let n = (normal * mesh.tri.normals[k]).normalize_or_zero();
    (p, n)
}

/// Per-pixel-lighting varyings.
pub(super) fn lit<V: LitVarying>(scene: &PreparedScene, fi: &FrameInst, out: &mut Vec<V>) {
    let mesh = &scene.meshes[fi.mesh as usize];
    let tri = &mesh.tri;
    per_item(out, tri.positions.len(), |k| {
        let (p, n) = world(scene, fi, mesh, k);
        let uv = tri.uvs.as_ref().map_or(Vec2::ZERO, |u| u[k]);
        let c = tri.colors.as_ref().map_or(Vec4::ONE, |c| c[k]);
        V::new(p, n, uv, c)
    });
}

/// The lighting equation at a vertex or facet centroid, seen from the side `n` points to.
fn lit_colour(d: &DrawParams, lights: &LightSet, eye: Vec3, p: Vec3, n: Vec3, c: Vec4) -> Vec4 {
    let base = d.base * c;
    let s = Surface {
        diffuse: base.truncate(),
        ..d.surface
    };
    illuminate::<false>(lights, &s, p, n, eye).extend(base.w)
}

impl Lit<'_> {
    /// Gouraud: lighting per vertex, colours interpolated. Double-sided materials also get
    /// the colour of the back side (normal flipped), chosen per triangle by the shader.
    pub fn gouraud(&self, fi: &FrameInst, out: &mut Vec<(Vec4, Vec4)>) {
        let d = &self.params[fi.param as usize];
        let mesh = &self.scene.meshes[fi.mesh as usize];
        let tri = &mesh.tri;
        per_item(out, tri.positions.len(), |k| {
            let (p, n) = world(self.scene, fi, mesh, k);
            let c = tri.colors.as_ref().map_or(Vec4::ONE, |c| c[k]);
            let front = lit_colour(d, self.lights, self.eye, p, n, c);
            let back = if d.double_sided {
                lit_colour(d, self.lights, self.eye, p, -n, c)
            } else {
                front
            };
            (front, back)
        });
    }

    /// Flat: one lighting evaluation per facet, at its area-weighted centroid with its plane
    /// normal turned towards the eye on double-sided materials; every corner of the
    /// (unindexed) triangles carries its facet's colour. `facets` is scratch memory.
    pub fn flat(&self, fi: &FrameInst, facets: &mut Vec<Vec4>, out: &mut Vec<Vec4>) {
        let d = &self.params[fi.param as usize];
        let mesh = &self.scene.meshes[fi.mesh as usize];
        let (tri, flat) = (&mesh.tri, mesh.flat());
        let normal = self.scene.instances[fi.inst as usize].normal;
        facets.clear();
        per_item(facets, tri.facet_normals.len(), |f| {
            let p = fi.world.transform_point3(flat.centroids[f]);
            let mut n = (normal * tri.facet_normals[f]).normalize_or_zero();
            if d.double_sided && n.dot(self.eye - p) < 0.0 {
                n = -n;
            }
            lit_colour(d, self.lights, self.eye, p, n, flat.first_colors[f])
        });
        let facets = &*facets;
        // Indexed (corner by corner), so the extend writes in place without a list of chunks.
        per_item(out, 3 * tri.triangle_facets.len(), |c| {
            let f = tri.triangle_facets[c / 3] as usize;
            facets.get(f).copied().unwrap_or(Vec4::ZERO)
        });
    }
}

/// Debug views: the quantity itself as a Vec3.
pub(super) fn debug(scene: &PreparedScene, fi: &FrameInst, mode: Debug, out: &mut Vec<Vec3>) {
    let mesh = &scene.meshes[fi.mesh as usize];
    let tri = &mesh.tri;
    per_item(out, tri.positions.len(), |k| match mode {
        Debug::Normals => world(scene, fi, mesh, k).1,
        Debug::Depth => Vec3::splat(-fi.model_view.transform_point3(tri.positions[k]).z),
        Debug::Uv => tri.uvs.as_ref().map_or(Vec2::ZERO, |u| u[k]).extend(0.0),
    });
}

/// Nothing per vertex (depth-only and counting passes).
pub(super) fn unit(scene: &PreparedScene, fi: &FrameInst, out: &mut Vec<()>) {
    let n = scene.meshes[fi.mesh as usize].tri.positions.len();
    out.extend(std::iter::repeat_n((), n));
}
