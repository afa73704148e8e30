//! The builder behind [`Bvh::build`](crate::bvh::Bvh::build): binned surface-area heuristic
//! (SAH) after Wald, "On fast Construction of SAH-based Bounding Volume Hierarchies" (IRT
//! 2007). This module owns the records the builder moves, the recursion and the layout of
//! the nodes; [`cut`] decides how each range of primitives is cut.
//!
//! The primitives are compact records ([`Prim`]: box and index in 32 bytes), partitioned in
//! place, so every pass reads and writes memory in order. A range is cut where the SAH
//! says, among the planes between equal bins of its centres on all three axes (or, for 2 to
//! 4 primitives, among every way to cut them in two); a range of up to [`MAX_LEAF`] becomes
//! a leaf when that costs less, and one primitive always does. Ranges of [`PARALLEL_MIN`] or
//! more build their two halves with `rayon::join`, each half below that into its own node
//! array; the arrays are spliced into one at the end, each node copied once with its child
//! index shifted. The nodes come out depth first, the two children of a node adjacent and
//! after it (what [`Bvh::refit`](crate::bvh::Bvh::refit) relies on), every box widened
//! ([`widen`](crate::bvh::widen)).
//!
//! Two guards keep any input finite: a range whose centres all coincide (identical boxes)
//! is cut in the middle of its records, and from [`MEDIAN_DEPTH`] down every cut is at the
//! median centre of the widest axis, so no leaf is deeper than `MEDIAN_DEPTH` plus `log2`
//! of the primitives (the recursion's and the traversal's depth).
//!
//! Rejected: `obvhs`'s PLOC (its `fastest_build` preset with leaves of up to 4), which took
//! 18-21 ms on the bunny's 69,451 triangles (`realist bench rays`, 2 threads), half of it
//! sorting and clustering, and barely ran faster on 2 threads than on 1. With this builder
//! the bench's build takes 10.5 ms (18.0 on 1 thread, against 20.5), and the tree traces
//! its primary and shadow rays 3-5% faster (153.1 and 57.2 ms against 158.6 and 59.8; on a
//! sphere of a million triangles, built in 210 ms against 392, 7% and 4% faster).

mod cut;

use glam::{Vec3, Vec3A, Vec4};
use rayon::prelude::*;

use crate::bvh::{from_lane, in_lane, Node};
use cut::{bounds_of, split, Bounds};

/// Most primitives in a leaf. With [`cut::NODE_COST`] at 1 the SAH seldom wants more:
/// allowing 8 changed 4 of the bunny's 74,947 nodes.
pub const MAX_LEAF: usize = 4;

/// Ranges of at least this many primitives build their halves in parallel (the bunny's
/// tree is built as 24 parts of 2,000 to 4,000 primitives).
const PARALLEL_MIN: usize = 4096;

/// The depth (the root's is 1) from which ranges are cut at the median instead of by SAH.
pub const MEDIAN_DEPTH: usize = 48;

/// A primitive as the builder moves it: its box, and in the minimum's fourth lane the index
/// [`Bvh::order`](crate::bvh::Bvh::order) will give for it.
#[derive(Clone, Copy, Debug)]
pub struct Prim {
    lo: Vec4,
    hi: Vec4,
}

impl Prim {
    #[must_use]
    pub fn new(min: Vec3, max: Vec3, index: u32) -> Self {
        Self {
            lo: min.extend(in_lane(index)),
            hi: max.extend(0.0),
        }
    }

    #[must_use]
    pub fn index(&self) -> u32 {
        from_lane(self.lo.w)
    }

    /// Its box holds nothing (its minimum is above its maximum on some axis).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.min().cmpgt(self.max()).any()
    }

    /// The minimum, its fourth lane (the index) cleared: nothing computed in that lane is
    /// used, but a subnormal there would cost a microcode assist per operation (the index's
    /// plain bits did: the first build was 25 times slower).
    #[inline(always)]
    fn min(&self) -> Vec3A {
        Vec3A::from_vec4(self.lo.with_w(0.0))
    }

    #[inline(always)]
    fn max(&self) -> Vec3A {
        Vec3A::from_vec4(self.hi)
    }

    /// Twice the box's centre (halving it would only cost a multiply).
    #[inline(always)]
    fn centre2(&self) -> Vec3A {
        self.min() + self.max()
    }
}

