//! The render form of a mesh: facets split into triangles, attributes flattened so every
//! triangle corner indexes one render vertex.
//!
//! A render vertex is a distinct tuple (vertex, normal index, one index per UV set, colour
//! index, tangent index) over the facet corners. Render vertex `v` is the first tuple seen at mesh vertex `v` (so, when every
//! channel is per vertex, render vertices *are* the mesh vertices and nothing is hashed or
//! searched); further tuples of a vertex are appended and found again through a short chain
//! per vertex, in corner order, so the result depends on the data only.
//!
//! Facets: triangles as they are; quads split along the diagonal that keeps both triangles
//! facing the facet normal (the shorter one when both do, i.e. when convex); larger polygons
//! fanned from their first corner when convex, otherwise ear-clipped in the facet's plane
//! (see `polygon.rs`). Every facet of `n` corners gives exactly `n - 2` triangles, so the
//! count matches [`TopologyReport::triangles`](super::TopologyReport::triangles).
//!
//! Points and line segments are copied as they are: render vertex `v` is mesh vertex `v`
//! for every mesh vertex, so their indices need no mapping.

use glam::{Vec2, Vec3, Vec4};
use rayon::prelude::*;

use super::normals::{unit, FALLBACK_NORMAL};
use super::{par, polygon, Channel, Facet, Mesh};

/// Triangles with flattened attributes, ready for the rasterizer.
#[derive(Clone, Debug, Default)]
pub struct TriMesh {
    pub positions: Vec<Vec3>,
    /// Unit normals, one per render vertex.
    pub normals: Vec<Vec3>,
    /// Texture coordinate sets, one value per render vertex each (`uvs[n]` = `TEXCOORD_n`).
    pub uvs: Vec<Vec<Vec2>>,
    pub colors: Option<Vec<Vec4>>,
    /// Tangents (unit `xyz`, handedness in `w`; see [`Mesh::tangents`]).
    pub tangents: Option<Vec<Vec4>>,
    /// Counter-clockwise triangles (front face) as render-vertex indices.
    pub triangles: Vec<[u32; 3]>,
    /// The facet each triangle came from; empty when every facet is a triangle (triangle
    /// `t` is facet `t`): read it through [`TriMesh::facet_of`].
    pub triangle_facets: Vec<u32>,
    /// Unit facet normals (zero for degenerate facets), indexed by facet; empty when every
    /// facet is a triangle: read them through [`TriMesh::facet_normal`], which then
    /// computes the triangle's. (At 10 million triangles the two tables held 160 MB that
    /// only flat shading reads.)
    pub facet_normals: Vec<Vec3>,
    /// The mesh vertex ([`Mesh::positions`]) of every render vertex, for meshes whose
    /// render vertices are not simply the mesh vertices; empty means the identity.
    pub vertex_of: Vec<u32>,
    /// Bounding sphere of the finite positions (centre, radius); radius < 0 if none.
    pub center: Vec3,
    pub radius: f32,
    /// Points as render-vertex indices ([`Mesh::points`]; render vertex `v < positions`
    /// of the mesh is always mesh vertex `v`).
    pub points: Vec<u32>,
    /// Line segments as render-vertex index pairs ([`Mesh::lines`]).
    pub lines: Vec<[u32; 2]>,
    /// The normals were read from the file: points and lines are lit only then (glTF's
    /// recommendation; without NORMAL they are unlit).
    pub file_normals: bool,
}

impl TriMesh {
    /// UV set `n`, if the mesh has it.
    #[must_use]
    pub fn uv_set(&self, n: u32) -> Option<&[Vec2]> {
        self.uvs.get(n as usize).map(Vec::as_slice)
    }

    /// The facet triangle `t` came from.
    #[must_use]
    #[inline]
    pub fn facet_of(&self, t: usize) -> usize {
        if self.triangle_facets.is_empty() {
            t
        } else {
            self.triangle_facets[t] as usize
        }
    }

    /// Facets: one per triangle when [`TriMesh::triangle_facets`] is empty.
    #[must_use]
    pub fn facet_count(&self) -> usize {
        if self.triangle_facets.is_empty() {
            self.triangles.len()
        } else {
            self.facet_normals.len()
        }
    }

    /// The unit normal of facet `f` (zero if degenerate or out of range): stored, or, when
    /// every facet is a triangle, computed from the triangle's positions exactly as
    /// [`Mesh::new`] computes a facet's (so the two agree bit for bit at rest).
    #[must_use]
    pub fn facet_normal(&self, f: usize) -> Vec3 {
        if !self.triangle_facets.is_empty() {
            return self.facet_normals.get(f).copied().unwrap_or(Vec3::ZERO);
        }
        self.triangles
            .get(f)
            .map_or(Vec3::ZERO, |t| super::build::newell(&self.positions, t).0)
    }

