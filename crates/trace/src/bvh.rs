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

    fn set(&mut self, slot: usize, box_of: &Node, child: u32) {
        let (a, b) = (box_of.min(), box_of.max());
        for axis in 0..3 {
            self.lo[axis][slot] = a[axis];
            self.hi[axis][slot] = b[axis];
        }
        self.child[slot] = child;
        self.used |= 1 << slot;
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

/// `obvhs`'s fastest preset (one PLOC pass with the shortest search, no reinsertion) with
/// leaves of up to 4 primitives collapsed where the surface-area cost says so. Measured on
/// the bunny and ground (`realist bench rays`, 2 threads): leaves of 1 (the preset) built in
/// 19.7 ms and traced in 156 + 56 ms (primary + shadow); of 4, 18.1 ms and 145 + 54 ms; of
/// 8 the same as 4; a longer search or reinsertion cost 1 to 5 ms more build for 1-2% less
/// trace.
fn build_params() -> BvhBuildParams {
    BvhBuildParams {
        max_prims_per_leaf: 4,
        ..BvhBuildParams::fastest_build()
    }
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
        let built = obvhs::bvh2::builder::build_bvh2(&prims, build_params(), &mut took);
        Self::from_obvhs(&built, boxes)
    }

    /// Copies `b` depth first, leaves' primitives made contiguous in visiting order.
    fn from_obvhs(b: &obvhs::bvh2::Bvh2, boxes: &[(Vec3, Vec3)]) -> Self {
        let mut out = Self {
            nodes: Vec::with_capacity(b.nodes.len()),
            wide: Vec::new(),
            leaves: Vec::new(),
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
        out.make_wide();
        out
    }

    /// Collapses the binary tree into [`Node4`]s: each takes an inner node's two children
    /// and opens the largest inner ones among them until it holds four.
    fn make_wide(&mut self) {
        self.wide.clear();
        self.leaves.clear();
        let Some(root) = self.nodes.first() else {
            return;
        };
        if root.count() > 0 {
            // A single leaf: one wide node holding it.
            let mut n = Node4::EMPTY;
            n.set(0, root, LEAF);
            self.leaves.push([root.index(), root.count()]);
            self.wide.push(n);
            return;
        }
        self.wide.reserve(self.nodes.len() / 2);
        self.wide.push(Node4::EMPTY);
        // Half the surface of each box, or -1 for a leaf (never opened).
        let area: Vec<f32> = self
            .nodes
            .iter()
            .map(|n| {
                let e = n.max() - n.min();
                if n.count() > 0 {
                    -1.0
                } else {
                    e.x * e.y + e.y * e.z + e.z * e.x
                }
            })
            .collect();
        // (binary inner node, wide slot to fill)
        let mut todo = vec![(0usize, 0usize)];
        while let Some((b, w)) = todo.pop() {
            let n = self.nodes[b];
            let mut kids: [usize; 4] = [n.index() as usize, n.index() as usize + 1, 0, 0];
            let mut len = 2;
            while len < 4 {
                // The inner child with the largest box surface opens into its two.
                let mut open = 0;
                for i in 1..len {
                    if area[kids[i]] > area[kids[open]] {
                        open = i;
                    }
                }
                if area[kids[open]] < 0.0 {
                    break;
                }
                let first = self.nodes[kids[open]].index() as usize;
                kids[open] = first;
                kids[len] = first + 1;
                len += 1;
            }
            let mut out = Node4::EMPTY;
            for (slot, &k) in kids[..len].iter().enumerate() {
                let c = self.nodes[k];
                if c.count() > 0 {
                    out.set(slot, &c, LEAF | self.leaves.len() as u32);
                    self.leaves.push([c.index(), c.count()]);
                } else {
                    let at = self.wide.len();
                    self.wide.push(Node4::EMPTY);
                    out.set(slot, &c, at as u32);
                    todo.push((k, at));
                }
            }
            self.wide[w] = out;
        }
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
