//! Primitive builders: counts, closed topology, outward normals, UVs, limits.

use glam::Vec3;

use super::*;
use crate::{MeshError, NormalSource, MAX_SEGMENTS};

/// The centroid of a facet's corners.
fn centroid(mesh: &Mesh, f: usize) -> Vec3 {
    let ring = &mesh.corners[mesh.facets()[f].corners()];
    ring.iter()
        .map(|&v| mesh.positions[v as usize])
        .sum::<Vec3>()
        / ring.len() as f32
}

#[track_caller]
fn assert_closed(mesh: &Mesh, euler: i64) {
    let r = mesh.topology();
    assert_eq!(r.euler_characteristic, euler, "{}: {r:?}", mesh.name);
    assert_eq!(
        (r.boundary_edges, r.non_manifold_edges),
        (0, 0),
        "{}",
        mesh.name
    );
    assert_eq!(
        (r.degenerate_facets, r.isolated_vertices, r.components),
        (0, 0, 1)
    );
    assert_eq!(mesh.normal_source, NormalSource::Analytic);
    assert_all_normals_unit(mesh);
}

#[test]
fn sphere_layout_counts_and_topology() {
    let (s, st) = (16u32, 8u32);
    let mesh = Mesh::sphere(2.0, s, st).unwrap();
    assert_eq!(mesh.positions.len(), (2 + (st - 1) * s) as usize);
    assert_eq!(
        mesh.positions[0],
        Vec3::new(0.0, 2.0, 0.0),
        "vertex 0 is the north pole"
    );
    assert_eq!(*mesh.positions.last().unwrap(), Vec3::new(0.0, -2.0, 0.0));
    let south = mesh.positions.len() as u32 - 1;
    // Rings run north to south.
    for i in 1..st - 1 {
        let (a, b) = (1 + (i - 1) * s, 1 + i * s);
        assert!(mesh.positions[a as usize].y > mesh.positions[b as usize].y);
    }
    for f in mesh.facets() {
        let ring = &mesh.corners[f.corners()];
        let at_pole = ring.iter().any(|&v| v == 0 || v == south);
        assert_eq!(f.len, if at_pole { 3 } else { 4 }, "{ring:?}");
    }
    let r = mesh.topology();
    assert_eq!(
        (r.facets, r.triangles),
        ((s * st) as usize, (2 * s * (st - 1)) as usize)
    );
    assert_eq!(r.edges, (s * (st - 1) + s * st) as usize);
    assert_closed(&mesh, 2);
}

#[test]
fn sphere_normals_are_exact_and_outward() {
    let mesh = Mesh::sphere(3.0, 24, 12).unwrap();
    assert!(
        mesh.normals.indices.is_none(),
        "sphere normals are per vertex"
    );
    for (c, &v) in mesh.corners.iter().enumerate() {
        let n = mesh.normals.at(c, v);
        assert_unit(n);
        assert_close(n, mesh.positions[v as usize] / 3.0, 1e-6);
    }
    for f in 0..mesh.facets().len() {
        assert!(
            mesh.facets()[f].normal.dot(centroid(&mesh, f)) > 0.0,
            "facet {f} faces inwards"
        );
    }
    // UVs: v grows southwards from 0 at the north pole; the seam column reaches u = 1.
    let uvs = mesh.uvs.first().unwrap();
    assert!(uvs.indices.is_some());
    assert_eq!(uvs.at(0, 0).y, 0.0);
    assert!(uvs.values.iter().any(|t| t.x == 1.0));
    let tri = mesh.triangulate();
    tri.normals.iter().for_each(|&n| assert_unit(n));
    assert!((tri.radius - 3.0).abs() < 1e-5 && tri.center.length() < 1e-5);
}

#[test]
fn other_primitives_are_closed_and_face_outwards() {
    let shapes = [
        (Mesh::cube(2.0).unwrap(), 2),
        (Mesh::cylinder(1.0, 2.0, 12, true).unwrap(), 2),
        (Mesh::cone(1.0, 2.0, 12).unwrap(), 2),
        (Mesh::torus(2.0, 0.5, 16, 8).unwrap(), 0),
    ];
    for (mesh, euler) in &shapes {
        assert_closed(mesh, *euler);
        for f in 0..mesh.facets().len() {
            let c = centroid(mesh, f);
            // Outward from the axis for the torus tube, from the origin otherwise.
            let tube_centre = if mesh.name == "torus" {
                2.0 * Vec3::new(c.x, 0.0, c.z).normalize()
            } else {
                Vec3::ZERO
            };
            assert!(
                mesh.facets()[f].normal.dot(c - tube_centre) > 0.0,
                "{} facet {f}",
                mesh.name
            );
            // Analytic corner normals lean the same way as their facet.
            for k in mesh.facets()[f].corners() {
                let n = mesh.normals.at(k, mesh.corners[k]);
                assert!(
                    n.dot(mesh.facets()[f].normal) > 0.5,
                    "{} corner {k}",
                    mesh.name
                );
            }
        }
    }
    let cube = &shapes[0].0;
    assert_eq!(
        (
            cube.positions.len(),
            cube.facets().len(),
            cube.normals.values.len()
        ),
        (8, 6, 6)
    );
    assert!(cube.facets().iter().all(|f| f.len == 4));

    let tube = Mesh::cylinder(1.0, 2.0, 12, false).unwrap().topology();
    assert_eq!((tube.boundary_edges, tube.euler_characteristic), (24, 0));
}

#[test]
fn tessellation_counts_are_clamped_and_limited() {
    let tiny = Mesh::sphere(1.0, 0, 1).unwrap();
    assert_eq!(tiny.positions.len(), 2 + 2 * 3);
    assert_closed(&tiny, 2);
    assert_eq!(Mesh::torus(1.0, 0.5, 2, 2).unwrap().positions.len(), 9);
    assert!(Mesh::sphere(1.0, MAX_SEGMENTS, 4).is_ok());
    let err = Mesh::sphere(1.0, MAX_SEGMENTS + 1, 4).unwrap_err();
    assert_eq!(
        err,
        MeshError::Segments {
            primitive: "sphere",
            parameter: "slices",
            count: MAX_SEGMENTS + 1,
            max: MAX_SEGMENTS
        }
    );
    assert!(matches!(
        Mesh::cube(f32::NAN),
        Err(MeshError::Dimension {
            parameter: "size",
            ..
        })
    ));
    assert!(matches!(
        Mesh::cone(-1.0, 1.0, 8),
        Err(MeshError::Dimension {
            parameter: "radius",
            ..
        })
    ));
    assert!(matches!(
        Mesh::torus(1.0, f32::INFINITY, 8, 8),
        Err(MeshError::Dimension {
            parameter: "minor",
            ..
        })
    ));
    // Zero size is legal: degenerate facets, unit normals.
    assert_all_normals_unit(&Mesh::cylinder(0.0, 0.0, 8, true).unwrap());
}
