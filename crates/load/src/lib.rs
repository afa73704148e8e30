//! Loaders: OBJ/MTL (through `tobj`), glTF 2.0 / GLB (through `gltf`'s JSON types), STL
//! (binary and ASCII, `stl.rs`) and PLY (ASCII and binary, `ply.rs`) into one [`Scene`]. No
//! `tobj` or `gltf` type escapes this module.
//!
//! Everything a loader reads comes from a file that may be hostile, so the module keeps
//! these invariants:
//!
//! - **Bounded memory.** Every file is read by `files::read_capped` (regular files only),
//!   and every large allocation (file bytes, buffers, decoded texels, estimated geometry) is
//!   charged to one `Budget` of [`LoadOptions::max_bytes`] *before* it is made. No length
//!   field of a file is trusted to size an allocation.
//! - **No escape from the model's folder.** `mtllib`, `map_Kd` and glTF URIs are resolved
//!   relative to the model, canonicalised, and must stay inside the model's folder; glTF
//!   also accepts `data:` URIs. Nothing else (`file://`, `http://`, absolute paths).
//! - **No panics on file data, no recursion on file-controlled depth.** The node graph is
//!   walked with an explicit stack; indices are checked with `get`. [`load`] still runs the
//!   loader under `catch_unwind` as a last line of defence: a panic becomes
//!   [`LoadError::Panic`] naming the file.
//! - **Errors are one line and start with the file path**; they say which accessor,
//!   primitive, mesh or line was wrong and what was expected. What does not stop a load
//!   (a missing texture or MTL file, dropped faces, skipped primitives) goes to
//!   [`LoadReport`](crate::scene::LoadReport) instead.
//!
//! A load can be watched and cancelled from another thread through a shared [`Progress`]
//! ([`LoadOptions::progress`]); `progress.rs` says where the loaders look at it and what
//! that costs.
//!
//! Faces with fewer than three corners or three distinct vertices, and faces touching a
//! non-finite position, are dropped (and counted in the report) by every loader, so the
//! renderer never sees them.

// The crates below this one, under the module names the code uses (`crate::scene::...`).
use realist_color as color;
use realist_mesh as mesh;
use realist_scene as scene;
use realist_texture as texture;

use std::cell::Cell;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::mesh::{MeshData, NormalOptions};
use crate::scene::Scene;
use crate::texture::{Texture, UvGenerator};

mod files;
mod gltf;
mod images;
mod ktx2;
mod obj;
mod ply;
mod progress;
mod stl;

pub use self::gltf::GltfError;
pub use self::images::MAX_SIDE as MAX_TEXTURE_SIDE;
pub use self::obj::ObjError;
pub use self::ply::PlyError;
use self::progress::Tracker;
pub use self::progress::{Progress, Stage};
pub use self::stl::StlError;

/// Options shared by the loaders.
#[derive(Clone, Debug)]
pub struct LoadOptions {
    /// How normals are averaged where a file has none (OBJ).
    pub normals: NormalOptions,
    /// Memory budget for the whole document (file bytes, geometry, decoded textures).
    pub max_bytes: u64,
    /// Where the load reports its stage and fraction, and where it can be cancelled from
    /// another thread (`None`: nobody watches; the load behaves the same).
    pub progress: Option<Arc<Progress>>,
    /// Texture coordinates generated for every mesh after loading, replacing UV set 0 (the
    /// textbook's §9.5; [`Scene::apply_uv_generator`]); `None` keeps the file's.
    pub uv: Option<UvGenerator>,
    /// Which of the file's scenes is drawn (0-based, in file order; `realist render
    /// --scene N`): `None` draws the file's default scene (glTF's `scene`, else the first).
    /// Only glTF files hold several; any other file has one scene, number 0. An index the
    /// file does not have is [`LoadError::Scene`].
    pub scene: Option<usize>,
}

impl Default for LoadOptions {
    fn default() -> Self {
        Self {
            normals: NormalOptions::default(),
            max_bytes: 2 << 30,
            progress: None,
            uv: None,
            scene: None,
        }
    }
}

