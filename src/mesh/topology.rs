//! Topology report: counts of vertices, edges, facets, boundary and non-manifold edges,
//! degenerate facets, connected components, bounding box.

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
    pub bounds_min: [f32; 3],
    pub bounds_max: [f32; 3],
}
