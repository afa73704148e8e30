//! A bounding-volume hierarchy: a binary tree built by our own binned-SAH builder
//! (module `sah`, in parallel), its nodes depth first (children after their parent, which
//! is what [`Bvh::refit`] walks backwards) with every box widened by a few ulps of its
//! coordinates, then collapsed into a tree of four children to a node, which queries
//! traverse. The widening and the slab test's `1/d` (infinite for a zero component, never
//! clamped) follow Ize, "Robust BVH Ray Traversal" (JCGT 2(2), 2013): a box that exactly
//! touches a vertex or an edge is never missed through rounding, which with the watertight
//! triangle test keeps closed meshes closed.
//!
//! On the bunny (69,451 triangles, `realist bench rays`, 2 threads) [`crate::Mesh::new`]
//! takes 10.5 ms: about 7 in the builder, 1 collapsing into the wide tree (while the
//! triangles are gathered into slot order on the other thread), half a millisecond making
//! the records, and in the bench about 1,400 page faults (the allocator hands each build
//! fresh pages). `obvhs`'s PLOC, which built the tree before, took 18-21 ms.

use glam::{Mat4, Vec3, Vec3A, Vec4};
use rayon::prelude::*;

use crate::sah;
pub use crate::sah::Prim;

/// Flips the exponent bits of a count or index kept in a float lane: a small integer's own
/// bits are a subnormal float, and SSE arithmetic on a subnormal takes a microcode assist
/// even in a lane whose result is thrown away (the compiler computes a box's extent on all
/// four lanes). Flipped, an index below 2^23 is a float from 1 to 2. Collapsing the bunny's
/// tree into the wide one took 2.0 ms with the plain bits, 0.7 ms with these.
const LANE_TAG: u32 = 0x3F80_0000;

/// `v` as a float lane's value.
#[inline(always)]
pub(crate) fn in_lane(v: u32) -> f32 {
    f32::from_bits(v ^ LANE_TAG)
}

/// The count or index [`in_lane`] stored.
#[inline(always)]
pub(crate) fn from_lane(f: f32) -> u32 {
    f.to_bits() ^ LANE_TAG
}

/// One node, 32 bytes: its box, and either its first child (the second follows it) with a
/// count of 0, or its first primitive and their count (a leaf). The count and index ride in
/// the boxes' fourth lanes (as `in_lane` keeps them), so each corner loads as one SIMD
/// vector.
#[derive(Clone, Copy, Debug)]
pub struct Node {
    lo: Vec4,
    hi: Vec4,
}

impl Default for Node {
    /// A zero box, an inner node whose children would be at 0.
    fn default() -> Self {
        Self::new(Vec3::ZERO, Vec3::ZERO, 0, 0)
    }
}

impl Node {
    #[must_use]
    pub fn new(min: Vec3, max: Vec3, count: u32, index: u32) -> Self {
        Self {
            lo: min.extend(in_lane(count)),
            hi: max.extend(in_lane(index)),
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
        from_lane(self.lo.w)
    }

    /// First child, or first primitive slot of a leaf.
    #[inline(always)]
    #[must_use]
    pub fn index(&self) -> u32 {
        from_lane(self.hi.w)
    }
}

/// The tag of a [`Node4`] child that is a leaf (its low bits: the first primitive slot).
pub(crate) const LEAF: u32 = 1 << 31;

/// Four children's boxes as lanes (x, y and z of their minima and maxima), tested against a
/// ray at once; a child is another node (its index) or a leaf ([`LEAF`] | its index in
/// the tree's leaf table). Empty slots are masked out.
#[derive(Clone, Copy, Debug)]
pub struct Node4 {
    pub(crate) lo: [Vec4; 3],
    pub(crate) hi: [Vec4; 3],
    pub(crate) child: [u32; 4],
    /// Bit `i` set: slot `i` holds a child.
    pub(crate) used: u32,
}

impl Node4 {
    const EMPTY: Self = Self {
        lo: [Vec4::ZERO; 3],
        hi: [Vec4::ZERO; 3],
        child: [0; 4],
        used: 0,
    };

