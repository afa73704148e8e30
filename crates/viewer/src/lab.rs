//! The texture lab's work off the UI thread, the way [`super::loader`] loads models: an
//! image file decoded for one material slot, and a model's texture coordinates generated
//! by a [`UvGenerator`] (the textbook's §9.5) and the scene prepared again. Each runs on a
//! thread of its own and wakes the UI when it is done; nothing here panics on a bad file:
//! a failure is a one-line message that starts with the file's path.

use std::path::{Path, PathBuf};
use std::sync::mpsc::{channel, Receiver, TryRecvError};
use std::sync::Arc;

use super::panels::Side;
use crate::render::PreparedScene;
use crate::scene::{Scene, Slot};
use crate::texture::{Texture, UvGenerator};

/// Work running on a thread of its own, and its result once it has finished.
pub struct Background<T> {
    rx: Receiver<T>,
    /// What the thread works on, for the message when it ends without a result.
    what: String,
}

impl<T: Send + 'static> Background<T> {
    /// Runs `work` on a new thread named `name`; `done` is called when it finishes (to
    /// wake the UI).
    pub fn start(
        name: &str,
        what: String,
        work: impl FnOnce() -> T + Send + 'static,
        done: Arc<dyn Fn() + Send + Sync>,
    ) -> Self {
        let (tx, rx) = channel();
        // If the thread cannot start (or panics), `tx` is dropped and `poll` says so.
        let _ = std::thread::Builder::new()
            .name(name.into())
            .spawn(move || {
                let _ = tx.send(work());
                done();
            });
        Self { rx, what }
    }

    /// The result, once the work has finished; `Err` if the thread ended without one.
    pub fn poll(&self) -> Option<Result<T, String>> {
        match self.rx.try_recv() {
            Ok(out) => Some(Ok(out)),
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => Some(Err(format!(
                "{}: the thread ended without a result",
                self.what
            ))),
        }
    }
}

/// A decoded image, or the one-line error naming the file.
pub type ImageOutcome = Result<Arc<Texture>, String>;

/// Reads `path` for `slot` with the loader `realist render --texture IMG` uses
/// ([`crate::load::load_image`]; colour slots sRGB-decoded, data slots linear). The texture
/// is named by the file's absolute path, so that a saved scene file can name it.
///
/// # Errors
/// The loader's one-line message, which starts with the path: missing, unreadable, too
/// large, not an image, corrupt.
pub fn read_image(path: &Path, slot: Slot) -> ImageOutcome {
    let mut t = crate::load::load_image(path, slot.srgb()).map_err(|e| e.to_string())?;
    t.name = std::fs::canonicalize(path)
        .or_else(|_| std::path::absolute(path))
        .unwrap_or_else(|_| path.to_owned())
        .display()
        .to_string();
    Ok(Arc::new(t))
}

/// An image being read for one slot of one side of the split view.
pub struct ImageLoad {
    pub side: Side,
    pub slot: Slot,
    pub path: PathBuf,
    task: Background<ImageOutcome>,
}

impl ImageLoad {
    /// Starts reading `path` for `slot` of `side` on a new thread.
    #[must_use]
    pub fn start(side: Side, slot: Slot, path: PathBuf, done: Arc<dyn Fn() + Send + Sync>) -> Self {
        let p = path.clone();
        let task = Background::start(
            "realist-image",
            path.display().to_string(),
            move || read_image(&p, slot),
            done,
        );
        Self {
            side,
            slot,
            path,
            task,
        }
    }

    /// The outcome, once reading has finished.
    #[must_use]
    pub fn poll(&self) -> Option<ImageOutcome> {
        self.task.poll().map(|r| r.and_then(|o| o))
    }
}

/// `base` (a scene as loaded, with its file's texture coordinates) prepared for drawing with
/// the coordinates of `uv`: `None` keeps the file's (and shares `base`), a generator replaces
/// UV set 0 of every mesh in a copy ([`Scene::apply_uv_generator`]).
#[must_use]
pub fn prepare(base: &Arc<Scene>, uv: Option<UvGenerator>) -> PreparedScene {
    match uv {
        None => PreparedScene::new(Arc::clone(base)),
        Some(g) => {
            let mut scene = Scene::clone(base);
            scene.apply_uv_generator(&g);
            PreparedScene::new(scene)
        }
    }
}

/// Texture coordinates being generated for a scene.
pub struct UvTask {
    /// The scene they are generated for (the result is dropped if another scene has
    /// replaced it meanwhile).
    pub base: Arc<Scene>,
    pub uv: Option<UvGenerator>,
    task: Background<Arc<PreparedScene>>,
}

impl UvTask {
    /// Starts [`prepare`] on a new thread.
    #[must_use]
    pub fn start(
        base: Arc<Scene>,
        uv: Option<UvGenerator>,
        done: Arc<dyn Fn() + Send + Sync>,
    ) -> Self {
        let b = Arc::clone(&base);
        let task = Background::start(
            "realist-uv",
            format!("{}: the {} map", base.report.file, uv_name(uv)),
            move || Arc::new(prepare(&b, uv)),
            done,
        );
        Self { base, uv, task }
    }

    /// The prepared scene, once it is ready.
    #[must_use]
    pub fn poll(&self) -> Option<Result<Arc<PreparedScene>, String>> {
        self.task.poll()
    }
}

/// The name of a UV choice as `--uv` and the scene-file key `uv` write it.
#[must_use]
pub fn uv_name(uv: Option<UvGenerator>) -> String {
    uv.map_or_else(|| "mesh".to_owned(), |g| g.to_string())
}
