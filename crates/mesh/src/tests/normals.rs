//! Read, flat and averaged normals; weighting; crease splitting; degenerate input.

use glam::Vec3;

use super::*;
use crate::{Channel, NormalSource, FALLBACK_NORMAL};

/// Two triangles around the origin: T1 in the XY plane (normal +Z, area 1/2, angle 90
/// degrees at the origin), T2 in the ZX plane (normal +Y, area 2, angle 45 degrees).
fn asymmetric_fan() -> MeshData {
    let p = vec![
        Vec3::ZERO,
        Vec3::X,
        Vec3::Y,
        Vec3::new(0.0, 0.0, 2.0),
        Vec3::new(2.0, 0.0, 2.0),
    ];
    triangles(p, vec![0, 1, 2, 0, 3, 4])
}

#[test]
fn weightings_differ_and_match_hand_computed_values() {
    let at_origin = |w| {
        let mesh = Mesh::new(asymmetric_fan(), averaged(w, None)).unwrap();
        assert_eq!(
            mesh.normal_source,
            NormalSource::Averaged(NormalOptions {
                weighting: w,
                crease_degrees: None
            })
        );
        assert!(mesh.normals.indices.is_none());
        mesh.normals.values[0]
    };
    // Uniform (the seed): (Z + Y) / 2, normalised.
    assert_close(
        at_origin(Weighting::Uniform),
        Vec3::new(0.0, 1.0, 1.0).normalize(),
        EPS,
    );
    // Area: 0.5 Z + 2 Y.
    assert_close(
        at_origin(Weighting::Area),
        Vec3::new(0.0, 2.0, 0.5).normalize(),
        EPS,
    );
    // Angle: (pi/2) Z + (pi/4) Y.
    assert_close(
        at_origin(Weighting::Angle),
        Vec3::new(0.0, 1.0, 2.0).normalize(),
        EPS,
    );
    // Vertices of one facet only take its normal.
    let mesh = Mesh::new(asymmetric_fan(), averaged(Weighting::Angle, None)).unwrap();
    assert_close(mesh.normals.values[1], Vec3::Z, EPS);
    assert_close(mesh.normals.values[4], Vec3::Y, EPS);
}

#[test]
fn crease_splits_cube_corners_and_none_averages() {
    for w in [Weighting::Uniform, Weighting::Area, Weighting::Angle] {
        let mesh = Mesh::new(bare_cube(), averaged(w, Some(60.0))).unwrap();
        assert_eq!(
            mesh.normals.values.len(),
            24,
            "8 vertices x 3 faces, no duplicates"
        );
        let normals = corner_normals(&mesh);
        for v in 0..8u32 {
            let mut distinct: Vec<Vec3> = Vec::new();
            for c in (0..24).filter(|&c| mesh.corners[c] == v) {
                if !distinct.contains(&normals[c]) {
                    distinct.push(normals[c]);
                }
            }
            assert_eq!(distinct.len(), 3, "vertex {v}: {distinct:?}");
        }
        // Split normals are the face normals.
        for (c, n) in normals.iter().enumerate() {
            assert_close(*n, mesh.facets()[c / 4].normal, EPS);
        }

        let smooth = Mesh::new(bare_cube(), averaged(w, None)).unwrap();
        assert!(smooth.normals.indices.is_none());
        assert_eq!(smooth.normals.values.len(), 8);
        for (p, n) in smooth.positions.iter().zip(&smooth.normals.values) {
            assert_close(*n, p.normalize(), EPS);
        }
    }
}

#[test]
fn crease_keeps_smooth_vertices_per_vertex() {
    // A finely tessellated sphere's facets meet at a few degrees: nothing splits.
    let sphere = Mesh::sphere(1.0, 32, 16).unwrap();
    let data = triangles(Vec::new(), Vec::new());
    let data = MeshData {
        positions: sphere.positions.clone(),
        corners: sphere.corners.clone(),
        facet_sizes: Some(sphere.facets().iter().map(|f| f.len).collect()),
        ..data
    };
    let mesh = Mesh::new(data, NormalPolicy::default()).unwrap();
    assert!(mesh.normals.indices.is_none());
    for (p, n) in mesh.positions.iter().zip(&mesh.normals.values) {
        assert!(n.dot(*p) > 0.99, "{n} at {p}");
    }
}

