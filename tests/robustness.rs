//! Determinism across thread counts, near-plane and behind-the-eye geometry, and hostile
//! coordinates (NaN, Inf, 1e30, zero-area facets): no panic, no NaN pixel, sensible coverage.

mod common;

use common::{assert_finite, covered, render, render_with, scene_of, triangles};
use std::path::Path;

use glam::{Vec3, Vec4};
use realist::mesh::Mesh;
use realist::render::{Settings, Shot};
use realist::scene::{self, Camera, Material};
use realist::shade::Shading;

#[test]
fn one_and_two_threads_are_bit_identical() {
    let mut demo = scene::demo();
    // Add a dense mesh so many tiles and batches are involved.
    let mut torus = Mesh::torus(1.5, 0.4, 160, 60).expect("torus");
    torus.material = Some(0);
    demo.meshes.push(torus);
    demo.instances.push(realist::scene::Instance {
        mesh: demo.meshes.len() - 1,
        world: glam::Mat4::from_rotation_x(1.0),
        name: "torus".into(),
        style: realist::scene::Style::Inherit,
        node: None,
        skin: None,
        copies: None,
    });
    for mode in [
        None,
        Some(Shading::Phong),
        Some(Shading::Gouraud),
        Some(Shading::Flat),
        Some(Shading::Wireframe),
    ] {
        let opts = Shot {
            width: 333,
            height: 201,
            camera: demo.cameras.first().cloned(),
            settings: Settings {
                shading: mode,
                ..Settings::default()
            },
        };
        let (a, sa) = render_with(&demo, &opts, 1);
        let (b, sb) = render_with(&demo, &opts, 2);
        let bits = |fb: &realist::raster::Framebuffer| {
            fb.color
                .iter()
                .flat_map(|c| c.to_array().map(f32::to_bits))
                .collect::<Vec<_>>()
        };
        assert!(bits(&a) == bits(&b), "{mode:?}: 1 and 2 threads differ");
        assert_eq!(sa, sb, "{mode:?}: counters differ");
        assert!(covered(&a) > 1000, "{mode:?}: nothing drawn");
    }
}

/// A floor plane that extends far behind the camera: it crosses the eye plane, so without
/// near clipping its projection would wrap around. Seen from a camera looking horizontally,
/// exactly the rows below the horizon must be covered.
#[test]
fn floor_crossing_the_near_plane_renders_below_the_horizon() {
    let s = 100.0;
    let floor = triangles(
        vec![
            Vec3::new(-s, -1.0, -s),
            Vec3::new(s, -1.0, -s),
            Vec3::new(s, -1.0, s),
            Vec3::new(-s, -1.0, s),
        ],
        vec![0, 2, 1, 0, 3, 2],
    );
    let mut scene = scene_of(
        floor,
        Material {
            double_sided: true,
            ..Material::default()
        },
    );
    scene.lights = vec![realist::scene::Light::ambient(Vec3::ONE)];
    let cam = Camera {
        eye: Vec3::ZERO,
        target: Vec3::new(0.0, 0.0, -1.0),
        near: 0.05,
        far: 500.0,
        ..Camera::default()
    };
    let (w, h) = (160u32, 120u32);
    let fb = render(&scene, w, h, Some(Shading::Flat), Some(cam));
    assert_finite(&fb, "floor");
    let bg = Shot::default().settings.background;
    for y in 0..h {
        let row: Vec<bool> = (0..w).map(|x| fb.pixel(x, y) != bg).collect();
        // The horizon is at the image centre; the floor recedes to it, so rows just below the
        // centre may be partly empty where the finite floor ends (100 units away).
        if y >= h / 2 + 2 {
            assert!(
                row.iter().all(|&c| c),
                "row {y} below the horizon not fully covered"
            );
        }
        if y < h / 2 {
            assert!(
                row.iter().all(|&c| !c),
                "row {y} above the horizon covered: wrap-around"
            );
        }
    }
}

#[test]
fn triangle_behind_the_eye_draws_nothing() {
    let tri = triangles(
        vec![
            Vec3::new(-1.0, -1.0, 5.0),
            Vec3::new(1.0, -1.0, 5.0),
            Vec3::new(0.0, 1.0, 5.0),
        ],
        vec![0, 1, 2],
    );
    let scene = scene_of(
        tri,
        Material {
            double_sided: true,
            ..Material::default()
        },
    );
    let cam = Camera {
        eye: Vec3::ZERO,
        target: Vec3::new(0.0, 0.0, -1.0),
        near: 0.1,
        far: 100.0,
        ..Camera::default()
    };
    for mode in Shading::ALL {
        let fb = render(&scene, 64, 48, Some(mode), Some(cam.clone()));
        assert_eq!(
            covered(&fb),
            0,
            "{mode}: a triangle behind the eye was drawn"
        );
    }
}

