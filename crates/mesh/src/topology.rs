//! Topology report: counts of vertices, edges, facets, boundary and non-manifold edges,
//! degenerate facets, connected components, bounding box.
//!
//! Conventions: `vertices` counts every position, used or not, and the Euler characteristic
//! is `V - E + F` with that count (a closed genus-g surface without isolated vertices gives
//! 2 - 2g). Components group facets connected through shared vertices; isolated vertices are
//! not components. Edges count half-edge uses: a facet that runs along an edge twice counts
//! twice in [`Edge::facet_count`](super::Edge::facet_count).

use super::{Facet, Mesh};

/// What `realist info` prints about a mesh.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct TopologyReport {
    pub vertices: usize,
    pub edges: usize,
    pub facets: usize,
    /// Triangles after triangulating the facets.
    pub triangles: usize,
    /// Edges used by exactly one facet.
    pub boundary_edges: usize,
    /// Edges used by more than two facets.
    pub non_manifold_edges: usize,
    /// Facets with zero area (no normal).
    pub degenerate_facets: usize,
    /// Vertices used by no facet.
    pub isolated_vertices: usize,
    /// Connected components (facets connected through shared edges or vertices).
    pub components: usize,
    /// V - E + F.
    pub euler_characteristic: i64,
    /// V - E + F counting only vertices used by a facet: for a manifold mesh this is
    /// `2 * components - 2 * genus - boundary_loops` (Euler-Poincare).
    pub euler_characteristic_used: i64,
    /// Closed loops formed by the boundary edges (holes).
    pub boundary_loops: usize,
    /// Total genus (handles) from Euler-Poincare, when the mesh is edge-manifold and the
    /// formula gives a whole non-negative number; `None` otherwise.
    pub genus: Option<i64>,
    /// Bounds of the finite positions; both all-zero when no position is finite.
    pub bounds_min: [f32; 3],
    pub bounds_max: [f32; 3],
}

/// Counts everything in a [`TopologyReport`].
pub(super) fn report(mesh: &Mesh) -> TopologyReport {
    let mut used = vec![false; mesh.positions.len()];
    for &v in &mesh.corners {
        used[v as usize] = true;
    }
    let isolated_vertices = used.iter().filter(|&&u| !u).count();
    let (bounds_min, bounds_max) = match mesh.bounds() {
        Some((lo, hi)) => (lo.to_array(), hi.to_array()),
        None => ([0.0; 3], [0.0; 3]),
    };
    let count_edges =
        |keep: fn(u32) -> bool| mesh.edges().iter().filter(|e| keep(e.facet_count)).count();
    let (v, e, f) = (
        mesh.positions.len() as i64,
        mesh.edges().len() as i64,
        mesh.facets().len() as i64,
    );
    let components = components(mesh.positions.len(), &mesh.corners, mesh.facets());
    let boundary_loops = boundary_loops(mesh);
    let used_chi = v - isolated_vertices as i64 - e + f;
    let non_manifold = mesh.edges().iter().any(|e| e.facet_count > 2);
    let twice_genus = 2 * components as i64 - used_chi - boundary_loops as i64;
    let genus =
        (!non_manifold && twice_genus >= 0 && twice_genus % 2 == 0).then_some(twice_genus / 2);
    TopologyReport {
        vertices: mesh.positions.len(),
        edges: mesh.edges().len(),
        facets: mesh.facets().len(),
        triangles: mesh.facets().iter().map(|f| f.len as usize - 2).sum(),
        boundary_edges: count_edges(|n| n == 1),
        non_manifold_edges: count_edges(|n| n > 2),
        degenerate_facets: mesh.facets().iter().filter(|f| f.is_degenerate()).count(),
        isolated_vertices,
        components,
        euler_characteristic: v - e + f,
        euler_characteristic_used: used_chi,
        boundary_loops,
        genus,
        bounds_min,
        bounds_max,
    }
}

/// Number of groups of facets connected through shared vertices (union-find over vertices).
pub(super) fn components(vertex_count: usize, corners: &[u32], facets: &[Facet]) -> usize {
    let mut parent: Vec<u32> = (0..vertex_count as u32).collect();
    fn root(parent: &mut [u32], mut v: u32) -> u32 {
        while parent[v as usize] != v {
            // Path halving.
            let grand = parent[parent[v as usize] as usize];
            parent[v as usize] = grand;
            v = grand;
        }
        v
    }
    for facet in facets {
        let ring = &corners[facet.corners()];
        let mut a = root(&mut parent, ring[0]);
        for &v in &ring[1..] {
            let b = root(&mut parent, v);
            // Union towards the smaller index: deterministic, and keeps trees shallow enough
            // together with path halving.
            let (lo, hi) = (a.min(b), a.max(b));
            parent[hi as usize] = lo;
            a = lo;
        }
    }
    let mut roots = vec![false; vertex_count];
    for &v in corners {
        roots[root(&mut parent, v) as usize] = true;
    }
    roots.iter().filter(|&&r| r).count()
}

/// Number of connected groups of boundary edges (each hole of a manifold mesh is one loop).
fn boundary_loops(mesh: &Mesh) -> usize {
    let boundary: Vec<[u32; 2]> = mesh
        .edges()
        .iter()
        .filter(|e| e.facet_count == 1)
        .map(|e| e.vertices)
        .collect();
    if boundary.is_empty() {
        return 0;
    }
    let mut ids: Vec<u32> = boundary.iter().flatten().copied().collect();
    ids.sort_unstable();
    ids.dedup();
    let index = |v: u32| ids.binary_search(&v).unwrap_or(0) as u32;
    let corners: Vec<u32> = boundary
        .iter()
        .flat_map(|e| [index(e[0]), index(e[1])])
        .collect();
    // Each boundary edge as a two-corner "facet" for the shared union-find.
    let facets: Vec<Facet> = (0..boundary.len() as u32)
        .map(|k| Facet {
            first: 2 * k,
            len: 2,
            normal: glam::Vec3::ZERO,
            area: 0.0,
        })
        .collect();
    components(ids.len(), &corners, &facets)
}
