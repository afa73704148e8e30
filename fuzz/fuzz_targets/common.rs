//! Shared by the fuzz targets: the loaders take paths, so inputs are written to files in a
//! per-process scratch folder. A loader panic comes back as `LoadError::Panic`, which is a
//! finding: the targets turn it into a real panic so libFuzzer records the input.

#![allow(dead_code)]

use std::path::{Path, PathBuf};

use realist::load::{load, LoadError, LoadOptions};
use realist::scene::Scene;

/// The scratch folder of this fuzzing process.
pub fn scratch() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("realist-fuzz-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    dir
}

/// Writes `bytes` to `name` in the scratch folder.
pub fn write(name: &str, bytes: &[u8]) -> PathBuf {
    let path = scratch().join(name);
    std::fs::write(&path, bytes).expect("scratch folder is writable");
    path
}

/// Loads a model with a budget small enough that fuzzing never swaps; panics on a loader
/// panic (the finding), returns the scene or `None` on an ordinary error.
pub fn load_model(path: &Path) -> Option<Scene> {
    let opts = LoadOptions {
        max_bytes: 256 << 20,
        ..LoadOptions::default()
    };
    match load(path, &opts) {
        Ok(scene) => Some(scene),
        Err(LoadError::Panic { message, .. }) => panic!("loader panicked: {message}"),
        Err(e) => {
            let msg = e.to_string();
            assert!(
                !msg.contains('\n'),
                "error message is not one line: {msg:?}"
            );
            None
        }
    }
}

/// Splits `data` at the first `sep` byte: (before, after).
pub fn split(data: &[u8], sep: u8) -> (&[u8], &[u8]) {
    match data.iter().position(|&b| b == sep) {
        Some(i) => (&data[..i], &data[i + 1..]),
        None => (data, &[]),
    }
}
