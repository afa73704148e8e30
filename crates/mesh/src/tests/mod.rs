//! Unit tests of the mesh module, one file per concern, with shared fixtures here.

mod build;
mod normals;
mod parallel;
mod primitives;
mod reference;
mod triangulate;

use glam::{Vec2, Vec3};

use super::{Channel, Mesh, MeshData, NormalOptions, NormalPolicy, Weighting, NO_FACET};

/// Largest tolerated difference between floats that should agree.
const EPS: f32 = 1e-5;

#[track_caller]
fn assert_close(actual: Vec3, expected: Vec3, eps: f32) {
    let diff = (actual - expected).abs().max_element();
    assert!(
        diff <= eps,
        "{actual} != {expected} (off by {diff}, tolerance {eps})"
    );
}

#[track_caller]
fn assert_unit(n: Vec3) {
    assert!(n.is_finite(), "non-finite normal {n}");
    assert!(
        (n.length() - 1.0).abs() < 1e-5,
        "normal {n} has length {}",
        n.length()
    );
}

fn triangles(positions: Vec<Vec3>, corners: Vec<u32>) -> MeshData {
    MeshData {
        name: "test".into(),
        positions,
        corners,
        ..MeshData::default()
    }
}

fn polygons(positions: Vec<Vec3>, corners: Vec<u32>, sizes: Vec<u32>) -> MeshData {
    MeshData {
        facet_sizes: Some(sizes),
        ..triangles(positions, corners)
    }
}

fn averaged(weighting: Weighting, crease_degrees: Option<f32>) -> NormalPolicy {
    NormalPolicy::Average(NormalOptions {
        weighting,
        crease_degrees,
    })
}

/// The normal at every corner.
fn corner_normals(mesh: &Mesh) -> Vec<Vec3> {
    mesh.corners
        .iter()
        .enumerate()
        .map(|(c, &v)| mesh.normals.at(c, v))
        .collect()
}

/// Positions and corners of the cube primitive, without its normals and UVs.
fn bare_cube() -> MeshData {
    let cube = Mesh::cube(2.0).expect("valid cube");
    polygons(cube.positions, cube.corners, vec![4; 6])
}

/// The cube as glTF stores it: 24 vertices, 4 per face, per-vertex normals and UVs.
fn split_cube() -> MeshData {
    let cube = Mesh::cube(2.0).expect("valid cube");
    let uvs = cube.uvs.first().expect("cube has UVs");
    let mut data = polygons(Vec::new(), (0..24).collect(), vec![4; 6]);
    let (mut normals, mut texcoords) = (Vec::new(), Vec::<Vec2>::new());
    for (c, &v) in cube.corners.iter().enumerate() {
        data.positions.push(cube.positions[v as usize]);
        normals.push(cube.normals.at(c, v));
        texcoords.push(uvs.at(c, v));
    }
    data.normals = Some(Channel::per_vertex(normals));
    data.uvs = vec![Channel::per_vertex(texcoords)];
    data
}

/// Every normal value and every TriMesh normal is a finite unit vector.
#[track_caller]
fn assert_all_normals_unit(mesh: &Mesh) {
    mesh.normals.values.iter().for_each(|&n| assert_unit(n));
    mesh.triangulate()
        .normals
        .iter()
        .for_each(|&n| assert_unit(n));
    for f in mesh.facets() {
        assert!(f.normal == Vec3::ZERO || (f.normal.length() - 1.0).abs() < EPS);
        assert!(f.area.is_finite() && f.area >= 0.0);
    }
}

/// The structural invariants of a [`Mesh`] (see the module docs).
#[track_caller]
fn assert_invariants(mesh: &Mesh) {
    let mut uses = vec![0u32; mesh.edges().len()];
    let mut first_facets = vec![Vec::new(); mesh.edges().len()];
    for (f, facet) in mesh.facets().iter().enumerate() {
        let ring = facet.corners();
        for c in ring.clone() {
            let next = if c + 1 == ring.end { ring.start } else { c + 1 };
            let (a, b) = (mesh.corners[c], mesh.corners[next]);
            let e = mesh.corner_edges()[c] as usize;
            assert_eq!(mesh.edges()[e].vertices, [a.min(b), a.max(b)], "corner {c}");
            uses[e] += 1;
            first_facets[e].push(f as u32);
        }
    }
    assert!(mesh
        .edges()
        .windows(2)
        .all(|w| w[0].vertices < w[1].vertices));
    for (e, edge) in mesh.edges().iter().enumerate() {
        assert_eq!(edge.facet_count, uses[e]);
        let expected = [0, 1].map(|i| first_facets[e].get(i).copied().unwrap_or(NO_FACET));
        assert_eq!(edge.facets, expected, "edge {e}");
    }
    if let Some(ix) = &mesh.normals.indices {
        assert_eq!(ix.len(), mesh.corners.len());
        assert!(ix.iter().all(|&i| (i as usize) < mesh.normals.values.len()));
    } else {
        assert_eq!(mesh.normals.values.len(), mesh.positions.len());
    }
}
