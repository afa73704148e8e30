use base64::Engine as _;
use glam::{Vec3, Vec4};
use serde_json::{json, Value};

use crate::scene::{AlphaMode, Scene};
use crate::tests::TempDir;
use crate::texture::{Filter, Wrap};
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
fn materials_textures_and_samplers() {
    let png_uri = png_uri([0, 255, 0, 255]);
    let mut d = Doc::default();
    let tri = d.floats(&TRI, "VEC3");
    let uv = d.u8s(&[0, 0, 255, 0, 0, 255], "VEC2", true);
    let text = d.finish(json!({
        "meshes": [{"primitives": [
            {"attributes": {"POSITION": tri, "TEXCOORD_0": uv}, "material": 0},
            {"attributes": {"POSITION": tri}, "material": 1},
            {"attributes": {"POSITION": tri}, "material": 2},
            {"attributes": {"POSITION": tri}}
        ]}],
        "nodes": [{"mesh": 0}],
        "materials": [
            {"pbrMetallicRoughness": {"baseColorFactor": [1, 0.5, 0.25, 1], "baseColorTexture": {"index": 0},
              "metallicFactor": 0, "roughnessFactor": 0.5}, "alphaMode": "MASK", "alphaCutoff": 0.3,
             "doubleSided": true, "emissiveFactor": [0.1, 0.2, 0.3]},
            {"pbrMetallicRoughness": {"baseColorTexture": {"index": 1}}, "alphaMode": "BLEND"},
            {"pbrMetallicRoughness": {"baseColorTexture": {"index": 2}}}
        ],
        "textures": [{"source": 0}, {"source": 0, "sampler": 0}, {"source": 1}],
        "samplers": [{"magFilter": 9728, "minFilter": 9728, "wrapS": 33071, "wrapT": 33648}],
        "images": [{"uri": png_uri}, {}]
    }));
    let scene = load_text(&TempDir::new("gltf-mat"), &text).unwrap();
    assert_eq!(
        scene.textures.len(),
        1,
        "one image decoded once; its two samplers belong to the slots"
    );
    let s = scene.materials[1].base_color_texture.unwrap().sampler;
    assert_eq!(
        (s.filter, s.wrap_u, s.wrap_v),
        (Filter::Nearest, Wrap::ClampToEdge, Wrap::MirroredRepeat)
    );
    // No sampler: the default, mipmapped.
    let s = scene.materials[0].base_color_texture.unwrap().sampler;
    assert_eq!(s.filter, Filter::Trilinear);
    let m = &scene.materials[0];
    assert_eq!(m.base_color, Vec4::new(1.0, 0.5, 0.25, 1.0));
    assert_eq!(
        (m.alpha_mode, m.double_sided, m.roughness),
        (AlphaMode::Mask(0.3), true, 0.5)
    );
    assert_eq!(m.emissive, Vec3::new(0.1, 0.2, 0.3));
    assert_eq!(m.base_color_texture.map(|t| t.texture), Some(0));
    assert_eq!(scene.materials[1].alpha_mode, AlphaMode::Blend);
    assert!(scene.materials[2].base_color_texture.is_none());
    let uvs = scene.meshes[0].uvs.first().unwrap();
    assert_eq!(uvs.values[1], glam::Vec2::new(1.0, 0.0));
    // A primitive without a material gets the specification's default (white, metallic 1,
    // roughness 1), added once after the file's own.
    let k = scene.meshes[3].material.expect("the default material");
    let d = &scene.materials[k];
    assert_eq!(
        (d.base_color, d.metallic, d.roughness, d.pbr.is_some()),
        (Vec4::ONE, 1.0, 1.0, true)
    );
    let w = scene.report.warnings.join("\n");
    assert!(
        w.contains("image 1: has neither a uri nor a bufferView"),
        "{w}"
    );
}

