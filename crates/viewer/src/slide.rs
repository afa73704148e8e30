//! The image a rectangular spotlight projects (a slide, the textbook's pipeline chapter, §4.3),
//! read off the UI thread: a PNG or JPEG file decoded on a thread of its own, the way
//! [`super::loader`] loads models. A file that cannot be read or decoded gives a one-line error
//! that starts with its path; nothing panics and the light keeps the image it had.

use std::io::Read as _;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{channel, Receiver, TryRecvError};
use std::sync::Arc;

use crate::load::MAX_TEXTURE_SIDE;
use crate::texture::Texture;

/// Largest slide file read, in bytes.
pub const MAX_FILE_BYTES: u64 = 256 << 20;
/// Largest allocation the decoder may make, in bytes.
pub const MAX_DECODE_BYTES: u64 = 1 << 30;

/// The file extensions the picker offers.
pub const EXTENSIONS: [&str; 3] = ["png", "jpg", "jpeg"];

/// A decoded slide, or the one-line error naming the file.
pub type Outcome = Result<Arc<Texture>, String>;

/// Reads and decodes `path` into an sRGB texture, which the lighting samples with the projector's sampler (bilinear,
/// clamped to the edges).
///
/// # Errors
/// A one-line message starting with the path: unreadable, too large, not a PNG or JPEG,
/// corrupt.
pub fn decode(path: &Path) -> Result<Texture, String> {
    let fail = |why: String| format!("{}: {why}", path.display());
    let file = std::fs::File::open(path).map_err(|e| fail(e.to_string()))?;
    let meta = file.metadata().map_err(|e| fail(e.to_string()))?;
    if !meta.is_file() {
        return Err(fail("not a regular file".into()));
    }
    if meta.len() > MAX_FILE_BYTES {
        return Err(fail(format!(
            "{} bytes, more than the {MAX_FILE_BYTES} a slide may have",
            meta.len()
        )));
    }
    let mut bytes = Vec::new();
    file.take(MAX_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| fail(e.to_string()))?;
    let mut reader = image::ImageReader::new(std::io::Cursor::new(&bytes))
        .with_guessed_format()
        .map_err(|e| fail(e.to_string()))?;
    if reader.format().is_none() {
        return Err(fail("not a PNG or JPEG image".into()));
    }
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_TEXTURE_SIDE);
    limits.max_image_height = Some(MAX_TEXTURE_SIDE);
    limits.max_alloc = Some(MAX_DECODE_BYTES);
    reader.limits(limits);
    let rgba = reader
        .decode()
        .map_err(|e| fail(e.to_string().replace('\n', " ")))?
        .into_rgba8();
    let (w, h) = rgba.dimensions();
    let texels = rgba
        .as_raw()
        .chunks_exact(4)
        .map(|c| [c[0], c[1], c[2], c[3]])
        .collect();
    let name = path
        .file_name()
        .map_or_else(|| "slide".into(), |n| n.to_string_lossy().into_owned());
    // Sampled with the projector's sampler (`IMAGE_SAMPLER`) by the lighting.
    Texture::new(name, w, h, texels, true).map_err(|e| fail(e.to_string()))
}

/// A slide being decoded for light `light` of the editor's list.
pub struct SlideLoad {
    pub light: usize,
    pub path: PathBuf,
    rx: Receiver<Outcome>,
}

impl SlideLoad {
    /// Starts decoding `path` on a new thread; `done` is called when it finishes (to wake
    /// the UI).
    #[must_use]
    pub fn start(light: usize, path: PathBuf, done: Arc<dyn Fn() + Send + Sync>) -> Self {
        let (tx, rx) = channel();
        let p = path.clone();
        // If the thread cannot start, `tx` is dropped and `poll` reports it.
        let _ = std::thread::Builder::new()
            .name("realist-slide".into())
            .spawn(move || {
                let _ = tx.send(decode(&p).map(Arc::new));
                done();
            });
        Self { light, path, rx }
    }

    /// The outcome, once decoding has finished.
    #[must_use]
    pub fn poll(&self) -> Option<Outcome> {
        match self.rx.try_recv() {
            Ok(out) => Some(out),
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => Some(Err(format!(
                "{}: the decoding thread ended without a result",
                self.path.display()
            ))),
        }
    }
}
