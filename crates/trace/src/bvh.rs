//! A binary bounding-volume hierarchy: built by `obvhs` (PLOC with reinsertion, in
//! parallel), then copied into our own node array in depth-first order (children after
//! their parent, which is what [`Bvh::refit`] walks backwards) with every box widened by a
//! few ulps of its coordinates, and traversed by our own code. The widening and the slab
//! test's `1/d` (infinite for a zero component, never clamped) follow Ize, "Robust BVH Ray
//! Traversal" (JCGT 2(2), 2013): a box that exactly touches a vertex or an edge is never
//! missed through rounding, which with the watertight triangle test keeps closed meshes
//! closed.

use glam::{Vec3, Vec3A, Vec4};
use obvhs::aabb::Aabb;
use obvhs::BvhBuildParams;

/// One node, 32 bytes: its box, and either its first child (the second follows it) with a
/// count of 0, or its first primitive and their count (a leaf). The count and index ride in
/// the boxes' fourth lanes, so each corner loads as one SIMD vector.
#[derive(Clone, Copy, Debug, Default)]
pub struct Node {
    lo: Vec4,
    hi: Vec4,
}

impl Node {
    #[must_use]
    pub fn new(min: Vec3, max: Vec3, count: u32, index: u32) -> Self {
        Self {
            lo: min.extend(f32::from_bits(count)),
            hi: max.extend(f32::from_bits(index)),
        }
    }

    #[inline(always)]
    #[must_use]
    pub fn min(&self) -> Vec3 {
        self.lo.truncate()
    }

    #[inline(always)]
    #[must_use]
    pub fn max(&self) -> Vec3 {
        self.hi.truncate()
    }

    /// Primitives of a leaf (0 for an inner node).
    #[inline(always)]
    #[must_use]
    pub fn count(&self) -> u32 {
        self.lo.w.to_bits()
    }

    /// First child, or first primitive slot of a leaf.
    #[inline(always)]
    #[must_use]
    pub fn index(&self) -> u32 {
        self.hi.w.to_bits()
    }
}

/// A hierarchy over boxes; [`Bvh::order`] maps its primitive slots to the caller's indices.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    pub nodes: Vec<Node>,
    /// Primitive slot -> the index the caller gave.
    pub order: Vec<u32>,
    /// Depth of the deepest leaf (the traversal's stack size).
    pub depth: usize,
}

fn to34(v: Vec3) -> glam34::Vec3A {
    glam34::Vec3A::new(v.x, v.y, v.z)
}

fn from34(v: glam34::Vec3A) -> Vec3 {
    Vec3::new(v.x, v.y, v.z)
}

/// A box widened by 4 ulps of its largest coordinate on each side (Ize 2013).
#[must_use]
pub fn widen(min: Vec3, max: Vec3) -> (Vec3, Vec3) {
    let m = min.abs().max(max.abs()).max_element();
    let pad = Vec3::splat(4.0 * f32::EPSILON * m + f32::MIN_POSITIVE);
    (min - pad, max + pad)
}

struct Boxed(Aabb);

impl obvhs::Boundable for Boxed {
    fn aabb(&self) -> Aabb {
        self.0
    }
}

impl Bvh {
    /// Builds over `boxes` (each `(min, max)`, all finite: the caller leaves out what is
    /// not).
    #[must_use]
    pub fn build(boxes: &[(Vec3, Vec3)]) -> Self {
        if boxes.is_empty() {
            return Self::default();
        }
        let prims: Vec<Boxed> = boxes
            .iter()
            .map(|&(a, b)| {
                Boxed(Aabb {
                    min: to34(a),
                    max: to34(b),
                })
            })
            .collect();
        let mut took = std::time::Duration::ZERO;
        let built = obvhs::bvh2::builder::build_bvh2(&prims, BvhBuildParams::fastest_build(), &mut took);
        Self::from_obvhs(&built, boxes)
    }

    /// Copies `b` depth first, leaves' primitives made contiguous in visiting order.
    fn from_obvhs(b: &obvhs::bvh2::Bvh2, boxes: &[(Vec3, Vec3)]) -> Self {
        let mut out = Self {
            nodes: Vec::with_capacity(b.nodes.len()),
            order: Vec::with_capacity(boxes.len()),
            depth: 0,
        };
        if b.nodes.is_empty() {
            return out;
        }
        // (obvhs node, our slot, depth); a slot is reserved before its children are copied.
        out.nodes.push(Node::default());
        let mut todo = vec![(0usize, 0usize, 1usize)];
        while let Some((src, dst, depth)) = todo.pop() {
            out.depth = out.depth.max(depth);
            let n = &b.nodes[src];
            let (min, max) = widen(from34(n.aabb.min), from34(n.aabb.max));
            if n.prim_count > 0 {
                let first = out.order.len() as u32;
                let range = n.first_index as usize..(n.first_index + n.prim_count) as usize;
                out.order.extend_from_slice(&b.primitive_indices[range]);
                out.nodes[dst] = Node::new(min, max, n.prim_count, first);
            } else {
                let first = out.nodes.len();
                out.nodes.push(Node::default());
                out.nodes.push(Node::default());
                out.nodes[dst] = Node::new(min, max, 0, first as u32);
                todo.push((n.first_index as usize + 1, first + 1, depth + 1));
                todo.push((n.first_index as usize, first, depth + 1));
            }
        }
        out
    }

