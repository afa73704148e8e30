//! Load then render: the first byte picks the format (glTF, GLB or OBJ), the rest is the
//! file; whatever loads is rendered at 64x64 in every shading mode, and no pixel may be NaN.
#![no_main]

mod common;

use realist::render::{self, PreparedScene, Settings, Shot};
use realist::shade::Shading;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let Some((&selector, body)) = data.split_first() else {
        return;
    };
    let name = match selector % 3 {
        0 => "case.gltf",
        1 => "case.glb",
        _ => "case.obj",
    };
    let path = common::write(name, body);
    let Some(scene) = common::load_model(&path) else {
        return;
    };
    let prepared = PreparedScene::new(scene);
    for mode in Shading::ALL {
        let opts = Shot {
            width: 64,
            height: 64,
            settings: Settings {
                shading: Some(mode),
                ..Settings::default()
            },
            ..Shot::default()
        };
        let frame = render::render(&prepared, &opts);
        let image = frame.image();
        assert!(
            image.color.iter().all(|c| c.is_finite()),
            "{mode}: non-finite pixel"
        );
        assert!(
            image.depth.iter().all(|d| d.is_finite()),
            "{mode}: non-finite depth"
        );
    }
});
