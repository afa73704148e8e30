//! A KTX2 file (Basis Universal ETC1S or UASTC) for the KTX2 transcoder (`KHR_texture_basisu`).
//! A panic inside the decoder comes back as an error starting "decoder panicked": a finding.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Err(e) = realist::load::fuzzing::ktx2(data) {
        assert!(!e.contains("decoder panicked"), "{e}");
        assert!(!e.contains('\n'), "error message is not one line: {e:?}");
    }
});