/// Why a file could not be loaded. Every variant's message is one line that starts with
/// the file's path.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path}: unknown model format (expected .obj, .gltf, .glb, .stl or .ply)")]
    UnknownFormat { path: PathBuf },
    #[error("{path}: loader panicked: {message}")]
    Panic { path: PathBuf, message: String },
    #[error("{path}: {what} needs {bytes} bytes, over the memory budget ({used} of {limit} bytes already in use)")]
    TooLarge {
        path: PathBuf,
        what: String,
        bytes: u64,
        used: u64,
        limit: u64,
    },
    /// [`LoadOptions::scene`] names a scene the file does not have.
    #[error("{path}: there is no scene {index}: the file has {}", scene_count(*count))]
    Scene {
        path: PathBuf,
        index: usize,
        count: usize,
    },
    #[error("{path}: cannot use image: {reason}")]
    Image { path: PathBuf, reason: String },
    /// [`Progress::cancel`] was called during the load.
    #[error("{path}: load cancelled")]
    Cancelled { path: PathBuf },
    #[error(transparent)]
    Obj(#[from] ObjError),
    #[error(transparent)]
    Gltf(#[from] GltfError),
    #[error(transparent)]
    Stl(#[from] StlError),
    #[error(transparent)]
    Ply(#[from] PlyError),
}

/// "no scenes", "1 scene (number 0)" or "N scenes (0 to N-1)".
fn scene_count(count: usize) -> String {
    match count {
        0 => "no scenes".into(),
        1 => "1 scene (number 0)".into(),
        n => format!("{n} scenes (0 to {})", n - 1),
    }
}

/// Loads a model file, choosing the loader by extension (`.obj`, `.gltf`, `.glb`, `.stl`,
/// `.ply`, any case).
///
/// A panic inside a loader is caught and returned as [`LoadError::Panic`].
///
/// With [`LoadOptions::progress`], the load runs on a helper thread while this one waits;
/// the stage and fraction are published as it goes and end at ([`Stage::Done`], 1) on
/// success. If the `Progress` is cancelled before this function returns, it returns
/// [`LoadError::Cancelled`] (whatever the load had come to, unless it panicked), within a
/// few milliseconds of the cancel; the helper stops at its next checkpoint.
pub fn load(path: &Path, opts: &LoadOptions) -> Result<Scene, LoadError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let gltf = matches!(ext.as_deref(), Some("gltf" | "glb"));
    if let Some(index) = opts.scene.filter(|&i| i > 0 && !gltf) {
        return Err(LoadError::Scene {
            path: path.to_owned(),
            index,
            count: 1,
        });
    }
    let loader: Loader = match ext.as_deref() {
        Some("obj") => obj::load_obj,
        Some("gltf" | "glb") => gltf::load_gltf,
        Some("stl") => stl::load_stl,
        Some("ply") => ply::load_ply,
        _ => {
            return Err(LoadError::UnknownFormat {
                path: path.to_owned(),
            })
        }
    };
    match &opts.progress {
        None => run(loader, path, opts),
        Some(progress) => {
            let (owned_path, opts) = (path.to_owned(), opts.clone());
            progress::watch(path, progress, move || run(loader, &owned_path, &opts))
        }
    }
}

/// Runs `loader` under [`guarded`], reporting to `opts.progress` (if any).
fn run(loader: Loader, path: &Path, opts: &LoadOptions) -> Result<Scene, LoadError> {
    let tracker = Tracker::new(path, opts.progress.as_ref());
    let result = guarded(path, || {
        tracker.check()?;
        let mut scene = loader(path, opts, &tracker)?;
        if let Some(generator) = &opts.uv {
            scene.apply_uv_generator(generator);
        }
        scene.check_texture_slots();
        Ok(scene)
    });
    match result {
        Err(e @ LoadError::Panic { .. }) => Err(e),
        _ if tracker.is_cancelled() => Err(tracker.cancelled()),
        Ok(scene) => {
            tracker.finish();
            Ok(scene)
        }
        Err(e) => Err(e),
    }
}

/// A format's loader.
type Loader = fn(&Path, &LoadOptions, &Tracker) -> Result<Scene, LoadError>;

/// Loads an image file (PNG, JPEG, Radiance HDR or OpenEXR) as a colour texture, e.g. for
/// `--texture IMG`: 8-bit images stay sRGB-encoded, 16-bit ones are decoded to linear light,
/// float ones are kept. The file and the decoded texels must fit [`LoadOptions::default`]'s
/// memory budget, and the image may be at most [`MAX_TEXTURE_SIDE`] texels wide and high.
pub fn load_texture(path: &Path) -> Result<Texture, LoadError> {
    load_image(path, true)
}

/// Loads an image file for a slot of colour space `srgb` (colour) or linear data (normal,
/// bump and occlusion maps); see [`load_texture`].
pub fn load_image(path: &Path, srgb: bool) -> Result<Texture, LoadError> {
    guarded(path, || {
        let budget = Budget::new(path, LoadOptions::default().max_bytes);
        let bytes = files::read_capped(path, &budget, "image file")?;
        let name = path
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        images::decode(&bytes, &name, &budget, srgb).map_err(|e| e.into_load_error(path))
    })
}

/// The compressed-data decoders alone, for the fuzz targets in `fuzz/` (not a stable API):
/// each returns what it decoded or the error the loader would report. A panic inside a
/// decoder comes back as an `Err` (as in the loader), so the targets check it by message.
#[doc(hidden)]
pub mod fuzzing {
    use std::path::Path;

    use super::gltf::{draco, meshopt};
    use super::Budget;

    /// A meshopt bufferView: byte 0 picks the mode (ATTRIBUTES, TRIANGLES, INDICES) and the
    /// extension (EXT or KHR), byte 1 the filter, byte 2 the byteStride (in units of 2 or 4)
    /// and bytes 3..5 the count (little-endian u16); the rest is the compressed stream.
    /// Returns the decoded byte count.
    pub fn meshopt(data: &[u8]) -> Result<usize, String> {
        let (Some(&a), Some(&b), Some(&c), Some(&lo), Some(&hi)) = (
            data.first(),
            data.get(1),
            data.get(2),
            data.get(3),
            data.get(4),
        ) else {
            return Err("short input".into());
        };
        let mode = ["ATTRIBUTES", "TRIANGLES", "INDICES"][usize::from(a % 3)];
        let ext = if a & 0x80 != 0 {
            meshopt::KHR
        } else {
            meshopt::EXT
        };
        let filter =
            ["NONE", "OCTAHEDRAL", "QUATERNION", "EXPONENTIAL", "COLOR"][usize::from(b % 5)];
        let stride = if mode == "ATTRIBUTES" {
            4 * (usize::from(c % 64) + 1)
        } else {
            2 * (usize::from(c % 2) + 1)
        };
        let count = usize::from(u16::from_le_bytes([lo, hi]));
        let source = data.get(5..).unwrap_or(&[]);
        let object = serde_json::json!({"buffer": 0, "byteLength": source.len(),
            "byteStride": stride, "count": count, "mode": mode, "filter": filter});
        let mut map = serde_json::Map::new();
        map.insert(ext.into(), object);
        let c = meshopt::Compressed::of(Some(&map)).ok_or("no extension")??;
        let budget = Budget::new(Path::new("fuzz"), 64 << 20);
        let out =
            meshopt::decode(&c, source, &budget, "bufferView 0").map_err(|e| e.to_string())??;
        Ok(out.len())
    }

    /// A Draco stream: returns the decoded (points, faces).
    pub fn draco(data: &[u8]) -> Result<(usize, usize), String> {
        let mesh = draco::decode(data, 64 << 20)?;
        Ok((mesh.num_points(), mesh.num_faces()))
    }

    /// A KTX2 (Basis Universal) image: returns its size and texel count.
    pub fn ktx2(data: &[u8]) -> Result<(u32, u32, usize), String> {
        let budget = Budget::new(Path::new("fuzz"), 256 << 20);
        match super::ktx2::decode(data, "fuzz.ktx2", &budget, true) {
            Ok(t) => Ok((t.width, t.height, t.texels.len())),
            Err(super::images::DecodeError::Invalid(e)) => Err(e),
            Err(super::images::DecodeError::Budget(e)) => Err(e.to_string()),
        }
    }
}

/// Runs `f`, turning a panic into [`LoadError::Panic`].
fn guarded<T>(path: &Path, f: impl FnOnce() -> Result<T, LoadError>) -> Result<T, LoadError> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).unwrap_or_else(|payload| {
        Err(LoadError::Panic {
            path: path.to_owned(),
            message: panic_message(payload.as_ref()),
        })
    })
}

