//! Two levels: a [`Mesh`]'s hierarchy over its triangles in its own space (built once, refit
//! when a pose moves its vertices) and the [`Scene`]'s over its instances' world boxes (a
//! copy of a mesh is an instance with its own placement, not a copy of its triangles).

use std::sync::Arc;

use glam::{Affine3A, Mat4, Vec3};
use rayon::prelude::*;

use crate::bvh::{with_stack, Bvh, Entry, Node, Prim, Slabs};
use crate::triangle::Sheared;

/// A mesh's triangles in its own space and their hierarchy.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub(crate) bvh: Bvh,
    /// Triangles in the hierarchy's slot order.
    pub(crate) tris: Vec<[Vec3; 3]>,
    /// Triangles left out (a vertex not finite, or an index out of range).
    pub skipped: usize,
    /// The plane every triangle lies in, if they all do (a floor, a wall, the ground): unit
    /// normal `n` and offset `d` of `n·p = d`, and the margin that counts as on it.
    plane: Option<(Vec3, f32, f32)>,
}

/// The plane all of `tris` lie in (within a millionth of their extent), if one does.
/// `around`, a box known to hold them all, lets a mesh that is not flat be told at its
/// first triangle off the plane (its margin is at least the exact box's), before the exact
/// box is folded.
fn common_plane(tris: &[[Vec3; 3]], around: Option<(Vec3, Vec3)>) -> Option<(Vec3, f32, f32)> {
    let first = tris.iter().find_map(|t| {
        let n = (t[1] - t[0]).cross(t[2] - t[0]);
        (n.length_squared() > 0.0).then(|| (n.normalize(), t[0]))
    })?;
    let (n, p) = first;
    let d = n.dot(p);
    let margin = |(lo, hi): (Vec3, Vec3)| {
        1e-6 * (hi - lo).max_element() + 8.0 * f32::EPSILON * lo.abs().max(hi.abs()).max_element()
    };
    let on = |margin: f32| {
        tris.iter()
            .all(|t| t.iter().all(|v| (n.dot(*v) - d).abs() <= margin))
    };
    if around.is_some_and(|b| !on(margin(b))) {
        return None;
    }
    let exact = tris
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), t| {
            let (a, b) = tri_box(t);
            (lo.min(a), hi.max(b))
        });
    let margin = margin(exact);
    on(margin).then_some((n, d, margin))
}

fn tri_box(t: &[Vec3; 3]) -> (Vec3, Vec3) {
    (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]))
}

fn corners(positions: &[Vec3], t: [u32; 3]) -> Option<[Vec3; 3]> {
    let p = |i: u32| positions.get(i as usize).copied().filter(|v| v.is_finite());
    Some([p(t[0])?, p(t[1])?, p(t[2])?])
}

impl Mesh {
    /// The hierarchy over `triangles` (indices into `positions`). A triangle with an index out
    /// of range or a vertex that is not finite is left out and counted in [`Mesh::skipped`].
    #[must_use]
    pub fn new(positions: &[Vec3], triangles: &[[u32; 3]]) -> Self {
        // One record per triangle kept, carrying the caller's index (which `order` keeps);
        // the corners are read again in slot order rather than kept in a second array. A
        // triangle left out is first an empty box (made in parallel, in place), then
        // dropped.
        let mut prims: Vec<Prim> = triangles
            .par_iter()
            .enumerate()
            .map(|(i, &t)| match corners(positions, t) {
                Some(c) => {
                    let (lo, hi) = tri_box(&c);
                    Prim::new(lo, hi, i as u32)
                }
                None => Prim::new(Vec3::INFINITY, Vec3::NEG_INFINITY, i as u32),
            })
            .collect();
        if prims.par_iter().any(Prim::is_empty) {
            prims.retain(|p| !p.is_empty());
        }
        let kept = prims.len();
        // The triangles in slot order are gathered while the wide tree is made (every slot's
        // triangle has its corners: it was kept).
        let (bvh, slot_tris) = Bvh::build_prims_with(prims, |order| {
            order
                .par_iter()
                .map(|&k| corners(positions, triangles[k as usize]).unwrap_or([Vec3::NAN; 3]))
                .collect::<Vec<_>>()
        });
        let plane = common_plane(&slot_tris, bvh.bounds());
        Self {
            bvh,
            tris: slot_tris,
            skipped: triangles.len() - kept,
            plane,
        }
    }