/// Triangles with NaN, Inf and 1e30 coordinates, and zero-area facets, next to a good one.
#[test]
fn hostile_coordinates_do_not_panic_or_poison_pixels() {
    let bad = [
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        1e30,
        -1e30,
        1e6,
        3e38,
    ];
    let mut positions = vec![
        Vec3::new(-1.0, -1.0, 0.0),
        Vec3::new(1.0, -1.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
    ];
    let mut corners = vec![0, 1, 2];
    for (k, &b) in bad.iter().enumerate() {
        let base = positions.len() as u32;
        positions.extend([
            Vec3::new(b, 0.0, 0.0),
            Vec3::new(0.5, b, 0.2),
            Vec3::new(0.1, 0.3, b),
        ]);
        corners.extend([base, base + 1, base + 2]);
        // Mixed: one hostile vertex shared with the good triangle's vertices.
        corners.extend([0, base + k as u32 % 3, 1]);
    }
    // Zero-area facets: repeated vertex, collinear vertices.
    let base = positions.len() as u32;
    positions.extend([
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.5, 0.5, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
    ]);
    corners.extend([base, base, base + 1, base, base + 1, base + 2]);
    let mesh = triangles(positions, corners);
    for n in mesh.normals.values.iter() {
        assert!(n.is_finite(), "non-finite normal {n}");
    }
    let scene = scene_of(
        mesh,
        Material {
            double_sided: true,
            base_color: Vec4::ONE,
            ..Material::default()
        },
    );
    let cam = Camera {
        eye: Vec3::new(0.0, 0.0, 4.0),
        near: 0.1,
        far: 100.0,
        ..Camera::default()
    };
    for mode in Shading::ALL {
        for size in [(64, 48), (1, 1), (3, 200)] {
            let fb = render(&scene, size.0, size.1, Some(mode), Some(cam.clone()));
            assert_finite(&fb, mode.name());
        }
        let fb = render(&scene, 64, 48, Some(mode), Some(cam.clone()));
        assert!(covered(&fb) > 100, "{mode}: the good triangle vanished");
    }
    // The default camera must cope with a scene whose bounds include 1e30.
    let fb = render(&scene, 64, 48, Some(Shading::Phong), None);
    assert_finite(&fb, "default camera");
}

/// On a closed mesh only front faces are visible, so drawing it double-sided must not change
/// a pixel in any lit mode (Gouraud used to flip vertex normals near the silhouette).
#[test]
fn double_sided_closed_mesh_looks_single_sided() {
    let sphere = Mesh::sphere(1.0, 12, 6).expect("sphere");
    let single = scene_of(
        sphere.clone(),
        Material {
            specular: Vec3::splat(0.4),
            ..Material::default()
        },
    );
    let double = scene_of(
        sphere,
        Material {
            double_sided: true,
            specular: Vec3::splat(0.4),
            ..Material::default()
        },
    );
    let mut cam = Camera {
        eye: Vec3::new(0.8, 1.0, 2.6),
        ..Camera::default()
    };
    cam.fit(Vec3::ZERO, 1.0);
    for mode in [
        Shading::Gouraud,
        Shading::Phong,
        Shading::Blinn,
        Shading::Flat,
        Shading::Normals,
    ] {
        let a = render(&single, 128, 128, Some(mode), Some(cam.clone()));
        let b = render(&double, 128, 128, Some(mode), Some(cam.clone()));
        let differ = a
            .color
            .iter()
            .zip(&b.color)
            .filter(|(x, y)| (**x - **y).abs().max_element() > 1e-6)
            .count();
        assert_eq!(differ, 0, "{mode}: double-sided changed {differ} pixels");
    }
}

/// A sheared / non-uniformly scaled instance near the edge of the view is still drawn: the
/// object culling test must not use a bounding sphere that is too small.
#[test]
fn sheared_instance_at_the_view_edge_is_not_culled() {
    let mut scene = scene_of(Mesh::cube(1.0).expect("cube"), Material::default());
    let cam = Camera {
        eye: Vec3::new(0.0, 0.0, 20.0),
        near: 1.0,
        far: 100.0,
        ..Camera::default()
    };
    let tan = libm::tanf(cam.yfov * 0.5); // square image
    let mut drawn_all = true;
    let mut visible_cases = 0;
    for k in 0..100 {
        // Long along x after a 45 degree rotation: world = T * S(10, 1, 1) * R(45).
        let x = 20.0 * tan + 4.0 + k as f32 * 0.05;
        scene.instances[0].world = glam::Mat4::from_translation(Vec3::new(x, 0.0, 0.0))
            * glam::Mat4::from_scale(Vec3::new(10.0, 1.0, 1.0))
            * glam::Mat4::from_rotation_z(std::f32::consts::FRAC_PI_4);
        let opts = Shot {
            width: 64,
            height: 64,
            camera: Some(cam.clone()),
            settings: Settings {
                shading: Some(Shading::Flat),
                ..Settings::default()
            },
        };
        let (_, stats) = common::render_with(&scene, &opts, 2);
        // Exact visibility: does any transformed corner project inside the view?
        let inside = (0..8).any(|i| {
            let c = Vec3::new(
                if i & 1 == 0 { -0.5 } else { 0.5 },
                if i & 2 == 0 { -0.5 } else { 0.5 },
                if i & 4 == 0 { -0.5 } else { 0.5 },
            );
            let w = scene.instances[0].world.transform_point3(c);
            w.x < (20.0 - w.z) * tan
        });
        visible_cases += usize::from(inside);
        if inside && stats.objects_culled > 0 {
            drawn_all = false;
        }
    }
    assert!(visible_cases > 10, "the sweep never reached the view edge");
    assert!(drawn_all, "a visible sheared instance was culled");
}

#[test]
fn a_file_with_nothing_to_draw_is_an_error_naming_it_not_an_empty_image() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("nothing-to-draw");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let notes = dir.join("notes.obj");
    std::fs::write(&notes, "Shopping list\nmilk\nbread\n").unwrap();
    let png = dir.join("notes.png");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_realist"))
        .arg("render")
        .arg(&notes)
        .arg("-o")
        .arg(&png)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{stderr}");
    assert!(
        stderr.contains(&format!("{}: nothing to draw", notes.display())),
        "{stderr}"
    );
    assert!(!png.exists(), "no image written");
    // `info` still describes it (that is what it is for).
    let info = std::process::Command::new(env!("CARGO_BIN_EXE_realist"))
        .arg("info")
        .arg(&notes)
        .output()
        .unwrap();
    assert!(info.status.success());
    assert!(String::from_utf8_lossy(&info.stdout).contains("0 meshes"));
}