/// The message of a caught panic, on one line.
fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    one_line(
        payload
            .downcast_ref::<&str>()
            .copied()
            .or_else(|| payload.downcast_ref::<String>().map(String::as_str))
            .unwrap_or("unknown panic"),
    )
}

/// `message` on one line: each line break, with the spaces around it, becomes one space
/// (decoders' messages may be wrapped, as draco-core's are; a load error is one line).
pub(crate) fn one_line(message: &str) -> String {
    if !message.contains(['\n', '\r']) {
        return message.to_owned();
    }
    message
        .split(['\n', '\r'])
        .map(str::trim)
        .filter(|part| !part.is_empty())
        .collect::<Vec<_>>()
        .join(" ")
}

/// Runs a third-party decoder (meshopt, Draco, Basis Universal), turning a panic inside it
/// into an error message, so the caller can name the item it was decoding; its messages
/// come back on one line.
pub(crate) fn catch_decoder<T>(f: impl FnOnce() -> Result<T, String>) -> Result<T, String> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(f))
        .unwrap_or_else(|payload| {
            Err(format!(
                "decoder panicked: {}",
                panic_message(payload.as_ref())
            ))
        })
        .map_err(|e| one_line(&e))
}

/// Memory accounting for one load: every large allocation is charged here before it is
/// made, and the load fails with [`LoadError::TooLarge`] once `max_bytes` would be passed.
pub(crate) struct Budget {
    path: PathBuf,
    limit: u64,
    used: Cell<u64>,
}

