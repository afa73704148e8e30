//! Generated UVs on the primitives: finite, no smeared seam strip, the primitives' own
//! analytic UVs reproduced, box faces whole, degenerate meshes survived, deterministic.

use glam::{Vec2, Vec3};

use super::*;
use crate::texture::Axis;
use crate::{MeshData, NormalPolicy};

/// Largest difference between UVs that should agree (f32 trigonometry of the builders).
const EPS: f32 = 1e-5;

fn primitives() -> Vec<Mesh> {
    vec![
        Mesh::sphere(1.0, 32, 16).unwrap(),
        Mesh::sphere(2.0, 7, 5).unwrap(),
        Mesh::cylinder(1.0, 2.0, 24, true).unwrap(),
        Mesh::cylinder(0.5, 3.0, 3, false).unwrap(),
        Mesh::cone(1.0, 2.0, 16).unwrap(),
        Mesh::torus(1.0, 0.3, 32, 16).unwrap(),
        Mesh::cube(2.0).unwrap(),
        Mesh::grid(1.0, 2.0, 4, 3).unwrap(),
    ]
}

fn all_generators() -> Vec<UvGenerator> {
    let mut g = UvGenerator::PRESETS.to_vec();
    for axis in [Axis::X, Axis::Z] {
        g.push(UvGenerator::Cylindrical { axis });
        g.push(UvGenerator::Spherical { axis });
    }
    g
}

/// The generated UV of every corner.
fn corner_uvs(mesh: &Mesh, ch: &Channel<Vec2>) -> Vec<Vec2> {
    mesh.corners
        .iter()
        .enumerate()
        .map(|(c, &v)| ch.at(c, v))
        .collect()
}

/// `a` and `b` differ by a whole number of turns in u (within `EPS`) and agree in v.
fn same_modulo_turns(a: Vec2, b: Vec2) -> bool {
    let du = (a.x - b.x).rem_euclid(1.0);
    du.min(1.0 - du) < EPS && (a.y - b.y).abs() < EPS
}

#[test]
fn every_corner_uv_is_finite_and_the_channel_valid() {
    for mesh in primitives() {
        for g in all_generators() {
            let ch = generate_uvs(&mesh, &g);
            match &ch.indices {
                Some(ix) => {
                    assert_eq!(ix.len(), mesh.corners.len());
                    assert!(ix.iter().all(|&i| (i as usize) < ch.values.len()));
                }
                None => assert_eq!(ch.values.len(), mesh.positions.len()),
            }
            assert!(
                ch.values.iter().all(|uv| uv.is_finite()),
                "{} {g}",
                mesh.name
            );
        }
    }
}

/// The seam test: after triangulation no triangle of a cylindrical or spherical map spans
/// more than half a turn in u, except the caps, which are mapped planar.
#[test]
fn no_triangle_smears_across_the_seam() {
    for mesh in primitives() {
        for g in all_generators().into_iter().filter(UvGenerator::wraps_u) {
            let frame = uv_frame(&mesh);
            let mut textured = mesh.clone();
            textured.uvs = vec![generate_uvs(&mesh, &g)];
            let tri = textured.triangulate();
            let uvs = &tri.uvs[0];
            for (t, corners) in tri.triangles.iter().enumerate() {
                let us = corners.map(|v| uvs[v as usize].x);
                let extent = us.iter().copied().fold(f32::MIN, f32::max)
                    - us.iter().copied().fold(f32::MAX, f32::min);
                if extent <= MAX_WRAP_EXTENT {
                    continue;
                }
                // Only a cap may: its UVs are the planar map along the axis.
                let f = &mesh.facets()[tri.facet_of(t)];
                for c in f.corners() {
                    let p = mesh.positions[mesh.corners[c] as usize];
                    let want = g.cap(&frame, p, f.normal);
                    let got = textured.uvs[0].at(c, mesh.corners[c]);
                    assert!(
                        (got - want).length() < EPS,
                        "{} {g}: triangle {t}",
                        mesh.name
                    );
                }
            }
        }
    }
}

