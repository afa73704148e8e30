//! The vertex/edge/facet model of the seed (its `Object3d`, `Vertex3d`, `Edge`, `Facet`).
//!
//! A [`Mesh`] is an indexed polygon mesh. Topology lives on *vertices* (unique positions):
//! every facet lists its corners as vertex indices, every edge knows its two vertices and the
//! facets that use it. Attributes that may differ between the facets meeting at a vertex
//! (normals at a crease, UVs at a texture seam, colours) are [`Channel`]s that can be indexed
//! per facet corner, so a texture seam does not cut the topology and normal averaging sees the
//! true neighbourhood of a vertex.
//!
//! This module knows nothing of file formats, cameras or pixels.

use glam::{Vec2, Vec3, Vec4};

mod normals;
mod primitives;
mod topology;
mod triangulate;

pub use normals::{NormalOptions, Weighting};
pub use topology::TopologyReport;
pub use triangulate::TriMesh;

/// Marks an absent facet in [`Edge::facets`].
pub const NO_FACET: u32 = u32::MAX;

/// A polygon of the mesh. Its corners are `Mesh::corners[first..first + len]`, in
/// counter-clockwise order seen from the front (right-handed, as in OBJ and glTF).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Facet {
    /// Index of the facet's first corner in [`Mesh::corners`].
    pub first: u32,
    /// Number of corners (>= 3).
    pub len: u32,
    /// Unit plane normal (Newell's method), or `Vec3::ZERO` for a degenerate facet.
    pub normal: Vec3,
    /// Area in model units squared (0 for a degenerate facet).
    pub area: f32,
}

impl Facet {
    /// The corner index range of this facet in [`Mesh::corners`].
    #[must_use]
    pub fn corners(&self) -> std::ops::Range<usize> {
        self.first as usize..(self.first + self.len) as usize
    }

    /// True if the facet has (numerically) zero area and therefore no normal.
    #[must_use]
    pub fn is_degenerate(&self) -> bool {
        self.normal == Vec3::ZERO
    }
}

/// An edge between two vertices, shared by the facets that use it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Edge {
    /// The two vertex indices, smaller first.
    pub vertices: [u32; 2],
    /// The first two facets that use this edge ([`NO_FACET`] where absent).
    pub facets: [u32; 2],
    /// How many facets use the edge: 1 = boundary, 2 = manifold, more = non-manifold.
    pub facet_count: u32,
}

/// A per-vertex or per-corner attribute.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel<T> {
    /// The distinct attribute values.
    pub values: Vec<T>,
    /// One index into `values` per facet corner (parallel to [`Mesh::corners`]);
    /// `None` means the channel is indexed by vertex index (one value per vertex).
    pub indices: Option<Vec<u32>>,
}

impl<T: Copy> Channel<T> {
    /// A channel with one value per vertex.
    #[must_use]
    pub fn per_vertex(values: Vec<T>) -> Self {
        Self { values, indices: None }
    }

    /// The value at facet corner `corner` whose vertex is `vertex`.
    #[must_use]
    #[inline]
    pub fn at(&self, corner: usize, vertex: u32) -> T {
        match &self.indices {
            Some(ix) => self.values[ix[corner] as usize],
            None => self.values[vertex as usize],
        }
    }
}

/// Where a mesh's normals came from (reported by `realist info`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NormalSource {
    /// Read from the file.
    File,
    /// Averaged from adjacent facet normals.
    Averaged(NormalOptions),
    /// One normal per facet (glTF without NORMAL: the spec asks for flat normals).
    Flat,
    /// Exact normals from a primitive builder (sphere, cylinder, ...).
    Analytic,
}

/// Raw mesh data as a loader or builder has it, before topology and normals are derived.
#[derive(Clone, Debug, Default)]
pub struct MeshData {
    pub name: String,
    pub positions: Vec<Vec3>,
    /// Vertex index per facet corner.
    pub corners: Vec<u32>,
    /// Corner count per facet; `None` means every facet is a triangle.
    pub facet_sizes: Option<Vec<u32>>,
    pub normals: Option<Channel<Vec3>>,
    pub uvs: Option<Channel<Vec2>>,
    /// Linear RGBA vertex colours.
    pub colors: Option<Channel<Vec4>>,
    /// Index into `Scene::materials`.
    pub material: Option<usize>,
}

/// Why mesh data could not become a [`Mesh`].
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum MeshError {
    #[error("corner {corner} refers to vertex {index}, but there are only {count} vertices")]
    VertexIndex { corner: usize, index: u32, count: usize },
    #[error("{channel} index {index} at corner {corner} is out of range (only {count} values)")]
    ChannelIndex { channel: &'static str, corner: usize, index: u32, count: usize },
    #[error("{channel} has {got} entries, expected {expected}")]
    ChannelLength { channel: &'static str, got: usize, expected: usize },
    #[error("facet sizes add up to {sum} corners, but there are {corners}")]
    FacetSizes { sum: u64, corners: usize },
    #[error("facet {facet} has {len} corners; a facet needs at least 3")]
    FacetTooSmall { facet: usize, len: u32 },
    #[error("triangle list has {0} corners, not a multiple of 3")]
    NotTriangles(usize),
    #[error("mesh is too large: {0}")]
    TooLarge(&'static str),
}

/// The vertex/edge/facet mesh.
#[derive(Clone, Debug)]
pub struct Mesh {
    pub name: String,
    /// Vertex positions (the seed's `Vertex3d`), model space.
    pub positions: Vec<Vec3>,
    /// Vertex index of every facet corner; facet `f` owns `corners[f.first..f.first + f.len]`.
    pub corners: Vec<u32>,
    pub facets: Vec<Facet>,
    pub edges: Vec<Edge>,
    /// For every corner `c` of a facet, the edge from `c` to the facet's next corner.
    pub corner_edges: Vec<u32>,
    /// Always present: read, averaged, flat or analytic (see `normal_source`).
    pub normals: Channel<Vec3>,
    pub normal_source: NormalSource,
    pub uvs: Option<Channel<Vec2>>,
    pub colors: Option<Channel<Vec4>>,
    pub material: Option<usize>,
}

/// What to do when the data has no normals.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NormalPolicy {
    /// Average adjacent facet normals (OBJ, primitives without exact normals).
    Average(NormalOptions),
    /// One normal per facet (what the glTF spec requires when NORMAL is absent).
    Flat,
}

impl Default for NormalPolicy {
    fn default() -> Self {
        NormalPolicy::Average(NormalOptions::default())
    }
}

// --- API to be implemented (bodies filled in by the mesh work) ---
impl Mesh {
    /// Builds topology (edges, facet normals and areas) and, where `data` has no normals,
    /// normals according to `policy`. Fails on out-of-range indices or inconsistent sizes.
    pub fn new(data: MeshData, policy: NormalPolicy) -> Result<Mesh, MeshError> {
        let _ = (data, policy);
        todo!()
    }

    /// Axis-aligned bounds of the finite positions, or `None` if there are none.
    #[must_use]
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        todo!()
    }

    /// Triangulates facets and flattens attributes for rendering.
    #[must_use]
    pub fn triangulate(&self) -> TriMesh {
        todo!()
    }

    /// Counts for `realist info`.
    #[must_use]
    pub fn topology(&self) -> TopologyReport {
        todo!()
    }
}
