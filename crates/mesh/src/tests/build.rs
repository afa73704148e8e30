//! Validation, facet normals, edges, topology report, welding.

use glam::Vec3;
use proptest::prelude::*;

use super::*;
use crate::{Channel, MeshError, NormalPolicy, NO_FACET};

#[test]
fn out_of_range_vertex_index_is_an_error() {
    let data = triangles(vec![Vec3::ZERO; 3], vec![0, 1, 3]);
    let err = Mesh::new(data, NormalPolicy::default()).unwrap_err();
    assert_eq!(
        err,
        MeshError::VertexIndex {
            corner: 2,
            index: 3,
            count: 3
        }
    );
}

#[test]
fn inconsistent_sizes_and_channels_are_errors() {
    let tri = || triangles(vec![Vec3::X, Vec3::Y, Vec3::Z], vec![0, 1, 2]);
    let new = |data| Mesh::new(data, NormalPolicy::Flat).unwrap_err();
    assert_eq!(
        new(triangles(vec![Vec3::ZERO; 3], vec![0, 1])),
        MeshError::NotTriangles(2)
    );
    let sizes = |s: Vec<u32>| MeshData {
        facet_sizes: Some(s),
        ..tri()
    };
    assert_eq!(
        new(sizes(vec![2, 1])),
        MeshError::FacetTooSmall { facet: 0, len: 2 }
    );
    assert_eq!(
        new(sizes(vec![3, 3])),
        MeshError::FacetSizes { sum: 6, corners: 3 }
    );
    assert_eq!(
        new(sizes(vec![u32::MAX; 4])),
        MeshError::FacetSizes {
            sum: 4 * u64::from(u32::MAX),
            corners: 3
        }
    );
    let normals = |ch| MeshData {
        normals: Some(ch),
        ..tri()
    };
    assert_eq!(
        new(normals(Channel::per_vertex(vec![Vec3::Z; 2]))),
        MeshError::ChannelLength {
            channel: "normals",
            got: 2,
            expected: 3
        }
    );
    let indexed = Channel {
        values: vec![Vec3::Z],
        indices: Some(vec![0, 0, 1]),
    };
    assert_eq!(
        new(normals(indexed)),
        MeshError::ChannelIndex {
            channel: "normals",
            corner: 2,
            index: 1,
            count: 1
        }
    );
    let short = Channel {
        values: vec![Vec3::Z],
        indices: Some(vec![0, 0]),
    };
    assert_eq!(
        new(normals(short)),
        MeshError::ChannelLength {
            channel: "normals",
            got: 2,
            expected: 3
        }
    );
}

#[test]
fn newell_normal_and_area_of_a_non_planar_quad() {
    // A unit square lifted at one corner: Newell's normal is the average plane's.
    let p = vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.2), Vec3::Y];
    let mesh = Mesh::new(polygons(p, vec![0, 1, 2, 3], vec![4]), NormalPolicy::Flat).unwrap();
    let f = mesh.facets()[0];
    // Vector area = 1/2 sum p_i x p_i+1 = (-0.1, -0.1, 1).
    let expected = Vec3::new(-0.1, -0.1, 1.0);
    assert_close(f.normal, expected.normalize(), EPS);
    assert!((f.area - expected.length()).abs() < EPS);
}

#[test]
fn edges_are_unique_sorted_and_linked_to_corners() {
    let mesh = Mesh::cube(1.0).unwrap();
    assert_eq!(mesh.edges().len(), 12);
    assert!(mesh
        .edges()
        .windows(2)
        .all(|w| w[0].vertices < w[1].vertices));
    for e in mesh.edges() {
        assert!(e.vertices[0] < e.vertices[1]);
        assert_eq!(e.facet_count, 2);
        assert!(e.facets[0] < e.facets[1] && e.facets[1] != NO_FACET);
    }
    for f in mesh.facets() {
        for c in f.corners() {
            let next = if c + 1 == f.corners().end {
                f.corners().start
            } else {
                c + 1
            };
            let (a, b) = (mesh.corners[c], mesh.corners[next]);
            let e = mesh.edges()[mesh.corner_edges()[c] as usize];
            assert_eq!(e.vertices, [a.min(b), a.max(b)]);
        }
    }
    // Building twice gives the same table.
    assert_eq!(Mesh::cube(1.0).unwrap().edges(), mesh.edges());
}

