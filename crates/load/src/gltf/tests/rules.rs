//! One test per hardening rule not already covered by `hostile.rs` and the module's other
//! tests: non-finite transforms and positions, camera planes, missing image sources, the
//! memory budget for geometry, attribute types and sparse counts.

use serde_json::json;

use super::*;

#[test]
fn overflowing_node_transforms_skip_the_node_with_a_warning() {
    let mut d = Doc::default();
    let tri = d.floats(&TRI, "VEC3");
    let text = d.finish(json!({
        "meshes": [{"primitives": [{"attributes": {"POSITION": tri}}]}],
        "nodes": [{"scale": [1e30, 1e30, 1e30], "children": [1]},
                  {"scale": [1e30, 1e30, 1e30], "mesh": 0},
                  {"mesh": 0, "translation": [1, 0, 0]}],
        "scenes": [{"nodes": [0, 2]}], "scene": 0}));
    let scene = load_text(&TempDir::new("gltf-inf-node"), &text).unwrap();
    assert_eq!(scene.instances.len(), 1, "only the finite node is drawn");
    assert!(scene.instances[0].world.is_finite());
    assert!(
        scene
            .report
            .warnings
            .iter()
            .any(|w| w == "node 1 has a non-finite transform; skipped with its children"),
        "{:?}",
        scene.report.warnings
    );
}

#[test]
fn non_finite_positions_drop_their_triangles() {
    let mut d = Doc::default();
    let mut pos = QUAD.to_vec();
    pos.extend_from_slice(&[f32::NAN, 0.0, 0.0]);
    let p = d.floats(&pos, "VEC3");
    let ix = d.u8s(&[0, 1, 2, 2, 1, 3, 1, 4, 3], "SCALAR", false);
    let text = d.finish(one_mesh_scene(
        json!([{"attributes": {"POSITION": p}, "indices": ix}]),
    ));
    let scene = load_text(&TempDir::new("gltf-nan-pos"), &text).unwrap();
    assert_eq!(scene.meshes[0].facets().len(), 2);
    assert!(scene.meshes[0].positions.iter().all(|p| p.is_finite()));
    assert!(
        scene
            .report
            .warnings
            .iter()
            .any(|w| w.contains("dropped 1 face(s) with NaN or infinite positions")),
        "{:?}",
        scene.report.warnings
    );
}

#[test]
fn camera_zfar_before_znear_is_warned_and_refitted() {
    let mut d = Doc::default();
    let tri = d.floats(&TRI, "VEC3");
    let text = d.finish(json!({
        "meshes": [{"primitives": [{"attributes": {"POSITION": tri}}]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 1.0, "zfar": 0.5}},
                    {"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.0}}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 0, 5]},
                  {"camera": 1, "translation": [0, 0, 5]}],
        "scenes": [{"nodes": [0, 1, 2]}], "scene": 0}));
    let scene = load_text(&TempDir::new("gltf-cam-planes"), &text).unwrap();
    assert_eq!(scene.cameras.len(), 1);
    let cam = &scene.cameras[0];
    assert!(cam.near < cam.far && cam.far.is_finite(), "{cam:?}");
    assert!(
        scene
            .report
            .warnings
            .iter()
            .any(|w| w.contains("zfar 0.5 is not beyond znear 1")),
        "{:?}",
        scene.report.warnings
    );
    assert!(
        scene
            .report
            .skipped
            .iter()
            .any(|s| s.contains("camera 1") && s.contains("znear 0")),
        "{:?}",
        scene.report.skipped
    );
}