    /// The node over `kids` (up to four; empty slots are zero boxes, masked out), with
    /// child codes `child`: the four corners transposed into lanes at once.
    fn of(kids: &[Node], child: [u32; 4]) -> Self {
        let k = |i: usize| kids.get(i).copied().unwrap_or_default();
        let (a, b, c, d) = (k(0), k(1), k(2), k(3));
        let lo = Mat4::from_cols(a.lo, b.lo, c.lo, d.lo).transpose();
        let hi = Mat4::from_cols(a.hi, b.hi, c.hi, d.hi).transpose();
        Self {
            lo: [lo.x_axis, lo.y_axis, lo.z_axis],
            hi: [hi.x_axis, hi.y_axis, hi.z_axis],
            child,
            used: (1 << kids.len()) - 1,
        }
    }
}

/// A hierarchy over boxes; [`Bvh::order`] maps its primitive slots to the caller's indices.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    /// The binary tree (what [`Bvh::refit`] updates).
    pub nodes: Vec<Node>,
    /// The same tree four children to a node, each node's four boxes tested at once
    /// (what queries traverse); made from `nodes` after a build or a refit.
    pub(crate) wide: Vec<Node4>,
    /// The wide tree's leaves: first primitive slot and count.
    pub(crate) leaves: Vec<[u32; 2]>,
    /// Primitive slot -> the index the caller gave.
    pub order: Vec<u32>,
    /// Depth of the deepest leaf (the traversal's stack size).
    pub depth: usize,
}

/// A box widened by 4 ulps of its largest coordinate on each side (Ize 2013).
#[must_use]
pub fn widen(min: Vec3, max: Vec3) -> (Vec3, Vec3) {
    let m = min.abs().max(max.abs()).max_element();
    let pad = Vec3::splat(4.0 * f32::EPSILON * m + f32::MIN_POSITIVE);
    (min - pad, max + pad)
}

impl Bvh {
    /// Builds over `boxes` (each `(min, max)`, all finite: the caller leaves out what is
    /// not); [`Bvh::order`] gives each slot's index into `boxes`.
    #[must_use]
    pub fn build(boxes: &[(Vec3, Vec3)]) -> Self {
        Self::build_prims(
            boxes
                .iter()
                .enumerate()
                .map(|(i, &(a, b))| Prim::new(a, b, i as u32))
                .collect(),
        )
    }

    /// Builds over `prims` (boxes all finite); [`Bvh::order`] gives each slot the index its
    /// [`Prim`] carried.
    #[must_use]
    pub fn build_prims(prims: Vec<Prim>) -> Self {
        Self::build_prims_with(prims, |_| ()).0
    }

    /// [`Bvh::build_prims`], running `then(order)` (the caller gathering its data into slot
    /// order) on another thread while the binary tree is collapsed into the wide one.
    #[must_use]
    pub fn build_prims_with<R: Send>(
        mut prims: Vec<Prim>,
        then: impl FnOnce(&[u32]) -> R + Send,
    ) -> (Self, R) {
        if prims.is_empty() {
            return (Self::default(), then(&[]));
        }
        let (nodes, depth) = sah::build(&mut prims);
        let order: Vec<u32> = prims.par_iter().map(Prim::index).collect();
        drop(prims);
        let (mut wide, mut leaves) = (Vec::new(), Vec::new());
        let ((), r) = rayon::join(|| collapse(&nodes, &mut wide, &mut leaves), || then(&order));
        let bvh = Self {
            nodes,
            wide,
            leaves,
            order,
            depth,
        };
        (bvh, r)
    }

