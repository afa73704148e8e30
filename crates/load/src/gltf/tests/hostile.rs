//! Broken and hostile documents: lying GLB headers, URIs that leave the folder, bad
//! indices and accessor ranges, unsupported versions and extensions.

use serde_json::json;

use super::*;
use crate::gltf::glb;

#[test]
fn glb_loads_and_a_lying_chunk_length_is_an_error() {
    let dir = TempDir::new("gltf-glb");
    let bin = f32_bytes(&TRI);
    let json = json!({"asset": {"version": "2.0"}, "buffers": [{"byteLength": 36}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}], "nodes": [{"mesh": 0}]});
    let bytes = glb::build(json.to_string().as_bytes(), Some(&bin));
    let scene = load(&dir.write("ok.glb", &bytes), &LoadOptions::default()).unwrap();
    assert_eq!(
        (scene.meshes.len(), scene.report.format.as_str()),
        (1, "GLB")
    );
    let mut lying = bytes;
    lying[12..16].copy_from_slice(&0xFFFF_FFF0u32.to_le_bytes());
    let path = dir.write("lying.GLB", &lying);
    let err = load(&path, &LoadOptions::default()).unwrap_err();
    assert!(
        matches!(err, LoadError::Gltf(crate::GltfError::Glb { .. })),
        "{err}"
    );
    assert!(
        err.to_string().starts_with(&format!(
            "{}: malformed GLB: chunk at byte 12 claims",
            path.display()
        )),
        "{err}"
    );
}

#[test]
fn buffer_uris_may_not_leave_the_folder() {
    let outer = TempDir::new("gltf-uri");
    outer.write("outside.bin", [0u8; 64]);
    let dir = TempDir(outer.0.join("model"));
    for (uri, expect) in [
        ("../outside.bin", "outside the model's folder"),
        ("file:///dev/zero", "scheme `file:`"),
        ("/dev/zero", "absolute"),
    ] {
        let text = json!({"asset": {"version": "2.0"}, "buffers": [{"byteLength": 36, "uri": uri}],
            "bufferViews": [{"buffer": 0, "byteLength": 36}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}], "nodes": [{"mesh": 0}]});
        let err = load_text(&dir, &text.to_string()).unwrap_err().to_string();
        assert!(
            err.contains("buffer 0: ") && err.contains(expect),
            "{uri}: {err}"
        );
    }
}

#[test]
fn bad_indices_and_ranges_are_errors_with_context() {
    let dir = TempDir::new("gltf-bad");
    let mut d = Doc::default();
    let tri = d.floats(&TRI, "VEC3");
    let ix = d.u8s(&[0, 1, 5], "SCALAR", false);
    let err = load_text(
        &dir,
        &d.finish(one_mesh_scene(
            json!([{"attributes": {"POSITION": tri}, "indices": ix}]),
        )),
    );
    let err = err.unwrap_err().to_string();
    assert!(
        err.ends_with(
            "mesh 0 primitive 0: index 5 at position 2 is out of range: there are 3 vertices"
        ),
        "{err}"
    );

    let mut d = Doc::default();
    let tri = d.floats(&TRI, "VEC3");
    d.accessors[tri]["count"] = json!(1000);
    let err = load_text(
        &dir,
        &d.finish(one_mesh_scene(json!([{"attributes": {"POSITION": tri}}]))),
    )
    .unwrap_err();
    assert!(
        err.to_string()
            .contains("accessor 0 (mesh 0 primitive 0 POSITION): needs 12000 bytes"),
        "{err}"
    );

    let mut d = Doc::default();
    let uv = d.u8s(&[0, 0, 1, 1, 2, 2], "VEC2", false);
    let err = load_text(
        &dir,
        &d.finish(one_mesh_scene(json!([{"attributes": {"POSITION": uv}}]))),
    )
    .unwrap_err();
    assert!(
        err.to_string().contains("has 2 components, expected [3]"),
        "{err}"
    );

    let err = load_text(&dir, r#"{"asset": {"version": "1.0"}}"#).unwrap_err();
    assert!(
        err.to_string()
            .ends_with("asset version 1.0 is not glTF 2.x"),
        "{err}"
    );
    let err = load_text(
        &dir,
        r#"{"asset": {"version": "2.0"}, "extensionsRequired": ["EXT_no_such_thing"]}"#,
    );
    assert!(err
        .unwrap_err()
        .to_string()
        .contains("requires extension EXT_no_such_thing"));
}

#[test]
fn mesh_quantization_allows_integer_positions() {
    let dir = TempDir::new("gltf-quant");
    let make = |extension: bool| {
        let mut d = Doc::default();
        let bytes: Vec<u8> = [0i16, 0, 0, 0, 2, 0, 0, 0, 0, -3, 0, 0]
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        let view = d.view(&bytes);
        d.views[view]["byteStride"] = json!(8);
        let pos = d.accessor(
            json!({"bufferView": view, "componentType": 5122, "count": 3, "type": "VEC3"}),
        );
        let mut rest = one_mesh_scene(json!([{"attributes": {"POSITION": pos}}]));
        if extension {
            rest["extensionsUsed"] = json!(["KHR_mesh_quantization"]);
            rest["extensionsRequired"] = json!(["KHR_mesh_quantization"]);
        }
        d.finish(rest)
    };
    let scene = load_text(&dir, &make(true)).unwrap();
    assert_eq!(
        scene.meshes[0].positions,
        [
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, -3.0, 0.0)
        ]
    );
    let err = load_text(&dir, &make(false)).unwrap_err().to_string();
    assert!(
        err.contains("component type I16 (normalized: false), expected FLOAT"),
        "{err}"
    );
}

#[test]
fn a_second_joint_set_of_the_wrong_length_leaves_the_mesh_unskinned() {
    // JOINTS_0/WEIGHTS_0 fit the three vertices, JOINTS_1/WEIGHTS_1 hold two: the
    // primitive loads unskinned with a warning (this panicked, found by the anim_pose fuzz
    // target: the weights were normalised with zero influences left).
    let mut d = Doc::default();
    let tri = d.floats(&TRI, "VEC3");
    let joints = d.u8s(&[0; 12], "VEC4", false);
    let weights = d.floats(&[1.0, 0.0, 0.0, 0.0].repeat(3), "VEC4");
    let joints1 = d.u8s(&[0; 8], "VEC4", false);
    let weights1 = d.floats(&[0.0; 8], "VEC4");
    let ibm = d.floats(&glam::Mat4::IDENTITY.to_cols_array(), "MAT4");
    let text = d.finish(json!({
        "meshes": [{"primitives": [{"attributes": {"POSITION": tri,
            "JOINTS_0": joints, "WEIGHTS_0": weights,
            "JOINTS_1": joints1, "WEIGHTS_1": weights1}}]}],
        "nodes": [{"mesh": 0, "skin": 0}, {}],
        "skins": [{"joints": [1], "inverseBindMatrices": ibm}],
        "scenes": [{"nodes": [0, 1]}], "scene": 0}));
    let scene = load_text(&TempDir::new("gltf-joint-sets"), &text).unwrap();
    assert_eq!(scene.meshes.len(), 1);
    assert!(
        scene.report.warnings.iter().any(|w| w
            .contains("JOINTS_1/WEIGHTS_1 have 2/2 elements but POSITION has 3")
            && w.contains("not skinned")),
        "{:?}",
        scene.report.warnings
    );
}
