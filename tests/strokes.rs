//! Points and lines, and choosing a glTF scene:
//!
//! - golden images of the Khronos samples `MeshPrimitiveModes` (every primitive mode, at the
//!   default 1-pixel size and at 5-pixel points and 3-pixel lines) and `MultipleScenes`
//!   (both scenes, chosen by `LoadOptions::scene`), from
//!   `$REALIST_SHARED/models/gltf/khronos/` (reported as ignored when `REALIST_SHARED` is
//!   unset);
//! - a line behind a nearer triangle is hidden where the triangle covers it;
//! - a points and lines scene renders the same on 1 and 2 threads;
//! - OBJ `p` and `l` elements load as points and line segments;
//! - an out-of-range `--scene` is an error naming the file and the count.
//!
//! The pixel rules themselves are unit-tested in `src/raster/line.rs`, the modes' counts
//! and warnings in `src/load/gltf/primitive.rs`. The hidden-line test renders the line
//! alone first, so it sees the line in the columns the triangle later covers (the test
//! fails if the depth test lets it through).

mod common;

use std::path::PathBuf;

use glam::{Mat4, Vec3, Vec4};
use realist::load::{load, LoadError, LoadOptions};
use realist::mesh::{Mesh, MeshData, NormalPolicy};
use realist::render::{PreparedScene, Settings, Shot};
use realist::scene::{Camera, Instance, Material, Scene, Style};

/// Golden images with points, lines and PBR-shaded triangles: coverage is exact; shading
/// may move a code value on a few pixels between platforms' libm.
const STROKES: common::Tolerance = common::Tolerance {
    max_channel: 2,
    max_fraction: 0.002,
};

/// The Khronos sample `name` in the shared test data (for tests marked as needing it).
fn khronos(name: &str) -> PathBuf {
    realist_testkit::shared(name)
        .join("models/gltf/khronos")
        .join(name)
        .join(format!("{name}.gltf"))
}

/// Renders `scene` head-on (front view), framed on its bounds.
fn front(scene: Scene, w: u32, h: u32, point: f32, line: f32) -> realist::raster::Framebuffer {
    let p = PreparedScene::new(scene);
    let (lo, hi) = p.bounds().expect("bounds");
    let opts = Shot {
        width: w,
        height: h,
        camera: Some(Camera::frame_box(lo, hi, w as f32 / h as f32, 0.0, 0.0)),
        settings: Settings {
            point_size: point,
            line_width: line,
            ..Settings::default()
        },
    };
    common::render_prepared(&p, &opts.settings, &opts.view(p.scene()), 2).0
}

#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn mesh_primitive_modes_golden() {
    let path = khronos("MeshPrimitiveModes");
    let scene = load(&path, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    // Every mode is loaded: 7 meshes, 7 instances, the four point and line ones reported.
    assert_eq!((scene.meshes.len(), scene.instances.len()), (7, 7));
    let counts: Vec<(usize, usize)> = scene
        .meshes
        .iter()
        .map(|m| (m.points.len(), m.lines.len()))
        .collect();
    assert_eq!(&counts[..4], &[(7, 0), (0, 6), (0, 7), (0, 6)]);
    assert_eq!(scene.report.loaded.len(), 4, "{:?}", scene.report);
    assert!(
        scene.report.skipped.is_empty(),
        "{:?}",
        scene.report.skipped
    );
    for (name, point, line) in [
        ("MeshPrimitiveModes", 1.0, 1.0),
        ("MeshPrimitiveModes-wide", 5.0, 3.0),
    ] {
        let fb = front(scene.clone(), 240, 240, point, line);
        common::assert_finite(&fb, name);
        common::check_golden(&format!("strokes-{name}"), &fb, STROKES);
    }
}

