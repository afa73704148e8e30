//! The panels around the viewport. Each panel is a struct in its own file that owns its
//! state and implements [`Panel`]; it sees the viewer only through a [`Cx`]: the settings it
//! edits, the camera, what the panels and the viewport share ([`Shared`]), a read-only view
//! of the session ([`Session`]) and a queue of [`Command`]s that the app carries out after
//! the UI pass (open a file, save the scene file, generate texture coordinates, ...). A new
//! panel is a new file and a line in [`Panels::default`]'s list.
//!
//! The menu bar, the status bar and the open-file picker are in [`chrome`]; the keys and
//! what they do in [`crate::keys`].

use std::path::{Path, PathBuf};
use std::sync::Arc;

use eframe::egui::{self, Pos2};

use super::app::Split;
use super::app::{scene_name, Shown};
use super::keys::Action;
use super::loader::{LoadTask, OpenScene};
use super::navigate::Navigator;
use super::viewport::ViewportState;
use crate::render::{Output, PreparedScene, Settings, View};
use crate::texture::UvGenerator;

pub mod chrome;
mod colour;
pub mod edit;
pub mod environment;
pub mod lights;
mod materials;
pub mod measure;
mod probe;
pub mod save;
mod scene;
mod screenshot;
mod section;
pub mod shading;
mod stats;
pub mod text;
pub mod textures;

pub use colour::ColourPanel;
pub use environment::EnvironmentPanel;
pub use lights::{light_names, LightsPanel};
pub use materials::MaterialsPanel;
pub use measure::{Measure, MeasurePanel};
pub use probe::ProbePanel;
pub use save::SavePanel;
pub use scene::ScenePanel;
pub use screenshot::ScreenshotPanel;
pub use section::SectionPanel;
pub use shading::ShadingPanel;
pub use stats::StatsPanel;

/// Where a panel sits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dock {
    /// The left side panel (what is drawn and how).
    Left,
    /// The right side panel (what is there: probe, scene, colour).
    Right,
    /// Its own floating window (drawn every pass; it decides whether it is open).
    Window,
}