    /// The root's box (widened), if there is anything in the tree.
    #[must_use]
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        self.nodes.first().map(|n| (n.min(), n.max()))
    }

    /// Remakes the wide tree from the binary one.
    fn make_wide(&mut self) {
        collapse(&self.nodes, &mut self.wide, &mut self.leaves);
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
                let (a, b) = (
                    self.nodes[n.index() as usize],
                    self.nodes[n.index() as usize + 1],
                );
                (a.min().min(b.min()), a.max().max(b.max()))
            };
            let (min, max) = if n.count() > 0 {
                widen(min, max)
            } else {
                (min, max)
            };
            self.nodes[k] = Node::new(min, max, n.count(), n.index());
        }
        self.make_wide();
    }
}

/// Collapses the binary tree `nodes` into [`Node4`]s (`wide`, their leaves in `leaves`,
/// both cleared first): each takes an inner node's two children and opens the largest
/// inner ones among them until it holds four.
fn collapse(nodes: &[Node], wide: &mut Vec<Node4>, leaves: &mut Vec<[u32; 2]>) {
    wide.clear();
    leaves.clear();
    let Some(root) = nodes.first() else {
        return;
    };
    if root.count() > 0 {
        // A single leaf: one wide node holding it.
        leaves.push([root.index(), root.count()]);
        wide.push(Node4::of(&[*root], [LEAF, 0, 0, 0]));
        return;
    }
    // A binary tree of `l` leaves has `l - 1` inner nodes and `l` leaves, and a wide node
    // takes one to three of the inner ones: about two on the bunny (18,909 wide nodes for
    // 37,599 inner ones), so room for a third of all the nodes seldom has to grow. (Room
    // for half, the bound, made each of the bench's builds fault 1,860 pages instead of
    // 1,380: the allocator gave back more memory between builds.)
    wide.reserve(nodes.len() / 3);
    leaves.reserve(nodes.len().div_ceil(2));
    wide.push(Node4::EMPTY);
    // Half the surface of a node's box, or -1 for a leaf (never opened).
    let area = |n: &Node| {
        let e = n.max() - n.min();
        if n.count() > 0 {
            -1.0
        } else {
            e.x * e.y + e.y * e.z + e.z * e.x
        }
    };
    // (first child of a binary inner node, wide slot to fill); the first child is taken
    // first, so the binary nodes are read mostly in their order.
    let mut todo = vec![(root.index() as usize, 0usize)];
    while let Some((first, w)) = todo.pop() {
        let mut kids = [
            nodes[first],
            nodes[first + 1],
            Node::default(),
            Node::default(),
        ];
        let mut areas = [area(&kids[0]), area(&kids[1]), 0.0, 0.0];
        let mut len = 2;
        while len < 4 {
            // The inner child with the largest box surface opens into its two.
            let mut open = 0;
            for i in 1..len {
                if areas[i] > areas[open] {
                    open = i;
                }
            }
            if areas[open] < 0.0 {
                break;
            }
            let first = kids[open].index() as usize;
            (kids[open], kids[len]) = (nodes[first], nodes[first + 1]);
            (areas[open], areas[len]) = (area(&kids[open]), area(&kids[len]));
            len += 1;
        }
        let mut child = [0u32; 4];
        let mut inner = [(0usize, 0usize); 4];
        let mut inners = 0;
        for (code, c) in child.iter_mut().zip(&kids[..len]) {
            if c.count() > 0 {
                *code = LEAF | leaves.len() as u32;
                leaves.push([c.index(), c.count()]);
            } else {
                *code = wide.len() as u32;
                inner[inners] = (c.index() as usize, wide.len());
                wide.push(Node4::EMPTY);
                inners += 1;
            }
        }
        wide[w] = Node4::of(&kids[..len], child);
        todo.extend(inner[..inners].iter().rev());
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

/// A stack entry: a child's code and its entry distance.
pub type Entry = (u32, f32);

thread_local! {
    /// Each thread's traversal stack, shared by the two levels of a query (the mesh's
    /// traversal works above the instances').
    static STACK: std::cell::RefCell<Vec<Entry>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Runs `f` with this thread's traversal stack (a fresh one if it is in use).
pub fn with_stack<R>(f: impl FnOnce(&mut Vec<Entry>) -> R) -> R {
    STACK.with(|s| match s.try_borrow_mut() {
        Ok(mut s) => f(&mut s),
        Err(_) => f(&mut Vec::new()),
    })
}

impl Bvh {
    /// Visits the leaves the ray meets, nearer ones first. `leaf(first, count, tmax,
    /// stack)` tests primitive slots `first..first + count` and returns the new `tmax`
    /// (smaller after a hit) or `None` to stop (an any-hit query that found one); it may use
    /// the stack above its current length (a second level of hierarchy). Returns the last
    /// `tmax`.
    #[inline]
    pub fn traverse(
        &self,
        slabs: &Slabs,
        tmin: f32,
        mut tmax: f32,
        stack: &mut Vec<Entry>,
        mut leaf: impl FnMut(u32, u32, f32, &mut Vec<Entry>) -> Option<f32>,
    ) -> f32 {
        if self.wide.is_empty() {
            return tmax;
        }
        let o = [
            Vec4::splat(slabs.origin.x),
            Vec4::splat(slabs.origin.y),
            Vec4::splat(slabs.origin.z),
        ];
        let inv = [
            Vec4::splat(slabs.inv.x),
            Vec4::splat(slabs.inv.y),
            Vec4::splat(slabs.inv.z),
        ];
        let base = stack.len();
        let mut code = 0u32;
        loop {
            if code & LEAF != 0 {
                let [first, count] = self.leaves[(code & !LEAF) as usize];
                match leaf(first, count, tmax, stack) {
                    Some(t) => tmax = t,
                    None => {
                        stack.truncate(base);
                        return tmax;
                    }
                }
            } else {
                let n = &self.wide[code as usize];
                let t0x = (n.lo[0] - o[0]) * inv[0];
                let t1x = (n.hi[0] - o[0]) * inv[0];
                let t0y = (n.lo[1] - o[1]) * inv[1];
                let t1y = (n.hi[1] - o[1]) * inv[1];
                let t0z = (n.lo[2] - o[2]) * inv[2];
                let t1z = (n.hi[2] - o[2]) * inv[2];
                let enter = t0x
                    .min(t1x)
                    .max(t0y.min(t1y))
                    .max(t0z.min(t1z).max(Vec4::splat(tmin)));
                let leave = t0x
                    .max(t1x)
                    .min(t0y.max(t1y))
                    .min(t0z.max(t1z).min(Vec4::splat(tmax)));
                let mut hit = enter.cmple(leave).bitmask() & n.used;
                if hit != 0 {
                    // The nearest child met is taken next; the others wait on the stack,
                    // the farthest deepest.
                    let e = enter.to_array();
                    let mut near = hit.trailing_zeros() as usize;
                    hit &= hit - 1;
                    if hit == 0 {
                        code = n.child[near];
                        continue;
                    }
                    let mut order = [0usize; 3];
                    let mut k = 0;
                    while hit != 0 {
                        let mut i = hit.trailing_zeros() as usize;
                        hit &= hit - 1;
                        if e[i] < e[near] {
                            std::mem::swap(&mut i, &mut near);
                        }
                        let mut j = k;
                        while j > 0 && e[order[j - 1]] < e[i] {
                            order[j] = order[j - 1];
                            j -= 1;
                        }
                        order[j] = i;
                        k += 1;
                    }
                    for &i in &order[..k] {
                        stack.push((n.child[i], e[i]));
                    }
                    code = n.child[near];
                    continue;
                }
            }
            // Next from the stack: what is now beyond a hit is passed over.
            loop {
                if stack.len() <= base {
                    return tmax;
                }
                let Some((c, near)) = stack.pop() else {
                    return tmax;
                };
                if near <= tmax {
                    code = c;
                    break;
                }
            }
        }
    }
}