#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn multiple_scenes_golden_and_choice() {
    let path = khronos("MultipleScenes");
    // The file's default scene is 1.
    let default = load(&path, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(default.graph.drawn, Some(1));
    assert_eq!(default.graph.scenes.len(), 2);
    for k in 0..2 {
        let opts = LoadOptions {
            scene: Some(k),
            ..LoadOptions::default()
        };
        let scene = load(&path, &opts).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(scene.graph.drawn, Some(k));
        assert_eq!(scene.instances.len(), 1);
        let fb = front(scene, 160, 120, 1.0, 1.0);
        common::check_golden(&format!("strokes-MultipleScenes-{k}"), &fb, STROKES);
    }
    let opts = LoadOptions {
        scene: Some(2),
        ..LoadOptions::default()
    };
    let err = load(&path, &opts).unwrap_err();
    assert!(
        matches!(
            err,
            LoadError::Scene {
                index: 2,
                count: 2,
                ..
            }
        ),
        "{err}"
    );
    let text = err.to_string();
    assert!(text.starts_with(&path.display().to_string()), "{text}");
    assert!(
        text.ends_with("there is no scene 2: the file has 2 scenes (0 to 1)"),
        "{text}"
    );
}

#[test]
fn only_gltf_has_more_than_one_scene() {
    let dir = common::temp_dir("strokes-scene");
    let path = dir.join("one.obj");
    std::fs::write(&path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let opts = |scene| LoadOptions {
        scene: Some(scene),
        ..LoadOptions::default()
    };
    assert!(load(&path, &opts(0)).is_ok());
    let err = load(&path, &opts(1)).unwrap_err().to_string();
    assert!(
        err.ends_with("one.obj: there is no scene 1: the file has 1 scene (number 0)"),
        "{err}"
    );
}

/// A mesh of only points and line segments (no facets, no normals: unlit) in `color`.
fn strokes_mesh(positions: Vec<Vec3>, points: Vec<u32>, lines: Vec<[u32; 2]>) -> Mesh {
    let data = MeshData {
        name: "strokes".into(),
        positions,
        ..MeshData::default()
    };
    let mut mesh = Mesh::new(data, NormalPolicy::Flat).expect("mesh");
    mesh.set_strokes(points, lines).expect("indices in range");
    mesh
}

/// A scene of `meshes`, mesh `i` with material `i` of base colour `colors[i]`.
fn scene(meshes: Vec<Mesh>, colors: &[Vec4]) -> Scene {
    let mut s = Scene::default();
    for (i, (mut m, c)) in meshes.into_iter().zip(colors).enumerate() {
        m.material = Some(i);
        s.materials.push(Material {
            base_color: *c,
            ..Material::default()
        });
        s.meshes.push(m);
        s.instances.push(Instance {
            mesh: i,
            world: Mat4::IDENTITY,
            name: format!("mesh {i}"),
            style: Style::Inherit,
            node: None,
            skin: None,
            copies: None,
        });
    }
    s
}

fn camera() -> Camera {
    let mut c = Camera {
        eye: Vec3::new(0.0, 0.0, 4.0),
        target: Vec3::ZERO,
        ..Camera::default()
    };
    c.fit(Vec3::ZERO, 1.8);
    c
}

fn is_red(c: Vec4) -> bool {
    c.x > 0.9 && c.y < 0.05 && c.z < 0.05
}

#[test]
fn a_line_behind_a_triangle_is_hidden() {
    let red = Vec4::new(1.0, 0.0, 0.0, 1.0);
    let green = Vec4::new(0.1, 0.8, 0.1, 1.0);
    let line = strokes_mesh(
        vec![Vec3::new(-1.5, 0.0, -0.5), Vec3::new(1.5, 0.0, -0.5)],
        Vec::new(),
        vec![[0, 1]],
    );
    let quad = common::triangles(
        vec![
            Vec3::new(-0.4, -0.4, 0.5),
            Vec3::new(0.4, -0.4, 0.5),
            Vec3::new(0.4, 0.4, 0.5),
            Vec3::new(-0.4, 0.4, 0.5),
        ],
        vec![0, 1, 2, 0, 2, 3],
    );
    let render = |s: &Scene| {
        let opts = Shot {
            width: 96,
            height: 64,
            camera: Some(camera()),
            ..Shot::default()
        };
        common::render_with(s, &opts, 2).0
    };
    let alone = render(&scene(vec![line.clone()], &[red]));
    let both = render(&scene(vec![line, quad], &[red, green]));
    let red_columns = |fb: &realist::raster::Framebuffer| -> Vec<u32> {
        (0..fb.width * fb.height)
            .filter(|&i| is_red(fb.color[i as usize]))
            .map(|i| i % fb.width)
            .collect()
    };
    let alone_cols = red_columns(&alone);
    // Unlit (no normals): exactly the base colour; one pixel per column it spans (about
    // half of the image's 96 at this distance).
    assert!(alone_cols.len() >= 45, "{}", alone_cols.len());
    let mut unique = alone_cols.clone();
    unique.dedup();
    assert_eq!(unique.len(), alone_cols.len(), "one pixel per column");
    let cols = red_columns(&both);
    let (lo, hi) = (both.width / 2 - 4, both.width / 2 + 4);
    assert!(alone_cols.iter().any(|c| (lo..hi).contains(c)));
    assert!(
        !cols.iter().any(|c| (lo..hi).contains(c)),
        "the line shows through: {cols:?}"
    );
    // Outside the quad it is still drawn.
    assert!(cols.len() > alone_cols.len() / 2, "{}", cols.len());
}

#[test]
fn one_and_two_threads_draw_the_same_points_and_lines() {
    // Many overlapping points and lines of different colours at different depths, so the
    // image depends on the order they are drawn in.
    let n = 400;
    let mut positions = Vec::new();
    for i in 0..n {
        let t = i as f32 / n as f32 * std::f32::consts::TAU * 3.0;
        positions.push(Vec3::new(
            libm::cosf(t) * (0.3 + i as f32 / n as f32),
            libm::sinf(t),
            libm::sinf(t * 0.7),
        ));
    }
    let lines: Vec<[u32; 2]> = (0..n as u32 - 7).map(|i| [i, i + 7]).collect();
    let points: Vec<u32> = (0..n as u32).collect();
    let meshes = vec![
        strokes_mesh(positions.clone(), points, Vec::new()),
        strokes_mesh(positions, Vec::new(), lines),
    ];
    let s = scene(
        meshes,
        &[Vec4::new(0.9, 0.8, 0.1, 1.0), Vec4::new(0.2, 0.4, 0.9, 1.0)],
    );
    let opts = Shot {
        width: 200,
        height: 150,
        camera: Some(camera()),
        settings: Settings {
            point_size: 3.0,
            line_width: 2.0,
            ..Settings::default()
        },
    };
    let (one, stats) = common::render_with(&s, &opts, 1);
    let (two, _) = common::render_with(&s, &opts, 2);
    assert!(
        stats.points_drawn > 300 && stats.lines_drawn > 300,
        "{stats:?}"
    );
    assert!(common::covered(&one) > 2000);
    assert_eq!(one.color, two.color);
    assert_eq!(one.depth, two.depth);
}

#[test]
fn obj_points_and_lines_load_and_draw() {
    let dir = common::temp_dir("strokes-obj");
    let path = dir.join("lines.obj");
    std::fs::write(
        &path,
        "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nv 0 0 0\no outline\nl 1 2 3 4 1\no dots\np 5 -1\n",
    )
    .unwrap();
    let scene = load(&path, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let strokes: Vec<(usize, usize)> = scene
        .meshes
        .iter()
        .map(|m| (m.points.len(), m.lines.len()))
        .collect();
    assert_eq!(strokes, vec![(0, 4), (2, 0)]);
    assert_eq!(scene.report.loaded.len(), 2, "{:?}", scene.report);
    assert!(
        scene.report.warnings.is_empty(),
        "{:?}",
        scene.report.warnings
    );
    // Bounds include the points' and lines' vertices.
    let (lo, hi) = scene.bounds().expect("bounds");
    assert_eq!(
        (lo, hi),
        (Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0))
    );
    let opts = Shot {
        width: 64,
        height: 64,
        ..Shot::default()
    };
    let (fb, stats) = common::render_with(&scene, &opts, 2);
    assert_eq!((stats.lines_drawn, stats.points_drawn), (4, 2));
    assert!(common::covered(&fb) > 100);
}