/// A panel: its sections, its windows and dialogs, and what it does on keys and new scenes.
/// Only [`Panel::dock`] and [`Panel::ui`] are required.
pub trait Panel: std::any::Any {
    /// Where it sits.
    fn dock(&self) -> Dock;
    /// Draws its sections (each a collapsing header) into its side panel, or its window.
    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>);
    /// Every pass before the layout, open or not: background work that finished.
    fn poll(&mut self, _cx: &mut Cx<'_>) {}
    /// Every pass after the layout, open or not: its file dialogs.
    fn dialogs(&mut self, _ctx: &egui::Context, _cx: &mut Cx<'_>) {}
    /// Its entries in the File menu.
    fn file_menu(&mut self, _ui: &mut egui::Ui, _cx: &mut Cx<'_>) {}
    /// A key's action (every panel sees every action after [`crate::keys::act`]).
    fn act(&mut self, _action: Action, _cx: &mut Cx<'_>) {}
    /// A scene was installed.
    fn installed(&mut self, _what: &Installed<'_>) {}
}

/// What changed when a scene was installed.
pub struct Installed<'a> {
    /// Another scene (not the same file reloaded): what belonged to the old one goes.
    pub fresh: bool,
    /// A scene file's settings, taken as they are.
    pub settings: Option<&'a Settings>,
    /// Where "Save scene" writes unless told otherwise.
    pub save_path: String,
}

/// Which tile cost the viewport shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CostView {
    #[default]
    Off,
    /// Fill time per tile.
    Time,
    /// Fragments per tile.
    Fragments,
}

/// Which half of a split view.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Side {
    A,
    B,
}

/// A probed pixel.
#[derive(Clone, Debug)]
pub struct ProbeView {
    /// In the frame's pixels.
    pub pixel: [u32; 2],
    pub frame_size: [u32; 2],
    /// Where it was clicked (points).
    pub at: Pos2,
    pub side: Side,
    /// `None`: the ray met nothing (background).
    pub probe: Option<crate::render::Probe>,
    /// The frame's sRGB8 colour there (left half only).
    pub shown_rgb: Option<[u8; 3]>,
    /// The depth buffer's value there.
    pub buffer_depth: Option<f32>,
    /// The settings of its side when it was read (it is read again when they change).
    pub settings: Box<Settings>,
}

/// What the panels, the viewport and the keys share: the toggles a key and a panel both
/// change, and the probed pixel the viewport sets and the probe panel shows.
#[derive(Clone, Debug)]
pub struct Shared {
    /// The side panels are shown (Tab).
    pub panels_visible: bool,
    /// The keys window (H).
    pub cheat_sheet: bool,
    /// The 64x64 tile grid over the view (G).
    pub tile_grid: bool,
    /// The tile cost over the view (K).
    pub tile_cost: CostView,
    /// Each light's position and cone over the view (L; off until asked for, so a model
    /// opens on a clean view).
    pub light_gizmos: bool,
    /// The light whose row the pointer is over (its gizmo is highlighted).
    pub hovered_light: Option<usize>,
    /// The pixel last probed.
    pub probe: Option<ProbeView>,
    /// Scroll the side panel to the probe section once.
    pub open_probe: bool,
    /// The camera has been moved (the viewport's one-line hint on moving it goes).
    pub moved: bool,
    /// The points picked for measuring, and whether a click picks one (D).
    pub measure: Measure,
    /// The axes in the corner of the view (X).
    pub axes: bool,
    /// The window fills the screen (F11).
    pub fullscreen: bool,
}

impl Default for Shared {
    fn default() -> Self {
        Self {
            panels_visible: true,
            cheat_sheet: false,
            tile_grid: false,
            tile_cost: CostView::Off,
            light_gizmos: false,
            hovered_light: None,
            probe: None,
            open_probe: false,
            moved: false,
            measure: Measure::default(),
            axes: true,
            fullscreen: false,
        }
    }
}

/// The model's texture coordinates as the controls show them.
#[derive(Clone, Copy, Debug)]
pub struct UvView {
    /// The generator chosen (`None`: the file's UVs).
    pub chosen: Option<UvGenerator>,
    /// Still being generated.
    pub pending: bool,
}

/// What the panels may read about the session: the scene, the frame on screen, the files.
pub struct Session<'a> {
    /// What is drawn.
    pub scene: &'a Arc<PreparedScene>,
    /// The frame on screen.
    pub shown: Option<&'a Shown>,
    /// The file the scene came from, a model or a scene file (`None`: the built-in demo).
    pub model: Option<&'a Path>,
    /// The scene file open.
    pub scene_file: Option<&'a OpenScene>,
    /// How long the model took to load and prepare.
    pub load_millis: Option<f64>,
    /// A load under way.
    pub loading: Option<&'a LoadTask>,
    /// The last error, shown until dismissed or the next success.
    pub error: Option<&'a str>,
    /// The status bar's message.
    pub notice: Option<&'a str>,
    /// The recent files, newest first.
    pub recent: &'a [PathBuf],
    /// The texture coordinates chosen.
    pub uv: UvView,
    /// Loads and renders run in the calling thread (UI tests).
    pub synchronous: bool,
    /// What wakes the UI from another thread.
    pub repaint: &'a Arc<dyn Fn() + Send + Sync>,
    /// An animation plays.
    pub playing: bool,
    /// The frame on screen is the final one for the current view and settings.
    pub settled: bool,
    /// The last "Save scene": the message, or why not.
    pub saved: Option<&'a Result<String, String>>,
}

impl Session<'_> {
    /// The name shown for the scene (see [`crate::ViewerApp::scene_name`]).
    #[must_use]
    pub fn name(&self) -> String {
        scene_name(self.model, self.scene_file)
    }

    /// Nothing is open yet: the viewer started on a file that is still loading (or failed
    /// before the demo took its place).
    #[must_use]
    pub fn nothing_open(&self) -> bool {
        nothing_open(self.model, self.scene)
    }

    /// The folder of the open file (where file pickers start).
    #[must_use]
    pub fn folder(&self) -> Option<&Path> {
        self.model.and_then(Path::parent)
    }
}

/// Nothing is open: no file, and the scene on screen is the empty one the viewer starts
/// with while its first file loads.
#[must_use]
pub fn nothing_open(model: Option<&Path>, scene: &PreparedScene) -> bool {
    model.is_none() && scene.scene().instances.is_empty()
}

