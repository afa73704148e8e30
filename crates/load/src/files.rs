//! File access for the loaders: size-capped reads of regular files, and resolution of paths
//! named inside a model (`mtllib`, `map_Kd`, glTF URIs) that must stay inside the model's
//! folder.

use std::io::Read;
use std::path::{Path, PathBuf};

use super::progress::{Stage, Tracker};
use super::{Budget, LoadError};

/// Reads `path`, which must be a regular file, charging its size to `budget` as `what`.
/// At most the charged size plus one byte is ever read, so a special file or one that grows
/// while read cannot exhaust memory.
pub(crate) fn read_capped(path: &Path, budget: &Budget, what: &str) -> Result<Vec<u8>, LoadError> {
    read_chunked(path, budget, what, |_, _| Ok(()))
}

/// [`read_capped`] for the model file itself: the [`Stage::Reading`] stage, filling the
/// progress bar up to `until`, with a checkpoint every [`CHUNK`] bytes.
pub(crate) fn read_model(
    path: &Path,
    budget: &Budget,
    what: &str,
    tracker: &Tracker,
    until: f32,
) -> Result<Vec<u8>, LoadError> {
    read_chunked(path, budget, what, |done, total| match done {
        0 => tracker.begin(Stage::Reading, until, total),
        _ => tracker.advance(done),
    })
}

/// Bytes read between two calls of the progress callback.
const CHUNK: u64 = 4 << 20;

/// [`read_capped`], calling `step(bytes read, file size)` before each [`CHUNK`].
fn read_chunked(
    path: &Path,
    budget: &Budget,
    what: &str,
    mut step: impl FnMut(u64, u64) -> Result<(), LoadError>,
) -> Result<Vec<u8>, LoadError> {
    let io = |source| LoadError::Io {
        path: path.to_owned(),
        source,
    };
    let meta = std::fs::metadata(path).map_err(io)?;
    if !meta.is_file() {
        return Err(io(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "not a regular file",
        )));
    }
    budget.charge(meta.len(), || format!("{what} {}", path.display()))?;
    let file = std::fs::File::open(path).map_err(io)?;
    // `meta.len()` is already charged; allow one more byte to detect growth.
    let cap = meta.len().saturating_add(1);
    let mut bytes = Vec::with_capacity(usize::try_from(meta.len()).unwrap_or(0));
    let mut file = file.take(cap);
    loop {
        step(bytes.len() as u64, meta.len())?;
        let n = (&mut file)
            .take(CHUNK)
            .read_to_end(&mut bytes)
            .map_err(io)?;
        if n == 0 {
            break;
        }
    }
    if bytes.len() as u64 > meta.len() {
        return Err(io(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            "file grew while being read",
        )));
    }
    Ok(bytes)
}

/// The canonical folder of a model file: where its relative references are resolved and
/// which they must not leave.
pub(crate) fn model_folder(model: &Path) -> Result<PathBuf, LoadError> {
    let parent = match model.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    parent.canonicalize().map_err(|source| LoadError::Io {
        path: model.to_owned(),
        source,
    })
}

/// Resolves `reference` relative to `base` (a folder inside `root`) and checks that the
/// result exists and lies inside `root` (canonical). Returns the canonical path, or a
/// one-line reason.
pub(crate) fn resolve_inside(
    root: &Path,
    base: &Path,
    reference: &Path,
) -> Result<PathBuf, String> {
    if reference.as_os_str().is_empty() {
        return Err("empty file name".into());
    }
    let joined = base.join(reference);
    let canonical = joined
        .canonicalize()
        .map_err(|e| format!("{}: {e}", reference.display()))?;
    if !canonical.starts_with(root) {
        return Err(format!(
            "{} is outside the model's folder {}",
            reference.display(),
            root.display()
        ));
    }
    if !canonical.is_file() {
        return Err(format!("{} is not a regular file", reference.display()));
    }
    Ok(canonical)
}

/// `bytes` as text: borrowed when they are valid UTF-8 (checked with `str::from_utf8`,
/// several times faster on a large ASCII file than `String::from_utf8_lossy`, which walks
/// the bytes chunk by chunk), else a copy with the invalid bytes replaced by U+FFFD.
pub(crate) fn text(bytes: &[u8]) -> std::borrow::Cow<'_, str> {
    match std::str::from_utf8(bytes) {
        Ok(s) => std::borrow::Cow::Borrowed(s),
        Err(_) => String::from_utf8_lossy(bytes),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resolve_rejects_escapes_and_devices() {
        let dir = std::env::temp_dir().join(format!("realist-files-{}", std::process::id()));
        let sub = dir.join("model");
        std::fs::create_dir_all(&sub).unwrap();
        std::fs::write(sub.join("a.bin"), [1u8, 2, 3]).unwrap();
        std::fs::write(dir.join("outside.bin"), [0u8]).unwrap();
        let root = sub.canonicalize().unwrap();
        assert!(resolve_inside(&root, &root, Path::new("a.bin")).is_ok());
        assert!(resolve_inside(&root, &root, Path::new("../outside.bin"))
            .unwrap_err()
            .contains("outside"));
        assert!(resolve_inside(&root, &root, Path::new("/dev/zero")).is_err());
        assert!(resolve_inside(&root, &root, Path::new("missing.bin")).is_err());
        let budget = Budget::new(Path::new("t"), 2);
        assert!(matches!(
            read_capped(&root.join("a.bin"), &budget, "buffer"),
            Err(LoadError::TooLarge { .. })
        ));
        let budget = Budget::new(Path::new("t"), 100);
        assert!(read_capped(Path::new("/dev/zero"), &budget, "buffer").is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
