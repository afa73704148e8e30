//! Material overrides (by name and by index) and material variants: read, checked and
//! written back.

use std::path::Path;

use glam::Vec4;

use super::*;
use crate::render::Lights;
use crate::scene::AlphaMode;
use crate::shade::Shading;
use realist_testkit::TempDir;

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
