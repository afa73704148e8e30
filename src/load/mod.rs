//! Loaders: OBJ/MTL (through `tobj`) and glTF 2.0 / GLB (through `gltf`) into one
//! [`Scene`]. No `tobj` or `gltf` type escapes this module.

use std::path::{Path, PathBuf};

use crate::mesh::NormalOptions;
use crate::scene::Scene;

/// Options shared by the loaders.
#[derive(Clone, Debug)]
pub struct LoadOptions {
    /// How normals are averaged where a file has none (OBJ).
    pub normals: NormalOptions,
    /// Memory budget for the whole document (file bytes, geometry, decoded textures).
    pub max_bytes: u64,
}

impl Default for LoadOptions {
    fn default() -> Self {
        Self { normals: NormalOptions::default(), max_bytes: 2 << 30 }
    }
}

/// Why a file could not be loaded. Every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    #[error("{path}: {source}")]
    Io { path: PathBuf, source: std::io::Error },
    #[error("{path}: unknown model format (expected .obj, .gltf or .glb)")]
    UnknownFormat { path: PathBuf },
    #[error("{path}: loader panicked: {message}")]
    Panic { path: PathBuf, message: String },
}

/// Loads a model file, choosing the loader by extension.
pub fn load(path: &Path, opts: &LoadOptions) -> Result<Scene, LoadError> {
    let _ = opts;
    Err(LoadError::UnknownFormat { path: path.to_owned() })
}
