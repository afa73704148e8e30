//! glTF / GLB bytes into the glTF loader (GLB when the bytes start with the GLB magic).
#![no_main]

mod common;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let name = if data.starts_with(b"glTF") {
        "case.glb"
    } else {
        "case.gltf"
    };
    let path = common::write(name, data);
    let _ = common::load_model(&path);
});
