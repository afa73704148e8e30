//! Triangulation: quads, convex and concave polygons, render vertices, edges.

use glam::{Mat3, Vec3};

use super::*;

/// Signed area of a triangle about `normal`.
fn signed_area(p: &[Vec3], t: [u32; 3], normal: Vec3) -> f32 {
    let [a, b, c] = t.map(|i| p[i as usize]);
    0.5 * (b - a).cross(c - a).dot(normal)
}

#[test]
fn concave_pentagon_gives_three_triangles_facing_the_facet() {
    // An "M"-like outline with a reflex corner at (1, 0.5): a fan from corner 0 would flip.
    let flat = [(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (1.0, 0.5), (0.0, 2.0)];
    let tilt = Mat3::from_euler(glam::EulerRot::XYZ, 0.7, -0.4, 1.9);
    for rotation in [Mat3::IDENTITY, tilt] {
        let p: Vec<Vec3> = flat
            .iter()
            .map(|&(x, y)| rotation * Vec3::new(x, y, 0.0))
            .collect();
        let mesh = Mesh::new(
            polygons(p, vec![0, 1, 2, 3, 4], vec![5]),
            NormalPolicy::Flat,
        )
        .unwrap();
        let normal = mesh.facets()[0].normal;
        assert_close(normal, rotation * Vec3::Z, EPS);
        let tri = mesh.triangulate();
        assert_eq!(tri.triangles.len(), 3);
        assert_eq!(tri.triangle_facets, vec![0; 3]);
        let mut total = 0.0;
        for &t in &tri.triangles {
            let area = signed_area(&tri.positions, t, normal);
            assert!(area > 0.0, "triangle {t:?} faces away");
            total += area;
        }
        assert!(
            (total - 2.5).abs() < 1e-5,
            "triangles overlap or miss: {total}"
        );
    }
}

#[test]
fn quads_split_along_the_diagonal_that_keeps_orientation() {
    // Arrowhead with its reflex corner at 3: only the (longer) diagonal 1-3 is inside.
    let dart = vec![
        Vec3::ZERO,
        Vec3::new(4.0, 1.0, 0.0),
        Vec3::new(0.0, 2.0, 0.0),
        Vec3::new(0.5, 1.0, 0.0),
    ];
    let mesh = Mesh::new(
        polygons(dart, vec![0, 1, 2, 3], vec![4]),
        NormalPolicy::Flat,
    )
    .unwrap();
    let tri = mesh.triangulate();
    assert_eq!(tri.triangles.len(), 2);
    assert!(tri
        .triangles
        .iter()
        .all(|&t| signed_area(&tri.positions, t, Vec3::Z) > 0.0));
    assert!(tri
        .triangles
        .iter()
        .all(|t| t.contains(&1) && t.contains(&3)));

    // Convex: the shorter diagonal (0-2 here).
    let kite = vec![
        Vec3::ZERO,
        Vec3::new(3.0, -1.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(-1.0, 3.0, 0.0),
    ];
    let mesh = Mesh::new(
        polygons(kite, vec![0, 1, 2, 3], vec![4]),
        NormalPolicy::Flat,
    )
    .unwrap();
    assert!(mesh
        .triangulate()
        .triangles
        .iter()
        .all(|t| t.contains(&0) && t.contains(&2)));
}

#[test]
fn convex_polygon_fans_and_degenerate_polygon_does_not_loop() {
    let hexagon: Vec<Vec3> = (0..6)
        .map(|i| {
            let a = i as f32 * std::f32::consts::TAU / 6.0;
            Vec3::new(libm::cosf(a), libm::sinf(a), 0.0)
        })
        .collect();
    let mesh = Mesh::new(
        polygons(hexagon, (0..6).collect(), vec![6]),
        NormalPolicy::Flat,
    )
    .unwrap();
    assert_eq!(
        mesh.triangulate().triangles,
        vec![[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 5]]
    );

    // Self-intersecting (bow-tie-like) and all-collinear outlines still give n - 2 triangles.
    let bowtie = vec![
        Vec3::ZERO,
        Vec3::new(2.0, 2.0, 0.0),
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::new(0.0, 2.0, 0.0),
        Vec3::new(1.0, 3.0, 0.0),
    ];
    let line: Vec<Vec3> = (0..7).map(|i| Vec3::new(i as f32, 0.0, 0.0)).collect();
    for p in [bowtie, line] {
        let n = p.len() as u32;
        let mesh = Mesh::new(
            polygons(p, (0..n).collect(), vec![n]),
            NormalPolicy::default(),
        )
        .unwrap();
        assert_eq!(mesh.triangulate().triangles.len(), n as usize - 2);
    }
}

#[test]
fn render_vertices_follow_the_channels() {
    // All per vertex: render vertices are the mesh vertices.
    let smooth = Mesh::new(bare_cube(), averaged(Weighting::Angle, None)).unwrap();
    let tri = smooth.triangulate();
    assert_eq!(tri.positions, smooth.positions);
    assert_eq!(tri.triangles.len(), 12);

    // Creased cube with per-corner UVs: one render vertex per (vertex, face).
    let cube = Mesh::cube(2.0).unwrap();
    let tri = cube.triangulate();
    assert_eq!(tri.positions.len(), 24);
    assert_eq!(tri.uv_set(0).map(<[_]>::len), Some(24));
    for (t, &f) in tri.triangles.iter().zip(&tri.triangle_facets) {
        let facet_normal = tri.facet_normals[f as usize];
        assert!(signed_area(&tri.positions, *t, facet_normal) > 0.0);
        for &r in t {
            assert_close(tri.normals[r as usize], facet_normal, EPS);
        }
    }
    // Wireframes draw the mesh edges as render-vertex pairs: the same positions (render
    // vertex v is mesh vertex v, though this cube's seams split every vertex in three).
    assert_eq!(cube.edges().len(), 12);
    for e in cube.edges() {
        assert_eq!(
            e.vertices.map(|v| cube.positions[v as usize]),
            e.vertices.map(|v| tri.positions[v as usize])
        );
    }
}

proptest::proptest! {
    /// Star-shaped outlines (random radii at increasing angles) are simple polygons, mostly
    /// concave: ear clipping must tile them exactly with counter-clockwise triangles.
    #[test]
    fn star_polygons_are_tiled_exactly(radii in proptest::collection::vec(0.2f32..2.0, 5..40)) {
        let n = radii.len();
        let p: Vec<Vec3> = radii
            .iter()
            .enumerate()
            .map(|(i, &r)| {
                let a = i as f32 * std::f32::consts::TAU / n as f32;
                Vec3::new(r * libm::cosf(a), r * libm::sinf(a), 0.0)
            })
            .collect();
        let shoelace: f32 = (0..n).map(|i| 0.5 * p[i].truncate().perp_dot(p[(i + 1) % n].truncate())).sum();
        let data = polygons(p, (0..n as u32).collect(), vec![n as u32]);
        let tri = Mesh::new(data, NormalPolicy::Flat).unwrap().triangulate();
        proptest::prop_assert_eq!(tri.triangles.len(), n - 2);
        let mut total = 0.0;
        for &t in &tri.triangles {
            let area = signed_area(&tri.positions, t, Vec3::Z);
            proptest::prop_assert!(area > -1e-6, "triangle {:?} has area {}", t, area);
            total += area;
        }
        proptest::prop_assert!((total - shoelace).abs() < 1e-4 * shoelace, "{} vs {}", total, shoelace);
    }
}

#[test]
fn a_mesh_of_triangles_keeps_no_facet_tables_and_computes_the_same_normals() {
    let sphere = Mesh::sphere(1.0, 24, 12).unwrap().triangulate();
    let corners = sphere.triangles.iter().flatten().copied().collect();
    let mesh = Mesh::new(
        triangles(sphere.positions.clone(), corners),
        NormalPolicy::Flat,
    )
    .unwrap();
    assert_eq!(mesh.corners.len(), 3 * mesh.facets().len());
    let tri = mesh.triangulate();
    assert!(tri.triangle_facets.is_empty() && tri.facet_normals.is_empty());
    assert_eq!(tri.facet_count(), mesh.facets().len());
    for (f, facet) in mesh.facets().iter().enumerate() {
        assert_eq!(tri.facet_of(f), f);
        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
        assert_eq!(bits(tri.facet_normal(f)), bits(facet.normal), "facet {f}");
    }
    assert_eq!(tri.facet_normal(mesh.facets().len()), Vec3::ZERO);
    // A polygon mesh keeps both.
    let cube = Mesh::cube(1.0).unwrap().triangulate();
    assert_eq!((cube.triangle_facets.len(), cube.facet_count()), (12, 6));
    assert_eq!(cube.facet_of(11), 5);
}
