//! The reusable renderer: supersampling by jittered passes against a larger render
//! box-filtered and against the analytic sphere, a reused renderer against a fresh one,
//! stopping, the overdraw count, per-tile costs, picking from the depth buffer, and the
//! pixel probe against the renderer's own buffers.

use std::sync::atomic::{AtomicUsize, Ordering};

use glam::{Mat4, Vec3, Vec4};

use realist::mesh::Mesh;
use realist::quality::metrics::compare;
use realist::quality::sphere::SphereSetup;
use realist::quality::LinearImage;
use realist::raster::Target;
use realist::render::{self, Interrupted, Output, PreparedScene, Renderer, Settings, Shot, View};
use realist::scene::{self, Camera, Instance, Light, Material, Scene, Style};
use realist::shade::Shading;

const W: u32 = 160;
const H: u32 = 120;

fn sphere_setup() -> (SphereSetup, PreparedScene) {
    let setup = SphereSetup::standard(W, H);
    let scene = setup.scene(64, 32).expect("sphere");
    (setup, PreparedScene::new(scene))
}

fn view(camera: &Camera, width: u32, height: u32) -> View {
    View {
        camera: camera.clone(),
        width,
        height,
    }
}

fn linear(target: &Target) -> LinearImage {
    LinearImage::from_framebuffer(&target.resolve())
}

fn pixels(r: &Renderer) -> Vec<[u8; 4]> {
    let t = r.target().expect("frame");
    let mut px = vec![[0u8; 4]; (t.width * t.height) as usize];
    r.write_rgba8(&mut px);
    px
}

#[test]
fn jittered_supersampling_matches_a_larger_render_box_filtered() {
    let (setup, scene) = sphere_setup();
    let black = Vec4::new(0.0, 0.0, 0.0, 1.0);
    let reference = setup.reference(false);
    for n in [2u32, 4] {
        let settings = Settings {
            samples: n,
            shading: Some(Shading::Phong),
            background: black,
            ..Settings::default()
        };
        let mut r = Renderer::new();
        r.render(&scene, &settings, &view(&setup.camera, W, H));
        let jittered = linear(r.target().expect("frame"));
        let big = render::render(
            &scene,
            &Shot {
                width: W * n,
                height: H * n,
                camera: Some(setup.camera.clone()),
                settings: Settings {
                    shading: Some(Shading::Phong),
                    background: black,
                    ..Settings::default()
                },
            },
        );
        let boxed = LinearImage::from_framebuffer(&big.image()).downsample(n);
        let m = compare(&jittered, &boxed, 1.0);
        eprintln!("{n}x{n}: jittered vs box-filtered larger render: {m:?}");
        // The same sample positions; only the vertex snap grid differs (1/256 of a pixel
        // here, 1/(256 n) there), which can move a sample lying within 1/256 pixel of a
        // silhouette to the other side: at most a few samples of 1/n^2 each.
        let one_sample = 1.0 / f64::from(n * n);
        assert!(
            m.mean_de2000 < 0.01 && m.max_abs <= one_sample,
            "{n}x{n}: {m:?}"
        );
        assert!(m.over_threshold <= 10, "{n}x{n}: {m:?}");
        // And supersampling converges on the analytic sphere.
        let one = {
            let mut r1 = Renderer::new();
            let s1 = Settings {
                samples: 1,
                ..settings.clone()
            };
            r1.render(&scene, &s1, &view(&setup.camera, W, H));
            compare(&linear(r1.target().expect("frame")), &reference, 1.0)
        };
        let ss = compare(&jittered, &reference, 1.0);
        eprintln!("{n}x{n} vs analytic: {ss:?}; 1 sample: {one:?}");
        assert!(ss.rmse < one.rmse * 0.75, "{n}x{n}: {ss:?} vs {one:?}");
        assert_eq!(r.report().samples, n);
    }
}

