use std::path::Path;

use glam::{Vec2, Vec3, Vec4};

use super::*;
use crate::render::{Ground, Lights, Output, ToneMap};
use crate::scene::{
    AlphaMode, Attenuation, Light, LightKind, Slot, SlotOverride, SlotOverrides, TextureSource,
};
use crate::shade::{Fog, FogDistance, Shading, ShadowSettings};
use crate::texture::{Filter, Texture};
use realist_testkit::TempDir;
use std::sync::Arc;

fn toml(text: &str) -> Result<SceneFile, SceneFileError> {
    SceneFile::parse(text, Format::Toml, Path::new("dir/exp.toml"))
}

fn err(text: &str) -> String {
    match toml(text) {
        Ok(f) => panic!("accepted:\n{text}\n{f:?}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn filter_key_takes_every_filter_and_names_itself_in_errors() {
    let scene = crate::scene::demo();
    for f in Filter::COMMON {
        let file = toml(&format!("model = \"demo\"\nfilter = \"{}\"\n", f.name())).unwrap();
        assert_eq!(file.settings(&scene).unwrap().filter, Some(f));
    }
    for bad in ["aniso:20", "aniso:1", "aniso", "linear"] {
        let e = err(&format!("model = \"demo\"\nfilter = \"{bad}\"\n"));
        assert!(
            e.contains(&format!("unknown filter '{bad}'")) && e.contains("line 2"),
            "{e}"
        );
        assert!(e.contains("trilinear") && e.contains("aniso:N"), "{e}");
    }
}

#[test]
fn unknown_keys_and_bad_types_name_the_file_and_key() {
    let e = err("model = \"demo\"\n[fog]\nnear = 1\nfar = 2\nnaer = 3\n");
    assert!(
        e.starts_with("dir/exp.toml: line 5: unknown field `naer`"),
        "{e}"
    );
    let e = err("model = \"demo\"\ncolour = 1\n");
    assert!(
        e.contains("unknown field `colour`") && e.contains("line 2"),
        "{e}"
    );
    let e = err("model = \"demo\"\n[[light]]\nkind = \"spot\"\ninnr = 3\n");
    assert!(e.contains("unknown field `innr`"), "{e}");
    let e = err("model = \"demo\"\nshading = \"phung\"\n");
    assert!(e.contains("unknown shading mode 'phung'"), "{e}");
    let e = err("model = \"demo\"\nsize = [-1, 5]\n");
    assert!(e.starts_with("dir/exp.toml: line 2"), "{e}");
    let e = err("model = \"demo\"\nbackground = \"#12345\"\n");
    assert!(e.contains("\"#rrggbb\""), "{e}");
    let json = SceneFile::parse(
        r#"{"model": "demo", "fog": {"near": 1, "far": 2, "colr": [1, 1, 1]}}"#,
        Format::Json,
        Path::new("x.json"),
    )
    .unwrap_err()
    .to_string();
    assert!(json.starts_with("x.json: unknown field `colr`"), "{json}");
}

#[test]
fn bad_values_are_errors_naming_the_key() {
    let cases = [
        ("", "model: missing"),
        ("model = \"demo\"\n[primitive]\nshape = \"cube\"\n", "give model or [primitive]"),
        ("[primitive]\nshape = \"cube\"\nslices = 8\n", "`slices` is not used by a cube"),
        ("[primitive]\nshape = \"sphere\"\nslices = 2\n", "slices: 2 is not between 3"),
        ("[primitive]\nshape = \"sphere\"\nradius = nan\n", "radius: NaN is not between"),
        ("model = \"demo\"\nsize = [20000, 10]\n", "size: 20000x10"),
        ("model = \"demo\"\nsize = [8000, 8000]\n", "size: 8000x8000 with 1x multisampling"),
        ("model = \"demo\"\nmsaa = 3\n", "msaa = 3: expected samples per pixel, one of 1, 4"),
        ("model = \"demo\"\nsamples = 0\n", "samples = 0: expected samples per pixel side, a whole number from 1 to 8"),
        ("model = \"demo\"\nlight_scale = -1\n", "light_scale: -1 is not between"),
        ("model = \"demo\"\n[fog]\nnear = 5\nfar = 2\n", "fog.near: 5 is not below far (2)"),
        ("model = \"demo\"\n[fog]\nnear = nan\nfar = 2\n", "fog.near = NaN: expected a distance in scene units from 0 to 10000000"),
        ("model = \"demo\"\n[shadow]\nsize = 100000\n", "shadow.size = 100000: expected texels per side, a whole number from 16 to 8192"),
        ("model = \"demo\"\n[shadow]\npcf = 99\n", "shadow.pcf = 99: expected a filter radius in texels, a whole number from 0 to 16"),
        ("model = \"demo\"\n[ground]\nextent = 0\n", "ground.extent = 0: expected multiples of the scene's radius from 0.001 to 1000"),
        ("model = \"demo\"\nbackground = [1, 2, 0.5]\n", "background: component 2 is not between 0 and 1"),
        ("model = \"demo\"\n[camera]\nnear = 3\nfar = 1\n", "camera.near: 3 is not below far (1)"),
        ("model = \"demo\"\n[camera]\ngltf = 0\nazimuth = 3\n", "camera.gltf: a file camera takes no"),
        ("model = \"demo\"\n[camera]\neye = [0, 0, 1]\nazimuth = 3\n", "camera.eye: give eye"),
        ("model = \"demo\"\n[camera]\nyfov = 200\n", "camera.yfov: 200 is not between 0.1 and 179"),
        ("model = \"demo\"\n[[light]]\nkind = \"spot\"\ninner = 40\nouter = 30\n", "light[0].inner: 40 degrees is wider than outer"),
        ("model = \"demo\"\n[[light]]\nkind = \"spot\"\nouter = 95\n", "light[0].outer: 95 is not between 0 and 89"),
        ("model = \"demo\"\n[[light]]\nkind = \"spot\"\ndirection = [0, 0, 0]\n", "light[0].direction: is the zero vector"),
        ("model = \"demo\"\n[[light]]\nkind = \"spot\"\ndirection = [0, 0, 1]\ntarget = [0, 0, 0]\n", "light[0].target: give direction or target"),
        ("model = \"demo\"\n[[light]]\nkind = \"point\"\nintensity = inf\n", "light[0].intensity: inf"),
        ("model = \"demo\"\n[[light]]\nkind = \"point\"\ncolor = [1, 1, 1, 1]\n", "light[0].color: has 3 components"),
        ("model = \"demo\"\n[[light]]\nkind = \"point\"\nattenuation = { mode = \"linear\", near = 1 }\n", "light[0].attenuation.far: is required"),
        ("model = \"demo\"\n[[light]]\nkind = \"point\"\nattenuation = { mode = \"linear\", near = 5, far = 1 }\n", "light[0].attenuation.far: 1 must be above 0 and not below near"),
        ("model = \"demo\"\n[[light]]\nkind = \"point\"\nattenuation = { mode = \"range\", range = 1, near = 2 }\n", "light[0].attenuation.near: is not used by mode = \"range\""),
        ("model = \"demo\"\nlights = \"auto\"\n[[light]]\nkind = \"point\"\n", "lights: is \"auto\""),
        ("model = \"demo\"\nlights_follow_camera = true\n", "lights_follow_camera: needs lights"),
        ("model = \"demo\"\n[[material]]\nshininess = 3\n", "material[0]: give exactly one of index or name"),
        ("model = \"demo\"\n[[material]]\nindex = 0\nshininess = 0\n", "material[0].shininess: 0 is not between 1 and 2000"),
        ("model = \"demo\"\n[[material]]\nindex = 0\nalpha_cutoff = 0.5\n", "material[0].alpha_cutoff: is only used with alpha_mode = \"mask\""),
        ("model = \"demo\"\n[compare]\n", "compare.variant: 0 variants"),
        ("model = \"demo\"\n[compare]\ncolumns = 3\n[[compare.variant]]\nlabel = \"a\"\n", "compare.columns: 3 is not between 1 and the number of variants (1)"),
        ("model = \"demo\"\nsize = [4000, 4000]\n[compare]\ncolumns = 2\n[[compare.variant]]\nlabel = \"a\"\n[[compare.variant]]\nlabel = \"b\"\n[[compare.variant]]\nlabel = \"c\"\n", "compare.variant: the grid would be 8000x"),
        ("model = \"demo\"\n[compare]\n[[compare.variant]]\nlabel = \" \"\n", "compare.variant[0].label: is empty"),
        ("model = \"demo\"\nhidden = [1.5]\n", "hidden[0]: 1.5 is not an instance number"),
        ("model = \"demo\"\nhidden = [0, -1]\n", "hidden[1]: -1 is not an instance number"),
        ("model = \"demo\"\nhidden = [1e18]\n", "hidden[0]: 1000000000000000000 is not an instance number (a whole number from 0 to 16777215)"),
    ];
    for (text, want) in cases {
        let e = err(text);
        assert!(
            e.starts_with("dir/exp.toml: ") && e.contains(want),
            "for:\n{text}\nwant '{want}' in: {e}"
        );
    }
}

#[test]
fn model_references_are_checked_against_the_model() {
    let file = toml("model = \"demo\"\nhidden = [1, 40]\n").unwrap();
    let scene = file.load_model(&LoadOptions::default()).unwrap();
    let e = file.settings(&scene).unwrap_err().to_string();
    let parts = scene.instances.len();
    assert!(
        e.contains("hidden[1]:")
            && e.contains(&format!("has {parts} part(s) (0 to {}), not 40", parts - 1)),
        "{e}"
    );
    let file = toml("model = \"demo\"\nhidden = [1]\n").unwrap();
    let s = file.settings(&scene).unwrap();
    assert_eq!(s.hidden.iter().collect::<Vec<_>>(), vec![1]);
    let file = toml("model = \"demo\"\n[camera]\ngltf = 1\n").unwrap();
    let scene = file.load_model(&LoadOptions::default()).unwrap();
    let e = file.camera(&scene, 1.0).unwrap_err().to_string();
    assert!(
        e.contains("camera.gltf:") && e.contains("1 camera(s) (0 to 0), not 1"),
        "{e}"
    );
    let file = toml("[primitive]\nshape = \"cube\"\n[camera]\ngltf = 0\n").unwrap();
    let scene = file.load_model(&LoadOptions::default()).unwrap();
    let e = file.camera(&scene, 1.0).unwrap_err().to_string();
    assert!(e.contains("has no cameras"), "{e}");

    let file = toml("model = \"demo\"\n[[material]]\nname = \"chrome\"\nshininess = 5\n").unwrap();
    let scene = crate::scene::demo();
    let e = file.settings(&scene).unwrap_err().to_string();
    assert!(
        e.contains("material[0].name: no material is named 'chrome' (the model has: wireframe, faceted, smooth"),
        "{e}"
    );
    let file = toml("model = \"demo\"\n[[material]]\nindex = 7\nshininess = 5\n").unwrap();
    let e = file.settings(&scene).unwrap_err().to_string();
    assert!(
        e.contains(&format!(
            "7, but the model has only {} material(s)",
            scene.materials.len()
        )),
        "{e}"
    );

    let file = toml("model = \"no/such/model.obj\"\n").unwrap();
    let e = file
        .load_model(&LoadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("dir/exp.toml: dir/no/such/model.obj"), "{e}");
    let file = toml("model = \"demo\"\ntexture = \"missing.png\"\n").unwrap();
    let e = file.settings(&scene).unwrap_err().to_string();
    assert!(e.contains("texture: dir/missing.png"), "{e}");
}

#[test]
fn overrides_apply_by_name_and_index() {
    let file = toml(
        "model = \"demo\"\nshading = \"gouraud\"\n\
         [[material]]\nname = \"smooth\"\nshininess = 300\nbase_color = \"#ff0000\"\n\
         [[material]]\nindex = 0\nalpha_mode = \"mask\"\nalpha_cutoff = 0.25\nbase_color = [0, 1, 0, 0.5]\n",
    )
    .unwrap();
    let scene = crate::scene::demo();
    let s = file.settings(&scene).unwrap();
    let m = s.materials.unwrap();
    assert_eq!(m.len(), scene.materials.len());
    assert_eq!(m[2].shininess, 300.0);
    // sRGB #ff0000 is linear (1, 0, 0); the alpha stays the model's.
    assert_eq!(m[2].base_color, Vec4::new(1.0, 0.0, 0.0, 1.0));
    assert_eq!(m[0].alpha_mode, AlphaMode::Mask(0.25));
    assert_eq!(m[0].base_color, Vec4::new(0.0, 1.0, 0.0, 0.5));
    assert_eq!(m[1], scene.materials[1]);
    assert_eq!(s.shading, Some(Shading::Gouraud));
    assert_eq!(s.lights, Lights::Auto);
}

#[test]
fn lights_convert_from_degrees_and_targets() {
    let file = toml(
        "model = \"demo\"\n[[light]]\nkind = \"spot\"\nposition = [0, 4, 0]\ntarget = [0, 0, 0]\n\
         inner = 10\nouter = 20\nattenuation = { mode = \"range\", range = 9 }\n\
         [[light]]\nkind = \"rect\"\nrect = [30, 15]\nup = [0, 0, 1]\n",
    )
    .unwrap();
    let s = file.settings(&crate::scene::demo()).unwrap();
    let Lights::Custom {
        lights,
        follow_camera: false,
    } = &s.lights
    else {
        panic!("{:?}", s.lights)
    };
    assert_eq!(lights[0].direction, Vec3::new(0.0, -4.0, 0.0));
    assert!((lights[0].inner - 10f32.to_radians()).abs() < 1e-7);
    assert!((lights[0].outer - 20f32.to_radians()).abs() < 1e-7);
    assert_eq!(lights[0].attenuation, Attenuation::Range(9.0));
    assert_eq!(lights[1].kind, LightKind::Rect);
    assert!((lights[1].rect - Vec2::new(30f32.to_radians(), 15f32.to_radians())).length() < 1e-7);
    assert_eq!(lights[1].up, Vec3::Z);
}

#[test]
fn light_flag_syntax() {
    let l = parse_light("spot:pos=0,4,2:target=0,0,0:inner=20:outer=30:color=1,0.5,0.25:att=linear,1,10:shadow:name=key")
        .unwrap();
    assert_eq!(l.kind, LightKind::Spot);
    assert_eq!(
        (l.position, l.direction),
        (Vec3::new(0.0, 4.0, 2.0), Vec3::new(0.0, -4.0, -2.0))
    );
    assert_eq!(l.color, Vec3::new(1.0, 0.5, 0.25));
    assert_eq!(
        l.attenuation,
        Attenuation::Linear {
            near: 1.0,
            far: 10.0
        }
    );
    assert!(l.shadow && l.name == "key");
    assert_eq!(
        parse_light("point:att=range,5").unwrap().attenuation,
        Attenuation::Range(5.0)
    );
    assert_eq!(
        parse_light("ambient:color=0.1,0.1,0.1").unwrap().kind,
        LightKind::Ambient
    );
    for (bad, want) in [
        ("lamp", "unknown light kind 'lamp'"),
        ("spot:pos=1,2", "pos: expected 3 numbers"),
        ("spot:outer=120", "--light.outer: 120"),
        ("point:att=linear,1", "att=linear,1"),
        ("point:glow=1", "unknown light key 'glow'"),
        ("rect:image=/no/such.png", "/no/such.png"),
    ] {
        let e = parse_light(bad).unwrap_err();
        assert!(e.contains(want), "{bad}: {e}");
    }
}

#[test]
fn shadow_and_extra_lights_make_the_automatic_rig_explicit() {
    let rig = shadow_every_light(&Lights::Auto, &[]);
    let Lights::Custom {
        lights,
        follow_camera: true,
    } = &rig
    else {
        panic!("{rig:?}")
    };
    assert_eq!(lights.len(), Light::default_rig(glam::Mat3::IDENTITY).len());
    assert!(lights.iter().all(|l| l.shadow == l.kind.can_shadow()));
    let own = [Light::point(Vec3::ONE, Vec3::ONE)];
    let spot = Light::spot(Vec3::Y, Vec3::NEG_Y, Vec3::ONE, 0.2, 0.3);
    let added = add_lights(&Lights::Auto, &own, std::slice::from_ref(&spot));
    assert_eq!(
        added,
        Lights::Custom {
            lights: vec![own[0].clone(), spot.clone()],
            follow_camera: false
        }
    );
    // No lights of its own: the added ones replace the default rig.
    let added = add_lights(&Lights::Auto, &[], std::slice::from_ref(&spot));
    assert_eq!(
        added,
        Lights::Custom {
            lights: vec![spot],
            follow_camera: false
        }
    );
}

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
fn a_material_variant_is_read_checked_and_written_by_name() {
    let model = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models/pbr/variants.glb");
    let dir = TempDir::new("scenefile-variant");
    let text = |v: &str| {
        format!(
            "model = {:?}\nmaterial_variant = \"{v}\"\n",
            model.display().to_string()
        )
    };
    let path = dir.write("v.toml", text("blue"));
    let loaded = SceneFile::load(&path).unwrap();
    assert_eq!(loaded.settings.variant.as_deref(), Some("blue"));
    let (mut file, _) =
        SceneFile::from_settings(&loaded.model, 1.0, &loaded.settings, &loaded.view);
    let again = dir.0.join("again.toml");
    file.save(&again).unwrap();
    assert!(std::fs::read_to_string(&again)
        .unwrap()
        .contains("material_variant = \"blue\""));
    let bad = dir.write("bad.toml", text("purple"));
    let e = SceneFile::load(&bad).unwrap_err().to_string();
    assert!(
        e.contains("material_variant")
            && e.contains("'purple' is not a material variant")
            && e.contains("it has: red, blue, none"),
        "{e}"
    );
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
fn comparisons_lay_out_labelled_cells() {
    let file = toml(
        "size = [40, 30]\n[primitive]\nshape = \"sphere\"\nslices = 8\nstacks = 4\n\
         [compare]\ntitle = \"T\"\ncolumns = 2\nlabel_size = 10\n\
         [[compare.variant]]\nlabel = \"flat\"\nshading = \"flat\"\n\
         [[compare.variant]]\nlabel = \"shiny\"\nmaterial = [{ index = 0, shininess = 500 }]\n\
         [[compare.variant]]\nlabel = \"third\"\n",
    )
    .unwrap();
    let loaded = file.resolve(&LoadOptions::default()).unwrap();
    let cmp = loaded.comparison.unwrap();
    assert_eq!(cmp.variants.len(), 3);
    assert_eq!(cmp.variants[0].settings.shading, Some(Shading::Flat));
    assert_eq!(
        cmp.variants[1].settings.materials.as_ref().unwrap()[0].shininess,
        500.0
    );
    assert_eq!(cmp.variants[2].settings, loaded.settings);
    // Two columns, two rows of 30 + 18 px (label strip), a 23 px title strip.
    let red = [200u8, 0, 0].repeat(40 * 30);
    let img = compose(&cmp, (40, 30), &[red.clone(), red.clone(), red]);
    assert_eq!((img.width, img.height), (80, 23 + 2 * (30 + 18)));
    let px = |x: u32, y: u32| {
        let i = ((y * img.width + x) * 3) as usize;
        [img.rgb[i], img.rgb[i + 1], img.rgb[i + 2]]
    };
    assert_eq!(px(5, 23 + 5), [200, 0, 0]);
    assert_eq!(px(45, 23 + 48 + 5), [32, 32, 36], "no fourth cell");
    // Labels are drawn in the strips: some light pixels under each of the three cells.
    for (x0, y0) in [(0, 23 + 30), (40, 23 + 30), (0, 23 + 48 + 30)] {
        let lit = (x0..x0 + 40)
            .flat_map(|x| (y0..y0 + 18).map(move |y| (x, y)))
            .filter(|&(x, y)| px(x, y)[0] > 150)
            .count();
        assert!(lit > 5, "label at {x0},{y0}: {lit}");
    }
    let (rendered, _) = cmp.render(
        &crate::render::PreparedScene::new(loaded.scene),
        &loaded.view,
    );
    assert_eq!((rendered.width, rendered.height), (img.width, img.height));
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