/// What a panel asks of the session; the app does it after the UI pass, in order.
#[derive(Clone, Debug)]
pub enum Command {
    /// Open a model or a scene file.
    Open(PathBuf),
    /// Show the built-in demo.
    OpenDemo,
    /// Load the open file again.
    Reload,
    /// The previous (-1) or next (+1) model in the open file's folder.
    StepFile(i32),
    /// Save the scene file there.
    SaveScene(PathBuf),
    /// Draw the model with these texture coordinates (`None`: its own).
    SetUv(Option<UvGenerator>),
    /// Play or pause the animation.
    TogglePlay,
    /// A message for the status bar.
    Notice(String),
    /// An error for the status bar.
    Error(String),
    /// Clear the status bar's error.
    DismissError,
}

/// A panel's narrow view of the viewer for one call.
pub struct Cx<'a> {
    /// Side A's settings (the frame).
    pub settings: &'a mut Settings,
    /// The split view, side B's settings among them.
    pub split: &'a mut Split,
    /// Refine a still image up to this many samples per axis (1, 2 or 4).
    pub max_samples: &'a mut u32,
    /// The camera controller.
    pub nav: &'a mut Navigator,
    /// What the panels, the viewport and the keys share.
    pub shared: &'a mut Shared,
    /// The viewport's rectangle and size.
    pub viewport: &'a mut ViewportState,
    /// The camera moved by input during this pass.
    pub interacting: &'a mut bool,
    /// The session, read-only.
    pub session: Session<'a>,
    /// Requests to the session.
    pub commands: &'a mut Vec<Command>,
}

impl Cx<'_> {
    /// The scene drawn.
    #[must_use]
    pub fn scene(&self) -> &Arc<PreparedScene> {
        self.session.scene
    }

    /// The view of the viewport as it is now.
    #[must_use]
    pub fn view(&self) -> View {
        super::viewport::view_of(self.nav, self.viewport)
    }

    /// Asks the session to do `c` after this pass.
    pub fn ask(&mut self, c: Command) {
        self.commands.push(c);
    }

    /// A message for the status bar.
    pub fn notice(&mut self, message: impl Into<String>) {
        self.commands.push(Command::Notice(message.into()));
    }

    /// Side `side`'s settings.
    pub fn side(&mut self, side: Side) -> &mut Settings {
        match side {
            Side::A => self.settings,
            Side::B => &mut self.split.b,
        }
    }
}

/// Every panel, in the order they are laid out, and the open-file picker.
pub struct Panels {
    list: Vec<Box<dyn Panel>>,
    /// The open-file picker.
    picker: Option<egui_file::FileDialog>,
}

impl Default for Panels {
    fn default() -> Self {
        // The panel list: a new panel is a line here and a file of its own.
        let list: Vec<Box<dyn Panel>> = vec![
            Box::new(ShadingPanel::default()),
            Box::new(LightsPanel::default()),
            Box::new(EnvironmentPanel::default()),
            Box::new(SectionPanel::default()),
            Box::new(MaterialsPanel::default()),
            Box::new(StatsPanel),
            Box::new(ProbePanel),
            Box::new(MeasurePanel),
            Box::new(SavePanel::default()),
            Box::new(ScenePanel::default()),
            Box::new(ColourPanel::default()),
            Box::new(ScreenshotPanel::default()),
        ];
        Self { list, picker: None }
    }
}

impl Panels {
    /// Adds `panel` after the others of its dock (a panel of another crate, or a test's).
    pub fn add(&mut self, panel: Box<dyn Panel>) {
        self.list.push(panel);
    }

    /// The panel of type `P`.
    #[must_use]
    pub fn get<P: Panel>(&self) -> Option<&P> {
        self.list
            .iter()
            .find_map(|p| (p.as_ref() as &dyn std::any::Any).downcast_ref::<P>())
    }

    /// The panel of type `P`, to change.
    pub fn get_mut<P: Panel>(&mut self) -> Option<&mut P> {
        self.list
            .iter_mut()
            .find_map(|p| (p.as_mut() as &mut dyn std::any::Any).downcast_mut::<P>())
    }

    /// Tells every panel that a scene was installed.
    pub fn installed(&mut self, what: &Installed<'_>) {
        for p in &mut self.list {
            p.installed(what);
        }
    }

    /// Every panel's background work.
    pub fn poll(&mut self, cx: &mut Cx<'_>) {
        for p in &mut self.list {
            p.poll(cx);
        }
    }