#[test]
fn a_reused_renderer_draws_what_a_fresh_one_draws() {
    let demo = PreparedScene::new(scene::demo());
    let cam = demo.scene().cameras[0].clone();
    let mut reused = Renderer::new();
    let cases = [
        (Settings::default(), 200, 150),
        (
            Settings {
                shading: Some(Shading::Flat),
                wireframe_overlay: true,
                ..Settings::default()
            },
            97,
            61,
        ),
        (
            Settings {
                samples: 2,
                ..Settings::default()
            },
            200,
            150,
        ),
        (
            Settings {
                output: Output::Overdraw,
                ..Settings::default()
            },
            64,
            64,
        ),
        (Settings::default(), 200, 150),
    ];
    for (k, (settings, w, h)) in cases.iter().enumerate() {
        let v = view(&cam, *w, *h);
        reused.render(&demo, settings, &v);
        let mut fresh = Renderer::new();
        fresh.render(&demo, settings, &v);
        assert_eq!(pixels(&reused), pixels(&fresh), "case {k}");
        assert_eq!(
            reused.report().stats,
            fresh.report().stats,
            "case {k} counters"
        );
    }
}

#[test]
fn a_stopped_frame_reports_interrupted_and_the_next_one_is_whole() {
    let demo = PreparedScene::new(scene::demo());
    let v = view(&demo.scene().cameras[0], 320, 240);
    let settings = Settings {
        samples: 2,
        ..Settings::default()
    };
    let mut r = Renderer::new();
    // Stop after a few tiles.
    let asked = AtomicUsize::new(0);
    let stop = || asked.fetch_add(1, Ordering::Relaxed) > 3;
    assert_eq!(
        r.render_until(&demo, &settings, &v, &stop).err(),
        Some(Interrupted)
    );
    assert!(!r.complete());
    r.render(&demo, &settings, &v);
    assert!(r.complete());
    let mut fresh = Renderer::new();
    fresh.render(&demo, &settings, &v);
    assert_eq!(pixels(&r), pixels(&fresh));
}

/// Two overlapping squares facing the camera, one behind the other, and a third square
/// facing away (culled).
fn squares() -> PreparedScene {
    let mut s = Scene::default();
    let quad = Mesh::cube(1.0).expect("cube");
    s.meshes.push(quad);
    s.materials.push(Material::default());
    for (x, z) in [(0.0, 0.0), (0.5, -1.0)] {
        s.instances.push(Instance {
            mesh: 0,
            world: Mat4::from_translation(Vec3::new(x, 0.0, z)),
            name: "cube".into(),
            style: Style::Inherit,
            node: None,
            skin: None,
            copies: None,
        });
    }
    PreparedScene::new(s)
}

#[test]
fn overdraw_counts_fragments_and_tile_costs_add_up() {
    let scene = squares();
    let cam = Camera {
        eye: Vec3::new(0.2, 0.0, 6.0),
        target: Vec3::new(0.2, 0.0, 0.0),
        ..Camera::default()
    };
    let v = view(&cam, 200, 150);
    let mut r = Renderer::new();
    let settings = Settings {
        output: Output::Overdraw,
        ..Settings::default()
    };
    r.render(&scene, &settings, &v);
    let target = r.target().expect("frame");
    let count = |x: u32, y: u32| target.pixel(x, y).expect("pixel").0.x;
    // Background counts nothing; a cube's front faces only (back faces culled): 1 where
    // one cube is seen, 2 where the front cube covers the back one.
    assert_eq!(count(0, 0), 0.0);
    let counts: Vec<f32> = (0..200).map(|x| count(x, 75)).collect();
    assert!(counts.contains(&1.0) && counts.contains(&2.0), "{counts:?}");
    assert!(
        counts.iter().all(|c| [0.0, 1.0, 2.0].contains(c)),
        "{counts:?}"
    );
    let total: f32 = (0..150)
        .flat_map(|y| (0..200).map(move |x| (x, y)))
        .map(|(x, y)| count(x, y))
        .sum();
    let stats = r.report().stats;
    assert_eq!(total as u64, stats.pixels_shaded);
    let costs: u64 = r.tile_costs().iter().map(|c| c.fragments).sum();
    assert_eq!(costs, stats.pixels_shaded);
    assert_eq!(r.tile_costs().len(), target.tiles.len());
    // The shaded image's costs add up too, and depth rejects fewer fragments than overdraw.
    r.render(&scene, &Settings::default(), &v);
    let shaded: u64 = r.tile_costs().iter().map(|c| c.fragments).sum();
    assert_eq!(shaded, r.report().stats.pixels_shaded);
    assert!(shaded <= stats.pixels_shaded);
    // The ramp: black, then blue-ish for one, brighter for more, white at 16.
    assert_eq!(render::overdraw_color(0.0), Vec4::new(0.0, 0.0, 0.0, 1.0));
    assert!(render::overdraw_color(1.0).z > 0.5);
    assert_eq!(render::overdraw_color(40.0), Vec4::ONE);
}