#[test]
fn texture_without_a_usable_image_is_drawn_without_it() {
    let mut d = Doc::default();
    let tri = d.floats(&TRI, "VEC3");
    let text = d.finish(json!({
        "meshes": [{"primitives": [{"attributes": {"POSITION": tri}, "material": 0},
                                   {"attributes": {"POSITION": tri}, "material": 1}]}],
        "materials": [{"name": "a", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}},
                      {"name": "b", "pbrMetallicRoughness": {"baseColorTexture": {"index": 1}}}],
        "textures": [{"source": 7}, {"source": 0}],
        "images": [{"mimeType": "image/png"}],
        "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0}));
    let scene = load_text(&TempDir::new("gltf-no-image"), &text).unwrap();
    assert!(scene
        .materials
        .iter()
        .all(|m| m.base_color_texture.is_none()));
    let w = &scene.report.warnings;
    assert!(
        w.iter().any(|w| w.starts_with("image 7: does not exist")),
        "{w:?}"
    );
    assert!(
        w.iter()
            .any(|w| w.starts_with("image 0: has neither a uri nor a bufferView")),
        "{w:?}"
    );
}

#[test]
fn geometry_is_charged_to_the_memory_budget() {
    let mut d = Doc::default();
    let n = 30_000usize;
    let pos: Vec<f32> = (0..n * 3).map(|i| (i % 97) as f32).collect();
    let p = d.floats(&pos, "VEC3");
    let text = d.finish(one_mesh_scene(json!([{"attributes": {"POSITION": p}}])));
    let dir = TempDir::new("gltf-budget");
    let path = dir.write("model.gltf", &text);
    assert!(load(&path, &LoadOptions::default()).is_ok());
    // The file itself (~480 kB of base64) fits, the decoded and built mesh does not.
    let opts = LoadOptions {
        max_bytes: text.len() as u64 * 3,
        ..LoadOptions::default()
    };
    let err = load(&path, &opts).unwrap_err();
    assert!(matches!(err, LoadError::TooLarge { .. }), "{err}");
    let msg = err.to_string();
    assert!(
        msg.starts_with(&path.display().to_string()) && msg.contains("over the memory budget"),
        "{msg}"
    );
}

#[test]
fn attribute_types_are_checked_per_semantic() {
    let dir = TempDir::new("gltf-attr-types");
    for (semantic, ty, values) in [
        ("NORMAL", "VEC2", vec![0.0f32; 6]),
        ("TEXCOORD_0", "VEC3", vec![0.0; 9]),
        ("COLOR_0", "VEC2", vec![0.0; 6]),
    ] {
        let mut d = Doc::default();
        let tri = d.floats(&TRI, "VEC3");
        let a = d.floats(&values, ty);
        let text = d.finish(one_mesh_scene(
            json!([{"attributes": {"POSITION": tri, semantic: a}}]),
        ));
        let msg = match load_text(&dir, &text) {
            Err(e) => e.to_string(),
            Ok(scene) => scene.report.warnings.join(" | "),
        };
        assert!(
            msg.contains(semantic) && msg.contains("components"),
            "{semantic} as {ty}: {msg}"
        );
    }
    // POSITION as unsigned bytes without KHR_mesh_quantization.
    let mut d = Doc::default();
    let p = d.u8s(&[0, 0, 0, 1, 0, 0, 0, 1, 0], "SCALAR", false);
    d.accessors[p]["type"] = json!("VEC3");
    d.accessors[p]["count"] = json!(3);
    let err = load_text(
        &dir,
        &d.finish(one_mesh_scene(json!([{"attributes": {"POSITION": p}}]))),
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("POSITION"), "{err}");
}

#[test]
fn sparse_counts_and_indices_are_checked() {
    let dir = TempDir::new("gltf-sparse-bad");
    for (count, indices, expect) in [
        (
            5u32,
            vec![0u8, 1, 2, 0, 1],
            "sparse count 5 exceeds count 3",
        ),
        (
            1,
            vec![3u8],
            "sparse index 3 (entry 0) is not below count 3",
        ),
    ] {
        let mut d = Doc::default();
        let tri = d.floats(&TRI, "VEC3");
        let iv = d.view(&indices);
        let vv = d.view(&f32_bytes(&vec![9.0; 3 * indices.len()]));
        d.accessors[tri]["sparse"] = json!({"count": count,
            "indices": {"bufferView": iv, "componentType": 5121},
            "values": {"bufferView": vv}});
        let err = load_text(
            &dir,
            &d.finish(one_mesh_scene(json!([{"attributes": {"POSITION": tri}}]))),
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains(expect), "{err}");
    }
}