#[test]
fn topology_report_counts() {
    // Two triangles sharing an edge, a separate triangle, an isolated vertex and a
    // zero-area triangle.
    let p = vec![
        Vec3::ZERO,
        Vec3::X,
        Vec3::Y,
        Vec3::ONE,
        Vec3::new(5.0, 0.0, 0.0),
        Vec3::new(6.0, 0.0, 0.0),
        Vec3::new(5.0, 1.0, 0.0),
        Vec3::new(9.0, 9.0, 9.0),
        Vec3::new(7.0, 0.0, 0.0),
    ];
    let data = triangles(p, vec![0, 1, 2, 2, 1, 3, 4, 5, 6, 4, 5, 8]);
    let r = Mesh::new(data, NormalPolicy::default()).unwrap().topology();
    assert_eq!((r.vertices, r.facets, r.triangles), (9, 4, 4));
    // Edges: 5 in the pair, 3 + 2 in the second group (4-5 shared).
    assert_eq!(
        (r.edges, r.boundary_edges, r.non_manifold_edges),
        (10, 8, 0)
    );
    assert_eq!(
        (r.degenerate_facets, r.isolated_vertices, r.components),
        (1, 1, 2)
    );
    assert_eq!(r.euler_characteristic, 9 - 10 + 4);
    assert_eq!((r.bounds_min, r.bounds_max), ([0.0; 3], [9.0; 3]));
}

#[test]
fn weld_restores_the_cube_topology_and_keeps_attributes() {
    let split = split_cube();
    let before = Mesh::new(split.clone(), NormalPolicy::default()).unwrap();
    let r = before.topology();
    assert_eq!((r.vertices, r.boundary_edges, r.components), (24, 24, 6));

    let welded = Mesh::new(split.weld_positions(), NormalPolicy::default()).unwrap();
    let r = welded.topology();
    assert_eq!((r.vertices, r.edges, r.facets), (8, 12, 6));
    assert_eq!(
        (r.boundary_edges, r.euler_characteristic, r.components),
        (0, 2, 1)
    );
    // Nothing lost: every corner sees the same position, normal and UV as before.
    let (uv0, uv1) = (before.uvs.first().unwrap(), welded.uvs.first().unwrap());
    for c in 0..24 {
        let (v0, v1) = (before.corners[c], welded.corners[c]);
        assert_eq!(before.positions[v0 as usize], welded.positions[v1 as usize]);
        assert_eq!(before.normals.at(c, v0), welded.normals.at(c, v1));
        assert_eq!(uv0.at(c, v0), uv1.at(c, v1));
    }
    assert!(
        welded.normals.indices.is_some(),
        "cube normals differ per face: per corner"
    );
}

#[test]
fn weld_keeps_consistent_channels_per_vertex() {
    let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Y, Vec3::X, Vec3::ONE];
    let mut data = triangles(p, vec![0, 1, 2, 3, 4, 5]);
    data.normals = Some(Channel::per_vertex(vec![Vec3::Z; 6]));
    let welded = data.weld_positions();
    assert_eq!(welded.positions.len(), 4);
    assert_eq!(welded.corners, vec![0, 1, 2, 2, 1, 3]);
    assert_eq!(welded.normals, Some(Channel::per_vertex(vec![Vec3::Z; 4])));
}

#[test]
fn weld_drops_vertices_no_corner_uses() {
    let p = vec![Vec3::ZERO, Vec3::splat(1e30), Vec3::X, Vec3::Y];
    let mut data = triangles(p, vec![0, 2, 3]);
    data.uvs = vec![Channel::per_vertex(vec![
        glam::Vec2::ZERO,
        glam::Vec2::ONE,
        glam::Vec2::X,
        glam::Vec2::Y,
    ])];
    let welded = data.weld_positions();
    assert_eq!(welded.positions, vec![Vec3::ZERO, Vec3::X, Vec3::Y]);
    assert_eq!(welded.corners, vec![0, 1, 2]);
    assert_eq!(
        welded.uvs,
        vec![Channel::per_vertex(vec![
            glam::Vec2::ZERO,
            glam::Vec2::X,
            glam::Vec2::Y
        ])]
    );
}

