//! [`ViewerApp`]: the viewer's state and its whole UI in [`ViewerApp::ui_contents`], which
//! `eframe::App::ui` calls and the UI tests drive directly.
//!
//! Each UI pass: take a finished frame from the worker (upload it once), lay out the
//! panels and the viewport (which turn input into camera moves and setting changes), then
//! submit a render job if the view or the settings differ from the last job's.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use eframe::egui::{self, ColorImage, TextureHandle, TextureOptions};

use super::files::{sibling_model, FileWatcher, RecentFiles};
use super::lab::{self, UvTask};
use super::loader::{self, FromFile, LoadTask, Loaded, OpenScene};
use super::navigate::Navigator;
use super::panels::{Command, Cx, Installed, Panel, Panels, Session, Shared, UvView};
use super::timeline::Timeline;
use super::viewport::ViewportState;
use super::worker::{Frame, Job, Level, RenderHost};
use crate::mesh::NormalOptions;
use crate::raster::TileCost;
use crate::render::{FrameReport, PreparedScene, Settings, View};
use crate::scene;
use crate::scenefile::{ModelSource, SceneFile};
use crate::texture::UvGenerator;

/// How the viewer starts.
#[derive(Clone, Debug, Default)]
pub struct ViewerOptions {
    /// A model or a scene file (`.toml`, `.json`) to open (else the built-in demo).
    pub model: Option<PathBuf>,
    /// Load and render in the calling thread, each job at its final quality (UI tests).
    pub synchronous: bool,
    /// Where the recent-files list lives (`None`: the user's config folder).
    pub recent_file: Option<PathBuf>,
    /// Render threads (0 = all cores).
    pub threads: usize,
    /// Start with the side panels hidden (Tab shows them).
    pub hide_panels: bool,
    /// Open animated files paused (else they play at once, looping).
    pub paused: bool,
}

/// The A | B split view.
#[derive(Clone, Debug)]
pub struct Split {
    pub enabled: bool,
    /// The divider's position as a fraction of the viewport width.
    pub divider: f32,
    /// The right half's settings.
    pub b: Settings,
    /// Show the ΔE00 difference of A and B in the right half instead of B.
    pub heat: bool,
}

/// A frame on screen: its textures and what the panels read about it.
pub struct Shown {
    pub job: u64,
    pub level: Level,
    pub view: View,
    pub last: bool,
    pub a: Arc<ColorImage>,
    pub tex_a: TextureHandle,
    pub tex_b: Option<TextureHandle>,
    pub tex_heat: Option<TextureHandle>,
    pub report_a: FrameReport,
    pub report_b: Option<FrameReport>,
    pub tile_costs: Vec<TileCost>,
    pub tiles_x: u32,
    pub depth: Vec<f32>,
    /// ΔE00 mean and 95th percentile of the split view.
    pub heat: Option<(f64, f64)>,
    /// When it arrived, and the frame before's arrival (for frames per second).
    pub arrived: Instant,
    pub interval: Option<f64>,
}