    /// The ray (in the mesh's space) starts clearly off the mesh's plane and runs away
    /// from it or along it, so it cannot meet the mesh: a shadow or reflection ray leaving a
    /// floor skips the floor's hierarchy.
    #[inline]
    fn leaves_plane(&self, o: Vec3, d: Vec3) -> bool {
        match self.plane {
            Some((n, off, margin)) => {
                let (s, ds) = (n.dot(o) - off, n.dot(d));
                (s > margin && ds >= 0.0) || (s < -margin && ds <= 0.0)
            }
            None => false,
        }
    }

    /// Moves the triangles to `positions` (same topology as built) and refits the boxes. A
    /// vertex that is not finite makes its triangle a point at the origin's box (never hit).
    pub fn refit(&mut self, positions: &[Vec3], triangles: &[[u32; 3]]) {
        for (slot, &k) in self.bvh.order.iter().enumerate() {
            let t = triangles
                .get(k as usize)
                .and_then(|&t| corners(positions, t));
            self.tris[slot] = t.unwrap_or([Vec3::NAN; 3]);
        }
        self.plane = common_plane(&self.tris, None);
        let tris = &self.tris;
        self.bvh.refit(|slot| {
            let t = &tris[slot];
            if t[0].is_finite() {
                tri_box(t)
            } else {
                (Vec3::ZERO, Vec3::ZERO)
            }
        });
    }

    /// All its triangles lie in one plane.
    #[must_use]
    pub fn is_flat(&self) -> bool {
        self.plane.is_some()
    }

    /// Triangles in the hierarchy.
    #[must_use]
    pub fn len(&self) -> usize {
        self.tris.len()
    }

    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.tris.is_empty()
    }

    /// Box of everything in the mesh, if anything.
    #[must_use]
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        self.bvh.bounds()
    }

    /// The nearest hit in `(tmin, tmax)` that `accept(triangle, front, t)` takes: `t`, the
    /// caller's triangle index, weights, side.
    #[inline]
    fn closest(
        &self,
        s: &Sheared,
        slabs: &Slabs,
        tmin: f32,
        tmax: f32,
        accept: &impl Fn(u32, bool, f32) -> bool,
        stack: &mut Vec<Entry>,
    ) -> Option<(f32, u32, [f32; 3], bool)> {
        let mut best = None;
        self.bvh
            .traverse(slabs, tmin, tmax, stack, |first, count, mut t, _| {
                for slot in first..first + count {
                    let [a, b, c] = self.tris[slot as usize];
                    if let Some((th, w, front)) = s.hit_sided(a, b, c, tmin, t) {
                        let tri = self.bvh.order[slot as usize];
                        if accept(tri, front, th) {
                            t = th;
                            best = Some((th, tri, w, front));
                        }
                    }
                }
                Some(t)
            });
        best
    }

    /// Whether anything lies in `(tmin, tmax)`.
    #[inline]
    fn any(
        &self,
        s: &Sheared,
        slabs: &Slabs,
        tmin: f32,
        tmax: f32,
        stack: &mut Vec<Entry>,
    ) -> bool {
        let mut found = false;
        self.bvh
            .traverse(slabs, tmin, tmax, stack, |first, count, t, _| {
                for slot in first..first + count {
                    let [a, b, c] = self.tris[slot as usize];
                    if s.hit(a, b, c, tmin, t).is_some() {
                        found = true;
                        return None;
                    }
                }
                Some(t)
            });
        found
    }
}

/// One placement of a mesh.
#[derive(Clone, Copy, Debug)]
pub struct Instance {
    pub mesh: u32,
    /// The caller's name for it (e.g. its instance and copy), returned in hits.
    pub key: u64,
    to_object: Affine3A,
    identity: bool,
}

