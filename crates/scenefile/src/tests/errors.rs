//! Reading and checking: the filter key, unknown keys, bad types and values named by file
//! and key, and references checked against the model.

use std::path::Path;

use super::*;
use crate::texture::Filter;

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
