//! The render form of a mesh: facets split into triangles, attributes flattened so every
//! triangle corner indexes one render vertex.

use glam::{Vec2, Vec3, Vec4};

/// Triangles with flattened attributes, ready for the rasterizer.
#[derive(Clone, Debug, Default)]
pub struct TriMesh {
    pub positions: Vec<Vec3>,
    /// Unit normals, one per render vertex.
    pub normals: Vec<Vec3>,
    pub uvs: Option<Vec<Vec2>>,
    pub colors: Option<Vec<Vec4>>,
    /// Counter-clockwise triangles (front face) as render-vertex indices.
    pub triangles: Vec<[u32; 3]>,
    /// The facet each triangle came from.
    pub triangle_facets: Vec<u32>,
    /// Unit facet normals (zero for degenerate facets), indexed by facet.
    pub facet_normals: Vec<Vec3>,
    /// Edges as render-vertex index pairs (for wireframe), one per mesh edge.
    pub edges: Vec<[u32; 2]>,
    /// Bounding sphere of the finite positions (centre, radius); radius < 0 if none.
    pub center: Vec3,
    pub radius: f32,
}