/// The viewer.
pub struct ViewerApp {
    /// What is drawn: `base` with the texture coordinates of `shown_uv`.
    pub scene: Arc<PreparedScene>,
    /// The scene as loaded, with its file's own texture coordinates.
    base: Arc<scene::Scene>,
    /// The UV generator asked for (the texture lab's "UV map"; `None`: the file's UVs). Kept
    /// when the model is reloaded; a newly opened file starts with its own (a scene file
    /// with its `uv` key).
    pub uv: Option<UvGenerator>,
    /// The UV generator `scene` was made with (differs from `uv` while `uv_task` runs).
    pub shown_uv: Option<UvGenerator>,
    /// Texture coordinates being generated off the UI thread.
    pub uv_task: Option<UvTask>,
    /// The file the scene came from, a model or a scene file (`None`: the built-in demo).
    pub model: Option<PathBuf>,
    /// The scene file open (then `model` is its path), for saving it again.
    pub scene_file: Option<OpenScene>,
    pub load_millis: Option<f64>,
    pub settings: Settings,
    pub split: Split,
    pub nav: Navigator,
    /// Refine a still image up to this many samples per axis (1, 2 or 4).
    pub max_samples: u32,
    pub normals: NormalOptions,
    pub host: RenderHost,
    pub shown: Option<Shown>,
    /// The last job submitted.
    last_job: Option<Job>,
    /// The camera moved by input during this UI pass.
    pub interacting: bool,
    pub loading: Option<LoadTask>,
    synchronous: bool,
    /// The last load's error, shown until the next success or dismissal.
    pub error: Option<String>,
    pub recent: RecentFiles,
    recent_file: Option<PathBuf>,
    watcher: Option<FileWatcher>,
    file_changed: Arc<AtomicBool>,
    repaint: Arc<dyn Fn() + Send + Sync>,
    /// Every panel, each with its own state.
    pub panels: Panels,
    /// What the panels, the viewport and the keys share (toggles, the probed pixel).
    pub shared: Shared,
    /// The last "Save scene": the message, or why not.
    saved: Option<Result<String, String>>,
    pub viewport: ViewportState,
    /// A short message for the status bar (e.g. where a screenshot went).
    pub notice: Option<String>,
    /// Animation playback.
    pub timeline: Timeline,
    /// The sphere around every pose of the open scene's animations (`None`: a still
    /// scene), for framing it.
    pub motion_sphere: Option<(glam::Vec3, f32)>,
    /// Frame the scene (or take the scene file's camera) for the viewport's aspect once its
    /// size is known (a new scene).
    frame_pending: bool,
    /// The window title last asked for.
    title: String,
    /// `REALIST_VIEWER_LOG=FILE`: one JSON line per frame shown and per UI pass, for
    /// measuring frame times and the time from launch to the first frame.
    trace: Option<std::fs::File>,
}

impl ViewerApp {
    /// A viewer on `opts.model` (or the demo). A model that fails to load leaves the demo on
    /// screen with the error shown.
    ///
    /// # Errors
    /// If the render thread cannot start.
    pub fn new(opts: ViewerOptions, repaint: Arc<dyn Fn() + Send + Sync>) -> Result<Self, String> {
        let host = if opts.synchronous {
            RenderHost::synchronous()
        } else {
            RenderHost::threaded(opts.threads, Arc::clone(&repaint))
                .map_err(|e| format!("could not start the render thread: {e}"))?
        };
        // With a model to open, nothing is shown until it loads (the demo only if it fails).
        let scene = Arc::new(PreparedScene::new(if opts.model.is_some() {
            scene::Scene::default()
        } else {
            scene::demo()
        }));
        let (center, radius) = scene.bounding_sphere();
        let nav = match scene.scene().cameras.first() {
            Some(cam) => Navigator::from_camera(cam, center, radius, Default::default()),
            None => Navigator::new(center, radius, 16.0 / 10.0),
        };
        // A corrupt list is not worth stopping for: start empty and say why.
        let (recent, recent_problem) = match &opts.recent_file {
            Some(p) => RecentFiles::load_from(p),
            None => RecentFiles::load(),
        };
        let mut app = Self {
            base: Arc::clone(scene.scene()),
            scene,
            uv: None,
            shown_uv: None,
            uv_task: None,
            model: None,
            scene_file: None,
            load_millis: None,
            settings: Settings::default(),
            split: Split {
                enabled: false,
                divider: 0.5,
                b: Settings {
                    shading: Some(crate::shade::Shading::Gouraud),
                    ..Settings::default()
                },
                heat: false,
            },
            nav,
            max_samples: 4,
            normals: NormalOptions::default(),
            host,
            shown: None,
            last_job: None,
            interacting: false,
            loading: None,
            synchronous: opts.synchronous,
            error: None,
            recent,
            recent_file: opts.recent_file,
            watcher: None,
            file_changed: Arc::new(AtomicBool::new(false)),
            repaint,
            panels: Panels::default(),
            shared: Shared::default(),
            saved: None,
            viewport: ViewportState::default(),
            notice: recent_problem,
            timeline: Timeline::default(),
            motion_sphere: None,
            frame_pending: true,
            title: String::new(),
            trace: std::env::var_os("REALIST_VIEWER_LOG")
                .and_then(|p| std::fs::File::create(p).ok()),
        };
        app.shared.panels_visible = !opts.hide_panels;
        app.timeline.autoplay = !opts.paused;
        app.installed(true, None);
        if let Some(m) = opts.model {
            app.open(m);
        }
        Ok(app)
    }

