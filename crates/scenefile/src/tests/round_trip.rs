//! Saving and reading back: every setting in TOML and JSON, model paths rebased, shortest
//! numbers, and generated texture coordinates.

use std::sync::Arc;

use glam::{Vec2, Vec3, Vec4};

use super::*;
use crate::render::{Ground, Lights, Output, ToneMap};
use crate::scene::{
    AlphaMode, Attenuation, Light, Slot, SlotOverride, SlotOverrides, TextureSource,
};
use crate::shade::{Fog, FogDistance, Shading, ShadowSettings};
use crate::texture::{Filter, Texture};
use realist_testkit::TempDir;

/// Settings with every field away from its default, as a viewer might have them.
fn everything(dir: &TempDir) -> (Settings, View) {
    let png = dir.0.join("slide.png");
    image::RgbaImage::from_fn(4, 2, |x, y| {
        image::Rgba([x as u8 * 60, y as u8 * 100, 7, 255])
    })
    .save(&png)
    .unwrap();
    let image = convert::image(&png).unwrap();
    let scene = crate::scene::demo();
    let mut materials = scene.materials.clone();
    materials[0].shininess = 123.5;
    materials[1].alpha_mode = AlphaMode::Mask(0.3);
    materials[1].base_color = Vec4::new(0.1, 0.2, 0.3, 0.4);
    materials[2].alpha_mode = AlphaMode::Blend;
    materials[2].double_sided = true;
    materials[2].specular = Vec3::new(0.7, 0.1, 0.9);
    materials[2].ambient = Vec3::splat(0.33);
    let lights = vec![
        Light::ambient(Vec3::splat(0.1)).with_name("amb"),
        Light::directional(Vec3::new(0.1, -1.0, 0.2), Vec3::ONE).with_shadow(true),
        Light::point(Vec3::new(1.0, 2.0, 3.0), Vec3::new(0.9, 0.8, 0.7))
            .with_attenuation(Attenuation::Linear {
                near: 0.5,
                far: 7.25,
            })
            .with_intensity(3.3),
        Light::spot(Vec3::Y * 4.0, Vec3::NEG_Y, Vec3::ONE, 0.123, 0.456)
            .with_attenuation(Attenuation::InverseSquare),
        Light::rect(
            Vec3::X,
            Vec3::NEG_X,
            Vec3::Z,
            Vec2::new(0.3, 0.2),
            Vec3::ONE,
        )
        .with_attenuation(Attenuation::Range(12.5))
        .with_image(image.clone())
        .with_shadow(true),
    ];
    let settings = Settings {
        shading: Some(Shading::Blinn),
        wireframe_overlay: true,
        output: Output::Overdraw,
        background: Vec4::new(0.1, 0.2, 0.3, 0.9),
        double_sided: true,
        subpixel_bits: 4,
        slots: {
            let mut slots = SlotOverrides::default();
            slots.set(
                Slot::BaseColor,
                Some(SlotOverride::source(TextureSource::Image(image), 1.0)),
            );
            let (noise, _) =
                TextureSource::bump_from_spec("noise:0.25", |_, _| Err::<Arc<Texture>, _>(""))
                    .unwrap();
            slots.set(Slot::Bump, Some(SlotOverride::source(noise, 0.125)));
            slots.set(Slot::Normal, Some(SlotOverride::Off));
            slots
        },
        filter: Some(Filter::Anisotropic(8)),
        lights: Lights::Custom {
            lights,
            follow_camera: true,
        },
        materials: Some(materials),
        samples: 3,
        msaa: 4,
        ray_depth: 12,
        kernel: None,
        fog: Some(Fog {
            color: Vec3::new(0.5, 0.6, 0.7),
            near: 1.5,
            far: 9.75,
            distance: FogDistance::Depth,
        }),
        environment: crate::render::Environment::Auto,
        single_scatter: true,
        sections: crate::render::Sections {
            planes: vec![
                Vec4::new(0.0, 0.0, 1.0, -0.25),
                Vec4::new(-1.0, 0.0, 0.0, 0.5),
            ],
            cap: Some(Vec3::new(0.25, 0.5, 0.75)),
        },
        env_background: None,
        exposure: -1.5,
        tone: ToneMap::ScaleMax,
        shadow: ShadowSettings {
            size: 512,
            pcf: 3,
            bias: 0.7,
            slope: 2.1,
        },
        ground: Some(Ground {
            color: Vec3::new(0.2, 0.3, 0.1),
            extent: 6.5,
        }),
        vertex_lighting: crate::render::VertexLighting::GL,
        hidden: {
            let mut h = crate::render::Hidden::default();
            h.set(2, true);
            h.set(3, true);
            h
        },
        // `material_variant`: checked against a model that has variants in
        // `a_material_variant_is_read_checked_and_written_by_name`.
        variant: None,
        // Not in scene files (yet): the defaults survive the round trip.
        point_size: 1.0,
        line_width: 1.0,
    };
    let view = View {
        camera: crate::scene::Camera {
            name: "scene file".into(),
            eye: Vec3::new(1.1, 2.2, 3.3),
            target: Vec3::new(0.1, -0.2, 0.3),
            up: Vec3::new(0.0, 1.0, 0.1),
            yfov: 0.777,
            near: 0.0123,
            far: 98.7,
            aspect: None,
            ortho: Some(2.5),
            lens: Default::default(),
        },
        width: 321,
        height: 123,
    };
    (settings, view)
}

