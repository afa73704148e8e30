//! Navigation between corners, facets and vertices, and the edge table.
//!
//! [`Ring`] answers "which facet owns corner `c`, which corners come before and after it";
//! a mesh of triangles needs no table for that (`c / 3`). [`VertexCorners`] lists the corners
//! of every vertex (counting sort, so in corner order); averaged normals and the edge table
//! both walk it.
//!
//! The edge table: the edges whose smaller vertex is `lo` are found among the corners of
//! `lo` (its outgoing edges, and the incoming ones, which start at the previous corner), then
//! sorted by (larger vertex, starting corner): a handful of entries per vertex, so `O(corners)`
//! time overall, no hashing, and an order that depends on the data only. Edges come out
//! sorted by `vertices`, and the corners of an edge in corner order, which is facet order. A
//! `HashMap` keyed by vertex pair was rejected: slower, and its iteration order is not
//! deterministic.

use std::ops::Range;

use rayon::prelude::*;

use super::{par, Edge, Facet, NO_FACET};

/// Corner-to-facet navigation.
pub(super) struct Ring<'a> {
    pub facets: &'a [Facet],
    /// The facet of every corner; empty when every facet is a triangle.
    table: Vec<u32>,
}

impl<'a> Ring<'a> {
    pub fn new(facets: &'a [Facet], corner_count: usize) -> Self {
        // Every facet has at least 3 corners: equality means all are triangles.
        let table = if facets.len() * 3 == corner_count {
            Vec::new()
        } else {
            corner_facets(facets, corner_count)
        };
        Self { facets, table }
    }

    /// Navigation for `corner_count` corners that are all triangles, without the facets
    /// (`facets` is then empty: only the navigation may be used).
    pub fn triangles(corner_count: usize) -> Self {
        debug_assert!(corner_count.is_multiple_of(3));
        Self {
            facets: &[],
            table: Vec::new(),
        }
    }

    /// The facet that owns corner `c`.
    #[inline]
    pub fn facet(&self, c: usize) -> usize {
        if self.table.is_empty() {
            c / 3
        } else {
            self.table[c] as usize
        }
    }

    /// The next corner of `c`'s facet (counter-clockwise).
    #[inline]
    pub fn next(&self, c: usize) -> usize {
        if self.table.is_empty() {
            return if c % 3 == 2 { c - 2 } else { c + 1 };
        }
        let f = &self.facets[self.table[c] as usize];
        if c + 1 == (f.first + f.len) as usize {
            f.first as usize
        } else {
            c + 1
        }
    }

    /// The previous corner of `c`'s facet.
    #[inline]
    pub fn prev(&self, c: usize) -> usize {
        if self.table.is_empty() {
            return if c.is_multiple_of(3) { c + 2 } else { c - 1 };
        }
        let f = &self.facets[self.table[c] as usize];
        if c == f.first as usize {
            (f.first + f.len - 1) as usize
        } else {
            c - 1
        }
    }

    /// The facet of every corner, as a table.
    pub fn facet_table(&self, corner_count: usize) -> Vec<u32> {
        if self.table.is_empty() {
            (0..corner_count as u32).map(|c| c / 3).collect()
        } else {
            self.table.clone()
        }
    }
}

/// The facet of every corner.
fn corner_facets(facets: &[Facet], corner_count: usize) -> Vec<u32> {
    let mut out = Vec::with_capacity(corner_count);
    for (f, facet) in facets.iter().enumerate() {
        out.extend(std::iter::repeat_n(f as u32, facet.len as usize));
    }
    out
}

/// The corners of every vertex, in corner order, with the vertices before and after each.
pub(super) struct VertexCorners {
    /// `around[start[v]..start[v + 1]]` are vertex `v`'s corners.
    start: Vec<u32>,
    around: Vec<u32>,
    /// Parallel to `around`: the vertices of the next and the previous corner, gathered
    /// while the corners are read in order, so that walking a vertex reads memory in order
    /// too.
    sides: Vec<[u32; 2]>,
}

impl VertexCorners {
    /// A counting sort of the corners by vertex. In parallel, each task owns a range of
    /// vertices (so a contiguous range of the output) and reads all corners in order, keeping
    /// those of its vertices: the same result as one pass, for any number of tasks.
    pub fn new(vertex_count: usize, corners: &[u32], ring: &Ring) -> Self {
        let mut start = vec![0u32; vertex_count + 1];
        for &v in corners {
            start[v as usize + 1] += 1;
        }
        for v in 1..start.len() {
            start[v] += start[v - 1];
        }
        let mut around = vec![0u32; corners.len()];
        let mut sides = vec![[0u32; 2]; corners.len()];
        let ranges = par::balanced(&start, par::parts(corners.len(), 1));
        let lengths = || {
            ranges
                .iter()
                .map(|r| (start[r.end] - start[r.start]) as usize)
        };
        let jobs: Vec<_> = ranges
            .iter()
            .zip(par::split_lengths(&mut around, lengths()))
            .zip(par::split_lengths(&mut sides, lengths()))
            .collect();
        jobs.into_par_iter().for_each(|((r, around), sides)| {
            let base = start[r.start];
            let mut cursor: Vec<u32> = start[r.clone()].iter().map(|&s| s - base).collect();
            let (lo, count) = (r.start as u32, r.len() as u32);
            for (c, &v) in corners.iter().enumerate() {
                let k = v.wrapping_sub(lo);
                if k < count {
                    let slot = &mut cursor[k as usize];
                    around[*slot as usize] = c as u32;
                    sides[*slot as usize] = [corners[ring.next(c)], corners[ring.prev(c)]];
                    *slot += 1;
                }
            }
        });
        Self {
            start,
            around,
            sides,
        }
    }