    /// Starts loading `path`, a model or a scene file (in the background, or now in
    /// synchronous mode).
    pub fn open(&mut self, path: PathBuf) {
        if let Some(t) = self.loading.take() {
            t.cancel();
        }
        // A reload keeps the UV choice; another file starts with its own coordinates.
        let same = self.model.as_deref() == Some(path.as_path());
        let uv = self.uv.filter(|_| same && !loader::is_scene_file(&path));
        if self.synchronous {
            let out = loader::load_now(&path, self.normals, uv, None);
            self.finish_load(out);
        } else {
            self.loading = Some(LoadTask::start(
                path,
                self.normals,
                uv,
                Arc::clone(&self.repaint),
            ));
        }
    }

    /// Installs a finished load, or shows its error (the current scene stays).
    fn finish_load(&mut self, out: loader::Outcome) {
        match out {
            Ok(Loaded {
                path,
                mut scene,
                base,
                uv,
                millis,
                from_file,
            }) => {
                // An animated scene is framed on where it moves, not only its rest pose.
                self.motion_sphere =
                    Arc::get_mut(&mut scene).and_then(super::timeline::motion_sphere);
                let (center, radius) = self
                    .motion_sphere
                    .unwrap_or_else(|| scene.bounding_sphere());
                let aspect = self.viewport.aspect();
                let same = self.model.as_deref() == Some(path.as_path());
                let file = from_file.is_some();
                let fresh = if let Some(f) = from_file {
                    // A scene file (opened or reloaded) sets everything it names: its
                    // settings now, its camera once the viewport's aspect is known.
                    self.nav = Navigator::new(center, radius, aspect);
                    self.frame_pending = true;
                    self.install_file_settings(f, &path);
                    true
                } else if same {
                    // A reload keeps the camera; only the scene's extent may have changed.
                    self.nav.new_scene(center, radius, aspect);
                    false
                } else {
                    self.nav = Navigator::new(center, radius, aspect);
                    self.frame_pending = true;
                    self.settings.materials = None;
                    true
                };
                if self.scene_file.is_some() && !loader::is_scene_file(&path) {
                    self.scene_file = None;
                }
                // A UV choice made during a reload of this model is generated next.
                let wanted = self.uv;
                let again = same && !loader::is_scene_file(&path) && wanted != uv;
                self.scene = scene;
                self.base = base;
                (self.uv, self.shown_uv, self.uv_task) = (uv, uv, None);
                if again {
                    self.set_uv_generator(wanted);
                }
                self.load_millis = Some(millis);
                self.error = None;
                self.recent.add(&path);
                self.save_state();
                self.watch(&path);
                self.model = Some(path);
                self.shared.probe = None;
                let taken = file.then(|| self.settings.clone());
                self.installed(fresh, taken.as_ref());
            }
            Err(e) => {
                if self.model.is_none() && self.scene.scene().instances.is_empty() {
                    // The first model failed: show the demo rather than nothing.
                    self.open_demo();
                }
                self.error = Some(e);
            }
        }
    }

    /// Takes a scene file's settings (the camera follows in the next UI pass).
    fn install_file_settings(&mut self, f: FromFile, path: &Path) {
        let FromFile {
            open,
            settings,
            notes,
        } = f;
        // The split view's B side follows A's fog, shadows and ground (as the panel keeps
        // it); fog and ground turned off and on again come back as the file set them.
        self.split.b.fog = settings.fog;
        self.split.b.shadow = settings.shadow;
        self.split.b.ground = settings.ground;
        self.settings = settings;
        self.scene_file = Some(open);
        let mut notice = format!("opened scene file {}", path.display());
        for n in notes {
            notice += &format!("; {n}");
        }
        self.notice = Some(notice);
    }