#[test]
fn degenerate_duplicate_and_inverted_facets_give_unit_normals() {
    let p = vec![
        Vec3::ZERO,
        Vec3::X,
        Vec3::Y,
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::new(5.0, 5.0, 5.0), // isolated
        Vec3::new(0.0, 0.0, 1.0),
    ];
    let corners = vec![
        0, 1, 2, // good, +Z
        0, 1, 2, // duplicate
        2, 1, 0, // inverted duplicates: with them the sums at vertex 2 cancel
        0, 2, 1, 0, 1, 3, // zero area (collinear)
        3, 3, 1, // repeated vertex
        0, 0, 0, // a point
        3, 1, 0, // zero area again, only facet of nothing new
        0, 5, 1, // a wall, normal +Y
    ];
    let data = triangles(p, corners);
    for policy in [
        NormalPolicy::Flat,
        averaged(Weighting::Uniform, None),
        averaged(Weighting::Area, None),
        averaged(Weighting::Angle, None),
        averaged(Weighting::Uniform, Some(45.0)),
        averaged(Weighting::Angle, Some(0.0)),
    ] {
        let mesh = Mesh::new(data.clone(), policy).unwrap();
        assert_all_normals_unit(&mesh);
        let r = mesh.topology();
        assert_eq!(
            (r.degenerate_facets, r.isolated_vertices),
            (4, 1),
            "{policy:?}"
        );
        assert_eq!(mesh.facets()[4].area, 0.0);
        if let NormalPolicy::Average(_) = policy {
            // Value v is vertex v's (first) normal.
            assert_eq!(mesh.normals.values[4], FALLBACK_NORMAL, "isolated vertex");
        }
    }
}

#[test]
fn file_normals_are_renormalised_and_repaired() {
    let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::ONE];
    let mut data = triangles(p, vec![0, 1, 2, 2, 1, 3]);
    data.normals = Some(Channel::per_vertex(vec![
        Vec3::new(0.0, 0.0, 3.0),
        Vec3::ZERO,
        Vec3::new(f32::NAN, 0.0, 1.0),
        Vec3::new(1e-30, 0.0, 1e-30),
    ]));
    let mesh = Mesh::new(data, NormalPolicy::default()).unwrap();
    assert_eq!(mesh.normal_source, NormalSource::File);
    assert_all_normals_unit(&mesh);
    let normals = corner_normals(&mesh);
    assert_close(normals[0], Vec3::Z, EPS);
    // Corners of the zero and NaN values take their facet's normal.
    assert_close(normals[1], mesh.facets()[0].normal, EPS);
    assert_close(normals[3], mesh.facets()[1].normal, EPS);
    assert_close(normals[5], Vec3::new(1.0, 0.0, 1.0).normalize(), EPS);
}

#[test]
fn flat_policy_and_recompute() {
    let mut mesh = Mesh::new(bare_cube(), NormalPolicy::Flat).unwrap();
    assert_eq!(mesh.normal_source, NormalSource::Flat);
    assert_eq!(mesh.normals.values.len(), 6);
    for (c, n) in corner_normals(&mesh).iter().enumerate() {
        assert_eq!(*n, mesh.facets()[c / 4].normal);
    }
    let policy = averaged(Weighting::Uniform, None);
    mesh.recompute_normals(policy);
    assert_eq!(
        mesh.normal_source,
        NormalSource::Averaged(NormalOptions {
            weighting: Weighting::Uniform,
            crease_degrees: None
        })
    );
    assert_eq!(mesh.normals.values.len(), 8);
}

#[test]
fn polynomial_atan2_matches_libm() {
    let mut worst = 0.0f64;
    for i in -50..=50 {
        for j in -50..=50 {
            let (y, x) = (f64::from(i) * 0.37, f64::from(j) * 0.53);
            worst = worst.max((crate::normals::atan2(y, x) - libm::atan2(y, x)).abs());
        }
    }
    assert!(worst < 1e-7, "max error {worst}");
    assert_eq!(crate::normals::atan2(0.0, 0.0), 0.0);
    assert!(crate::normals::atan2(f64::NAN, 1.0).is_nan());
}

#[test]
fn a_bad_file_normal_all_of_whose_facets_agree_is_repaired_in_place() {
    // Vertex 3 (zero normal) is in facet 1 only, vertex 4 (NaN) in the two degenerate
    // facets only: each gets one normal, so the channel stays per vertex.
    let p = vec![
        Vec3::ZERO,
        Vec3::X,
        Vec3::Y,
        Vec3::new(1.0, 1.0, 1.0),
        Vec3::new(2.0, 0.0, 0.0),
    ];
    let mut data = triangles(p, vec![0, 1, 2, 2, 1, 3, 0, 1, 4, 4, 1, 0]);
    data.normals = Some(Channel::per_vertex(vec![
        Vec3::Z,
        Vec3::Z,
        Vec3::Z,
        Vec3::ZERO,
        Vec3::new(f32::NAN, 0.0, 0.0),
    ]));
    let mesh = Mesh::new(data.clone(), NormalPolicy::default()).unwrap();
    assert!(mesh.normals.indices.is_none(), "still per vertex");
    assert_eq!(mesh.normals.values.len(), 5);
    assert_eq!(mesh.normals.values[3], mesh.facets()[1].normal);
    assert_eq!(mesh.normals.values[4], FALLBACK_NORMAL);
    // A bad vertex whose facets disagree (+Z, tilted, and the fallback) makes the channel
    // per corner.
    assert_ne!(mesh.facets()[0].normal, mesh.facets()[1].normal);
    data.normals.as_mut().unwrap().values[1] = Vec3::ZERO;
    let mesh = Mesh::new(data, NormalPolicy::default()).unwrap();
    assert!(mesh.normals.indices.is_some());
    let normals = corner_normals(&mesh);
    assert_eq!(normals[1], mesh.facets()[0].normal);
    assert_eq!(normals[4], mesh.facets()[1].normal);
}
