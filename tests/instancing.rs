//! `EXT_mesh_gpu_instancing`: `models/pbr/instanced.glb` (written by glTF-Transform, see
//! `tests/pbr-models/make.mjs`) places twelve copies of one box; they must land where the
//! file's translations, rotations and scales say (computed here in f64), draw exactly as the
//! same boxes given as separate instances would, and be found by the probe. A million
//! copies (the same file with longer accessors) must load in under 1 GB and render at
//! 1080p.

mod common;

use std::path::Path;
use std::process::Command;

use glam::{DMat4, DQuat, DVec3, Vec3, Vec4};
use realist::render::{probe, Lights, PreparedScene, Settings, Shot, View};
use realist::scene::{Camera, Light, Scene};
use realist::shade::Shading;

fn instanced() -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/pbr/instanced.glb");
    realist::load::load(&path, &realist::load::LoadOptions::default())
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Copy `i`'s model -> world matrix as make.mjs defines it, in f64: the node's translation
/// (0, -0.5, 0) times T (c - 1.5, 0, -r), R (about +Y by 0.3 i), S (0.5 + 0.1 i; copy 5
/// mirrored in x).
fn expected(i: usize) -> DMat4 {
    let (r, c) = ((i / 4) as f64, (i % 4) as f64);
    let s = 0.5 + 0.1 * i as f64;
    let scale = if i == 5 {
        DVec3::new(-0.9, 0.9, 0.9)
    } else {
        DVec3::splat(s)
    };
    DMat4::from_translation(DVec3::new(0.0, -0.5, 0.0))
        * DMat4::from_scale_rotation_translation(
            scale,
            DQuat::from_rotation_y(0.3 * i as f64),
            DVec3::new(c - 1.5, 0.0, -r),
        )
}

/// The box's eight corners (side 0.4 around the origin).
fn corners() -> impl Iterator<Item = DVec3> {
    (0..8).map(|k| {
        let bit = |b: usize| if k & b == 0 { -0.2 } else { 0.2 };
        DVec3::new(bit(1), bit(2), bit(4))
    })
}

#[test]
fn copies_are_placed_as_the_file_says() {
    let scene = instanced();
    assert!(
        !scene
            .report
            .skipped
            .iter()
            .any(|s| s.contains("EXT_mesh_gpu_instancing")),
        "{:?}",
        scene.report.skipped
    );
    assert_eq!(scene.instances.len(), 1, "one node, one primitive");
    let inst = &scene.instances[0];
    assert_eq!(inst.copy_count(), 12);
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for i in 0..12 {
        let (got, want) = (inst.placement(i), expected(i));
        for c in corners() {
            let (g, w) = (
                got.transform_point3(c.as_vec3()).as_dvec3(),
                want.transform_point3(c),
            );
            assert!((g - w).length() < 1e-5, "copy {i} corner {c}: {g} vs {w}");
            lo = lo.min(w);
            hi = hi.max(w);
        }
    }
    let (blo, bhi) = scene.bounds().expect("bounds");
    assert!(
        (blo.as_dvec3() - lo).abs().max_element() < 1e-5,
        "{blo} vs {lo}"
    );
    assert!(
        (bhi.as_dvec3() - hi).abs().max_element() < 1e-5,
        "{bhi} vs {hi}"
    );
}

/// The scene with every copy made a separate instance (what a loader without the
/// extension's support in the renderer would build).
fn expanded(scene: &Scene) -> Scene {
    let mut out = scene.clone();
    out.instances = scene
        .instances
        .iter()
        .flat_map(|inst| {
            inst.placements().map(|world| realist::scene::Instance {
                world,
                copies: None,
                ..inst.clone()
            })
        })
        .collect();
    out
}

/// A view that leaves the nearest copies out of the frame (so some are culled one by one)
/// with a shadow-casting light: the culled copies still cast shadows.
fn shot(shading: Option<Shading>) -> Shot {
    let mut sun = Light::directional(Vec3::new(-0.4, -1.0, -0.3), Vec3::ONE);
    sun.shadow = true;
    Shot {
        width: 240,
        height: 160,
        camera: Some(Camera {
            eye: Vec3::new(0.8, 1.2, 1.0),
            target: Vec3::new(0.3, -0.5, -1.2),
            yfov: 0.9,
            ..Camera::default()
        }),
        settings: Settings {
            shading,
            lights: Lights::Custom {
                lights: vec![sun],
                follow_camera: false,
            },
            background: Vec4::new(0.0, 0.0, 0.0, 1.0),
            ..Settings::default()
        },
    }
}

#[test]
fn copies_draw_exactly_as_separate_instances_would() {
    let scene = instanced();
    let separate = expanded(&scene);
    assert_eq!(separate.instances.len(), 12);
    for shading in [
        None,
        Some(Shading::Flat),
        Some(Shading::Gouraud),
        Some(Shading::Phong),
        Some(Shading::Wireframe),
    ] {
        let opts = shot(shading);
        let (a, sa) = common::render_with(&scene, &opts, 2);
        let (b, sb) = common::render_with(&separate, &opts, 2);
        assert_eq!(sa.objects_culled, sb.objects_culled, "{shading:?}");
        assert!(
            sa.objects_culled > 0 && sa.objects_culled < 12,
            "{shading:?}: the view must cull some copies, not all: {}",
            sa.objects_culled
        );
        assert_eq!(sa.triangles_in, sb.triangles_in, "{shading:?}");
        let covered = a
            .color
            .iter()
            .filter(|c| c.truncate() != Vec3::ZERO)
            .count();
        assert!(covered > 2000, "{shading:?}: {covered} pixels drawn");
        let differ = a
            .color
            .iter()
            .zip(&b.color)
            .filter(|(x, y)| x.to_array().map(f32::to_bits) != y.to_array().map(f32::to_bits))
            .count();
        assert_eq!(differ, 0, "{shading:?}: {differ} pixels differ");
        assert!(a.depth == b.depth, "{shading:?}: depth differs");
    }
}

