//! OBJ and MTL text (split at the first 0xFF byte) into the OBJ loader; the OBJ is prefixed
//! with `mtllib case.mtl` so the material parser is always reached.
#![no_main]

mod common;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let (obj, mtl) = common::split(data, 0xFF);
    common::write("case.mtl", mtl);
    let mut text = b"mtllib case.mtl\n".to_vec();
    text.extend_from_slice(obj);
    let path = common::write("case.obj", &text);
    let _ = common::load_model(&path);
});
