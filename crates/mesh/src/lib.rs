//! The vertex/edge/facet model of the textbook (its `Object3d`, `Vertex3d`, `Edge`, `Facet`).
//!
//! A [`Mesh`] is an indexed polygon mesh. Topology lives on *vertices* (unique positions):
//! every facet lists its corners as vertex indices, every edge knows its two vertices and the
//! facets that use it. Attributes that may differ between the facets meeting at a vertex
//! (normals at a crease, UVs at a texture seam, colours) are [`Channel`]s that can be indexed
//! per facet corner, so a texture seam does not cut the topology and normal averaging sees the
//! true neighbourhood of a vertex.
//!
//! This module knows nothing of file formats, cameras or pixels.
//!
//! # Invariants of a [`Mesh`] (established by [`Mesh::new`])
//!
//! - every corner index is `< positions.len()`; every facet has at least 3 corners and the
//!   facets cover `corners` contiguously, in order;
//! - `corners.len() + positions.len() < u32::MAX`, so every derived index (edges, render
//!   vertices) fits in a `u32`;
//! - a facet normal is unit length or exactly `Vec3::ZERO` (degenerate: zero area, non-finite
//!   corners); its area is finite and `>= 0`; nothing derived is ever NaN;
//! - [`Mesh::edges`] holds each undirected vertex pair used by consecutive corners exactly
//!   once, sorted by `vertices`; [`Mesh::corner_edges`]`[c]` is the edge from corner `c` to
//!   the next corner of its facet. The edge table is built on first use (a render without
//!   wireframe never needs it: at 10 million triangles it is 420 MB);
//! - every value of `normals` is a finite unit vector, whatever the input; generated
//!   per-vertex normals keep value `v` for vertex `v`, crease-split ones are appended;
//! - channel indices (per corner, parallel to `corners`) are in range;
//! - every index of `points` and `lines` is `< positions.len()` ([`Mesh::set_strokes`]).
//!
//! Points and lines ("strokes") live beside the facets in the same mesh: a glTF POINTS or
//! LINES primitive, or an OBJ group's `p`/`l` elements, is a mesh with no facets and only
//! strokes. So they share everything a mesh has (instances, materials, bounds, skinning and
//! morphing through the same vertices) and the triangle path does not change.
//!
//! The fields are public for reading. Code that mutates them must restore these invariants,
//! most simply by rebuilding through [`Mesh::new`].
//!
//! # Files
//!
//! | file | owns |
//! |---|---|
//! | `build.rs` | validation of [`MeshData`], facet normals and areas (Newell) |
//! | `adjacency.rs` | corner/facet/vertex navigation, the edge table |
//! | `normals.rs` | file, flat and averaged vertex normals, crease splitting |
//! | `weld.rs` | [`MeshData::weld_positions`] |
//! | `topology.rs` | [`TopologyReport`], connected components |
//! | `triangulate.rs` | [`TriMesh`]: render vertices, edges, bounding sphere |
//! | `polygon.rs` | triangulation of one facet: quads, fans, ear clipping |
//! | `primitives.rs` | sphere, cylinder, cone, torus, cube with analytic normals and UVs |

// The crates below this one, under the module names the code uses (`crate::scene::...`).
use realist_geom as geom;
use realist_texture as texture;

use glam::{Vec2, Vec3, Vec4};

use adjacency::{Ring, VertexCorners};

mod adjacency;
mod build;
mod cluster;
mod deform;
mod normals;
mod par;
mod polygon;
mod primitives;
mod tangents;
mod topology;
mod triangulate;
mod uvgen;
mod weld;

#[cfg(test)]
mod tests;

pub use build::DEGENERATE_ASPECT;
pub use cluster::cluster_triangles;
pub use deform::{cofactor, deform, Deform, MorphTarget, Posing};
pub use normals::{NormalOptions, Weighting, FALLBACK_NORMAL, MAX_CREASE_VALENCE};
pub use polygon::MAX_EAR_CLIP;
pub use primitives::{MAX_SEGMENTS, MIN_SEGMENTS};
pub use tangents::TangentError;
pub use topology::TopologyReport;
pub use triangulate::TriMesh;
pub use uvgen::{generate_uvs, generate_uvs_in, uv_frame, MAX_WRAP_EXTENT};

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
    /// The first two facets that use this edge, in facet order ([`NO_FACET`] where absent).
    /// Uses are facet sides: a facet that runs along the edge twice is listed twice.
    pub facets: [u32; 2],
    /// How many facet sides use the edge: 1 = boundary, 2 = manifold, more = non-manifold.
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
        Self {
            values,
            indices: None,
        }
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
    /// Texture coordinate sets (`uvs[n]` = `TEXCOORD_n`).
    pub uvs: Vec<Channel<Vec2>>,
    /// Linear RGBA vertex colours.
    pub colors: Option<Channel<Vec4>>,
    /// Tangents with handedness in `w` (see [`Mesh::tangents`]).
    pub tangents: Option<Channel<Vec4>>,
    /// Index into `Scene::materials`.
    pub material: Option<usize>,
}

