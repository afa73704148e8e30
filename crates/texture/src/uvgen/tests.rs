//! Per-point UV maps: the conventions of the table in the module documentation, frames,
//! robustness and names.

use glam::{Vec2, Vec3, Vec3Swizzles};

use super::*;

/// Largest difference between UVs that should agree.
const EPS: f32 = 1e-6;

#[track_caller]
fn assert_uv(got: Vec2, want: Vec2) {
    assert!((got - want).abs().max_element() <= EPS, "{got} vs {want}");
}

fn map(g: UvGenerator, p: Vec3) -> Vec2 {
    g.map(&UvFrame::UNIT, p, Vec3::ZERO)
}

#[test]
fn planar_maps_are_upright_seen_from_the_positive_axis() {
    let z = UvGenerator::Planar { axis: Axis::Z };
    assert_uv(map(z, Vec3::new(-1.0, 1.0, 0.3)), Vec2::ZERO);
    assert_uv(map(z, Vec3::new(1.0, 1.0, 0.0)), Vec2::X);
    assert_uv(map(z, Vec3::new(1.0, -1.0, 0.0)), Vec2::ONE);
    assert_uv(map(z, Vec3::new(-1.0, -1.0, -5.0)), Vec2::Y);
    // Seen from +x, right is -z; from +y, right is +x and up is -z.
    let x = UvGenerator::Planar { axis: Axis::X };
    assert_uv(map(x, Vec3::new(0.0, 1.0, 1.0)), Vec2::ZERO);
    let y = UvGenerator::Planar { axis: Axis::Y };
    assert_uv(map(y, Vec3::new(-1.0, 0.0, -1.0)), Vec2::ZERO);
    assert_uv(map(y, Vec3::new(1.0, 0.0, 1.0)), Vec2::ONE);
}

#[test]
fn longitude_runs_counter_clockwise_from_the_next_axis() {
    let cases = [
        (Axis::Y, [Vec3::Z, Vec3::X, -Vec3::Z, -Vec3::X]),
        (Axis::Z, [Vec3::X, Vec3::Y, -Vec3::X, -Vec3::Y]),
        (Axis::X, [Vec3::Y, Vec3::Z, -Vec3::Y, -Vec3::Z]),
    ];
    for (axis, ring) in cases {
        for g in [
            UvGenerator::Cylindrical { axis },
            UvGenerator::Spherical { axis },
        ] {
            for (k, &p) in ring.iter().enumerate() {
                let m = g.map_point(&UvFrame::UNIT, p, Vec3::ZERO);
                assert!(!m.on_axis);
                assert_uv(m.uv, Vec2::new(0.25 * k as f32, 0.5));
            }
        }
    }
    let cyl = UvGenerator::Cylindrical { axis: Axis::Y };
    assert_uv(map(cyl, Vec3::new(0.0, 1.0, 1.0)), Vec2::ZERO);
    assert_uv(map(cyl, Vec3::new(0.0, -1.0, 1.0)), Vec2::Y);
    // Just before the seam u is close to 1, never 1.
    let u = map(cyl, Vec3::new(-1e-9, 0.0, 1.0)).x;
    assert!((0.0..1.0).contains(&u), "{u}");
}

#[test]
fn sphere_poles_are_on_the_axis() {
    let g = UvGenerator::Spherical { axis: Axis::Y };
    for (p, v) in [(Vec3::Y, 0.0), (-Vec3::Y, 1.0), (Vec3::ZERO, 0.0)] {
        let m = g.map_point(&UvFrame::UNIT, p, Vec3::ZERO);
        assert!(m.on_axis, "{p}");
        assert_uv(m.uv, Vec2::new(0.0, v));
    }
    let v = map(g, Vec3::new(1.0, 1.0, 0.0)).y;
    assert!((v - 0.25).abs() < EPS, "45 degrees from the pole: {v}");
    // The latitude ignores a non-cubic frame.
    let frame = UvFrame::from_bounds(Vec3::new(-1.0, -3.0, -1.0), Vec3::new(1.0, 3.0, 1.0));
    let v = g.map(&frame, Vec3::new(1.0, 1.0, 0.0), Vec3::ZERO).y;
    assert!((v - 0.25).abs() < EPS, "{v}");
}

#[test]
fn box_picks_the_dominant_face_and_maps_it_upright() {
    let frame = UvFrame::UNIT;
    let faces = [
        (Vec3::X, Vec3::new(1.0, 1.0, 1.0)),
        (-Vec3::X, Vec3::new(-1.0, 1.0, -1.0)),
        (Vec3::Y, Vec3::new(-1.0, 1.0, -1.0)),
        (-Vec3::Y, Vec3::new(-1.0, -1.0, 1.0)),
        (Vec3::Z, Vec3::new(-1.0, 1.0, 1.0)),
        (-Vec3::Z, Vec3::new(1.0, 1.0, -1.0)),
    ];
    for (n, top_left) in faces {
        assert_uv(UvGenerator::Box.map(&frame, top_left, n), Vec2::ZERO);
        assert_uv(
            UvGenerator::Box.map(&frame, top_left, n * 0.3 + 0.1 * n.yzx()),
            Vec2::ZERO,
        );
    }
    // Ties prefer x, then y; no direction at all is +z.
    let p = Vec3::new(0.5, -0.5, 0.25);
    let planar = |axis| UvGenerator::Planar { axis }.map(&frame, p, Vec3::ZERO);
    assert_uv(
        UvGenerator::Box.map(&frame, p, Vec3::new(1.0, 1.0, 1.0)),
        planar(Axis::X),
    );
    assert_uv(
        UvGenerator::Box.map(&frame, p, Vec3::new(0.0, 1.0, -1.0)),
        planar(Axis::Y),
    );
    assert_uv(UvGenerator::Box.map(&frame, p, Vec3::ZERO), planar(Axis::Z));
    assert_uv(UvGenerator::Box.map(&frame, p, Vec3::NAN), planar(Axis::Z));
}