    /// The open scene file's camera for a viewport of `aspect` (without a `[camera]`, the
    /// demo's own camera for `model = "demo"`, as `realist render` takes it); `None` when no
    /// scene file is open or it leaves the view to the viewer's framing.
    fn file_camera(&self, aspect: f32) -> Result<Option<scene::Camera>, String> {
        let Some(f) = &self.scene_file else {
            return Ok(None);
        };
        let scene = self.scene.scene();
        match f.file.camera(scene, aspect).map_err(|e| e.to_string())? {
            Some(c) => Ok(Some(c)),
            None if f.model == ModelSource::Demo => Ok(scene.cameras.first().cloned()),
            None => Ok(None),
        }
    }

    /// What [`ViewerApp::save_scene`] writes about the model: the open scene file's model
    /// and light scale, the model file (absolute), or the demo.
    #[must_use]
    pub fn model_source(&self) -> (ModelSource, f32) {
        match (&self.scene_file, &self.model) {
            (Some(f), _) => (f.model.clone(), f.light_scale),
            (None, Some(m)) => (
                ModelSource::File(std::path::absolute(m).unwrap_or_else(|_| m.clone())),
                1.0,
            ),
            (None, None) => (ModelSource::Demo, 1.0),
        }
    }

    /// Where "Save scene" writes unless told otherwise: the open scene file, else
    /// `scene.toml` next to the model (or in the working folder for the demo).
    #[must_use]
    pub fn default_save_path(&self) -> String {
        let path = match (&self.scene_file, &self.model) {
            (Some(f), _) => f.file.path.clone(),
            (None, Some(m)) => match m.parent() {
                Some(dir) if !dir.as_os_str().is_empty() => dir.join("scene.toml"),
                _ => PathBuf::from("scene.toml"),
            },
            (None, None) => PathBuf::from("scene.toml"),
        };
        path.display().to_string()
    }

    /// Saves the current scene (model, settings, camera at the viewport's size) as a scene
    /// file at `path` (`.toml` or `.json`), which becomes the open scene file. The viewer's
    /// refinement (`max_samples`) is saved as the file's `samples`, so `realist render`
    /// gives the still frame on screen. Returns the notes on what was left out.
    ///
    /// # Errors
    /// The one-line message (naming the file) when the extension is wrong or the file
    /// cannot be written; nothing changes then.
    pub fn save_scene(&mut self, path: &Path) -> Result<Vec<String>, String> {
        let (model, light_scale) = self.model_source();
        let settings = Settings {
            samples: self.max_samples,
            ..self.settings.clone()
        };
        let view = self.current_view();
        let (mut file, notes) = SceneFile::from_settings(&model, light_scale, &settings, &view);
        file.set_uv(self.uv);
        file.save(path).map_err(|e| e.to_string())?;
        // The saved file is now the one open (as "save as" does); the recent list and the
        // watcher follow, the watcher anew so that this write is not taken for a change.
        self.scene_file = Some(OpenScene {
            file,
            model,
            light_scale,
        });
        self.recent.add(path);
        self.save_state();
        self.watch(path);
        self.file_changed.store(false, Ordering::SeqCst);
        self.model = Some(path.to_owned());
        Ok(notes)
    }

    /// Watches the current model for changes (reloaded when it changes on disk).
    fn watch(&mut self, path: &Path) {
        if self.synchronous {
            return;
        }
        let (flag, repaint) = (Arc::clone(&self.file_changed), Arc::clone(&self.repaint));
        self.watcher = FileWatcher::new(
            path,
            Box::new(move || {
                flag.store(true, Ordering::SeqCst);
                repaint();
            }),
        )
        .ok();
    }

    /// Shows the built-in demo scene again.
    pub fn open_demo(&mut self) {
        if let Some(t) = self.loading.take() {
            t.cancel();
        }
        let scene = Arc::new(PreparedScene::new(scene::demo()));
        self.motion_sphere = None;
        self.base = Arc::clone(scene.scene());
        (self.uv, self.shown_uv, self.uv_task) = (None, None, None);
        let (center, radius) = scene.bounding_sphere();
        self.nav = match scene.scene().cameras.first() {
            Some(cam) => Navigator::from_camera(cam, center, radius, Default::default()),
            None => Navigator::new(center, radius, self.viewport.aspect()),
        };
        self.scene = scene;
        self.frame_pending = true;
        self.model = None;
        self.scene_file = None;
        self.watcher = None;
        self.settings.materials = None;
        self.installed(true, None);
    }