#[test]
fn nan_and_inf_positions_do_not_panic() {
    let p = vec![
        Vec3::ZERO,
        Vec3::X,
        Vec3::Y,
        Vec3::new(f32::NAN, 0.0, 0.0),
        Vec3::new(0.0, f32::INFINITY, 0.0),
    ];
    let data = polygons(
        p,
        vec![0, 1, 2, 1, 3, 2, 0, 2, 4, 1, 3, 4, 0],
        vec![3, 3, 3, 4],
    );
    for policy in [
        NormalPolicy::Flat,
        averaged(Weighting::Angle, Some(30.0)),
        averaged(Weighting::Area, None),
    ] {
        let mesh = Mesh::new(data.clone(), policy).unwrap();
        assert_all_normals_unit(&mesh);
        assert_close(mesh.normals.at(0, 0), Vec3::Z, EPS);
        assert_eq!(
            mesh.facets().iter().filter(|f| f.is_degenerate()).count(),
            3
        );
        assert_eq!(mesh.bounds(), Some((Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0))));
        let tri = mesh.triangulate();
        assert_eq!(tri.triangles.len(), 5);
        assert!(tri.radius > 0.0 && tri.radius.is_finite());
        let _ = mesh.topology();
    }
    let all_nan = triangles(vec![Vec3::NAN; 3], vec![0, 1, 2]);
    let mesh = Mesh::new(all_nan, NormalPolicy::default()).unwrap();
    assert_eq!(mesh.bounds(), None);
    assert_eq!(mesh.triangulate().radius, -1.0);
    assert_all_normals_unit(&mesh);
}

/// Arbitrary small meshes: coordinates include NaN, infinities, huge and tiny values;
/// indices may be out of range; facets may repeat vertices.
pub(super) fn arbitrary_mesh() -> impl Strategy<Value = MeshData> {
    let coord = || {
        prop_oneof![
            6 => -4.0f32..4.0,
            1 => Just(f32::NAN),
            1 => Just(f32::INFINITY),
            1 => Just(3e38f32),
            1 => Just(1e-30f32),
            2 => Just(0.0f32),
        ]
    };
    let vector = move || prop::array::uniform3(coord()).prop_map(Vec3::from);
    let positions = prop::collection::vec(vector(), 1..12);
    let sizes = prop::collection::vec(3u32..7, 1..10);
    (positions, sizes)
        .prop_flat_map(move |(p, sizes)| {
            let total = sizes.iter().sum::<u32>() as usize;
            let bound = p.len() as u32 + 1; // one past the end: sometimes out of range
            let corners = prop::collection::vec(0..bound, total);
            let normals = prop::option::of(prop::collection::vec(vector(), p.len()));
            (Just(p), Just(sizes), corners, normals)
        })
        .prop_map(|(p, sizes, corners, normals)| MeshData {
            normals: normals.map(Channel::per_vertex),
            ..polygons(p, corners, sizes)
        })
}

proptest! {
    #[test]
    fn any_input_gives_an_error_or_a_sound_mesh(data in arbitrary_mesh(), crease in prop::option::of(0.0f32..200.0)) {
        let count = data.positions.len();
        let in_range = data.corners.iter().all(|&v| (v as usize) < count);
        let welded = data.clone().weld_positions();
        let generated = MeshData { normals: None, ..data.clone() };
        for (data, policy) in [
            (data, averaged(Weighting::Angle, crease)),
            (generated, averaged(Weighting::Uniform, crease)),
            (welded, averaged(Weighting::Area, crease)),
        ] {
            match Mesh::new(data, policy) {
                Err(e) => prop_assert!(!in_range, "unexpected error {e}"),
                Ok(mesh) => {
                    assert_invariants(&mesh);
                    assert_all_normals_unit(&mesh);
                    let r = mesh.topology();
                    let tri = mesh.triangulate();
                    prop_assert_eq!(tri.triangles.len(), r.triangles);
                    prop_assert_eq!(mesh.edges().len(), r.edges);
                    prop_assert!(tri.triangles.iter().flatten().all(|&i| (i as usize) < tri.positions.len()));
                    // Wireframes draw the mesh edges as render vertices: render vertex
                    // v is mesh vertex v.
                    prop_assert!(mesh.positions.len() <= tri.positions.len());
                    prop_assert!(mesh.positions.iter().zip(&tri.positions).all(|(a, b)| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits)));
                }
            }
        }
    }
}