impl Budget {
    pub(crate) fn new(path: &Path, limit: u64) -> Self {
        Self {
            path: path.to_owned(),
            limit,
            used: Cell::new(0),
        }
    }

    /// Charges `bytes` for `what` (evaluated only on failure).
    pub(crate) fn charge(
        &self,
        bytes: u64,
        what: impl FnOnce() -> String,
    ) -> Result<(), LoadError> {
        let used = self.used.get();
        match used.checked_add(bytes) {
            Some(total) if total <= self.limit => {
                self.used.set(total);
                Ok(())
            }
            _ => Err(LoadError::TooLarge {
                path: self.path.clone(),
                what: what(),
                bytes,
                used,
                limit: self.limit,
            }),
        }
    }

    /// Bytes still available.
    pub(crate) fn remaining(&self) -> u64 {
        self.limit.saturating_sub(self.used.get())
    }
}

/// Rough bytes a mesh of this size occupies once built (positions, attributes, corners,
/// facets, edges and the temporaries of building them); used to charge the [`Budget`].
pub(crate) fn mesh_bytes(vertices: u64, corners: u64, facets: u64) -> u64 {
    vertices
        .saturating_mul(64)
        .saturating_add(corners.saturating_mul(48))
        .saturating_add(facets.saturating_mul(96))
        .saturating_add(1024)
}