/// A range of primitives to build over: their slots `first..first + prims.len()`, their
/// box, the box of their centres (doubled, as [`Prim::centre2`]) and the depth of their
/// node (the root's is 1).
struct Range<'a> {
    prims: &'a mut [Prim],
    first: u32,
    bounds: Bounds,
    centres: Bounds,
    depth: usize,
}

/// Builds `r` into `nodes`, its node at `slot` (already there); returns the depth of its
/// deepest leaf.
fn build_into(r: Range, nodes: &mut Vec<Node>, slot: usize) -> usize {
    let (bounds, first, n, depth) = (r.bounds, r.first, r.prims.len() as u32, r.depth);
    match split(r) {
        None => {
            nodes[slot] = bounds.node(n, first);
            depth
        }
        Some((left, right)) => {
            let at = nodes.len();
            nodes.extend([Node::default(); 2]);
            nodes[slot] = bounds.node(0, at as u32);
            build_into(left, nodes, at).max(build_into(right, nodes, at + 1))
        }
    }
}

/// What the parallel levels build: a part built by one task (its root first, child indices
/// into its own array), or a node whose two halves were built apart.
enum Tree {
    Part { nodes: Vec<Node>, depth: usize },
    Inner { node: Node, halves: Box<[Tree; 2]> },
}

impl Tree {
    fn len(&self) -> usize {
        match self {
            Tree::Part { nodes, .. } => nodes.len(),
            Tree::Inner { halves, .. } => 1 + halves[0].len() + halves[1].len(),
        }
    }

    fn depth(&self) -> usize {
        match self {
            Tree::Part { depth, .. } => *depth,
            Tree::Inner { halves, .. } => halves[0].depth().max(halves[1].depth()),
        }
    }
}

fn build_tree(r: Range) -> Tree {
    let n = r.prims.len();
    if n < PARALLEL_MIN {
        let mut nodes = Vec::with_capacity(2 * n - 1);
        nodes.push(Node::default());
        let depth = build_into(r, &mut nodes, 0);
        return Tree::Part { nodes, depth };
    }
    let (bounds, first, depth) = (r.bounds, r.first, r.depth);
    match split(r) {
        None => Tree::Part {
            nodes: vec![bounds.node(n as u32, first)],
            depth,
        },
        Some((left, right)) => {
            let (a, b) = rayon::join(|| build_tree(left), || build_tree(right));
            Tree::Inner {
                node: bounds.node(0, 0),
                halves: Box::new([a, b]),
            }
        }
    }
}

/// `n` with its child index (if it is an inner node) moved by `shift`.
fn shifted(n: &Node, shift: u32) -> Node {
    if n.count() > 0 {
        *n
    } else {
        Node::new(n.min(), n.max(), 0, n.index() + shift)
    }
}

/// Lays `tree` out as one array, depth first: children adjacent and after their parent,
/// each part's nodes in the order they were built. (Copying the parts on both threads
/// measured no faster.)
fn splice(tree: Tree) -> Vec<Node> {
    if let Tree::Part { nodes, .. } = tree {
        return nodes;
    }
    let mut out = Vec::with_capacity(tree.len());
    out.push(Node::default());
    let mut todo = vec![(tree, 0usize)];
    while let Some((t, slot)) = todo.pop() {
        match t {
            Tree::Part { nodes, .. } => {
                // A child index `i` of the part (never its root) is now `shift + i`.
                let shift = out.len() as u32 - 1;
                out[slot] = shifted(&nodes[0], shift);
                out.extend(nodes[1..].iter().map(|n| shifted(n, shift)));
            }
            Tree::Inner { node, halves } => {
                let at = out.len();
                out.extend([Node::default(); 2]);
                out[slot] = Node::new(node.min(), node.max(), 0, at as u32);
                let [a, b] = *halves;
                todo.push((b, at + 1));
                todo.push((a, at));
            }
        }
    }
    out
}

/// The binary tree over `prims` (reordered into slot order), depth first, and the depth of
/// its deepest leaf. `prims` must not be empty.
pub fn build(prims: &mut [Prim]) -> (Vec<Node>, usize) {
    let (bounds, centres) = prims.par_chunks(PARALLEL_MIN).map(bounds_of).reduce(
        || (Bounds::EMPTY, Bounds::EMPTY),
        |a, b| (a.0.union(b.0), a.1.union(b.1)),
    );
    let tree = build_tree(Range {
        prims,
        first: 0,
        bounds,
        centres,
        depth: 1,
    });
    let depth = tree.depth();
    (splice(tree), depth)
}

#[cfg(test)]
mod tests;
