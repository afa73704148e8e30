//! A renderer that is called 60 times a second must not allocate per frame: after the first
//! frame at a size (with the modes in use), `Renderer::render` plus `write_rgba8` allocate
//! nothing. A counting global allocator (`stats_alloc`, so this crate stays free of
//! `unsafe`) counts every allocation of every thread while the second frame renders.
//!
//! This file holds one test so nothing else runs in the process while it counts.

use std::alloc::System;

use glam::{Vec3, Vec4};
use stats_alloc::{Region, StatsAlloc, INSTRUMENTED_SYSTEM};

use realist::load::{load, LoadOptions};
use realist::render::{Lights, Output, PreparedScene, Renderer, Settings, View};
use realist::scene::{self, AlphaMode, Camera, Light, Play};
use realist::shade::Shading;

#[global_allocator]
static GLOBAL: &StatsAlloc<System> = &INSTRUMENTED_SYSTEM;

/// The demo scene with its smooth sphere made transparent (a blended pass, sorted).
fn demo() -> PreparedScene {
    let mut s = scene::demo();
    s.materials[2].alpha_mode = AlphaMode::Blend;
    s.materials[2].base_color.w = 0.6;
    PreparedScene::new(s)
}

fn textured() -> PreparedScene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models/checker-cube.glb");
    PreparedScene::new(load(&path, &LoadOptions::default()).expect("checker-cube.glb"))
}

/// Allocations (and reallocations) while `f` runs.
fn allocations(f: impl FnOnce()) -> usize {
    let region = Region::new(GLOBAL);
    f();
    let c = region.change();
    c.allocations + c.reallocations
}

/// The fewest [`allocations`] of `f` over three runs. rayon's work-stealing deques grow
/// and shrink their buffers with the number of queued jobs, which depends on how the OS
/// schedules the pool's threads: on a loaded machine a frame now and then sees one or two
/// such allocations inside rayon. A per-frame allocation of the renderer's own shows in
/// every run.
fn fewest_allocations(mut f: impl FnMut()) -> usize {
    (0..3).map(|_| allocations(&mut f)).min().unwrap_or(0)
}

#[test]
fn a_second_frame_allocates_nothing() {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("pool");
    let demo = demo();
    let cube = textured();
    let camera = demo.scene().cameras[0].clone();
    // A camera inside the middle sphere: its triangles cross the near plane (clipping).
    let inside = Camera {
        eye: Vec3::new(0.1, 0.2, 0.3),
        target: Vec3::new(2.4, 0.0, -1.0),
        near: 0.01,
        far: 50.0,
        ..Camera::default()
    };
    let cube_cam = realist::render::default_camera(cube.scene(), 4.0 / 3.0);
    let custom = Lights::Custom {
        lights: vec![
            Light::ambient(Vec3::splat(0.1)),
            Light::point(Vec3::new(1.0, 2.0, 3.0), Vec3::ONE),
        ],
        follow_camera: true,
    };
    let base = Settings::default();
    let cases: Vec<(&str, &PreparedScene, Settings, Camera)> = vec![
        ("demo styles", &demo, base.clone(), camera.clone()),
        (
            "gouraud, double-sided",
            &demo,
            Settings {
                shading: Some(Shading::Gouraud),
                double_sided: true,
                ..base.clone()
            },
            camera.clone(),
        ),
        (
            "flat",
            &demo,
            Settings {
                shading: Some(Shading::Flat),
                ..base.clone()
            },
            camera.clone(),
        ),
        (
            "blinn, custom lights",
            &demo,
            Settings {
                shading: Some(Shading::Blinn),
                lights: custom,
                ..base.clone()
            },
            camera.clone(),
        ),
        (
            "phong + wireframe overlay, clipped",
            &demo,
            Settings {
                wireframe_overlay: true,
                ..base.clone()
            },
            inside,
        ),
        (
            "overdraw",
            &demo,
            Settings {
                output: Output::Overdraw,
                ..base.clone()
            },
            camera.clone(),
        ),
        (
            "fog, tone mapping, ground plane (the demo's spotlight casts shadows)",
            &demo,
            Settings {
                fog: Some(realist::shade::Fog::default()),
                tone: realist::render::ToneMap::Reinhard,
                ground: Some(realist::render::Ground::default()),
                shading: Some(Shading::Gouraud),
                ..base.clone()
            },
            camera.clone(),
        ),
        (
            "2x2 supersampling",
            &demo,
            Settings {
                samples: 2,
                ..base.clone()
            },
            camera.clone(),
        ),
        (
            "4x multisampling with the wireframe overlay",
            &demo,
            Settings {
                msaa: 4,
                wireframe_overlay: true,
                ..base.clone()
            },
            camera.clone(),
        ),
        ("textured", &cube, base.clone(), cube_cam.clone()),
        (
            "normals",
            &cube,
            Settings {
                shading: Some(Shading::Normals),
                ..base.clone()
            },
            cube_cam.clone(),
        ),
    ];
    pool.install(|| {
        for (name, scene, settings, camera) in &cases {
            let view = View {
                camera: camera.clone(),
                width: 320,
                height: 200,
            };
            let mut r = Renderer::new();
            let mut pixels = vec![[0u8; 4]; 320 * 200];
            r.render(scene, settings, &view);
            r.write_rgba8(&mut pixels);
            let n = fewest_allocations(|| {
                r.render(scene, settings, &view);
                r.write_rgba8(&mut pixels);
            });
            let drawn = r.report().stats.pixels_shaded;
            eprintln!("{name}: {drawn} fragments, {n} allocations in the second frame");
            assert!(drawn > 1000, "{name}: nothing drawn");
            assert_eq!(n, 0, "{name}: the second frame allocated");
        }
        // Playback: posing a skinned, animated mesh (joint matrices, skinning in parallel,
        // bounds) and drawing it.
        let mut tube = PreparedScene::new(scene::skinned_tube(40, 24, 6, 4).expect("tube"));
        let view = View {
            camera: realist::render::default_camera(tube.scene(), 1.6),
            width: 320,
            height: 200,
        };
        let mut r = Renderer::new();
        let mut t = 0.25;
        tube.pose_at(Play::All, t, true);
        r.render(&tube, &base, &view);
        let n = fewest_allocations(|| {
            t += 0.5;
            tube.pose_at(Play::All, t, true);
            r.render(&tube, &base, &view);
        });
        eprintln!("skinned playback: {n} allocations per posed frame");
        assert!(r.report().stats.pixels_shaded > 1000, "the tube is drawn");
        assert_eq!(n, 0, "posing and drawing a frame allocated");
        // Switching between two sizes it has seen (a viewer's reduced and full resolution).
        let (scene, settings) = (&demo, &base);
        let mut r = Renderer::new();
        let views: Vec<View> = [(640, 360), (160, 90)]
            .map(|(width, height)| View {
                camera: camera.clone(),
                width,
                height,
            })
            .to_vec();
        for v in &views {
            r.render(scene, settings, v);
        }
        let n = fewest_allocations(|| {
            for v in views.iter().chain(&views) {
                r.render(scene, settings, v);
            }
        });
        assert_eq!(n, 0, "switching sizes allocated");
        // Sanity: the counter does count.
        let n = allocations(|| drop(std::hint::black_box(vec![Vec4::ONE; 10])));
        assert!(n >= 1);
    });
}
