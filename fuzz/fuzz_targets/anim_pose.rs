//! Animation, skins and morph targets: a glTF or GLB (the first byte picks which and the
//! times) is loaded, then posed at several times, looping or not, with every animation and
//! with each one alone; every pose must keep the posed vertices, bounds, lights and cameras
//! finite or leave them out, and a small frame of it must have no NaN pixel.
#![no_main]

mod common;

use realist::render::{self, PreparedScene, Shot};
use realist::scene::Play;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let Some((&selector, body)) = data.split_first() else {
        return;
    };
    let name = if selector & 1 == 0 { "case.gltf" } else { "case.glb" };
    let path = common::write(name, body);
    let Some(scene) = common::load_model(&path) else {
        return;
    };
    let animations = scene.animations.len();
    let mut prepared = PreparedScene::new(scene);
    // Times before, inside and after the animations, and odd ones.
    let scale = f32::from(selector >> 1) / 8.0;
    let times = [0.0, scale, 1e-7, 0.5, 3.0 * scale + 0.1, -1.0, 1e9, f32::NAN];
    let plays = [Play::Rest, Play::All]
        .into_iter()
        .chain((0..animations.min(4)).map(Play::One))
        .chain([Play::One(usize::MAX)]);
    for play in plays {
        for (k, &t) in times.iter().enumerate() {
            prepared.pose_at(play, t, k % 2 == 0);
            if let Some((lo, hi)) = prepared.bounds() {
                assert!(lo.is_finite() && hi.is_finite(), "bounds {lo} {hi}");
                assert!(lo.cmple(hi).all(), "bounds {lo} > {hi}");
            }
            for l in prepared.lights() {
                assert!(l.position.is_finite() && l.direction.is_finite(), "light {l:?}");
            }
            for c in prepared.cameras() {
                assert!(c.eye.is_finite() && c.target.is_finite(), "camera {c:?}");
            }
        }
    }
    prepared.pose_at(Play::All, 0.5 * scale, true);
    let opts = Shot {
        width: 32,
        height: 32,
        ..Shot::default()
    };
    let frame = render::render(&prepared, &opts);
    let image = frame.image();
    assert!(image.color.iter().all(|c| c.is_finite()), "non-finite pixel");
});