#[test]
fn picking_and_the_probe_agree_with_the_depth_and_normal_buffers() {
    let (setup, scene) = sphere_setup();
    let v = view(&setup.camera, W, H);
    let phong = Settings {
        shading: Some(Shading::Phong),
        ..Settings::default()
    };
    let normals = Settings {
        shading: Some(Shading::Normals),
        ..Settings::default()
    };
    let mut r = Renderer::new();
    let mut rn = Renderer::new();
    r.render(&scene, &phong, &v);
    rn.render(&scene, &normals, &v);
    let target = r.target().expect("frame");
    let mut checked = 0;
    for (x, y) in [(80, 60), (60, 40), (100, 80), (70, 90), (95, 35)] {
        let (color, depth) = target.pixel(x, y).expect("pixel");
        let p = r.pick(x, y).expect("on the sphere");
        // The unit sphere of 64 x 32 facets: the point lies between its facets and the
        // sphere.
        assert!((p.length() - 1.0).abs() < 3e-3, "pick {p}");
        let probe = render::probe(&scene, &phong, &v, x, y).expect("probe hits");
        assert!(
            (probe.depth - depth).abs() <= 1e-4 * depth,
            "probe depth {} vs buffer {depth}",
            probe.depth
        );
        assert!(
            (probe.position - p).length() < 1e-3,
            "{} vs {p}",
            probe.position
        );
        // The normal view shows n * 0.5 + 0.5 (sRGB-encoded): decode and compare.
        let shown = rn.target().expect("frame").pixel(x, y).expect("pixel").0;
        let decode = |c: f32| realist::texture::linear_to_srgb(c) * 2.0 - 1.0;
        let n = Vec3::new(decode(shown.x), decode(shown.y), decode(shown.z));
        assert!(
            (n - probe.normal).length() < 2e-3,
            "normal {n} vs {}",
            probe.normal
        );
        // The shares add up to the colour, which is what the Phong pass drew.
        let sum = probe
            .lights
            .iter()
            .fold(probe.ambient, |a, s| a + s.diffuse + s.specular);
        assert!((sum - probe.color).length() < 1e-6);
        assert!(
            (probe.color - color.truncate()).abs().max_element() < 2e-3,
            "probe {} vs pixel {color}",
            probe.color
        );
        assert_eq!(probe.lights.len(), 3, "the rig's key, fill and rim lights");
        assert!(probe.front && probe.mode == Shading::Phong);
        checked += 1;
    }
    assert_eq!(checked, 5);
    // A supersampled frame keeps the depth of the pixel centres (a last depth pass without
    // the passes' sub-pixel shifts), so picking and probing agree with it too.
    let mut ss = Renderer::new();
    ss.render(
        &scene,
        &Settings {
            samples: 4,
            ..phong.clone()
        },
        &v,
    );
    let (one, four) = (target, ss.target().expect("frame"));
    for (x, y) in [(80, 60), (60, 40), (100, 80)] {
        assert_eq!(one.pixel(x, y).map(|p| p.1), four.pixel(x, y).map(|p| p.1));
    }
    // Nothing there: no pick, no probe.
    assert_eq!(r.pick(0, 0), None);
    assert!(render::probe(&scene, &phong, &v, 0, 0).is_none());
}

#[test]
fn custom_lights_follow_the_camera_or_stay_in_the_world() {
    let (setup, scene) = sphere_setup();
    let v = view(&setup.camera, W, H);
    let head = Light::directional(-Vec3::Z, Vec3::ONE);
    let follow = Settings {
        lights: render::Lights::Custom {
            lights: vec![head.clone()],
            follow_camera: true,
        },
        ..Settings::default()
    };
    // A headlight: the sphere's centre pixel faces it, so it is lit at N.L = 1 (diffuse K_d).
    let centre = render::probe(&scene, &follow, &v, W / 2, H / 2).expect("centre");
    assert!(
        (centre.lights[0].diffuse.x - centre.base.x).abs() < 0.02 * centre.base.x,
        "{centre:?}"
    );
    // The same light in world space shines along -Z, which the camera (azimuth 35) does not.
    let world = Settings {
        lights: render::Lights::Custom {
            lights: vec![head],
            follow_camera: false,
        },
        ..Settings::default()
    };
    let p = render::probe(&scene, &world, &v, W / 2, H / 2).expect("centre");
    assert!(
        p.lights[0].diffuse.x < centre.lights[0].diffuse.x - 0.05,
        "{p:?}"
    );
}