    /// Does what a key or a menu entry asks: the keys' own part, then each panel's.
    pub fn act(&mut self, a: Action, cx: &mut Cx<'_>) {
        super::keys::act(a, cx);
        if a == Action::Open {
            self.open_picker(cx);
        }
        for p in &mut self.list {
            p.act(a, cx);
        }
    }

    /// Opens the file picker (drawn by egui, so it works anywhere, Xvfb included).
    pub fn open_picker(&mut self, cx: &Cx<'_>) {
        let filter =
            Box::new(|p: &Path| super::files::is_model(p) || super::loader::is_scene_file(p));
        self.picker = Some(file_dialog(
            cx,
            "Open a model (.obj, .gltf, .glb, .stl, .ply) or a scene file (.toml, .json)",
            filter,
        ));
    }

    /// The side panels.
    pub fn side_panels(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        egui::Panel::left("controls")
            .resizable(true)
            .default_size(320.0)
            .size_range(200.0..=420.0)
            .show(ui, |ui| {
                text::bounded("controls-scroll").show(ui, |ui| self.docked(Dock::Left, ui, cx));
            });
        egui::Panel::right("inspect")
            .resizable(true)
            .default_size(300.0)
            .size_range(220.0..=520.0)
            .show(ui, |ui| {
                // Wide rows (the probe's light shares) scroll sideways: growing the panel
                // would shrink the viewport and re-render the frame just probed.
                text::bounded("inspect-scroll").show(ui, |ui| self.docked(Dock::Right, ui, cx));
            });
    }

    /// The panels docked at `dock`, in list order.
    fn docked(&mut self, dock: Dock, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        for p in self.list.iter_mut().filter(|p| p.dock() == dock) {
            p.ui(ui, cx);
        }
    }

    /// The floating windows and the dialogs.
    pub fn windows(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        let ctx = ui.ctx().clone();
        if cx.shared.cheat_sheet {
            let mut open = true;
            // Scrolls in a short window (every binding is a row).
            let height = (ctx.content_rect().height() - 80.0).max(200.0);
            egui::Window::new("Keys and mouse")
                .open(&mut open)
                .collapsible(false)
                .vscroll(true)
                .max_height(height)
                .show(&ctx, |ui| super::keys::cheat_sheet(ui, cx));
            cx.shared.cheat_sheet &= open;
        }
        if let Some(dialog) = &mut self.picker {
            if dialog.show(&ctx).selected() {
                if let Some(p) = dialog.path().map(Path::to_path_buf) {
                    self.picker = None;
                    cx.ask(Command::Open(p));
                }
            } else if !dialog.visible() {
                self.picker = None;
            }
        }
        self.docked(Dock::Window, ui, cx);
        for p in &mut self.list {
            p.dialogs(&ctx, cx);
        }
    }
}

/// One row of a two-column grid: a label and a monospace value.
fn row(ui: &mut egui::Ui, key: &str, value: String) {
    ui.label(key);
    ui.monospace(value);
    ui.end_row();
}

/// A file dialog for one file, starting in the open model's folder.
fn file_dialog(
    cx: &Cx<'_>,
    title: &str,
    filter: egui_file::Filter<PathBuf>,
) -> egui_file::FileDialog {
    let mut dialog = egui_file::FileDialog::open_file()
        .show_files_filter(filter)
        .title(title);
    if let Some(dir) = cx.session.folder() {
        dialog = dialog.initial_path(dir);
    }
    dialog.open();
    dialog
}

/// A one-line description of settings, for the split view's labels.
#[must_use]
pub fn describe(s: &Settings) -> String {
    let mut d = s
        .shading
        .map_or("per model".into(), |m| m.name().to_owned());
    if let Some(f) = s.filter {
        d += &format!(", {f:?} filter").to_lowercase();
    }
    if s.wireframe_overlay {
        d += " + wire";
    }
    if s.tone != crate::render::ToneMap::Auto {
        d += &format!(", {}", s.tone.name());
    }
    if !s.sections.is_empty() {
        d += &format!(", {} section plane(s)", s.sections.planes.len());
    }
    if let Some(v) = &s.variant {
        d += &format!(", variant {v}");
    }
    if s.output == Output::Overdraw {
        d = "overdraw".into();
    }
    d
}