    /// The corners of vertex `v`.
    #[inline]
    pub fn of(&self, v: usize) -> &[u32] {
        &self.around[self.start[v] as usize..self.start[v + 1] as usize]
    }

    /// The next and previous vertices of the corners of vertex `v`, parallel to [`Self::of`].
    #[inline]
    fn sides_of(&self, v: usize) -> &[[u32; 2]] {
        &self.sides[self.start[v] as usize..self.start[v + 1] as usize]
    }

    pub fn vertex_count(&self) -> usize {
        self.start.len() - 1
    }

    /// The corners of the vertices in `vertices`.
    fn of_range(&self, vertices: &Range<usize>) -> &[u32] {
        &self.around[self.start[vertices.start] as usize..self.start[vertices.end] as usize]
    }

    /// Vertex ranges of about equal corner counts, at most `parts` of them.
    fn ranges(&self, parts: usize) -> Vec<Range<usize>> {
        par::balanced(&self.start, parts)
    }
}

/// Insertion sort: the edges of one vertex are a handful.
fn sort_small(keys: &mut [u64]) {
    if keys.len() > 16 {
        keys.sort_unstable();
        return;
    }
    for i in 1..keys.len() {
        let key = keys[i];
        let mut j = i;
        while j > 0 && keys[j - 1] > key {
            keys[j] = keys[j - 1];
            j -= 1;
        }
        keys[j] = key;
    }
}

/// The edge table and, per corner, the index of the edge to the next corner of its facet.
///
/// In parallel: over ranges of vertices, each listing the edges of its vertices in vertex
/// order (so the concatenation is the table one pass would build), then over corners, each
/// finding its edge among the few whose smaller vertex is its own or its next corner's.
pub(super) fn edges(corners: &[u32], ring: &Ring, around: &VertexCorners) -> (Vec<Edge>, Vec<u32>) {
    let pieces: Vec<(Vec<Edge>, Vec<u32>)> = around
        .ranges(par::parts(corners.len(), 4))
        .into_par_iter()
        .map(|r| edges_of(r, ring, around))
        .collect();
    let mut edges = Vec::with_capacity(pieces.iter().map(|p| p.0.len()).sum());
    // The edges whose smaller vertex is `v` are `edges[first[v]..first[v + 1]]`.
    let mut first = Vec::with_capacity(around.vertex_count() + 1);
    let mut at = 0u32;
    for (piece, counts) in pieces {
        for n in counts {
            first.push(at);
            at += n;
        }
        edges.extend(piece);
    }
    first.push(at);
    let corner_edges = (0..corners.len())
        .into_par_iter()
        .with_min_len(par::MIN_ITEMS)
        .map(|c| {
            let (a, b) = (corners[c], corners[ring.next(c)]);
            let (lo, hi) = (a.min(b), a.max(b));
            let from = first[lo as usize] as usize;
            let to = first[lo as usize + 1] as usize;
            // Every corner's edge is in the table (it was listed from this very corner).
            let k = edges[from..to].iter().position(|e| e.vertices[1] == hi);
            debug_assert!(k.is_some(), "corner {c} has no edge");
            (from + k.unwrap_or(0)) as u32
        })
        .collect();
    (edges, corner_edges)
}

/// The edges whose smaller vertex is in `vertices`, in order, and how many each vertex has.
fn edges_of(vertices: Range<usize>, ring: &Ring, around: &VertexCorners) -> (Vec<Edge>, Vec<u32>) {
    let mut edges = Vec::with_capacity(around.of_range(&vertices).len() / 2 + 1);
    let mut counts = Vec::with_capacity(vertices.len());
    // (larger vertex << 32 | corner the edge starts from) for the edges of one vertex.
    let mut local: Vec<u64> = Vec::new();
    let key = |hi: u32, corner: usize| u64::from(hi) << 32 | corner as u64;
    for lo in vertices {
        local.clear();
        let lo32 = lo as u32;
        for (&k, &[next, prev]) in around.of(lo).iter().zip(around.sides_of(lo)) {
            // Outgoing k -> next, counted here unless the next vertex is smaller (then it is
            // an incoming edge there); incoming prev -> k when the previous vertex is larger.
            if next >= lo32 {
                local.push(key(next, k as usize));
            }
            if prev > lo32 {
                local.push(key(prev, ring.prev(k as usize)));
            }
        }
        sort_small(&mut local);
        let before = edges.len();
        for group in local.chunk_by(|a, b| a >> 32 == b >> 32) {
            let facet = |i: usize| {
                group
                    .get(i)
                    .map_or(NO_FACET, |&e| ring.facet(e as u32 as usize) as u32)
            };
            edges.push(Edge {
                vertices: [lo32, (group[0] >> 32) as u32],
                facets: [facet(0), facet(1)],
                facet_count: group.len() as u32,
            });
        }
        counts.push((edges.len() - before) as u32);
    }
    (edges, counts)
}