impl Instance {
    /// `to_world` places the mesh; `None` if it cannot be inverted or is not finite.
    #[must_use]
    pub fn new(mesh: u32, key: u64, to_world: Mat4) -> Option<Self> {
        let a = Affine3A::from_mat4(to_world);
        let det = a.matrix3.determinant();
        if !(det.is_finite() && det != 0.0 && a.translation.is_finite()) {
            return None;
        }
        Some(Self {
            mesh,
            key,
            to_object: a.inverse(),
            identity: to_world == Mat4::IDENTITY,
        })
    }
}

/// A ray: points `origin + t·dir` for `t` in `(tmin, tmax)`; `dir` need not be unit.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    pub origin: Vec3,
    pub dir: Vec3,
    pub tmin: f32,
    pub tmax: f32,
}

impl Ray {
    #[must_use]
    pub fn new(origin: Vec3, dir: Vec3, tmin: f32, tmax: f32) -> Self {
        Self {
            origin,
            dir,
            tmin,
            tmax,
        }
    }

    /// Finite origin and direction, and a range that is a number (a ray that is not meets
    /// nothing).
    #[must_use]
    pub fn is_valid(&self) -> bool {
        self.origin.is_finite()
            && self.dir.is_finite()
            && !self.tmin.is_nan()
            && !self.tmax.is_nan()
    }
}

/// The nearest hit of a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f32,
    /// Index into the scene's instances, and that instance's key.
    pub instance: u32,
    pub key: u64,
    /// The mesh's triangle (the caller's index).
    pub triangle: u32,
    /// Weights of the triangle's three corners.
    pub bary: [f32; 3],
    /// The ray met the triangle's counter-clockwise side (in the mesh's own space).
    pub front: bool,
}

/// Every instance of every mesh, and the hierarchy over their world boxes.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// Shared: scenes with other instances (another ground plane, other objects hidden)
    /// reuse a mesh's hierarchy.
    pub meshes: Vec<Arc<Mesh>>,
    pub(crate) instances: Vec<Instance>,
    /// Each instance's world box (widened): tested before a ray is carried into the
    /// instance's space, since a leaf of the instances' tree holds several.
    pub(crate) boxes: Vec<Node>,
    pub(crate) tlas: Bvh,
}

/// The world box of `mesh`'s box placed by the inverse of `to_object`.
fn placed_box(mesh: &Mesh, inst: &Instance) -> Option<(Vec3, Vec3)> {
    let (lo, hi) = mesh.bounds()?;
    if inst.identity {
        return Some((lo, hi));
    }
    let m = inst.to_object.inverse();
    let mut out = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    for k in 0..8 {
        let c = Vec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        );
        let w = m.transform_point3(c);
        out = (out.0.min(w), out.1.max(w));
    }
    (out.0.is_finite() && out.1.is_finite()).then(|| crate::bvh::widen(out.0, out.1))
}

impl Scene {
    /// Builds every mesh's hierarchy (in parallel) and the instances' over them.
    #[must_use]
    pub fn build(meshes: Vec<(Vec<Vec3>, Vec<[u32; 3]>)>, instances: Vec<Instance>) -> Self {
        let meshes = meshes
            .par_iter()
            .map(|(p, t)| Arc::new(Mesh::new(p, t)))
            .collect();
        Self::assemble(meshes, instances)
    }

    /// The scene over meshes already built.
    #[must_use]
    pub fn assemble(meshes: Vec<Arc<Mesh>>, instances: Vec<Instance>) -> Self {
        let mut s = Self {
            meshes,
            instances,
            boxes: Vec::new(),
            tlas: Bvh::default(),
        };
        s.rebuild_instances();
        s
    }

    /// Rebuilds the hierarchy over the instances (after a mesh was refit or an instance
    /// moved).
    pub fn rebuild_instances(&mut self) {
        let meshes = &self.meshes;
        self.instances
            .retain(|i| meshes.get(i.mesh as usize).is_some_and(|m| !m.is_empty()));
        let boxes: Vec<(Vec3, Vec3)> = self
            .instances
            .iter()
            .map(|i| placed_box(&meshes[i.mesh as usize], i).unwrap_or((Vec3::ZERO, Vec3::ZERO)))
            .collect();
        self.tlas = Bvh::build(&boxes);
        self.boxes = boxes
            .iter()
            .map(|&(lo, hi)| {
                let (lo, hi) = crate::bvh::widen(lo, hi);
                Node::new(lo, hi, 0, 0)
            })
            .collect();
    }

