//! Copy of the serial `adjacency.rs` before it went parallel (see `reference/mod.rs`).

use crate::{Edge, Facet, NO_FACET};

/// Corner-to-facet navigation.
pub(crate) struct Ring<'a> {
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
pub(crate) struct VertexCorners {
    /// `around[start[v]..start[v + 1]]` are vertex `v`'s corners.
    start: Vec<u32>,
    around: Vec<u32>,
    /// Parallel to `around`: the vertices of the next and the previous corner, gathered
    /// while the corners are read in order, so that walking a vertex reads memory in order
    /// too.
    sides: Vec<[u32; 2]>,
}

impl VertexCorners {
    pub fn new(vertex_count: usize, corners: &[u32], ring: &Ring) -> Self {
        let mut start = vec![0u32; vertex_count + 1];
        for &v in corners {
            start[v as usize + 1] += 1;
        }
        for v in 1..start.len() {
            start[v] += start[v - 1];
        }
        // Fill with start[v] as the cursor, which leaves it at start[v + 1]; shift back.
        let mut around = vec![0u32; corners.len()];
        let mut sides = vec![[0u32; 2]; corners.len()];
        for (c, &v) in corners.iter().enumerate() {
            let slot = start[v as usize] as usize;
            around[slot] = c as u32;
            sides[slot] = [corners[ring.next(c)], corners[ring.prev(c)]];
            start[v as usize] += 1;
        }
        start.copy_within(..vertex_count, 1);
        start[0] = 0;
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
pub(crate) fn edges(
    corner_count: usize,
    ring: &Ring,
    around: &VertexCorners,
) -> (Vec<Edge>, Vec<u32>) {
    let mut edges = Vec::with_capacity(corner_count / 2 + 1);
    let mut corner_edges = vec![0u32; corner_count];
    // (larger vertex << 32 | corner the edge starts from) for the edges of one vertex.
    let mut local: Vec<u64> = Vec::new();
    let key = |hi: u32, corner: usize| u64::from(hi) << 32 | corner as u64;
    for lo in 0..around.vertex_count() {
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
        for group in local.chunk_by(|a, b| a >> 32 == b >> 32) {
            let index = edges.len() as u32;
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
            for &e in group {
                corner_edges[e as u32 as usize] = index;
            }
        }
    }
    (edges, corner_edges)
}