    /// Tells the panels that a scene was installed (`fresh`: another scene; `settings`: a
    /// scene file's), and forgets the probed pixel and the hovered light.
    fn installed(&mut self, fresh: bool, settings: Option<&Settings>) {
        if fresh {
            self.shared.probe = None;
            self.shared.hovered_light = None;
        }
        self.panels.installed(&Installed {
            fresh,
            settings,
            save_path: self.default_save_path(),
        });
    }

    /// Opens the previous (`step` = -1) or next (+1) model in the current model's folder.
    pub fn step_file(&mut self, step: i32) {
        match self.model.as_deref().and_then(|m| sibling_model(m, step)) {
            Some(p) => self.open(p),
            None => self.notice = Some("no other model in this folder".into()),
        }
    }

    /// Draws the model with the texture coordinates of `uv` (the textbook's §9.5; `None`:
    /// the file's own): generated from the scene as loaded, off the UI thread (now in
    /// synchronous mode), then drawn in place of the scene on screen. The camera, the
    /// settings and the split view stay as they are.
    pub fn set_uv_generator(&mut self, uv: Option<UvGenerator>) {
        self.uv = uv;
        if uv == self.shown_uv {
            self.uv_task = None;
            return;
        }
        if self.uv_task.as_ref().is_some_and(|t| t.uv == uv) {
            return;
        }
        if self.synchronous {
            let scene = Arc::new(lab::prepare(&self.base, uv));
            self.install_uv(scene, uv);
        } else {
            self.uv_task = Some(UvTask::start(
                Arc::clone(&self.base),
                uv,
                Arc::clone(&self.repaint),
            ));
        }
    }

    /// Draws `scene`, the scene as loaded with the coordinates of `uv`.
    fn install_uv(&mut self, scene: Arc<PreparedScene>, uv: Option<UvGenerator>) {
        self.scene = scene;
        self.shown_uv = uv;
        self.uv_task = None;
        // The probe's UV and shading belong to the old coordinates.
        self.shared.probe = None;
        self.notice = Some(match uv {
            None => "texture coordinates: the model's own".to_owned(),
            Some(g) => {
                format!("texture coordinates: the {g} map on every mesh (the textbook's §9.5)")
            }
        });
    }

    /// Reloads the current model.
    pub fn reload(&mut self) {
        if let Some(m) = self.model.clone() {
            self.open(m);
        }
    }

    /// Saves what persists between runs (the recent files).
    pub fn save_state(&mut self) {
        // Losing the recent list is not worth an error dialog.
        let _ = match &self.recent_file {
            Some(p) => self.recent.save_to(p),
            None => self.recent.save(),
        };
    }

