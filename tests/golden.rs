//! Golden images of every shading mode on small scenes, with named tolerances.
//! A failure writes the render and a diff to `target/golden-diff/`; `REPLACE=1` regenerates.

mod common;

use common::{check_golden, checker_cube, render, scene_of, EXACT, SHADED};
use glam::{Vec3, Vec4};
use realist::mesh::Mesh;
use realist::scene::{self, Camera, Material};
use realist::shade::Shading;

fn sphere_scene() -> scene::Scene {
    let material = Material {
        base_color: Vec4::new(0.8, 0.3, 0.2, 1.0),
        specular: Vec3::splat(0.5),
        shininess: 30.0,
        ..Material::default()
    };
    scene_of(Mesh::sphere(1.0, 16, 10).expect("sphere"), material)
}

fn camera() -> Camera {
    let mut cam = Camera {
        eye: Vec3::new(1.5, 1.2, 3.2),
        ..Camera::default()
    };
    cam.fit(Vec3::ZERO, 1.8);
    cam
}

#[test]
fn sphere_in_every_mode() {
    let scene = sphere_scene();
    for mode in Shading::ALL {
        let fb = render(&scene, 128, 96, Some(mode), Some(camera()));
        common::assert_finite(&fb, mode.name());
        let tol = if mode == Shading::Wireframe {
            EXACT
        } else {
            SHADED
        };
        check_golden(&format!("sphere-{}", mode.name()), &fb, tol);
    }
}

#[test]
fn textured_checker_cube() {
    let fb = render(
        &checker_cube(),
        128,
        96,
        Some(Shading::Textured),
        Some(camera()),
    );
    check_golden("cube-textured", &fb, SHADED);
    let fb = render(&checker_cube(), 128, 96, Some(Shading::Uv), Some(camera()));
    check_golden("cube-uv", &fb, SHADED);
}

#[test]
fn demo_scene() {
    let demo = scene::demo();
    let fb = render(&demo, 320, 180, None, demo.cameras.first().cloned());
    check_golden("demo", &fb, SHADED);
}