/// A hidden instance (the viewer's hide and isolate) is drawn as if it were not in the
/// scene: no pixels, no shadow, not probed. `lit-stage.glb` is a ball over a floor lit by
/// a spotlight; the ball's shadow falls on the floor.
#[test]
fn a_hidden_instance_renders_as_if_removed_shadow_and_probe_included() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models/lit-stage.glb");
    let scene =
        realist::load::load(&path, &realist::load::LoadOptions::default()).expect("lit-stage");
    let ball = scene
        .instances
        .iter()
        .position(|i| i.name == "ball")
        .expect("a ball");
    let mut without = scene.clone();
    without.instances.remove(ball);
    for l in &mut without.lights {
        l.shadow = true;
    }
    let mut with = scene;
    for l in &mut with.lights {
        l.shadow = true;
    }
    let camera = with.cameras[0].clone();
    let v = view(&camera, W, H);
    let (with, without) = (PreparedScene::new(with), PreparedScene::new(without));
    let mut shown = Settings {
        lights: render::Lights::Auto,
        ..Settings::default()
    };
    let draw = |scene: &PreparedScene, settings: &Settings| {
        let mut r = Renderer::new();
        r.render(scene, settings, &v);
        pixels(&r)
    };
    let all = draw(&with, &shown);
    let mut hidden = shown.clone();
    hidden.hidden.set(ball, true);
    assert_eq!(hidden.hidden.count(), 1);
    let removed = draw(&without, &shown);
    let cut = draw(&with, &hidden);
    assert!(
        all.iter().zip(&removed).filter(|(a, b)| a != b).count() > 200,
        "the ball and its shadow show"
    );
    assert!(cut == removed, "hiding the ball draws the scene without it");
    // Isolating the floor is the same set; showing the ball again restores the frame.
    assert_eq!(
        render::Hidden::all_but(with.scene().instances.len(), [1 - ball]),
        hidden.hidden
    );
    hidden.hidden.set(ball, false);
    assert!(hidden.hidden.is_empty() && hidden.hidden == shown.hidden);
    // The probe at the ball's centre reads the ball, then (hidden) what lies behind it.
    let centre = (0..W * H)
        .filter(|&k| all[k as usize] != removed[k as usize])
        .find_map(|k| {
            let p = render::probe(&with, &shown, &v, k % W, k / W)?;
            (p.instance == ball).then_some(k)
        })
        .expect("a pixel of the ball");
    shown.hidden.set(ball, true);
    let behind = render::probe(&with, &shown, &v, centre % W, centre / W);
    assert!(
        behind.as_ref().is_none_or(|p| p.instance != ball),
        "{behind:?}"
    );
}

/// The probe on a skinned mesh (drawn from a posed copy of its rest mesh) names the scene's
/// mesh and material.
#[test]
fn the_probe_reads_a_skinned_mesh_and_names_its_scene_mesh() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models/anim/skin8.glb");
    let scene = realist::load::load(&path, &realist::load::LoadOptions::default()).expect("skin8");
    let mut prepared = PreparedScene::new(scene);
    prepared.pose_at(realist::scene::Play::All, 1.0, true);
    let (c, r) = prepared.bounding_sphere();
    let camera = Camera {
        eye: c + Vec3::new(0.0, 0.0, 3.0 * r),
        target: c,
        ..Camera::default()
    };
    let v = view(&camera, W, H);
    let settings = Settings::default();
    let mut r = Renderer::new();
    r.render(&prepared, &settings, &v);
    let px = pixels(&r);
    let bg = px[0];
    let k = (0..W * H)
        .find(|&k| px[k as usize] != bg)
        .expect("the bar is drawn");
    let p = render::probe(&prepared, &settings, &v, k % W, k / W).expect("the probe hits the bar");
    assert_eq!(p.mesh, 0, "the scene's mesh, not the posed copy");
    assert_eq!(p.material, prepared.scene().meshes[0].material);
}