    /// The whole UI.
    pub fn ui_contents(&mut self, ui: &mut egui::Ui) {
        let pass = Instant::now();
        self.interacting = false;
        self.poll_background();
        self.take_frames(ui.ctx());
        let mut commands = Vec::new();
        {
            let (mut cx, panels, timeline) = self.parts(&mut commands);
            panels.poll(&mut cx);
            panels.keyboard(ui, &mut cx);
            panels.menu_bar(ui, &mut cx);
            panels.status_bar(ui, &mut cx);
            timeline.bar(cx.session.scene.scene(), ui);
            if cx.shared.panels_visible {
                panels.side_panels(ui, &mut cx);
            }
            egui::CentralPanel::default()
                .frame(egui::Frame::NONE)
                .show(ui, |ui| super::viewport::show(&mut cx, ui));
            panels.windows(ui, &mut cx);
        }
        for c in commands {
            self.apply(c);
        }
        if self.frame_pending && self.viewport.size_px[0] > 0 {
            // Framed for the viewport's real aspect (a portrait window needs more distance),
            // or the scene file's camera with that aspect (the window keeps its size).
            let (center, radius) = self
                .motion_sphere
                .unwrap_or_else(|| self.scene.bounding_sphere());
            let aspect = self.viewport.aspect();
            match self.file_camera(aspect) {
                Ok(Some(cam)) => {
                    self.nav = Navigator::from_camera(&cam, center, radius, self.nav.up_axis());
                }
                other => {
                    if let Err(e) = other {
                        self.error = Some(e);
                    }
                    self.nav.frame(center, radius, aspect);
                    self.nav.set_home();
                }
            }
            self.frame_pending = false;
        }
        self.update_title(ui.ctx());
        let behind = self
            .shown
            .as_ref()
            .is_some_and(|s| s.job != self.host.submitted())
            && self.host.busy();
        self.interacting |= self.timeline.step(
            &mut self.scene,
            &self.base,
            behind,
            self.synchronous,
            ui.ctx(),
        );
        self.submit_if_changed();
        if self.loading.is_some() {
            // The progress bar moves: look again in a moment (nothing else polls).
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(100));
        }
        let line = format!(
            r#"{{"event":"ui","t_ms":{:.3},"ui_ms":{:.3},"interacting":{}}}"#,
            super::since_launch_ms(),
            pass.elapsed().as_secs_f64() * 1e3,
            self.interacting
        );
        self.trace_line(&line);
    }

    /// The panels' view of the app for one pass (see [`Cx`]), the panels and the timeline,
    /// borrowed apart.
    fn parts<'a>(
        &'a mut self,
        commands: &'a mut Vec<Command>,
    ) -> (Cx<'a>, &'a mut Panels, &'a mut Timeline) {
        let settled = self.settled();
        let session = Session {
            scene: &self.scene,
            shown: self.shown.as_ref(),
            model: self.model.as_deref(),
            scene_file: self.scene_file.as_ref(),
            load_millis: self.load_millis,
            loading: self.loading.as_ref(),
            error: self.error.as_deref(),
            notice: self.notice.as_deref(),
            recent: self.recent.list(),
            uv: UvView {
                chosen: self.uv,
                pending: self.uv_task.is_some(),
            },
            synchronous: self.synchronous,
            repaint: &self.repaint,
            playing: self.timeline.playing,
            settled,
            saved: self.saved.as_ref(),
        };
        let cx = Cx {
            settings: &mut self.settings,
            split: &mut self.split,
            max_samples: &mut self.max_samples,
            nav: &mut self.nav,
            shared: &mut self.shared,
            viewport: &mut self.viewport,
            interacting: &mut self.interacting,
            session,
            commands,
        };
        (cx, &mut self.panels, &mut self.timeline)
    }

    /// Runs `f` on the panel of type `P` with the panels' view of the app, then does what
    /// it asked (for tests and scripted use: what a click in that panel would do).
    /// `None` if there is no such panel.
    pub fn with_panel<P: Panel, R>(
        &mut self,
        f: impl FnOnce(&mut P, &mut Cx<'_>) -> R,
    ) -> Option<R> {
        let mut commands = Vec::new();
        let out = {
            let (mut cx, panels, _) = self.parts(&mut commands);
            let p = panels.get_mut::<P>()?;
            f(p, &mut cx)
        };
        for c in commands {
            self.apply(c);
        }
        Some(out)
    }

    /// Does what a panel asked.
    fn apply(&mut self, c: Command) {
        match c {
            Command::Open(p) => self.open(p),
            Command::OpenDemo => self.open_demo(),
            Command::Reload => self.reload(),
            Command::StepFile(step) => self.step_file(step),
            Command::SaveScene(path) => self.save_scene_reported(&path),
            Command::SetUv(uv) => self.set_uv_generator(uv),
            Command::TogglePlay => {
                let scene = Arc::clone(self.scene.scene());
                if scene.animations.is_empty() {
                    self.notice = Some("this scene has no animation".into());
                } else {
                    let length = super::timeline::duration(&scene, self.timeline.play);
                    self.timeline.toggle(length);
                }
            }
            Command::Notice(n) => self.notice = Some(n),
            Command::Error(e) => self.error = Some(e),
            Command::DismissError => self.error = None,
        }
    }

    /// Saves the scene file at `path` ([`ViewerApp::save_scene`]) and says how it went in
    /// the status bar and the scene file section.
    pub fn save_scene_reported(&mut self, path: &Path) {
        let result = if path.as_os_str().is_empty() {
            Err("no path to save the scene file to".to_owned())
        } else {
            self.save_scene(path).map(|notes| {
                let shown = std::path::absolute(path).unwrap_or_else(|_| path.to_owned());
                let mut msg = format!("saved scene file {}", shown.display());
                if !notes.is_empty() {
                    msg += &format!(" (left out: {})", notes.join("; "));
                }
                msg
            })
        };
        match &result {
            Ok(msg) => {
                self.notice = Some(msg.clone());
                self.error = None;
            }
            Err(e) => self.error = Some(e.clone()),
        }
        self.saved = Some(result);
    }

    /// Names the open file in the window's title when it changes.
    fn update_title(&mut self, ctx: &egui::Context) {
        let title = format!("realist: {}", self.scene_name());
        if title != self.title {
            ctx.send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.title = title;
        }
    }

    fn trace_line(&mut self, line: &str) {
        use std::io::Write as _;
        if let Some(f) = &mut self.trace {
            let _ = writeln!(f, "{line}");
        }
    }

    /// The scene as loaded (before the texture lab's coordinates).
    #[must_use]
    pub fn base_scene(&self) -> Arc<scene::Scene> {
        Arc::clone(&self.base)
    }

    /// Whether loads and renders run in the calling thread (UI tests).
    #[must_use]
    pub fn is_synchronous(&self) -> bool {
        self.synchronous
    }

    /// What wakes the UI from another thread.
    #[must_use]
    pub fn repaint_handle(&self) -> Arc<dyn Fn() + Send + Sync> {
        Arc::clone(&self.repaint)
    }

    /// Loads that finished (models, texture coordinates), and files that changed on disk
    /// (the panels' own background work is theirs: [`Panel::poll`]).
    fn poll_background(&mut self) {
        if let Some(out) = self.loading.as_ref().and_then(LoadTask::poll) {
            self.loading = None;
            self.finish_load(out);
        }
        let uv = self
            .uv_task
            .as_ref()
            .and_then(|t| Some((Arc::clone(&t.base), t.uv, t.poll()?)));
        if let Some((base, uv, out)) = uv {
            self.uv_task = None;
            match out {
                // Made for a scene since replaced (a load finished meanwhile): dropped.
                Ok(_) if !Arc::ptr_eq(&base, &self.base) => {}
                Ok(scene) => self.install_uv(scene, uv),
                Err(e) => {
                    self.uv = self.shown_uv;
                    self.error = Some(e);
                }
            }
        }
        if self.file_changed.swap(false, Ordering::SeqCst) && self.loading.is_none() {
            self.notice = Some("file changed on disk: reloaded".into());
            self.reload();
        }
    }

    /// Uploads the newest finished frame.
    fn take_frames(&mut self, ctx: &egui::Context) {
        let Some(frame) = self.host.take_frame() else {
            return;
        };
        let Frame {
            job,
            level,
            view,
            a,
            b,
            heat,
            depth,
            last,
        } = frame;
        let size = [view.width as usize, view.height as usize];
        let opts = if matches!(level, Level::Reduced(_)) {
            TextureOptions::LINEAR
        } else {
            TextureOptions::NEAREST
        };
        let img_a = Arc::new(ColorImage::new(size, a.pixels));
        let upload = |old: Option<TextureHandle>, name: &str, img: Arc<ColorImage>| {
            match old {
                // In place when the size is unchanged (glTexSubImage2D), else reallocated.
                Some(mut t) if t.size() == size => {
                    t.set_partial([0, 0], img, opts);
                    t
                }
                Some(mut t) => {
                    t.set(img, opts);
                    t
                }
                None => ctx.load_texture(name, img, opts),
            }
        };
        let old = self.shown.take();
        let (old_a, old_b, old_h, prev) = match old {
            Some(s) => (Some(s.tex_a), s.tex_b, s.tex_heat, Some(s.arrived)),
            None => (None, None, None, None),
        };
        let tex_a = upload(old_a, "frame-a", Arc::clone(&img_a));
        let (tex_b, report_b) = match b {
            Some(b) => (
                Some(upload(
                    old_b,
                    "frame-b",
                    Arc::new(ColorImage::new(size, b.pixels)),
                )),
                Some(b.report),
            ),
            None => (None, None),
        };
        let (tex_heat, heat) = match heat {
            Some(h) if h.pixels.len() == size[0] * size[1] => (
                Some(upload(
                    old_h,
                    "frame-heat",
                    Arc::new(ColorImage::new(size, h.pixels)),
                )),
                Some((h.mean, h.p95)),
            ),
            _ => (None, None),
        };
        let now = Instant::now();
        let line = format!(
            r#"{{"event":"frame","t_ms":{:.3},"job":{job},"level":"{}","width":{},"height":{},"render_ms":{:.3},"first":{}}}"#,
            super::since_launch_ms(),
            level.label(),
            view.width,
            view.height,
            a.report.times.total,
            prev.is_none()
        );
        self.trace_line(&line);
        self.shown = Some(Shown {
            job,
            level,
            view,
            last,
            a: img_a,
            tex_a,
            tex_b,
            tex_heat,
            report_a: a.report,
            report_b,
            tile_costs: a.tile_costs,
            tiles_x: a.tiles_x,
            depth,
            heat,
            arrived: now,
            interval: prev.map(|p| now.duration_since(p).as_secs_f64() * 1e3),
        });
    }

    /// The view of the viewport as it is now.
    #[must_use]
    pub fn current_view(&self) -> View {
        super::viewport::view_of(&self.nav, &self.viewport)
    }

    /// Submits a job if the view, the scene or the settings changed since the last one.
    fn submit_if_changed(&mut self) {
        if self.viewport.size_px[0] == 0 {
            return;
        }
        let view = self.current_view();
        let b = self.split.enabled.then_some(&self.split.b);
        let heat = self.split.enabled && self.split.heat;
        let same = self.last_job.as_ref().is_some_and(|j| {
            Arc::ptr_eq(&j.scene, &self.scene)
                && j.view == view
                && super::same::same(&j.a, &self.settings)
                && match (j.b.as_deref(), b) {
                    (Some(x), Some(y)) => super::same::same(x, y),
                    (x, y) => x.is_none() && y.is_none(),
                }
                && j.heat == heat
                && j.max_samples == self.max_samples
        });
        if same {
            return;
        }
        let job = Job {
            scene: Arc::clone(&self.scene),
            a: Arc::new(self.settings.clone()),
            b: b.map(|s| Arc::new(s.clone())),
            heat,
            view,
            interactive: self.interacting,
            max_samples: self.max_samples,
        };
        self.last_job = Some(job.clone());
        self.host.submit(job);
        if self.synchronous {
            // The frame is ready now; show it in this pass's successor.
            (self.repaint)();
        }
    }

    /// The frame on screen is the final one for the current view and settings.
    #[must_use]
    pub fn settled(&self) -> bool {
        self.shown
            .as_ref()
            .is_some_and(|s| s.last && s.job == self.host.submitted())
            && !self.host.busy()
    }

    /// The name shown for the scene: the file name or "demo", for a scene file also what it
    /// draws ("scene.toml (torus.obj)").
    #[must_use]
    pub fn scene_name(&self) -> String {
        scene_name(self.model.as_deref(), self.scene_file.as_ref())
    }

    /// The panel of type `P`.
    #[must_use]
    pub fn panel<P: Panel>(&self) -> Option<&P> {
        self.panels.get::<P>()
    }
}

/// The name shown for a scene from `model` (`None`: the demo), opened through `scene_file`.
#[must_use]
pub fn scene_name(model: Option<&Path>, scene_file: Option<&OpenScene>) -> String {
    let name = |p: &Path| {
        p.file_name().map_or_else(
            || p.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        )
    };
    let file = model.map(name);
    match (scene_file, file) {
        (Some(f), Some(file)) => {
            let drawn = match &f.model {
                ModelSource::Demo => "demo".to_owned(),
                ModelSource::File(m) => name(m),
                ModelSource::Primitive(_) => "primitive".to_owned(),
            };
            format!("{file} ({drawn})")
        }
        (_, Some(file)) => file,
        (_, None) => "demo (the textbook's figure 9-8)".into(),
    }
}