#[test]
fn saved_settings_read_back_the_same_in_toml_and_json() {
    let dir = TempDir::new("scenefile-round-trip");
    let (settings, view) = everything(&dir);
    let (mut file, notes) = SceneFile::from_settings(&ModelSource::Demo, 1.0, &settings, &view);
    assert!(notes.is_empty(), "{notes:?}");
    for name in ["sub/exp.toml", "exp.json"] {
        let path = dir.0.join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        file.save(&path).unwrap();
        let loaded = SceneFile::load(&path).unwrap();
        assert_eq!(loaded.settings, settings, "{name}");
        assert_eq!(loaded.view, view, "{name}");
        assert_eq!(loaded.model, ModelSource::Demo);
        let text = std::fs::read_to_string(&path).unwrap();
        // Paths are written relative to the file, angles in degrees.
        let slide = if name.starts_with("sub/") {
            "../slide.png"
        } else {
            "slide.png"
        };
        assert!(text.contains(slide), "{text}");
        let inner = format!("{}", export::tidy_degrees(0.456));
        assert!(
            inner.starts_with("26.12") && text.contains(&inner),
            "{inner}: {text}"
        );
    }
}

#[test]
fn model_paths_are_rebased_when_saved_elsewhere() {
    let dir = TempDir::new("scenefile-rebase");
    let model = dir.write("models/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    dir.write(
        "scenes/a.toml",
        "model = \"../models/tri.obj\"\nlight_scale = 0.5\n",
    );
    let loaded = SceneFile::load(&dir.0.join("scenes/a.toml")).unwrap();
    assert_eq!(
        loaded.model,
        ModelSource::File(dir.0.join("scenes/../models/tri.obj"))
    );
    let mut file = loaded.file;
    file.save(&dir.0.join("b.json")).unwrap();
    let text = std::fs::read_to_string(dir.0.join("b.json")).unwrap();
    assert!(text.contains("\"model\": \"models/tri.obj\""), "{text}");
    let again = SceneFile::load(&dir.0.join("b.json")).unwrap();
    assert_eq!(again.scene.meshes.len(), 1);
    let (exported, _) =
        SceneFile::from_settings(&ModelSource::File(model), 0.5, &again.settings, &again.view);
    assert_eq!(exported.doc.light_scale, Some(0.5));
}

#[test]
fn shortest_numbers_read_back_exactly() {
    for v in [0.1f32, 1.0 / 3.0, 123.456, 1e-7, 3.0e7] {
        assert_eq!(export::tidy(v) as f32, v);
    }
    for deg in [20.0f64, 0.5, 33.3, 89.0] {
        let rad = deg.to_radians() as f32;
        let back = export::tidy_degrees(rad);
        assert_eq!(back.to_radians() as f32, rad);
        assert!((back - deg).abs() < 1e-4, "{deg} -> {back}");
    }
    assert_eq!(export::tidy_degrees(20f64.to_radians() as f32), 20.0);
}

