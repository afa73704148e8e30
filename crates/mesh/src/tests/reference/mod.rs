//! The serial mesh building that the parallel one replaced, kept verbatim (only paths
//! changed, and the attribute sets that came after it: every UV set and the tangents join the
//! render-vertex key and are flattened as the other channels are) so tests can require the
//! parallel results to be bit-identical to it.

use crate::{Mesh, MeshData, NormalPolicy, NormalSource, TriMesh};

mod adjacency;
mod build;
mod normals;
mod triangulate;

use adjacency::{Ring, VertexCorners};

/// `Mesh::from_valid` as it was (the data must be valid).
pub(super) fn mesh(data: MeshData, policy: NormalPolicy) -> Mesh {
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
    let facets = build::facets(&positions, &corners, facet_sizes.as_deref());
    let ring = Ring::new(&facets, corners.len());
    let around = VertexCorners::new(positions.len(), &corners, &ring);
    let (edges, corner_edges) = adjacency::edges(corners.len(), &ring, &around);
    let (normals, normal_source) = match normals {
        // Never parallel: the crate's own (which since keeps a per-vertex channel per
        // vertex where it can).
        Some(read) => (
            crate::normals::from_file(
                read,
                &corners,
                &crate::adjacency::Ring::new(&facets, corners.len()),
                |f| crate::normals::usable(facets[f].normal),
            ),
            NormalSource::File,
        ),
        None => normals::generate(&positions, &corners, &ring, &around, policy),
    };
    Mesh {
        name,
        positions,
        corners,
        facets: std::sync::OnceLock::from(facets),
        edges: std::sync::OnceLock::from(crate::EdgeTable {
            edges,
            corner_edges,
        }),
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

/// `Mesh::triangulate` as it was.
pub(super) fn triangulate(mesh: &Mesh) -> TriMesh {
    triangulate::triangulate(mesh)
}