/// Why mesh data could not become a [`Mesh`].
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum MeshError {
    #[error("corner {corner} refers to vertex {index}, but there are only {count} vertices")]
    VertexIndex {
        corner: usize,
        index: u32,
        count: usize,
    },
    #[error("{channel} index {index} at corner {corner} is out of range (only {count} values)")]
    ChannelIndex {
        channel: &'static str,
        corner: usize,
        index: u32,
        count: usize,
    },
    #[error("{channel} has {got} entries, expected {expected}")]
    ChannelLength {
        channel: &'static str,
        got: usize,
        expected: usize,
    },
    #[error("facet sizes add up to {sum} corners, but there are {corners}")]
    FacetSizes { sum: u64, corners: usize },
    #[error("facet {facet} has {len} corners; a facet needs at least 3")]
    FacetTooSmall { facet: usize, len: u32 },
    #[error("triangle list has {0} corners, not a multiple of 3")]
    NotTriangles(usize),
    #[error("{what} {item} refers to vertex {index}, but there are only {count} vertices")]
    StrokeIndex {
        what: &'static str,
        item: usize,
        index: u32,
        count: usize,
    },
    #[error("mesh is too large: {0}")]
    TooLarge(&'static str),
    /// A primitive builder got a negative or non-finite dimension.
    #[error("{primitive}: {parameter} = {value} is not a finite number >= 0")]
    Dimension {
        primitive: &'static str,
        parameter: &'static str,
        value: f32,
    },
    /// A primitive builder was asked for more than [`MAX_SEGMENTS`] segments.
    #[error("{primitive}: {parameter} = {count} is above the limit of {max} segments")]
    Segments {
        primitive: &'static str,
        parameter: &'static str,
        count: u32,
        max: u32,
    },
}

/// The vertex/edge/facet mesh.
#[derive(Clone, Debug)]
pub struct Mesh {
    pub name: String,
    /// Vertex positions (the textbook's `Vertex3d`), model space.
    pub positions: Vec<Vec3>,
    /// Vertex index of every facet corner; facet `f` owns `corners[f.first..f.first + f.len]`.
    pub corners: Vec<u32>,
    /// The facets with their normals and areas ([`Mesh::facets`]): made at construction,
    /// except for a mesh of triangles whose normals come from the file, which needs them
    /// only for flat shading, tangents or a report (24 bytes a triangle).
    facets: std::sync::OnceLock<Vec<Facet>>,
    /// The edge table, built by [`Mesh::edges`] on first use.
    edges: std::sync::OnceLock<EdgeTable>,
    /// Always present: read, averaged, flat or analytic (see `normal_source`).
    pub normals: Channel<Vec3>,
    pub normal_source: NormalSource,
    /// Texture coordinate sets: `uvs[n]` is glTF's `TEXCOORD_n` (OBJ has one set); empty
    /// when the data has none. glTF's convention: origin at the image's top-left corner.
    pub uvs: Vec<Channel<Vec2>>,
    pub colors: Option<Channel<Vec4>>,
    /// Tangents (glTF `TANGENT`): unit `xyz` along +u, `w = ±1` the handedness of the
    /// bitangent `B = w (N × T)` (which runs along -v, towards the image's top), read from
    /// the file or generated with MikkTSpace ([`Mesh::generate_tangents`]).
    pub tangents: Option<Channel<Vec4>>,
    pub material: Option<usize>,
    /// `KHR_materials_variants`: under variant `v` the mesh takes material `k` of a pair
    /// `(v, k)` here (indices into `Scene::variants` and `Scene::materials`); a variant not
    /// listed keeps [`Mesh::material`] ([`Mesh::material_in`]).
    pub variants: Vec<(u32, usize)>,
    /// Skinning and morph target data (glTF), indexed by vertex; `None` for a rigid mesh.
    pub deform: Option<Box<Deform>>,
    /// Points (glTF POINTS, OBJ `p`) as vertex indices, beside the facets; drawn as squares
    /// of [`crate::render::Settings::point_size`] pixels. Set by [`Mesh::set_strokes`].
    pub points: Vec<u32>,
    /// Line segments (glTF LINES, LINE_LOOP, LINE_STRIP, OBJ `l`) as vertex index pairs,
    /// beside the facets; drawn [`crate::render::Settings::line_width`] pixels wide.
    pub lines: Vec<[u32; 2]>,
}

/// [`Mesh::edges`] and [`Mesh::corner_edges`].
#[derive(Clone, Debug, Default)]
struct EdgeTable {
    edges: Vec<Edge>,
    corner_edges: Vec<u32>,
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

impl Mesh {
    /// Builds topology (facet normals and areas; the edges on first use) and, where `data`
    /// has no normals, normals according to `policy`. Fails on out-of-range indices or inconsistent sizes.
    ///
    /// Normals read from `data` are renormalised; a zero or non-finite one is replaced, at the
    /// corners that use it, by the facet normal (the channel becomes per corner if needed).
    ///
    /// # Errors
    ///
    /// [`MeshError`] names the first corner, facet or channel that is inconsistent.
    pub fn new(data: MeshData, policy: NormalPolicy) -> Result<Mesh, MeshError> {
        build::validate(&data)?;
        Ok(Mesh::from_valid(data, policy))
    }

    /// [`Mesh::new`] for data already checked by `build::validate` (or built correct by
    /// construction, as the primitives are).
    fn from_valid(data: MeshData, policy: NormalPolicy) -> Mesh {
        let MeshData {
            name,
            positions,
            corners,
            facet_sizes,
            normals,
            uvs,
            colors,
            tangents,
            material,
        } = data;
        let triangles = facet_sizes
            .as_deref()
            .is_none_or(|s| 3 * s.len() == corners.len());
        let facets = std::sync::OnceLock::new();
        let (normals, normal_source) = match normals {
            Some(read) if triangles => {
                // Only a bad normal needs its facet's: computed for that facet alone.
                let ring = Ring::triangles(corners.len());
                let normal = |f: usize| {
                    let (n, _) = build::newell(&positions, &corners[3 * f..3 * f + 3]);
                    normals::usable(n)
                };
                (
                    normals::from_file(read, &corners, &ring, normal),
                    NormalSource::File,
                )
            }
            _ => {
                let all = build::facets(&positions, &corners, facet_sizes.as_deref());
                let ring = Ring::new(&all, corners.len());
                let out = match normals {
                    Some(read) => {
                        let normal = |f: usize| normals::usable(all[f].normal);
                        let ch = normals::from_file(read, &corners, &ring, normal);
                        (ch, NormalSource::File)
                    }
                    None => {
                        let around = VertexCorners::new(positions.len(), &corners, &ring);
                        normals::generate(&positions, &corners, &ring, &around, policy)
                    }
                };
                let _ = facets.set(all);
                out
            }
        };
        Mesh {
            name,
            positions,
            corners,
            facets,
            edges: std::sync::OnceLock::new(),
            normals,
            normal_source,
            uvs,
            colors,
            tangents,
            material,
            variants: Vec::new(),
            deform: None,
            points: Vec::new(),
            lines: Vec::new(),
        }
    }

    /// The mesh's material under material variant `variant` (`None`: the file's default
    /// look): the variant's mapping if the mesh has one, else [`Mesh::material`].
    #[must_use]
    pub fn material_in(&self, variant: Option<usize>) -> Option<usize> {
        variant
            .and_then(|v| self.variant_material(v))
            .or(self.material)
    }

    /// The material variant `v` maps this mesh to, if it maps it.
    #[must_use]
    pub fn variant_material(&self, v: usize) -> Option<usize> {
        self.variants
            .iter()
            .find(|(w, _)| *w as usize == v)
            .map(|&(_, k)| k)
    }

    /// Sets the mesh's points and line segments (vertex indices), after checking every
    /// index against the vertex count. Their vertices take part in the bounds as every
    /// vertex does; they have no facets, so their normals are the file's or a fallback.
    ///
    /// # Errors
    ///
    /// [`MeshError::StrokeIndex`] names the first point or segment with an index out of
    /// range; the mesh is then unchanged.
    pub fn set_strokes(&mut self, points: Vec<u32>, lines: Vec<[u32; 2]>) -> Result<(), MeshError> {
        let count = self.positions.len();
        let bad = |v: u32| v as usize >= count;
        if let Some(item) = points.iter().position(|&v| bad(v)) {
            return Err(MeshError::StrokeIndex {
                what: "point",
                item,
                index: points[item],
                count,
            });
        }
        if let Some(item) = lines.iter().position(|l| bad(l[0]) || bad(l[1])) {
            let index = if bad(lines[item][0]) {
                lines[item][0]
            } else {
                lines[item][1]
            };
            return Err(MeshError::StrokeIndex {
                what: "line",
                item,
                index,
                count,
            });
        }
        self.points = points;
        self.lines = lines;
        Ok(())
    }

    /// Every undirected edge of the facets once, sorted by `vertices` (built on first use,
    /// in parallel, then kept).
    #[must_use]
    pub fn edges(&self) -> &[Edge] {
        &self.edge_table().edges
    }

    /// For every corner `c` of a facet, the index in [`Mesh::edges`] of the edge from `c`
    /// to the facet's next corner.
    #[must_use]
    pub fn corner_edges(&self) -> &[u32] {
        &self.edge_table().corner_edges
    }

    /// The facets, with their normals and areas (computed on first use for a mesh of
    /// triangles with normals from the file, then kept).
    #[must_use]
    pub fn facets(&self) -> &[Facet] {
        // Only a mesh of triangles is left without: its facets need no sizes.
        self.facets
            .get_or_init(|| build::facets(&self.positions, &self.corners, None))
    }

    /// How many facets there are (without computing them).
    #[must_use]
    pub fn facet_count(&self) -> usize {
        self.facets.get().map_or(self.corners.len() / 3, Vec::len)
    }

    /// Whether every facet is a triangle.
    #[must_use]
    pub fn all_triangles(&self) -> bool {
        3 * self.facet_count() == self.corners.len()
    }

    /// Corner-to-facet navigation, without computing facet normals for a mesh of triangles.
    fn ring(&self) -> Ring<'_> {
        match self.facets.get() {
            Some(f) => Ring::new(f, self.corners.len()),
            None => Ring::triangles(self.corners.len()),
        }
    }

    fn edge_table(&self) -> &EdgeTable {
        self.edges.get_or_init(|| {
            let ring = self.ring();
            let around = VertexCorners::new(self.positions.len(), &self.corners, &ring);
            let (edges, corner_edges) = adjacency::edges(&self.corners, &ring, &around);
            EdgeTable {
                edges,
                corner_edges,
            }
        })
    }

    /// Whether the mesh has points or line segments.
    #[must_use]
    pub fn has_strokes(&self) -> bool {
        !self.points.is_empty() || !self.lines.is_empty()
    }

    /// Replaces the normals (read or generated) by ones generated with `policy`.
    pub fn recompute_normals(&mut self, policy: NormalPolicy) {
        let ring = Ring::new(self.facets(), self.corners.len());
        let around = VertexCorners::new(self.positions.len(), &self.corners, &ring);
        let (normals, source) =
            normals::generate(&self.positions, &self.corners, &ring, &around, policy);
        self.normals = normals;
        self.normal_source = source;
    }

    /// Axis-aligned bounds `(min, max)` of the finite positions (all three coordinates
    /// finite), or `None` if there are none.
    #[must_use]
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        bounds_of(&self.positions)
    }

    /// A bounding sphere `(centre, radius)` of the finite positions: the centre of
    /// [`Mesh::bounds`] and the largest distance from it. `None` if no position is finite.
    /// Not the minimal sphere, but never more than `sqrt(3)` times its radius.
    #[must_use]
    pub fn bounding_sphere(&self) -> Option<(Vec3, f32)> {
        bounding_sphere_of(&self.positions)
    }

    /// Triangulates facets and flattens attributes for rendering (see [`TriMesh`]).
    #[must_use]
    pub fn triangulate(&self) -> TriMesh {
        triangulate::triangulate(self)
    }

    /// Counts for `realist info`.
    #[must_use]
    pub fn topology(&self) -> TopologyReport {
        topology::report(self)
    }
}

/// Axis-aligned bounds `(min, max)` of the finite positions (all three coordinates
/// finite), or `None` if there are none.
#[must_use]
pub fn bounds_of(positions: &[Vec3]) -> Option<(Vec3, Vec3)> {
    let mut finite = positions.iter().filter(|p| p.is_finite());
    let first = *finite.next()?;
    Some(finite.fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p))))
}

/// [`Mesh::bounding_sphere`] of a list of positions.
#[must_use]
pub fn bounding_sphere_of(positions: &[Vec3]) -> Option<(Vec3, f32)> {
    let (lo, hi) = bounds_of(positions)?;
    let centre = (lo + hi) * 0.5;
    let radius2 = positions
        .iter()
        .filter(|p| p.is_finite())
        .map(|&p| p.distance_squared(centre))
        .fold(0.0f32, f32::max);
    // +inf when coordinates come near f32::MAX: still not NaN.
    Some((centre, radius2.sqrt()))
}