#[test]
fn uv_key_generates_texture_coordinates_and_reads_back() {
    use crate::texture::{Axis, UvGenerator};
    // Every generator's name reads back to itself, and "mesh" to none.
    let mut names = vec!["mesh".to_string()];
    names.extend(UvGenerator::PRESETS.iter().map(|g| g.to_string()));
    names.extend(["cylindrical:x", "spherical:z"].map(String::from));
    for name in &names {
        let file = toml(&format!("model = \"demo\"\nuv = \"{name}\"\n")).unwrap();
        let kw = file.doc.uv.expect(name).0;
        assert_eq!(schema::Keyword::keyword(kw), name.as_str());
        assert_eq!(
            file.uv().map(|g| g.to_string()),
            (name != "mesh").then(|| name.clone())
        );
    }
    let e = err("model = \"demo\"\nuv = \"spherical:w\"\n");
    assert!(
        e.starts_with("dir/exp.toml: line 2") && e.contains("unknown uv 'spherical:w'"),
        "{e}"
    );
    let e = err("model = \"demo\"\nuv = 3\n");
    assert!(e.starts_with("dir/exp.toml: line 2"), "{e}");

    // A primitive's own UVs are replaced by the file's generator, and the report says so.
    let dir = TempDir::new("scenefile-uv");
    let path = dir.write(
        "s.toml",
        "uv = \"planar:z\"\n[primitive]\nshape = \"sphere\"\nslices = 8\nstacks = 4\n",
    );
    let loaded = SceneFile::load(&path).unwrap();
    let mesh = &loaded.scene.meshes[0];
    assert_eq!(mesh.uvs.len(), 1);
    let expected = crate::mesh::generate_uvs(mesh, &UvGenerator::Planar { axis: Axis::Z });
    assert_eq!(mesh.uvs[0], expected);
    assert!(
        loaded
            .scene
            .report
            .generated
            .iter()
            .any(|g| g.contains("planar:z") && g.contains("§9.5")),
        "{:?}",
        loaded.scene.report.generated
    );
    // The caller's generator wins over the file's; "mesh" keeps the primitive's UVs.
    let file = SceneFile::read(&path).unwrap();
    let opts = LoadOptions {
        uv: Some(UvGenerator::Box),
        ..LoadOptions::default()
    };
    let boxed = file.load_model(&opts).unwrap();
    assert_eq!(
        boxed.meshes[0].uvs[0],
        crate::mesh::generate_uvs(&boxed.meshes[0], &UvGenerator::Box)
    );
    let mut own = file.clone();
    own.doc.uv = Some(schema::Kw(schema::UvChoice::Mesh));
    let own = own.load_model(&LoadOptions::default()).unwrap();
    let plain = crate::mesh::Mesh::sphere(1.0, 8, 4).unwrap();
    assert_eq!(own.meshes[0].uvs, plain.uvs);
    assert!(own.report.generated.is_empty());

    // Exported: set_uv writes the key, which reads back; None leaves the model's own.
    let (mut out, _) = SceneFile::from_settings(&loaded.model, 1.0, &loaded.settings, &loaded.view);
    assert_eq!(out.uv(), None);
    out.set_uv(Some(UvGenerator::Cylindrical { axis: Axis::X }));
    for name in ["e.toml", "e.json"] {
        out.save(&dir.0.join(name)).unwrap();
        let back = SceneFile::read(&dir.0.join(name)).unwrap();
        assert_eq!(
            back.uv(),
            Some(UvGenerator::Cylindrical { axis: Axis::X }),
            "{name}"
        );
        let text = std::fs::read_to_string(dir.0.join(name)).unwrap();
        assert!(text.contains("cylindrical:x"), "{text}");
    }
    out.set_uv(None);
    assert_eq!(out.doc.uv, None);
}