/// Where no facet surrounds the axis, every triangle spans at most its own share of the
/// turn: the seam strip is as narrow as its neighbours.
#[test]
fn seam_triangles_are_as_narrow_as_the_others() {
    let y = Axis::Y;
    let cases = [
        (
            Mesh::sphere(1.0, 32, 16).unwrap(),
            UvGenerator::Spherical { axis: y },
            32,
        ),
        (
            Mesh::sphere(1.0, 32, 16).unwrap(),
            UvGenerator::Cylindrical { axis: y },
            32,
        ),
        (
            Mesh::torus(1.0, 0.3, 40, 12).unwrap(),
            UvGenerator::Cylindrical { axis: y },
            40,
        ),
        (
            Mesh::torus(1.0, 0.3, 40, 12).unwrap(),
            UvGenerator::Spherical { axis: y },
            40,
        ),
        (
            Mesh::cylinder(1.0, 2.0, 24, false).unwrap(),
            UvGenerator::Cylindrical { axis: y },
            24,
        ),
    ];
    for (mesh, g, slices) in cases {
        let uvs = corner_uvs(&mesh, &generate_uvs(&mesh, &g));
        let mut seam_facets = 0;
        for f in mesh.facets() {
            let us: Vec<f32> = f.corners().map(|c| uvs[c].x).collect();
            let (lo, hi) = us
                .iter()
                .fold((f32::MAX, f32::MIN), |(a, b), &u| (a.min(u), b.max(u)));
            assert!(
                hi - lo <= 1.0 / slices as f32 + EPS,
                "{} {g}: {us:?}",
                mesh.name
            );
            seam_facets += usize::from(hi >= 1.0); // shifted: unshifted u is below 1
        }
        assert!(
            seam_facets > 0,
            "{} {g}: the seam was crossed somewhere",
            mesh.name
        );
    }
}

#[test]
fn spherical_and_cylindrical_maps_reproduce_the_primitives_uvs() {
    let cases = [
        (
            Mesh::sphere(1.5, 32, 16).unwrap(),
            UvGenerator::Spherical { axis: Axis::Y },
        ),
        (
            Mesh::cylinder(1.0, 3.0, 24, true).unwrap(),
            UvGenerator::Cylindrical { axis: Axis::Y },
        ),
        (
            Mesh::cylinder(1.0, 3.0, 8, false).unwrap(),
            UvGenerator::Cylindrical { axis: Axis::Y },
        ),
    ];
    for (mesh, g) in cases {
        let (own, generated) = (mesh.uvs[0].clone(), generate_uvs(&mesh, &g));
        let want = corner_uvs(&mesh, &own);
        for (c, got) in corner_uvs(&mesh, &generated).into_iter().enumerate() {
            assert!(
                same_modulo_turns(got, want[c]),
                "{} {g} corner {c}: {got} vs {}",
                mesh.name,
                want[c]
            );
        }
    }
    // The torus: longitude only (its v runs around the tube).
    let torus = Mesh::torus(1.0, 0.25, 32, 12).unwrap();
    let want = corner_uvs(&torus, &torus.uvs[0]);
    let got = corner_uvs(
        &torus,
        &generate_uvs(&torus, &UvGenerator::Cylindrical { axis: Axis::Y }),
    );
    for (a, b) in got.iter().zip(&want) {
        assert!(
            same_modulo_turns(Vec2::new(a.x, 0.0), Vec2::new(b.x, 0.0)),
            "{a} vs {b}"
        );
    }
}

#[test]
fn pole_corners_take_the_mean_longitude_of_their_facet() {
    let mesh = Mesh::sphere(1.0, 16, 8).unwrap();
    let uvs = corner_uvs(
        &mesh,
        &generate_uvs(&mesh, &UvGenerator::Spherical { axis: Axis::Y }),
    );
    let south = mesh.positions.len() as u32 - 1;
    let mut poles = 0;
    for f in mesh.facets() {
        let ring: Vec<usize> = f.corners().collect();
        let Some(&pole) = ring
            .iter()
            .find(|&&c| [0, south].contains(&mesh.corners[c]))
        else {
            continue;
        };
        let others: Vec<f32> = ring
            .iter()
            .filter(|&&c| c != pole)
            .map(|&c| uvs[c].x)
            .collect();
        let mean = others.iter().sum::<f32>() / others.len() as f32;
        assert!((uvs[pole].x - mean).abs() < EPS);
        assert!((uvs[pole].y - if mesh.corners[pole] == 0 { 0.0 } else { 1.0 }).abs() < EPS);
        poles += 1;
    }
    assert_eq!(poles, 32);
}