    /// Recomputes every box from the primitives' new boxes (`bounds(slot)` of primitive
    /// slot `slot`, in [`Bvh::order`]'s order): leaves first, then each parent from its children (children come after
    /// their parent, so one backwards pass does it). The tree keeps its shape: good while
    /// the primitives move a little (an animated pose), worse for large motions.
    pub fn refit(&mut self, bounds: impl Fn(usize) -> (Vec3, Vec3)) {
        for k in (0..self.nodes.len()).rev() {
            let n = self.nodes[k];
            let (min, max) = if n.count() > 0 {
                (n.index() as usize..(n.index() + n.count()) as usize).fold(
                    (Vec3::INFINITY, Vec3::NEG_INFINITY),
                    |(lo, hi), slot| {
                        let (a, b) = bounds(slot);
                        (lo.min(a), hi.max(b))
                    },
                )
            } else {
                let (a, b) = (self.nodes[n.index() as usize], self.nodes[n.index() as usize + 1]);
                (a.min().min(b.min()), a.max().max(b.max()))
            };
            let (min, max) = if n.count() > 0 { widen(min, max) } else { (min, max) };
            self.nodes[k] = Node::new(min, max, n.count(), n.index());
        }
    }
}

/// A ray's slab-test constants.
#[derive(Clone, Copy, Debug)]
pub struct Slabs {
    pub origin: Vec3A,
    pub inv: Vec3A,
}

impl Slabs {
    #[must_use]
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Self {
            origin: origin.into(),
            inv: Vec3A::ONE / Vec3A::from(dir),
        }
    }

    /// The entry distance into `n`'s box if the ray meets it within `(tmin, tmax)`. A zero
    /// direction component gives an infinite `1/d`, which is exact; only a ray lying in a
    /// box's face plane makes `0 * inf` (NaN), which the SIMD min and max pass over as
    /// their second operand.
    #[inline(always)]
    #[must_use]
    pub fn enter(&self, n: &Node, tmin: f32, tmax: f32) -> Option<f32> {
        let t0 = (Vec3A::from_vec4(n.lo) - self.origin) * self.inv;
        let t1 = (Vec3A::from_vec4(n.hi) - self.origin) * self.inv;
        let near = t0.min(t1).max_element();
        let far = t0.max(t1).min_element();
        let near = if near > tmin { near } else { tmin };
        let far = if far < tmax { far } else { tmax };
        (near <= far).then_some(near)
    }
}

/// A small stack that spills to the heap only for a tree deeper than it.
pub struct Stack {
    fixed: [u32; 64],
    len: usize,
    spill: Vec<u32>,
}

impl Stack {
    #[must_use]
    pub fn new() -> Self {
        Self {
            fixed: [0; 64],
            len: 0,
            spill: Vec::new(),
        }
    }

    #[inline(always)]
    pub fn push(&mut self, v: u32) {
        if self.len < self.fixed.len() {
            self.fixed[self.len] = v;
            self.len += 1;
        } else {
            self.spill.push(v);
        }
    }

    #[inline(always)]
    pub fn pop(&mut self) -> Option<u32> {
        if let Some(v) = self.spill.pop() {
            return Some(v);
        }
        if self.len == 0 {
            return None;
        }
        self.len -= 1;
        Some(self.fixed[self.len])
    }
}

impl Default for Stack {
    fn default() -> Self {
        Self::new()
    }
}

impl Bvh {
    /// Visits the leaves the ray meets, nearer child first. `leaf(first, count, tmax)`
    /// tests primitive slots `first..first + count` and returns the new `tmax` (smaller
    /// after a hit) or `None` to stop (an any-hit query that found one).
    #[inline]
    pub fn traverse(
        &self,
        slabs: &Slabs,
        tmin: f32,
        mut tmax: f32,
        mut leaf: impl FnMut(u32, u32, f32) -> Option<f32>,
    ) -> f32 {
        let Some(root) = self.nodes.first() else {
            return tmax;
        };
        if slabs.enter(root, tmin, tmax).is_none() {
            return tmax;
        }
        let mut stack = Stack::new();
        let mut at = 0u32;
        loop {
            let n = &self.nodes[at as usize];
            if n.count() > 0 {
                match leaf(n.index(), n.count(), tmax) {
                    Some(t) => tmax = t,
                    None => return tmax,
                }
            } else {
                let (a, b) = (n.index(), n.index() + 1);
                let ta = slabs.enter(&self.nodes[a as usize], tmin, tmax);
                let tb = slabs.enter(&self.nodes[b as usize], tmin, tmax);
                match (ta, tb) {
                    (Some(x), Some(y)) => {
                        let (near, far) = if x <= y { (a, b) } else { (b, a) };
                        stack.push(far);
                        at = near;
                        continue;
                    }
                    (Some(_), None) => {
                        at = a;
                        continue;
                    }
                    (None, Some(_)) => {
                        at = b;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            // Next from the stack (a far child pushed before a hit may now be beyond it:
            // retest it).
            loop {
                let Some(next) = stack.pop() else {
                    return tmax;
                };
                if slabs.enter(&self.nodes[next as usize], tmin, tmax).is_some() {
                    at = next;
                    break;
                }
            }
        }
    }
}
