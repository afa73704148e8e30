//! A group of instances drawn as one: the vertex stage appends their clip positions and
//! varyings to pooled buffers, and the rasterizer builds each draw from plain indices.

use std::time::Instant;

use glam::Vec4;

use super::Cx;
use crate::frame::{FrameData, FrameInst};
use crate::pool::{GroupScratch, Item};
use crate::prepare::PreparedScene;
use crate::raster::{self, Draw, DrawList, DrawState};

/// Which positions a group's draws use.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Geometry {
    /// The mesh's render vertices and triangles.
    Indexed,
    /// Flat shading's unindexed corners.
    Flat,
}

/// A group's draws, built on demand from plain indices.
struct GroupDraws<'a> {
    scene: &'a PreparedScene,
    insts: &'a [FrameInst],
    items: &'a [Item],
    sorted: &'a [[u32; 3]],
    clip: &'a [Vec4],
    var: &'a [f32],
    geometry: Geometry,
    state: fn(DrawState) -> DrawState,
    sections: &'a [Vec4],
}

impl DrawList for GroupDraws<'_> {
    fn count(&self) -> usize {
        self.items.len()
    }

    fn draw(&self, i: usize) -> Draw<'_> {
        let it = self.items[i];
        let fi = &self.insts[it.inst as usize];
        let mesh = &self.scene.meshes[fi.mesh as usize];
        let range = it.start as usize..(it.start + it.len) as usize;
        let vars = it.var_start as usize..(it.var_start + it.len * it.stride) as usize;
        Draw {
            id: fi.param,
            clip: &self.clip[range],
            varyings: &self.var[vars],
            stride: it.stride as usize,
            triangles: if it.sorted == u32::MAX {
                match self.geometry {
                    Geometry::Indexed => &mesh.tri.triangles,
                    Geometry::Flat => &mesh.flat().triangles,
                }
            } else {
                let first = it.sorted as usize;
                &self.sorted[first..first + mesh.tri.triangles.len()]
            },
            state: (self.state)(fi.state),
            // The ground plane is never cut.
            sections: if self.scene.instances[fi.inst as usize].ground {
                &[]
            } else {
                self.sections
            },
        }
    }
}

/// Appends one instance's varyings (one vertex per position) and returns their stride.
pub(super) type VertexFn<'a> = dyn FnMut(&FrameInst, &mut Vec<f32>) -> usize + 'a;

/// Draws the frame's instances for which `pick` holds as one group: the vertex stage
/// (`vertex` appends the varyings of each position) then the rasterizer. Returns false if
/// stopped.
pub(super) fn group<S: raster::FragmentShader>(
    cx: &mut Cx,
    fd: &FrameData,
    pick: &dyn Fn(usize, &FrameInst) -> bool,
    geometry: Geometry,
    mut vertex: impl FnMut(&FrameInst, &mut Vec<f32>) -> usize,
    shader: &S,
) -> bool {
    let (done, g) = group_with(cx, &fd.insts, pick, geometry, &mut vertex, shader, |s| s);
    cx.pool.put(g);
    done
}

/// Vertices a group transforms before it rasterizes what it has and starts again: a
/// million instanced copies are drawn in pieces of this size, not with all their vertices
/// at once (the pieces are drawn in order, so the image is the same).
const GROUP_VERTICES: usize = 1 << 21;

