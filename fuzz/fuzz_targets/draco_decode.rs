//! A Draco stream for the Draco decoder (`KHR_draco_mesh_compression`).
//! A panic inside the decoder comes back as an error starting "decoder panicked": a finding.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Err(e) = realist::load::fuzzing::draco(data) {
        assert!(!e.contains("decoder panicked"), "{e}");
        assert!(!e.contains('\n'), "error message is not one line: {e:?}");
    }
});
