//! Image bytes (PNG or JPEG) into the texture decoder, which enforces size and memory limits.
#![no_main]

mod common;

use realist::load::{load_texture, LoadError};

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let name = if data.starts_with(&[0xFF, 0xD8]) {
        "case.jpg"
    } else {
        "case.png"
    };
    let path = common::write(name, data);
    match load_texture(&path) {
        Ok(t) => assert_eq!(
            t.texels.len() as u64,
            u64::from(t.width) * u64::from(t.height)
        ),
        Err(LoadError::Panic { message, .. }) => panic!("decoder panicked: {message}"),
        Err(_) => {}
    }
});
