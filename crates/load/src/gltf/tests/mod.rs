use base64::Engine as _;
use glam::Vec3;
use serde_json::{json, Value};

use crate::scene::Scene;
use crate::tests::TempDir;
use crate::{load, LoadError, LoadOptions};

/// Builds a glTF document whose single buffer is a base64 `data:` URI.
#[derive(Default)]
struct Doc {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Doc {
    fn view(&mut self, bytes: &[u8]) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        self.views
            .push(json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()}));
        self.bin.extend_from_slice(bytes);
        self.views.len() - 1
    }

    fn accessor(&mut self, a: Value) -> usize {
        self.accessors.push(a);
        self.accessors.len() - 1
    }

    fn floats(&mut self, v: &[f32], ty: &str) -> usize {
        let n = components(ty);
        let view = self.view(&f32_bytes(v));
        self.accessor(
            json!({"bufferView": view, "componentType": 5126, "count": v.len() / n, "type": ty}),
        )
    }

    fn u8s(&mut self, v: &[u8], ty: &str, normalized: bool) -> usize {
        let view = self.view(v);
        let n = components(ty);
        self.accessor(json!({"bufferView": view, "componentType": 5121, "count": v.len() / n, "type": ty, "normalized": normalized}))
    }

    /// The document text, with `rest` (meshes, nodes, ...) merged in.
    fn finish(self, mut rest: Value) -> String {
        let uri = format!(
            "data:application/octet-stream;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&self.bin)
        );
        let obj = rest.as_object_mut().unwrap();
        obj.insert("asset".into(), json!({"version": "2.0"}));
        obj.entry("buffers")
            .or_insert(json!([{"byteLength": self.bin.len(), "uri": uri}]));
        obj.insert("bufferViews".into(), Value::Array(self.views));
        obj.insert("accessors".into(), Value::Array(self.accessors));
        rest.to_string()
    }
}

/// Components of an accessor type.
fn components(ty: &str) -> usize {
    match ty {
        "SCALAR" => 1,
        "VEC2" => 2,
        "VEC3" => 3,
        "MAT4" => 16,
        _ => 4,
    }
}

fn f32_bytes(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

const QUAD: [f32; 12] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0];
const TRI: [f32; 9] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];

fn load_text(dir: &TempDir, text: &str) -> Result<Scene, LoadError> {
    load(&dir.write("model.gltf", text), &LoadOptions::default())
}

/// A `data:` URI of a 2 x 2 PNG of one colour.
fn png_uri(rgba: [u8; 4]) -> String {
    let mut png = Vec::new();
    ::image::RgbaImage::from_pixel(2, 2, ::image::Rgba(rgba))
        .write_to(
            &mut std::io::Cursor::new(&mut png),
            ::image::ImageFormat::Png,
        )
        .unwrap();
    format!(
        "data:image/png;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&png)
    )
}