    #[must_use]
    pub fn instances(&self) -> &[Instance] {
        &self.instances
    }

    /// Triangles over all meshes (each once, however many instances place it).
    #[must_use]
    pub fn triangles(&self) -> usize {
        self.meshes.iter().map(|m| m.len()).sum()
    }

    /// The ray in instance `i`'s own space; `None` if it cannot meet the instance's mesh
    /// (it leaves the plane a flat mesh lies in).
    #[inline]
    pub(crate) fn local(&self, i: &Instance, ray: &Ray) -> Option<(Sheared, Slabs)> {
        let (o, d) = if i.identity {
            (ray.origin, ray.dir)
        } else {
            (
                i.to_object.transform_point3(ray.origin),
                i.to_object.transform_vector3(ray.dir),
            )
        };
        if self.meshes[i.mesh as usize].leaves_plane(o, d) {
            return None;
        }
        Some((Sheared::new(o, d)?, Slabs::new(o, d)))
    }

    /// The nearest hit of `ray`.
    #[must_use]
    pub fn closest(&self, ray: &Ray) -> Option<Hit> {
        self.closest_where(ray, |_, _, _, _| true)
    }

    /// The nearest hit of `ray` that `accept(instance, triangle, front, t)` takes (hidden
    /// instances, culled back faces, parts cut away are passed over).
    #[must_use]
    pub fn closest_where(
        &self,
        ray: &Ray,
        accept: impl Fn(&Instance, u32, bool, f32) -> bool,
    ) -> Option<Hit> {
        if !ray.is_valid() {
            return None;
        }
        let slabs = Slabs::new(ray.origin, ray.dir);
        let mut best = None;
        with_stack(|stack| {
            self.tlas.traverse(
                &slabs,
                ray.tmin,
                ray.tmax,
                stack,
                |first, count, mut t, stack| {
                    for slot in first..first + count {
                        let k = self.tlas.order[slot as usize];
                        if slabs.enter(&self.boxes[k as usize], ray.tmin, t).is_none() {
                            continue;
                        }
                        let inst = &self.instances[k as usize];
                        let Some((s, sl)) = self.local(inst, ray) else {
                            continue;
                        };
                        let take = |tri: u32, front: bool, t: f32| accept(inst, tri, front, t);
                        let mesh = &self.meshes[inst.mesh as usize];
                        if let Some((th, tri, w, front)) =
                            mesh.closest(&s, &sl, ray.tmin, t, &take, stack)
                        {
                            t = th;
                            best = Some(Hit {
                                t: th,
                                instance: k,
                                key: inst.key,
                                triangle: tri,
                                bary: w,
                                front,
                            });
                        }
                    }
                    Some(t)
                },
            );
        });
        best
    }

    /// Whether anything lies on `ray` within `(tmin, tmax)` (a shadow ray: the first hit
    /// found ends the search).
    #[must_use]
    pub fn occluded(&self, ray: &Ray) -> bool {
        if !ray.is_valid() {
            return false;
        }
        let slabs = Slabs::new(ray.origin, ray.dir);
        let mut found = false;
        with_stack(|stack| {
            self.tlas.traverse(
                &slabs,
                ray.tmin,
                ray.tmax,
                stack,
                |first, count, t, stack| {
                    for slot in first..first + count {
                        let k = self.tlas.order[slot as usize] as usize;
                        if slabs.enter(&self.boxes[k], ray.tmin, t).is_none() {
                            continue;
                        }
                        let inst = &self.instances[k];
                        let Some((s, sl)) = self.local(inst, ray) else {
                            continue;
                        };
                        if self.meshes[inst.mesh as usize].any(&s, &sl, ray.tmin, t, stack) {
                            found = true;
                            return None;
                        }
                    }
                    Some(t)
                },
            );
        });
        found
    }

    /// Refits mesh `m` to new vertex positions (same triangles) and the instances over it.
    pub fn refit(&mut self, m: usize, positions: &[Vec3], triangles: &[[u32; 3]]) {
        if let Some(mesh) = self.meshes.get_mut(m) {
            Arc::make_mut(mesh).refit(positions, triangles);
            self.rebuild_instances();
        }
    }
}