#[test]
fn planar_map_of_a_unit_quad() {
    let data = MeshData {
        name: "quad".into(),
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
        corners: vec![0, 1, 2, 3],
        facet_sizes: Some(vec![4]),
        ..MeshData::default()
    };
    let quad = Mesh::new(data, NormalPolicy::Flat).unwrap();
    let ch = generate_uvs(&quad, &UvGenerator::Planar { axis: Axis::Z });
    assert_eq!(ch.indices, None, "no seams: one UV per vertex");
    assert_eq!(ch.values, [Vec2::Y, Vec2::ONE, Vec2::X, Vec2::ZERO]);
    // Seen edge-on, the quad maps to a line; a given frame maps to its own plane.
    let frame = UvFrame::new(
        Vec3::new(0.5, 0.5, 0.0),
        Vec3::Y,
        -Vec3::X,
        Vec3::splat(0.5),
    );
    let ch = generate_uvs_in(&quad, &UvGenerator::Planar { axis: Axis::Z }, &frame);
    assert_eq!(ch.values, [Vec2::ZERO, Vec2::Y, Vec2::ONE, Vec2::X]);
}

#[test]
fn box_map_gives_every_cube_face_the_whole_square() {
    let cube = Mesh::cube(3.0).unwrap();
    let ch = generate_uvs(&cube, &UvGenerator::Box);
    let own = corner_uvs(&cube, &cube.uvs[0]);
    let got = corner_uvs(&cube, &ch);
    assert_eq!(got, own, "the cube's own upright face UVs");
    for f in cube.facets() {
        let mut square: Vec<[u32; 2]> = f.corners().map(|c| key(got[c])).collect();
        square.sort_unstable();
        let mut want = [Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::ONE].map(key).to_vec();
        want.sort_unstable();
        assert_eq!(square, want);
    }
    assert_eq!(ch.values.len(), 4, "equal UVs share a value");
}

#[test]
fn box_map_uses_one_face_per_facet() {
    let mesh = Mesh::sphere(1.0, 24, 12).unwrap();
    let frame = uv_frame(&mesh);
    let uvs = corner_uvs(&mesh, &generate_uvs(&mesh, &UvGenerator::Box));
    for f in mesh.facets() {
        for c in f.corners() {
            let p = mesh.positions[mesh.corners[c] as usize];
            assert_eq!(uvs[c], UvGenerator::Box.map(&frame, p, f.normal));
        }
    }
}

#[test]
fn degenerate_meshes_give_finite_uvs() {
    let tri = |positions: Vec<Vec3>| {
        let n = positions.len() as u32;
        let data = MeshData {
            positions,
            corners: (0..n).collect(),
            ..MeshData::default()
        };
        Mesh::new(data, NormalPolicy::default()).unwrap()
    };
    let meshes = [
        tri(vec![]),
        tri(vec![Vec3::ONE; 3]),
        tri(vec![Vec3::NAN, Vec3::X, Vec3::Y]),
        tri(vec![Vec3::INFINITY, Vec3::NEG_INFINITY, Vec3::NAN]),
        tri(vec![
            Vec3::splat(f32::MAX),
            Vec3::splat(f32::MIN),
            Vec3::new(1e-30, 0.0, 0.0),
        ]),
        tri(vec![
            Vec3::ZERO,
            Vec3::Y,
            -Vec3::Y,
            Vec3::ZERO,
            Vec3::Y * 2.0,
            Vec3::Y * 3.0,
        ]),
    ];
    for mesh in &meshes {
        for g in all_generators() {
            let ch = generate_uvs(mesh, &g);
            assert!(
                ch.values.iter().all(|uv| uv.is_finite()),
                "{g} {:?}",
                mesh.positions
            );
            assert_eq!(corner_uvs(mesh, &ch).len(), mesh.corners.len());
        }
    }
}

#[test]
fn deterministic_and_independent_of_the_split() {
    // Above `par::MIN_CORNERS`, so the work is cut into a number of ranges that depends on
    // the pool's thread count.
    let mesh = Mesh::torus(1.0, 0.4, 128, 64).unwrap();
    assert!(mesh.corners.len() >= par::MIN_CORNERS);
    let run = |threads: usize, g: &UvGenerator| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| generate_uvs(&mesh, g))
    };
    for g in all_generators() {
        let a = run(1, &g);
        assert_eq!(a, run(3, &g), "{g}");
        assert_eq!(a, generate_uvs(&mesh, &g), "{g}");
    }
}