fn one_mesh_scene(primitives: Value) -> Value {
    json!({"meshes": [{"primitives": primitives}], "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0})
}

#[test]
fn strips_and_fans_wind_counter_clockwise_with_u8_indices() {
    let mut d = Doc::default();
    let quad = d.floats(&QUAD, "VEC3");
    let ix = d.u8s(&[0, 1, 2, 3], "SCALAR", false);
    let fan = d.floats(
        &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0],
        "VEC3",
    );
    let text = d.finish(one_mesh_scene(json!([
        {"attributes": {"POSITION": quad}, "indices": ix, "mode": 5},
        {"attributes": {"POSITION": fan}, "mode": 6},
        {"attributes": {"POSITION": quad}, "mode": 1}
    ])));
    let scene = load_text(&TempDir::new("gltf-strip"), &text).unwrap();
    // The strip and the fan become two triangles each; the LINES primitive two segments.
    assert_eq!(scene.meshes.len(), 3);
    assert_eq!(scene.instances.len(), 3);
    for mesh in &scene.meshes[..2] {
        assert_eq!(mesh.facets().len(), 2);
        assert!(
            mesh.facets().iter().all(|f| f.normal.z > 0.99),
            "{:?}",
            mesh.facets()
        );
    }
    let lines = &scene.meshes[2];
    assert!((lines.facet_count() == 0));
    assert_eq!(lines.lines, [[0, 1], [2, 3]]);
    assert!(
        scene
            .report
            .loaded
            .iter()
            .any(|s| s.contains("2 line segments (LINES)")),
        "{:?}",
        scene.report.loaded
    );
    // Flat normals for the two triangle meshes (the lines are unlit: no NORMAL).
    assert!(
        scene.report.generated.len() >= 2,
        "{:?}",
        scene.report.generated
    );
}

#[test]
fn sparse_accessors_and_accessors_without_buffer_view() {
    let mut d = Doc::default();
    let sparse_ix = d.view(&[1, 2]);
    let sparse_val = d.view(&f32_bytes(&[1.0, 0.0, 0.0, 0.0, 1.0, 0.0]));
    let zeros = d.accessor(
        json!({"componentType": 5126, "count": 3, "type": "VEC3", "sparse": {
        "count": 2, "indices": {"bufferView": sparse_ix, "componentType": 5121},
        "values": {"bufferView": sparse_val}}}),
    );
    let base = d.view(&f32_bytes(&[0.0, 0.0, 0.0, 5.0, 5.0, 5.0, 0.0, 1.0, 0.0]));
    let one_ix = d.view(&[1]);
    let patched = d.accessor(
        json!({"bufferView": base, "componentType": 5126, "count": 3, "type": "VEC3",
        "sparse": {"count": 1, "indices": {"bufferView": one_ix, "componentType": 5121},
        "values": {"bufferView": sparse_val}}}),
    );
    let text = d.finish(one_mesh_scene(json!([
        {"attributes": {"POSITION": zeros}}, {"attributes": {"POSITION": patched}}
    ])));
    let scene = load_text(&TempDir::new("gltf-sparse"), &text).unwrap();
    let expected = [Vec3::ZERO, Vec3::X, Vec3::Y];
    assert_eq!(scene.meshes[0].positions, expected);
    assert_eq!(scene.meshes[1].positions, expected);
}

#[test]
fn node_transforms_compose_and_mirroring_is_left_to_the_renderer() {
    let mut d = Doc::default();
    let tri = d.floats(&TRI, "VEC3");
    let text = d.finish(json!({
        "meshes": [{"primitives": [{"attributes": {"POSITION": tri}}]}],
        "nodes": [
            {"translation": [1, 0, 0], "scale": [2, 2, 2], "children": [1]},
            {"translation": [0, 1, 0], "mesh": 0, "name": "child"},
            {"scale": [-1, 1, 1], "mesh": 0},
            {"matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 5, 1], "mesh": 0}
        ],
        "scenes": [{"nodes": [0, 2, 3]}]
    }));
    let scene = load_text(&TempDir::new("gltf-nodes"), &text).unwrap();
    assert_eq!(scene.meshes.len(), 1, "one mesh shared by three instances");
    let [child, mirrored, moved] = &scene.instances[..] else {
        panic!("{:?}", scene.instances)
    };
    assert_eq!(child.name, "child");
    assert!(
        child
            .world
            .transform_point3(Vec3::ZERO)
            .distance(Vec3::new(1.0, 2.0, 0.0))
            < 1e-6
    );
    assert!(mirrored.world.determinant() < 0.0);
    assert_eq!(
        moved.world.transform_point3(Vec3::ZERO),
        Vec3::new(0.0, 0.0, 5.0)
    );
}

#[test]
fn cycles_and_deep_chains_end() {
    let mut d = Doc::default();
    let tri = d.floats(&TRI, "VEC3");
    let mut nodes = vec![
        json!({"children": [1], "mesh": 0}),
        json!({"children": [0], "mesh": 0}),
    ];
    nodes.extend((2..1200).map(|i| json!({"children": [i + 1]})));
    nodes.push(json!({"mesh": 0}));
    let text = d.finish(json!({
        "meshes": [{"primitives": [{"attributes": {"POSITION": tri}}]}],
        "nodes": nodes,
        "scenes": [{"nodes": [0, 2]}]
    }));
    let scene = load_text(&TempDir::new("gltf-cycle"), &text).unwrap();
    assert_eq!(scene.instances.len(), 2);
    let w = scene.report.warnings.join("\n");
    assert!(w.contains("node 0 is reached twice"), "{w}");
    assert!(w.contains("deeper than 1024 levels"), "{w}");
}

#[test]
fn cameras_come_from_their_nodes() {
    let mut d = Doc::default();
    let tri = d.floats(&TRI, "VEC3");
    let text = d.finish(json!({
        "meshes": [{"primitives": [{"attributes": {"POSITION": tri}}]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}},
                    {"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 1, "znear": 0.1, "zfar": 10}}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 0, 5]}, {"camera": 1}]
    }));
    let scene = load_text(&TempDir::new("gltf-camera"), &text).unwrap();
    assert_eq!(
        scene.instances.len(),
        1,
        "all root nodes are drawn when there is no scene"
    );
    let [cam, ortho] = &scene.cameras[..] else {
        panic!("{:?}", scene.cameras)
    };
    assert_eq!(
        (cam.eye, cam.target, cam.up, cam.yfov, cam.ortho),
        (
            Vec3::new(0.0, 0.0, 5.0),
            Vec3::new(0.0, 0.0, 4.0),
            Vec3::Y,
            0.8,
            None
        )
    );
    assert!(cam.far.is_finite() && cam.far > 5.0, "{}", cam.far);
    assert_eq!(
        (ortho.ortho, ortho.near, ortho.far, ortho.aspect),
        (Some(1.0), 0.1, 10.0, Some(1.0))
    );
    assert!(
        scene.report.skipped.is_empty(),
        "{:?}",
        scene.report.skipped
    );
}

mod hostile;
mod lights;
mod materials;
mod rules;

#[test]
fn gpu_instancing_reads_copies_or_says_why_not() {
    let dir = TempDir::new("gltf-instancing");
    let mut doc = Doc::default();
    let tri = doc.floats(&TRI, "VEC3");
    let t = doc.floats(&[1.0, 0.0, 0.0, 0.0, 2.0, 0.0, f32::NAN, 0.0, 0.0], "VEC3");
    let s = doc.floats(&[2.0, 2.0, 2.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0], "VEC3");
    let short = doc.floats(&[1.0, 1.0, 1.0], "VEC3");
    // A quarter turn about +Z as normalized signed bytes (KHR_mesh_quantization's form).
    let view = doc.view(&[0, 0, 90, 90, 0, 0, 0, 127, 0, 0, 0, 127]);
    let r = doc.accessor(
        json!({"bufferView": view, "componentType": 5120, "normalized": true, "count": 3, "type": "VEC4"}),
    );
    let node = |attributes: Value| {
        json!({"mesh": 0, "translation": [0.0, 0.0, 5.0],
               "extensions": {"EXT_mesh_gpu_instancing": {"attributes": attributes}}})
    };
    let rest = json!({
        "extensionsUsed": ["EXT_mesh_gpu_instancing"],
        "extensionsRequired": ["EXT_mesh_gpu_instancing"],
        "meshes": [{"primitives": [{"attributes": {"POSITION": tri}}]}],
        "nodes": [
            node(json!({"TRANSLATION": t, "ROTATION": r, "SCALE": s})),
            node(json!({"TRANSLATION": t, "SCALE": short})),
            node(json!({"TRANSLATION": "zero"})),
            node(json!({"SCALE": 99})),
            node(json!({"_ID": t})),
        ],
        "scenes": [{"nodes": [0, 1, 2, 3, 4]}], "scene": 0
    });
    let scene = load_text(&dir, &doc.finish(rest)).expect("a required extension realist reads");
    let copies: Vec<usize> = scene.instances.iter().map(|i| i.copy_count()).collect();
    assert_eq!(copies, [2, 1, 1, 1, 1], "{:?}", scene.report.warnings);
    let first = &scene.instances[0];
    // Copy 0: translated by (1, 0, 0), scaled by 2, a quarter turn about +Z, under the
    // node's (0, 0, 5): the triangle's corner (1, 0, 0) lands at (1, 2, 5).
    let p = first.placement(0).transform_point3(Vec3::X);
    assert!((p - Vec3::new(1.0, 2.0, 5.0)).length() < 0.02, "{p}");
    // Copy 1: not turned (the identity quaternion), translated by (0, 2, 0).
    let p = first.placement(1).transform_point3(Vec3::X);
    assert!((p - Vec3::new(1.0, 2.0, 5.0)).length() < 1e-6, "{p}");
    let warned = |what: &str| scene.report.warnings.iter().any(|w| w.contains(what));
    let all = &scene.report.warnings;
    assert!(
        warned("1 of 3 copies have a non-finite transform"),
        "{all:?}"
    );
    assert!(warned("accessor 3 has 1, not 3"), "{all:?}");
    assert!(warned("TRANSLATION is not an accessor index"), "{all:?}");
    assert!(warned("is unusable"), "{all:?}");
    assert!(
        warned("has none of TRANSLATION, ROTATION and SCALE"),
        "{all:?}"
    );
    assert!(all
        .iter()
        .all(|w| !w.contains("non-finite") || w.contains("left out")));
    for inst in &scene.instances[1..] {
        assert_eq!(inst.placement(0), inst.world, "drawn once, at the node");
    }
}
