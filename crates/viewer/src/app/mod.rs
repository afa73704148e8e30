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

mod frames;

mod session;

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
    /// The world's up axis (`--up z` for scans that lie on their back; Ctrl+Y / Ctrl+Z
    /// change it, and it stays for the next file).
    pub up: Option<scene::Up>,
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
    /// B has been given A's settings (the first time the split was turned on).
    pub started: bool,
}

impl Split {
    /// Turns the split on or off; the first time it is turned on, B starts as a copy of
    /// `a` (so changing one thing on B compares just that), and keeps its own after.
    pub fn set_enabled(&mut self, on: bool, a: &Settings) {
        if on && !self.started {
            self.b = a.clone();
            self.started = true;
        }
        self.enabled = on;
    }
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
    /// The simplified copy of a very large scene, for frames while the camera moves.
    proxy: frames::Proxy,
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
    /// The full-screen state last asked of the window (F11 sends a change once), and the
    /// one the window last reported.
    pub fullscreen_sent: bool,
    fullscreen_seen: Option<bool>,
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
        let mut nav = match scene.scene().cameras.first() {
            Some(cam) => Navigator::from_camera(cam, center, radius, Default::default()),
            None => Navigator::new(center, radius, 16.0 / 10.0),
        };
        if let Some(up) = opts.up {
            nav.set_up_axis(up.into(), 16.0 / 10.0);
        }
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
                b: Settings::default(),
                heat: false,
                started: false,
            },
            nav,
            max_samples: 4,
            normals: NormalOptions::default(),
            host,
            shown: None,
            last_job: None,
            proxy: frames::Proxy::default(),
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
            fullscreen_sent: false,
            fullscreen_seen: None,
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
        // Full screen entered or left by the window manager: F11 toggles from there.
        let reported = ui.ctx().input(|i| i.viewport().fullscreen);
        if reported.is_some() && reported != self.fullscreen_seen {
            self.fullscreen_seen = reported;
            if let Some(f) = reported {
                self.shared.fullscreen = f;
                self.fullscreen_sent = f;
            }
        }
        if self.shared.fullscreen != self.fullscreen_sent {
            self.fullscreen_sent = self.shared.fullscreen;
            ui.ctx()
                .send_viewport_cmd(egui::ViewportCommand::Fullscreen(self.shared.fullscreen));
        }
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

    /// Names the open file in the window's title when it changes.
    fn update_title(&mut self, ctx: &egui::Context) {
        let title = if super::panels::nothing_open(self.model.as_deref(), &self.scene) {
            "realist".to_owned()
        } else {
            format!("realist: {}", self.scene_name())
        };
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