/// How many facets [`retain_facets`] removed, by reason.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Dropped {
    /// Facets with fewer than 3 corners.
    pub too_small: usize,
    /// Facets with a corner at a NaN or infinite position (or an out-of-range vertex).
    pub non_finite: usize,
    /// Facets with at least 3 corners but fewer than 3 distinct vertices (e.g. `f 1 1 2`).
    pub degenerate: usize,
}

impl Dropped {
    /// Report lines for the warnings list, prefixed with `what` (e.g. "object 'x'").
    pub(crate) fn warnings(&self, what: &str) -> Vec<String> {
        let mut out = Vec::new();
        if self.too_small > 0 {
            out.push(format!(
                "{what}: dropped {} face(s) with fewer than 3 vertices",
                self.too_small
            ));
        }
        if self.non_finite > 0 {
            out.push(format!(
                "{what}: dropped {} face(s) with NaN or infinite positions",
                self.non_finite
            ));
        }
        if self.degenerate > 0 {
            out.push(format!(
                "{what}: dropped {} degenerate face(s) (fewer than 3 distinct vertices)",
                self.degenerate
            ));
        }
        out
    }
}

/// Removes facets with fewer than 3 corners, with a corner at a non-finite position, or
/// with fewer than 3 distinct vertices, keeping `facet_sizes` and per-corner channel indices in step with `corners`.
pub(crate) fn retain_facets(data: &mut MeshData) -> Dropped {
    let mut dropped = Dropped::default();
    let sizes: Vec<u32> = match &data.facet_sizes {
        Some(s) => s.clone(),
        None => vec![3; data.corners.len() / 3],
    };
    let bad = |corners: &[u32]| {
        corners.iter().any(|&v| {
            data.positions
                .get(v as usize)
                .is_none_or(|p| !p.is_finite())
        })
    };
    let mut keep = Vec::with_capacity(sizes.len());
    let mut start = 0usize;
    for &n in &sizes {
        let end = start.saturating_add(n as usize).min(data.corners.len());
        let ok = if n < 3 {
            dropped.too_small += 1;
            false
        } else if bad(data.corners.get(start..end).unwrap_or(&[])) {
            dropped.non_finite += 1;
            false
        } else if distinct_below_3(data.corners.get(start..end).unwrap_or(&[])) {
            dropped.degenerate += 1;
            false
        } else {
            true
        };
        keep.push(ok);
        start = end;
    }
    if dropped == Dropped::default() {
        return dropped;
    }
    let corner_keep: Vec<bool> = sizes
        .iter()
        .zip(&keep)
        .flat_map(|(&n, &k)| std::iter::repeat_n(k, n as usize))
        .collect();
    let filter = |v: &mut Vec<u32>| {
        let mut it = corner_keep.iter();
        v.retain(|_| it.next().copied().unwrap_or(false));
    };
    filter(&mut data.corners);
    if let Some(ix) = data.normals.as_mut().and_then(|c| c.indices.as_mut()) {
        filter(ix);
    }
    for ix in data.uvs.iter_mut().filter_map(|c| c.indices.as_mut()) {
        filter(ix);
    }
    if let Some(ix) = data.tangents.as_mut().and_then(|c| c.indices.as_mut()) {
        filter(ix);
    }
    if let Some(ix) = data.colors.as_mut().and_then(|c| c.indices.as_mut()) {
        filter(ix);
    }
    let kept: Vec<u32> = sizes
        .iter()
        .zip(&keep)
        .filter(|(_, &k)| k)
        .map(|(&n, _)| n)
        .collect();
    data.facet_sizes = if kept.iter().all(|&n| n == 3) {
        None
    } else {
        Some(kept)
    };
    dropped
}

/// Whether `corners` name fewer than 3 distinct vertices (linear time: stops at the third).
fn distinct_below_3(corners: &[u32]) -> bool {
    let Some(&a) = corners.first() else {
        return true;
    };
    let Some(&b) = corners.iter().find(|&&v| v != a) else {
        return true;
    };
    !corners.iter().any(|&v| v != a && v != b)
}

#[cfg(test)]
pub(crate) mod tests;
