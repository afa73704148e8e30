//! Materials: the core factors and textures, samplers and their filters,
//! `KHR_materials_variants`, and the `KHR_materials_*` extensions with their textures.

use glam::Vec4;

use super::*;
use crate::scene::AlphaMode;
use crate::texture::{Filter, Wrap};

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