#[test]
fn frames_fit_bounds_and_repair_bad_input() {
    let f = UvFrame::from_bounds(Vec3::new(1.0, 2.0, 3.0), Vec3::new(3.0, 6.0, 3.0));
    assert_eq!(f.centre(), Vec3::new(2.0, 4.0, 3.0));
    assert_eq!(
        f.local(Vec3::new(3.0, 2.0, 3.0)).truncate(),
        Vec2::new(1.0, -1.0)
    );
    assert!(
        f.half_extent().z > 0.0,
        "a flat box gets a thin but positive extent"
    );
    let g = UvFrame::from_bounds(Vec3::new(3.0, 6.0, 3.0), Vec3::new(1.0, 2.0, 3.0));
    assert_eq!(
        g.local(Vec3::new(3.0, 2.0, 3.0)),
        f.local(Vec3::new(3.0, 2.0, 3.0))
    );
    for (lo, hi) in [
        (Vec3::NAN, Vec3::ONE),
        (Vec3::ZERO, Vec3::ZERO),
        (Vec3::splat(f32::MIN), Vec3::splat(f32::MAX)),
        (Vec3::NEG_INFINITY, Vec3::INFINITY),
    ] {
        let f = UvFrame::from_bounds(lo, hi);
        assert!(
            f.centre().is_finite() && f.half_extent().min_element() > 0.0,
            "{f:?}"
        );
        assert!(f.half_extent().is_finite(), "{f:?}");
    }
    // Axes are made orthonormal and right-handed.
    let f = UvFrame::new(
        Vec3::ZERO,
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::ONE,
    );
    assert_eq!(f.axes(), [Vec3::X, Vec3::Y, Vec3::Z]);
    let f = UvFrame::new(Vec3::NAN, Vec3::ZERO, Vec3::ZERO, Vec3::NAN);
    let [x, y, z] = f.axes();
    assert!(
        (x.cross(y) - z).length() < EPS && x.dot(y).abs() < EPS && (x.length() - 1.0).abs() < EPS
    );
    assert_eq!((f.centre(), f.half_extent()), (Vec3::ZERO, Vec3::ONE));
}

#[test]
fn non_finite_and_huge_points_map_to_finite_uvs() {
    let frame = UvFrame::from_bounds(Vec3::splat(-1e30), Vec3::splat(1e30));
    let generators = UvGenerator::PRESETS
        .into_iter()
        .chain(Axis::ALL.map(|axis| UvGenerator::Spherical { axis }));
    for g in generators {
        for p in [
            Vec3::NAN,
            Vec3::INFINITY,
            Vec3::splat(f32::MAX),
            Vec3::new(1e-30, 0.0, -1e-30),
        ] {
            for f in [UvFrame::UNIT, frame] {
                let m = g.map_point(&f, p, Vec3::new(f32::NAN, 1.0, 0.0));
                assert!(m.uv.is_finite(), "{g} {p}: {m:?}");
                assert!(g.cap(&f, p, -Vec3::Y).is_finite());
            }
        }
        assert_eq!(map(g, Vec3::NAN), Vec2::ZERO);
    }
}

#[test]
fn names_round_trip_and_errors_list_the_options() {
    let all = UvGenerator::PRESETS
        .into_iter()
        .chain(Axis::ALL.into_iter().flat_map(|axis| {
            [
                UvGenerator::Cylindrical { axis },
                UvGenerator::Spherical { axis },
            ]
        }));
    for g in all {
        assert_eq!(g.to_string().parse::<UvGenerator>(), Ok(g));
    }
    let names: Vec<String> = UvGenerator::PRESETS
        .iter()
        .map(ToString::to_string)
        .collect();
    assert_eq!(
        names,
        [
            "planar:x",
            "planar:y",
            "planar:z",
            "cylindrical",
            "spherical",
            "box"
        ]
    );
    assert_eq!("Planar".parse(), Ok(UvGenerator::Planar { axis: Axis::Z }));
    assert_eq!(
        " spherical:Z ".parse(),
        Ok(UvGenerator::Spherical { axis: Axis::Z })
    );
    for bad in ["planar:w", "box:x", "cubic", ""] {
        let err = bad.parse::<UvGenerator>().unwrap_err().to_string();
        assert!(
            err.contains("planar:x|y|z") && err.contains("box"),
            "{bad}: {err}"
        );
    }
}
