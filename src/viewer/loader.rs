//! Loading a model off the UI thread: the file is loaded and prepared (triangulated) on a
//! thread of its own with a [`Progress`] the status bar reads and the user can cancel. The
//! scene on screen stays until a load succeeds; a failed load only shows its error.

use std::path::{Path, PathBuf};
use std::sync::mpsc::{channel, Receiver, TryRecvError};
use std::sync::Arc;
use std::time::Instant;

use crate::load::{self, LoadOptions, Progress, Stage};
use crate::mesh::NormalOptions;
use crate::render::PreparedScene;

/// A model loaded and prepared.
pub struct Loaded {
    pub path: PathBuf,
    pub scene: Arc<PreparedScene>,
    /// Wall-clock milliseconds of load + prepare.
    pub millis: f64,
}

/// The outcome of a load: the model, or the one-line error (which names the file).
pub type Outcome = Result<Loaded, String>;

/// A load in progress.
pub struct LoadTask {
    pub path: PathBuf,
    progress: Arc<Progress>,
    rx: Receiver<Outcome>,
    started: Instant,
}

/// Loads and prepares `path` in the calling thread.
///
/// # Errors
/// The loader's one-line message naming the file.
pub fn load_now(path: &Path, normals: NormalOptions, progress: Option<Arc<Progress>>) -> Outcome {
    let t = Instant::now();
    let opts = LoadOptions {
        normals,
        progress,
        ..LoadOptions::default()
    };
    let scene = load::load(path, &opts).map_err(|e| e.to_string())?;
    let scene = Arc::new(PreparedScene::new(scene));
    Ok(Loaded {
        path: path.to_owned(),
        scene,
        millis: t.elapsed().as_secs_f64() * 1e3,
    })
}

impl LoadTask {
    /// Starts loading `path` on a new thread; `done` is called when it finishes (e.g. to
    /// wake the UI).
    #[must_use]
    pub fn start(path: PathBuf, normals: NormalOptions, done: Arc<dyn Fn() + Send + Sync>) -> Self {
        let progress = Progress::new();
        let (tx, rx) = channel();
        let (p, pr) = (path.clone(), Arc::clone(&progress));
        // If the thread cannot start, the closure (and `tx`) is dropped and `poll` reports
        // the disconnected channel as an error.
        let _ = std::thread::Builder::new()
            .name("realist-load".into())
            .spawn(move || {
                let out = load_now(&p, normals, Some(pr));
                let _ = tx.send(out);
                done();
            });
        Self {
            path,
            progress,
            rx,
            started: Instant::now(),
        }
    }

    /// The outcome, once the load has finished.
    pub fn poll(&self) -> Option<Outcome> {
        match self.rx.try_recv() {
            Ok(out) => Some(out),
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => Some(Err(format!(
                "{}: the loader thread ended without a result",
                self.path.display()
            ))),
        }
    }

    /// Asks the loader to stop; [`LoadTask::poll`] then reports the cancellation.
    pub fn cancel(&self) {
        self.progress.cancel();
    }

    /// The stage, the fraction done (if known) and the seconds since the start.
    #[must_use]
    pub fn status(&self) -> (Stage, Option<f32>, f32) {
        let (stage, fraction) = self.progress.snapshot();
        (stage, fraction, self.started.elapsed().as_secs_f32())
    }
}