    /// Whether there is nothing to draw: no triangles, points or lines.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty() && self.points.is_empty() && self.lines.is_empty()
    }
}

/// Marks an unset slot.
const UNSET: u32 = u32::MAX;

/// The key of a channel at a corner: its index if per corner, `UNSET` if per vertex (then the
/// vertex decides) or absent.
fn key<T>(ch: Option<&Channel<T>>, corner: usize) -> u32 {
    ch.and_then(|ch| ch.indices.as_ref())
        .map_or(UNSET, |ix| ix[corner])
}

/// The channels that take part in a render vertex's key, in key order: normals, each UV
/// set, colours, tangents.
struct Keyed<'a> {
    normals: &'a Channel<Vec3>,
    uvs: &'a [Channel<Vec2>],
    colors: Option<&'a Channel<Vec4>>,
    tangents: Option<&'a Channel<Vec4>>,
}

impl<'a> Keyed<'a> {
    fn of(mesh: &'a Mesh) -> Self {
        Self {
            normals: &mesh.normals,
            uvs: &mesh.uvs,
            colors: mesh.colors.as_ref(),
            tangents: mesh.tangents.as_ref(),
        }
    }

    /// Keys per render vertex.
    fn width(&self) -> usize {
        3 + self.uvs.len()
    }

    /// Key slot of the colours and of the tangents.
    fn colors_slot(&self) -> usize {
        1 + self.uvs.len()
    }

    fn tangents_slot(&self) -> usize {
        2 + self.uvs.len()
    }

    fn all_per_vertex(&self) -> bool {
        self.normals.indices.is_none()
            && self.uvs.iter().all(|c| c.indices.is_none())
            && self.colors.is_none_or(|c| c.indices.is_none())
            && self.tangents.is_none_or(|c| c.indices.is_none())
    }

    /// Writes the keys of corner `c` into `out` (`width()` values).
    fn keys(&self, c: usize, out: &mut [u32]) {
        out[0] = key(Some(self.normals), c);
        for (o, uv) in out[1..].iter_mut().zip(self.uvs) {
            *o = key(Some(uv), c);
        }
        out[self.colors_slot()] = key(self.colors, c);
        out[self.tangents_slot()] = key(self.tangents, c);
    }
}

/// Render vertices: for every corner its render vertex, and for every render vertex its mesh
/// vertex and its channel keys (`width` per render vertex, all `UNSET` for a vertex no
/// corner uses, none at all when every channel is per vertex).
struct RenderVertices {
    of_corner: Vec<u32>,
    vertex: Vec<u32>,
    keys: Vec<u32>,
    width: usize,
}

impl RenderVertices {
    /// Key `slot` of render vertex `r` (`UNSET` when every channel is per vertex).
    #[inline]
    fn key(&self, r: usize, slot: usize) -> u32 {
        self.keys
            .get(r * self.width + slot)
            .copied()
            .unwrap_or(UNSET)
    }
}

fn render_vertices(mesh: &Mesh) -> RenderVertices {
    let vertex_count = mesh.positions.len();
    let keyed = Keyed::of(mesh);
    let width = keyed.width();
    let identity: Vec<u32> = (0..vertex_count as u32).collect();
    if keyed.all_per_vertex() {
        return RenderVertices {
            of_corner: mesh.corners.clone(),
            vertex: identity,
            keys: Vec::new(),
            width,
        };
    }
    let mut vertex = identity;
    let mut keys = vec![UNSET; vertex_count * width];
    let mut used = vec![false; vertex_count];
    let mut chain = vec![UNSET; vertex_count];
    let mut of_corner = Vec::with_capacity(mesh.corners.len());
    let mut k = vec![UNSET; width];
    for (c, &v) in mesh.corners.iter().enumerate() {
        keyed.keys(c, &mut k);
        let at = |r: u32| r as usize * width..(r as usize + 1) * width;
        if !used[v as usize] {
            used[v as usize] = true;
            keys[at(v)].copy_from_slice(&k);
            of_corner.push(v);
            continue;
        }
        let mut r = v;
        while keys[at(r)] != k[..] {
            if chain[r as usize] == UNSET {
                // Validation keeps vertices + corners below u32::MAX.
                chain[r as usize] = vertex.len() as u32;
                keys.extend_from_slice(&k);
                vertex.push(v);
                chain.push(UNSET);
            }
            r = chain[r as usize];
        }
        of_corner.push(r);
    }
    RenderVertices {
        of_corner,
        vertex,
        keys,
        width,
    }
}