/// [`group`] with a state override, also returning the group's buffers (to be put back in
/// the pool).
pub(super) fn group_with<S: raster::FragmentShader>(
    cx: &mut Cx,
    insts: &[FrameInst],
    pick: &dyn Fn(usize, &FrameInst) -> bool,
    geometry: Geometry,
    vertex: &mut VertexFn<'_>,
    shader: &S,
    state: fn(DrawState) -> DrawState,
) -> (bool, Box<GroupScratch>) {
    let mut g = cx.pool.take::<GroupScratch>();
    g.clear();
    let mut start = Instant::now();
    for (k, fi) in insts.iter().enumerate() {
        if !pick(k, fi) {
            continue;
        }
        let mesh = &cx.scene.meshes[fi.mesh as usize];
        let positions = match geometry {
            Geometry::Indexed => &mesh.tri.positions,
            Geometry::Flat => &mesh.flat().corners,
        };
        let first = g.clip.len();
        let var_start = g.var.len();
        let mvp = match cx.light {
            Some(light) => light * fi.world,
            None => cx.jitter * fi.mvp,
        };
        raster::transform_positions_into(mvp, positions, &mut g.clip);
        let stride = vertex(fi, &mut g.var);
        let len = g.clip.len() - first;
        debug_assert_eq!(g.var.len() - var_start, len * stride);
        g.items.push(Item {
            inst: k as u32,
            start: first as u32,
            len: len as u32,
            var_start: var_start as u32,
            stride: stride as u32,
            sorted: u32::MAX,
        });
        if cx.sort {
            let it = g.items.last_mut().expect("just pushed");
            it.sorted = g.sorted.len() as u32;
            sort_back_to_front(
                &mesh.tri.triangles,
                geometry,
                &g.clip[first..],
                &mut g.keys,
                &mut g.sorted,
            );
        }
        if g.clip.len() >= GROUP_VERTICES {
            cx.vertex_nanos += start.elapsed().as_nanos() as u64;
            if !rasterize(cx, insts, &mut g, geometry, shader, state) {
                return (false, g);
            }
            g.clear();
            start = Instant::now();
        }
    }
    cx.vertex_nanos += start.elapsed().as_nanos() as u64;
    let done = rasterize(cx, insts, &mut g, geometry, shader, state);
    (done, g)
}

/// Rasterizes the draws gathered in `g`; returns false if stopped.
fn rasterize<S: raster::FragmentShader>(
    cx: &mut Cx,
    insts: &[FrameInst],
    g: &mut GroupScratch,
    geometry: Geometry,
    shader: &S,
    state: fn(DrawState) -> DrawState,
) -> bool {
    if g.items.is_empty() {
        return true;
    }
    let GroupScratch {
        clip,
        var,
        items,
        raster: scratch,
        sorted,
        ..
    } = g;
    let list = GroupDraws {
        scene: cx.scene,
        insts,
        items,
        sorted,
        clip,
        var,
        geometry,
        state,
        sections: if cx.light.is_none() { cx.sections } else { &[] },
    };
    raster::draw_list(
        cx.target, &list, shader, cx.stats, cx.bins, scratch, cx.stop,
    )
}

/// Appends an instance's triangles to `out` in back-to-front order of their centroids'
/// depth (the sum of the corners' clip z, which falls with distance in the reversed-depth
/// convention of [`Camera::projection`](crate::scene::Camera::projection), perspective or
/// parallel), ties in mesh order.
/// `clip` holds the instance's clip positions (for flat geometry, three per triangle).
fn sort_back_to_front(
    triangles: &[[u32; 3]],
    geometry: Geometry,
    clip: &[Vec4],
    keys: &mut Vec<(f32, u32)>,
    out: &mut Vec<[u32; 3]>,
) {
    keys.clear();
    keys.extend(triangles.iter().enumerate().map(|(t, tri)| {
        let corners = match geometry {
            Geometry::Indexed => *tri,
            Geometry::Flat => {
                let t = t as u32;
                [3 * t, 3 * t + 1, 3 * t + 2]
            }
        };
        let z: f32 = corners
            .iter()
            .map(|&k| clip.get(k as usize).map_or(0.0, |c| c.z))
            .sum();
        (if z.is_nan() { 0.0 } else { z }, t as u32)
    }));
    keys.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    out.extend(keys.iter().map(|&(_, t)| match geometry {
        Geometry::Indexed => triangles[t as usize],
        Geometry::Flat => [3 * t, 3 * t + 1, 3 * t + 2],
    }));
}