#[test]
fn the_probe_finds_the_copy_under_the_pixel() {
    let scene = instanced();
    let separate = expanded(&scene);
    let opts = shot(None);
    let (a, b) = (
        PreparedScene::new(scene.clone()),
        PreparedScene::new(separate.clone()),
    );
    let view: View = opts.view(a.scene());
    let mut hits = 0;
    for y in (0..opts.height).step_by(8) {
        for x in (0..opts.width).step_by(8) {
            let (p, q) = (
                probe(&a, &opts.settings, &view, x, y),
                probe(&b, &opts.settings, &view, x, y),
            );
            match (p, q) {
                (None, None) => {}
                (Some(p), Some(q)) => {
                    hits += 1;
                    assert_eq!(p.instance, 0, "({x}, {y})");
                    assert!((p.position - q.position).length() < 1e-5, "({x}, {y})");
                    assert!((p.normal - q.normal).length() < 1e-5, "({x}, {y})");
                    assert_eq!(p.front, q.front, "({x}, {y})");
                }
                (p, q) => panic!("({x}, {y}): {:?} vs {:?}", p.is_some(), q.is_some()),
            }
        }
    }
    assert!(hits > 20, "{hits} probes hit a copy");
}

/// instanced.glb with its three instancing accessors replaced by `n` copies in a square
/// grid one unit apart (the box's rotation and scale varying with the index), appended to
/// the binary chunk: the file's structure is glTF-Transform's, only the counts change.
fn forest(n: usize, dest: &Path) {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/pbr/instanced.glb");
    let bytes = std::fs::read(&src).expect("instanced.glb");
    let (mut json, bin_start) = common::glb_parts(&bytes);
    let bin_len = u32::from_le_bytes(bytes[bin_start - 8..bin_start - 4].try_into().unwrap());
    let mut bin = bytes[bin_start..bin_start + bin_len as usize].to_vec();
    let side = (n as f64).sqrt().ceil() as usize;
    let mut add = |json: &mut serde_json::Value, values: Vec<f32>, kind: &str| -> usize {
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let offset = bin.len();
        bin.extend(values.iter().flat_map(|v| v.to_le_bytes()));
        let views = json["bufferViews"].as_array_mut().unwrap();
        views.push(serde_json::json!({
            "buffer": 0, "byteOffset": offset, "byteLength": values.len() * 4
        }));
        let view = views.len() - 1;
        let accessor = serde_json::json!({
            "bufferView": view, "componentType": 5126, "count": n, "type": kind
        });
        let accessors = json["accessors"].as_array_mut().unwrap();
        accessors.push(accessor);
        accessors.len() - 1
    };
    let mut t = Vec::with_capacity(3 * n);
    let mut r = Vec::with_capacity(4 * n);
    let mut s = Vec::with_capacity(3 * n);
    for i in 0..n {
        t.extend([(i % side) as f32, 0.0, -((i / side) as f32)]);
        let half = (i % 97) as f32 * 0.03;
        r.extend([0.0, libm::sinf(half), 0.0, libm::cosf(half)]);
        s.extend([1.0 + (i % 5) as f32 * 0.2; 3]);
    }
    let (t, r, s) = (
        add(&mut json, t, "VEC3"),
        add(&mut json, r, "VEC4"),
        add(&mut json, s, "VEC3"),
    );
    let node = json["nodes"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .find(|n| n.get("extensions").is_some())
        .expect("the instanced node");
    node["extensions"]["EXT_mesh_gpu_instancing"]["attributes"] =
        serde_json::json!({"TRANSLATION": t, "ROTATION": r, "SCALE": s});
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    json["buffers"][0]["byteLength"] = bin.len().into();
    let mut text = serde_json::to_vec(&json).unwrap();
    while !text.len().is_multiple_of(4) {
        text.push(b' ');
    }
    let total = 12 + 8 + text.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((text.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(&text);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(&bin);
    std::fs::write(dest, out).expect("write the forest");
}

/// Most peak resident memory loading a million copies may take (the figure).
const LOAD_LIMIT_MB: f64 = 1000.0;

#[test]
fn a_million_copies_load_in_under_a_gigabyte_and_render_at_1080p() {
    let dir = common::temp_dir("forest");
    let file = dir.join("forest.glb");
    forest(1_000_000, &file);
    let png = dir.join("forest.png");
    let out = Command::new(env!("CARGO_BIN_EXE_realist"))
        .args(["render", "--size", "1920x1080", "--stats", "-o"])
        .arg(&png)
        .arg(&file)
        .output()
        .expect("run realist");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stats: serde_json::Value = serde_json::from_str(stdout.trim()).expect("stats JSON");
    eprintln!("a million copies at 1080p: {}", stats["ms"]);
    eprintln!("peak resident memory (MB): {}", stats["peak_mb"]);
    assert_eq!(stats["triangles_in"], 12_000_000, "{stats}");
    if let Some(load) = stats["peak_mb"]["load"].as_f64() {
        assert!(load < LOAD_LIMIT_MB, "loading took {load} MB");
    } else {
        eprintln!("the system does not report peak memory: not measured");
    }
    let img = image::open(&png).expect("the image").to_rgb8();
    assert_eq!((img.width(), img.height()), (1920, 1080));
    let bg = img.get_pixel(0, 0);
    let drawn = img.pixels().filter(|p| *p != bg).count();
    assert!(drawn > 100_000, "{drawn} pixels of boxes");
    let _ = std::fs::remove_dir_all(&dir);
}