/// Values of a channel per render vertex; `default` where a per-corner channel has no
/// corner at an unused vertex.
fn flatten<T: Copy + Send + Sync>(
    ch: &Channel<T>,
    rv: &RenderVertices,
    slot: usize,
    default: T,
) -> Vec<T> {
    (0..rv.vertex.len())
        .into_par_iter()
        .with_min_len(par::MIN_ITEMS)
        .map(|r| match (&ch.indices, rv.key(r, slot)) {
            (None, _) => ch.values[rv.vertex[r] as usize],
            (Some(_), UNSET) => default,
            (Some(_), i) => ch.values[i as usize],
        })
        .collect()
}

/// In parallel over vertices and ranges of facets (each writes its own triangles: a facet
/// of `n` corners always gives `n - 2`); the same result as one pass. Wireframes draw
/// [`Mesh::edges`] directly: render vertex `v` is mesh vertex `v` for every mesh vertex.
pub(super) fn triangulate(mesh: &Mesh) -> TriMesh {
    let rv = render_vertices(mesh);
    let keyed = Keyed::of(mesh);
    let positions = rv
        .vertex
        .par_iter()
        .with_min_len(par::MIN_ITEMS)
        .map(|&v| mesh.positions[v as usize])
        .collect();
    let mut normals = flatten(&mesh.normals, &rv, 0, FALLBACK_NORMAL);
    normals
        .par_iter_mut()
        .with_min_len(par::MIN_ITEMS)
        .for_each(|n| *n = unit(*n).unwrap_or(FALLBACK_NORMAL));
    let uvs = mesh
        .uvs
        .iter()
        .enumerate()
        .map(|(n, ch)| flatten(ch, &rv, 1 + n, Vec2::ZERO))
        .collect();
    let colors = mesh
        .colors
        .as_ref()
        .map(|ch| flatten(ch, &rv, keyed.colors_slot(), Vec4::ONE));
    let tangents = mesh.tangents.as_ref().map(|ch| {
        flatten(
            ch,
            &rv,
            keyed.tangents_slot(),
            Vec4::new(1.0, 0.0, 0.0, 1.0),
        )
    });
    // All triangles: the facet tables would be the identity and a copy.
    let (triangles, triangle_facets, facet_normals) = if mesh.all_triangles() {
        let triangles = rv
            .of_corner
            .par_chunks_exact(3)
            .with_min_len(par::MIN_ITEMS)
            .map(|t| [t[0], t[1], t[2]])
            .collect();
        (triangles, Vec::new(), Vec::new())
    } else {
        let (triangles, triangle_facets) = triangles(mesh, &rv.of_corner);
        let normals = mesh.facets().iter().map(|f| f.normal).collect();
        (triangles, triangle_facets, normals)
    };
    let (center, radius) = mesh.bounding_sphere().unwrap_or((Vec3::ZERO, -1.0));
    TriMesh {
        positions,
        normals,
        uvs,
        colors,
        tangents,
        triangles,
        triangle_facets,
        facet_normals,
        vertex_of: if rv.keys.is_empty() {
            Vec::new()
        } else {
            rv.vertex
        },
        center,
        radius,
        // Render vertex v is mesh vertex v for every v < positions (`render_vertices`).
        points: mesh.points.clone(),
        lines: mesh.lines.clone(),
        file_normals: matches!(mesh.normal_source, super::NormalSource::File),
    }
}

/// The triangles of every facet (as render vertices) and the facet of every triangle.
fn triangles(mesh: &Mesh, of_corner: &[u32]) -> (Vec<[u32; 3]>, Vec<u32>) {
    let count = |facets: &[Facet]| facets.iter().map(|f| f.len as usize - 2).sum::<usize>();
    let mut triangles = vec![[0u32; 3]; count(mesh.facets())];
    let mut triangle_facets = vec![0u32; triangles.len()];
    let ranges = par::facet_ranges(mesh.facets(), par::parts(mesh.corners.len(), 4));
    let lengths = || ranges.iter().map(|r| count(&mesh.facets()[r.clone()]));
    let jobs: Vec<_> = ranges
        .iter()
        .zip(par::split_lengths(&mut triangles, lengths()))
        .zip(par::split_lengths(&mut triangle_facets, lengths()))
        .collect();
    jobs.into_par_iter()
        .for_each(|((r, triangles), triangle_facets)| {
            let mut local = Vec::new();
            let mut scratch = polygon::Scratch::default();
            let mut out = triangles.iter_mut().zip(triangle_facets);
            for (f, facet) in mesh.facets()[r.clone()].iter().enumerate() {
                let corners = facet.corners();
                let ring = &mesh.corners[corners.clone()];
                let render = &of_corner[corners];
                local.clear();
                polygon::triangulate(
                    &mesh.positions,
                    ring,
                    facet.normal,
                    &mut local,
                    &mut scratch,
                );
                for (t, (slot, slot_facet)) in local.iter().zip(&mut out) {
                    *slot = t.map(|i| render[i as usize]);
                    *slot_facet = (r.start + f) as u32;
                }
            }
        });
    (triangles, triangle_facets)
}
