//! STL and PLY: the first byte picks the format (STL or PLY), the rest is the file; what
//! loads must have finite bounds, and a small frame of it no NaN pixel.
#![no_main]

mod common;

use realist::render::{self, PreparedScene, Shot};

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let Some((&selector, body)) = data.split_first() else {
        return;
    };
    let name = if selector & 1 == 0 { "case.stl" } else { "case.ply" };
    let path = common::write(name, body);
    let Some(scene) = common::load_model(&path) else {
        return;
    };
    if let Some((lo, hi)) = scene.bounds() {
        assert!(lo.is_finite() && hi.is_finite(), "bounds {lo} {hi}");
    }
    let prepared = PreparedScene::new(scene);
    let opts = Shot {
        width: 32,
        height: 32,
        ..Shot::default()
    };
    let frame = render::render(&prepared, &opts);
    let image = frame.image();
    assert!(image.color.iter().all(|c| c.is_finite()), "non-finite pixel");
});
