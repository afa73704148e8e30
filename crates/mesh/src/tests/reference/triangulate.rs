//! Copy of the serial `triangulate.rs` before it went parallel (see `reference/mod.rs`).

use glam::{Vec2, Vec3, Vec4};

use super::normals::unit;
use crate::{polygon, Channel, Mesh, TriMesh, FALLBACK_NORMAL};

/// Marks an unset slot.
const UNSET: u32 = u32::MAX;

/// The key of a channel at a corner: its index if per corner, `UNSET` if per vertex (then the
/// vertex decides) or absent.
fn key<T>(ch: Option<&Channel<T>>, corner: usize) -> u32 {
    ch.and_then(|ch| ch.indices.as_ref())
        .map_or(UNSET, |ix| ix[corner])
}

/// Render vertices: for every corner its render vertex, and for every render vertex its mesh
/// vertex and its channel keys (normals, each UV set, colours, tangents; all `UNSET` for a
/// vertex no corner uses). The UV sets and tangents were added to the key after the parallel
/// build, the same way in both.
struct RenderVertices {
    of_corner: Vec<u32>,
    vertex: Vec<u32>,
    keys: Vec<Vec<u32>>,
}

fn corner_keys(mesh: &Mesh, c: usize) -> Vec<u32> {
    let mut k = vec![key(Some(&mesh.normals), c)];
    k.extend(mesh.uvs.iter().map(|uv| key(Some(uv), c)));
    k.push(key(mesh.colors.as_ref(), c));
    k.push(key(mesh.tangents.as_ref(), c));
    k
}

fn render_vertices(mesh: &Mesh) -> RenderVertices {
    let vertex_count = mesh.positions.len();
    let all_per_vertex = mesh.normals.indices.is_none()
        && mesh.uvs.iter().all(|c| c.indices.is_none())
        && mesh.colors.as_ref().is_none_or(|c| c.indices.is_none())
        && mesh.tangents.as_ref().is_none_or(|c| c.indices.is_none());
    let width = 3 + mesh.uvs.len();
    let identity: Vec<u32> = (0..vertex_count as u32).collect();
    if all_per_vertex {
        return RenderVertices {
            of_corner: mesh.corners.clone(),
            vertex: identity,
            keys: vec![vec![UNSET; width]; vertex_count],
        };
    }
    let mut vertex = identity;
    let mut keys = vec![vec![UNSET; width]; vertex_count];
    let mut used = vec![false; vertex_count];
    let mut chain = vec![UNSET; vertex_count];
    let mut of_corner = Vec::with_capacity(mesh.corners.len());
    for (c, &v) in mesh.corners.iter().enumerate() {
        let k = corner_keys(mesh, c);
        if !used[v as usize] {
            (used[v as usize], keys[v as usize]) = (true, k);
            of_corner.push(v);
            continue;
        }
        let mut r = v;
        while keys[r as usize] != k {
            if chain[r as usize] == UNSET {
                // Validation keeps vertices + corners below u32::MAX.
                chain[r as usize] = keys.len() as u32;
                keys.push(k.clone());
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
    }
}

/// Values of a channel per render vertex; `default` where a per-corner channel has no
/// corner at an unused vertex.
fn flatten<T: Copy>(ch: &Channel<T>, rv: &RenderVertices, slot: usize, default: T) -> Vec<T> {
    (0..rv.vertex.len())
        .map(|r| match (&ch.indices, rv.keys[r][slot]) {
            (None, _) => ch.values[rv.vertex[r] as usize],
            (Some(_), UNSET) => default,
            (Some(_), i) => ch.values[i as usize],
        })
        .collect()
}

pub(crate) fn triangulate(mesh: &Mesh) -> TriMesh {
    let rv = render_vertices(mesh);
    let positions = rv
        .vertex
        .iter()
        .map(|&v| mesh.positions[v as usize])
        .collect();
    let normals = flatten(&mesh.normals, &rv, 0, FALLBACK_NORMAL)
        .into_iter()
        .map(|n| unit(n).unwrap_or(FALLBACK_NORMAL))
        .collect();
    let uvs = mesh
        .uvs
        .iter()
        .enumerate()
        .map(|(n, ch)| flatten(ch, &rv, 1 + n, Vec2::ZERO))
        .collect();
    let colors_slot = 1 + mesh.uvs.len();
    let colors = mesh
        .colors
        .as_ref()
        .map(|ch| flatten(ch, &rv, colors_slot, Vec4::ONE));
    let tangents = mesh
        .tangents
        .as_ref()
        .map(|ch| flatten(ch, &rv, colors_slot + 1, Vec4::new(1.0, 0.0, 0.0, 1.0)));

    let triangle_count = mesh.facets().iter().map(|f| f.len as usize - 2).sum();
    let mut triangles = Vec::with_capacity(triangle_count);
    let mut triangle_facets = Vec::with_capacity(triangle_count);
    let mut local = Vec::new();
    let mut scratch = polygon::Scratch::default();
    for (f, facet) in mesh.facets().iter().enumerate() {
        let corners = facet.corners();
        let ring = &mesh.corners[corners.clone()];
        let render = &rv.of_corner[corners];
        local.clear();
        polygon::triangulate(
            &mesh.positions,
            ring,
            facet.normal,
            &mut local,
            &mut scratch,
        );
        for t in &local {
            triangles.push(t.map(|i| render[i as usize]));
            triangle_facets.push(f as u32);
        }
    }

    // Since: a mesh of triangles keeps neither facet table (both implied).
    let mut facet_normals: Vec<Vec3> = mesh.facets().iter().map(|f| f.normal).collect();
    if triangle_count == mesh.facets().len() {
        triangle_facets.clear();
        facet_normals.clear();
    }
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
        vertex_of: Vec::new(),
        center,
        radius,
        points: Vec::new(),
        lines: Vec::new(),
        file_normals: false,
    }
}