#[test]
fn sampler_filters_map_to_mipmapping() {
    let mut png = Vec::new();
    ::image::RgbaImage::from_pixel(2, 2, ::image::Rgba([0, 255, 0, 255]))
        .write_to(
            &mut std::io::Cursor::new(&mut png),
            ::image::ImageFormat::Png,
        )
        .unwrap();
    let png_uri = format!(
        "data:image/png;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&png)
    );
    const NEAREST: u32 = 9728;
    const LINEAR: u32 = 9729;
    // (magFilter, minFilter) -> filter; None = absent.
    let cases: [(Option<u32>, Option<u32>, Filter); 12] = [
        (None, None, Filter::Trilinear),
        (Some(NEAREST), None, Filter::Trilinear),
        (Some(LINEAR), None, Filter::Trilinear),
        (None, Some(9984), Filter::Trilinear),
        (None, Some(9985), Filter::Trilinear),
        (Some(NEAREST), Some(9986), Filter::Trilinear),
        (Some(LINEAR), Some(9987), Filter::Trilinear),
        (Some(NEAREST), Some(NEAREST), Filter::Nearest),
        (Some(NEAREST), Some(LINEAR), Filter::Nearest),
        (Some(LINEAR), Some(NEAREST), Filter::Bilinear),
        (None, Some(NEAREST), Filter::Bilinear),
        (Some(LINEAR), Some(LINEAR), Filter::Bilinear),
    ];
    let samplers: Vec<Value> = cases
        .iter()
        .map(|&(mag, min, _)| {
            let mut s = serde_json::Map::new();
            if let Some(m) = mag {
                s.insert("magFilter".into(), json!(m));
            }
            if let Some(m) = min {
                s.insert("minFilter".into(), json!(m));
            }
            Value::Object(s)
        })
        .collect();
    let n = cases.len();
    let mut d = Doc::default();
    let tri = d.floats(&TRI, "VEC3");
    let uv = d.u8s(&[0, 0, 255, 0, 0, 255], "VEC2", true);
    let primitives: Vec<Value> = (0..n)
        .map(|i| json!({"attributes": {"POSITION": tri, "TEXCOORD_0": uv}, "material": i}))
        .collect();
    let materials: Vec<Value> = (0..n)
        .map(|i| json!({"pbrMetallicRoughness": {"baseColorTexture": {"index": i}}}))
        .collect();
    let textures: Vec<Value> = (0..n).map(|i| json!({"source": 0, "sampler": i})).collect();
    let text = d.finish(json!({
        "meshes": [{"primitives": primitives}],
        "nodes": [{"mesh": 0}],
        "materials": materials,
        "textures": textures,
        "samplers": samplers,
        "images": [{"uri": png_uri}]
    }));
    let scene = load_text(&TempDir::new("gltf-filters"), &text).unwrap();
    assert_eq!(scene.textures.len(), 1, "one image");
    for (i, (mag, min, want)) in cases.iter().enumerate() {
        let got = scene.materials[i]
            .base_color_texture
            .unwrap()
            .sampler
            .filter;
        assert_eq!(got, *want, "magFilter {mag:?} minFilter {min:?}");
    }
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
mod rules;

/// `KHR_materials_variants` on a triangle primitive and on a LINES primitive: both meshes
/// keep their mappings (with the scene's material indices), and a mapping to a material
/// that does not exist is a warning, not a mapping.
#[test]
fn material_variants_map_triangles_and_lines() {
    let dir = TempDir::new("gltf-variants");
    let mut doc = Doc::default();
    let tri = doc.floats(&TRI, "VEC3");
    let line = doc.floats(&[0.0, 0.0, 0.0, 1.0, 1.0, 0.0], "VEC3");
    let rest = json!({
        "extensionsUsed": ["KHR_materials_variants"],
        "extensions": {"KHR_materials_variants": {"variants": [{"name": "a"}, {"name": "b"}]}},
        "materials": [{"name": "m0"}, {"name": "m1"}],
        "meshes": [{"primitives": [
            {"attributes": {"POSITION": tri}, "material": 0, "extensions": {"KHR_materials_variants": {"mappings": [
                {"material": 1, "variants": [0]}, {"material": 5, "variants": [1]}]}}},
            {"attributes": {"POSITION": line}, "mode": 1, "material": 0, "extensions": {"KHR_materials_variants": {"mappings": [
                {"material": 1, "variants": [1]}]}}}
        ]}],
        "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0
    });
    let scene = load_text(&dir, &doc.finish(rest)).unwrap();
    assert_eq!(scene.variants, ["a", "b"]);
    let name = |k: Option<usize>| k.map(|k| scene.materials[k].name.clone());
    let (t, l) = (&scene.meshes[0], &scene.meshes[1]);
    assert!(
        !t.corners.is_empty() && l.corners.is_empty(),
        "a triangle and a line"
    );
    assert_eq!(name(t.material_in(None)).as_deref(), Some("m0"));
    assert_eq!(name(t.material_in(Some(0))).as_deref(), Some("m1"));
    assert_eq!(
        name(t.material_in(Some(1))).as_deref(),
        Some("m0"),
        "material 5 does not exist"
    );
    assert_eq!(name(l.material_in(Some(1))).as_deref(), Some("m1"));
    assert_eq!(name(l.material_in(Some(0))).as_deref(), Some("m0"));
    assert!(
        scene
            .report
            .warnings
            .iter()
            .any(|w| w.contains("mapping 1: `material` is not one of the file's 2 materials")),
        "{:?}",
        scene.report.warnings
    );
    assert!(!scene
        .report
        .skipped
        .iter()
        .any(|s| s.contains("KHR_materials_variants")));
}

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

#[test]
fn material_extensions_and_their_textures_or_why_not() {
    let png_uri = png_uri([10, 20, 30, 40]);
    let mut d = Doc::default();
    let tri = d.floats(&TRI, "VEC3");
    let uv = d.u8s(&[0, 0, 255, 0, 0, 255], "VEC2", true);
    let text = d.finish(json!({
        "extensionsUsed": ["KHR_materials_iridescence", "KHR_materials_anisotropy", "KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_dispersion",
                           "KHR_materials_diffuse_transmission", "KHR_materials_clearcoat",
                           "KHR_materials_sheen", "KHR_materials_specular"],
        "meshes": [{"primitives": [
            {"attributes": {"POSITION": tri, "TEXCOORD_0": uv}, "material": 0},
            {"attributes": {"POSITION": tri, "TEXCOORD_0": uv}, "material": 1}
        ]}],
        "nodes": [{"mesh": 0}],
        "materials": [
            {"extensions": {
                "KHR_materials_iridescence": {"iridescenceFactor": 0.5, "iridescenceIor": 1.8,
                    "iridescenceThicknessMaximum": 300, "iridescenceTexture": {"index": 0},
                    "iridescenceThicknessTexture": {"index": 0, "texCoord": 0}},
                "KHR_materials_anisotropy": {"anisotropyStrength": 0.25, "anisotropyRotation": 1.5,
                    "anisotropyTexture": {"index": 0}},
                "KHR_materials_diffuse_transmission": {"diffuseTransmissionFactor": 0.75,
                    "diffuseTransmissionColorFactor": [1, 0.5, 0],
                    "diffuseTransmissionColorTexture": {"index": 0}},
                "KHR_materials_clearcoat": {"clearcoatFactor": 1,
                    "clearcoatNormalTexture": {"index": 0, "scale": 0.5}},
                "KHR_materials_sheen": {"sheenColorFactor": [1, 1, 1], "sheenRoughnessTexture": {"index": 0}},
                "KHR_materials_specular": {"specularColorTexture": {"index": 0,
                    "extensions": {"KHR_texture_transform": {"offset": [0.5, 0]}}}},
                "KHR_materials_transmission": {"transmissionFactor": 0.9, "transmissionTexture": {"index": 0}},
                "KHR_materials_volume": {"thicknessFactor": 0.3, "attenuationDistance": 2,
                    "attenuationColor": [0.5, 0.25, 1], "thicknessTexture": {"index": 0}},
                "KHR_materials_dispersion": {"dispersion": 1.5}
            }},
            {"extensions": {
                "KHR_materials_iridescence": {"iridescenceFactor": 2, "iridescenceIor": 0.5},
                "KHR_materials_anisotropy": {"anisotropyStrength": "strong"},
                "KHR_materials_clearcoat": {"clearcoatTexture": {"index": "zero"},
                    "clearcoatRoughnessTexture": {"index": 7}},
                "KHR_materials_diffuse_transmission": {"diffuseTransmissionColorFactor": [1, -1, 0]},
                "KHR_materials_volume": {"attenuationDistance": 0},
                "KHR_materials_dispersion": {"dispersion": -1}
            }}
        ],
        "textures": [{"source": 0}],
        "images": [{"uri": png_uri}]
    }));
    let scene = load_text(&TempDir::new("gltf-layers"), &text).unwrap();
    use crate::scene::Slot;
    let m = &scene.materials[0];
    let p = m.pbr.unwrap();
    assert_eq!(
        (p.iridescence, p.iridescence_ior, p.iridescence_thickness),
        (0.5, 1.8, [100.0, 300.0])
    );
    assert_eq!((p.anisotropy, p.anisotropy_rotation), (0.25, 1.5));
    assert_eq!(
        (p.diffuse_transmission, p.diffuse_transmission_color),
        (0.75, Vec3::new(1.0, 0.5, 0.0))
    );
    for slot in [
        Slot::Iridescence,
        Slot::IridescenceThickness,
        Slot::Anisotropy,
        Slot::DiffuseTransmissionColor,
        Slot::ClearcoatNormal,
        Slot::SheenRoughness,
        Slot::SpecularColor,
    ] {
        assert!(m.slot(slot).is_some(), "{slot:?}");
    }
    assert_eq!(
        (
            p.transmission,
            p.thickness,
            p.attenuation_distance,
            p.dispersion
        ),
        (0.9, 0.3, 2.0, 1.5)
    );
    assert_eq!(p.attenuation_color, Vec3::new(0.5, 0.25, 1.0));
    assert!(m.slot(Slot::Transmission).is_some() && m.slot(Slot::Thickness).is_some());
    assert_eq!(m.slot(Slot::ClearcoatNormal).unwrap().scale, 0.5);
    assert_eq!(
        m.slot(Slot::SpecularColor).unwrap().transform.offset,
        glam::Vec2::new(0.5, 0.0)
    );
    assert!(m.slot(Slot::Clearcoat).is_none() && m.slot(Slot::DiffuseTransmission).is_none());
    // The colour slots decode sRGB, the data slots not: one image, two textures.
    assert_eq!(scene.textures.len(), 2);
    assert!(
        scene.report.skipped.is_empty(),
        "{:?}",
        scene.report.skipped
    );
    // The second material: every bad value named, its default used, the file drawn.
    let p = scene.materials[1].pbr.unwrap();
    assert_eq!(
        (p.iridescence, p.iridescence_ior, p.anisotropy),
        (0.0, 1.3, 0.0)
    );
    assert_eq!(p.diffuse_transmission_color, Vec3::ONE);
    assert_eq!((p.attenuation_distance, p.dispersion), (f32::INFINITY, 0.0));
    let w = scene.report.warnings.join("\n");
    for needle in [
        "iridescenceFactor 2 is not a number in 0..=1",
        "iridescenceIor 0.5 is not a number in 1..=",
        "anisotropyStrength \"strong\"",
        "clearcoatTexture {\"index\":\"zero\"} is not a textureInfo",
        "clear-coat roughness texture: texture 7 does not exist",
        "diffuseTransmissionColorFactor [1,-1,0] is not three non-negative numbers",
        "attenuationDistance 0 is not a number in",
        "dispersion -1 is not a number in 0..=",
    ] {
        assert!(w.contains(needle), "{needle} not in:\n{w}");
    }
}
