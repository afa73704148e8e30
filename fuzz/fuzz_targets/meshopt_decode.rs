//! A meshopt bufferView for the meshopt decoder (EXT/KHR, every mode and filter): see `realist::load::fuzzing::meshopt` for the layout.
//! A panic inside the decoder comes back as an error starting "decoder panicked": a finding.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Err(e) = realist::load::fuzzing::meshopt(data) {
        assert!(!e.contains("decoder panicked"), "{e}");
        assert!(!e.contains('\n'), "error message is not one line: {e:?}");
    }
});
