//! Loading a model or a scene file off the UI thread: the file is loaded and prepared
//! (triangulated) on a thread of its own with a [`Progress`] the status bar reads and the user
//! can cancel. A scene file (`.toml`, `.json`) is read and resolved against its model there
//! too ([`SceneFile::resolve`]), so a slow model never blocks the UI. The scene on screen
//! stays until a load succeeds; a failed load only shows its error.

use std::path::{Path, PathBuf};
use std::sync::mpsc::{channel, Receiver, TryRecvError};
use std::sync::Arc;
use std::time::Instant;

use crate::load::{self, LoadOptions, Progress, Stage};
use crate::mesh::NormalOptions;
use crate::render::{PreparedScene, Settings};
use crate::scene::Scene;
use crate::scenefile::{Format, ModelSource, SceneFile};
use crate::texture::UvGenerator;

/// An open scene file: what it names besides its settings, kept to save it again.
#[derive(Clone, Debug)]
pub struct OpenScene {
    /// The file as read (its `path`, its camera for the viewport's aspect).
    pub file: SceneFile,
    /// What it draws (for [`SceneFile::from_settings`]).
    pub model: ModelSource,
    /// The factor the model's own lights were scaled by.
    pub light_scale: f32,
}

/// What a scene file sets besides the scene itself.
pub struct FromFile {
    pub open: OpenScene,
    pub settings: Settings,
    /// What the viewer leaves out (e.g. the file's comparison layout).
    pub notes: Vec<String>,
}

/// Whether `path` names a scene file (by its extension: `.toml` or `.json`).
#[must_use]
pub fn is_scene_file(path: &Path) -> bool {
    Format::of(path).is_some()
}

/// A model loaded and prepared.
pub struct Loaded {
    pub path: PathBuf,
    /// `base` prepared with the texture coordinates of `uv`.
    pub scene: Arc<PreparedScene>,
    /// The scene with its file's own texture coordinates (what another UV choice starts
    /// from).
    pub base: Arc<Scene>,
    /// The UV generator `scene` was made with (`None`: the file's coordinates).
    pub uv: Option<UvGenerator>,
    /// Wall-clock milliseconds of load + prepare.
    pub millis: f64,
    /// Set when `path` is a scene file.
    pub from_file: Option<FromFile>,
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

/// Loads and prepares `path` (a model, or a scene file and its model) in the calling
/// thread, with the texture coordinates of `uv` (the textbook's §9.5; `None` keeps the
/// file's). A scene file's own `uv` key takes the place of `uv`.
///
/// # Errors
/// The loader's (or the scene file's) one-line message naming the file.
pub fn load_now(
    path: &Path,
    normals: NormalOptions,
    uv: Option<UvGenerator>,
    progress: Option<Arc<Progress>>,
) -> Outcome {
    let t = Instant::now();
    let opts = LoadOptions {
        normals,
        progress,
        ..LoadOptions::default()
    };
    let (scene, uv, from_file) = if is_scene_file(path) {
        // The model is loaded with its own coordinates (the base the viewer's UV choice
        // starts from) and the file's `uv` generator applied after, as any other choice.
        let mut file = SceneFile::read(path).map_err(|e| e.to_string())?;
        let file_uv = file.uv();
        file.set_uv(None);
        let mut l = file.resolve(&opts).map_err(|e| e.to_string())?;
        l.file.set_uv(file_uv);
        let mut notes = Vec::new();
        if l.comparison.is_some() {
            notes.push("its [compare] layout is for `realist render`".to_owned());
        }
        let from_file = FromFile {
            open: OpenScene {
                file: l.file,
                model: l.model,
                light_scale: l.light_scale,
            },
            settings: l.settings,
            notes,
        };
        (l.scene, file_uv, Some(from_file))
    } else {
        (
            load::load(path, &opts).map_err(|e| e.to_string())?,
            uv,
            None,
        )
    };
    // A file that draws nothing (a text file named `.obj`) is an error: the scene on
    // screen stays.
    scene.check_drawable(path)?;
    let base = Arc::new(scene);
    let scene = Arc::new(super::lab::prepare(&base, uv));
    Ok(Loaded {
        path: path.to_owned(),
        scene,
        base,
        uv,
        millis: t.elapsed().as_secs_f64() * 1e3,
        from_file,
    })
}

impl LoadTask {
    /// Starts loading `path` on a new thread; `done` is called when it finishes (e.g. to
    /// wake the UI).
    #[must_use]
    pub fn start(
        path: PathBuf,
        normals: NormalOptions,
        uv: Option<UvGenerator>,
        done: Arc<dyn Fn() + Send + Sync>,
    ) -> Self {
        let progress = Progress::new();
        let (tx, rx) = channel();
        let (p, pr) = (path.clone(), Arc::clone(&progress));
        // If the thread cannot start, the closure (and `tx`) is dropped and `poll` reports
        // the disconnected channel as an error.
        let _ = std::thread::Builder::new()
            .name("realist-load".into())
            .spawn(move || {
                let out = load_now(&p, normals, uv, Some(pr));
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
