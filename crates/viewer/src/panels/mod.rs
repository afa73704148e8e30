//! The panels around the viewport: the menu bar, the status bar, the side panels (shading,
//! split view, scene file, scene, lights and materials, probe, colour, stats) and the windows (cheat
//! sheet, file picker, screenshot). Each section lives in its own file; this one holds the
//! layout, the keyboard dispatcher and the shared panel state.

use std::path::PathBuf;

use eframe::egui::{self, Align2, Color32, FontId, Pos2, Rect, Vec2};

use super::app::ViewerApp;
use super::keys::{self, Action, BINDINGS, MOUSE};
use super::navigate::{Mode, UpAxis, View as Named};
use crate::render::{Output, Settings};
use crate::shade::Shading;

mod colour;
pub mod edit;
pub mod environment;
pub mod lights;
mod materials;
mod probe;
pub mod save;
mod scene;
mod screenshot;
mod shading;
mod stats;
pub mod text;
pub mod textures;

pub use colour::ColourState;
pub use environment::EnvironmentUi;
pub use lights::{light_names, LightsUi};
pub use save::SaveUi;
pub use screenshot::Screenshot;

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
}

/// UI state of the panels and windows.
pub struct Panels {
    pub visible: bool,
    pub cheat_sheet: bool,
    pub tile_grid: bool,
    pub tile_cost: CostView,
    pub probe: Option<ProbeView>,
    /// Scroll the side panel to the probe section once.
    pub open_probe: bool,
    pub picker: Option<egui_file::FileDialog>,
    pub screenshot: Screenshot,
    pub colour: ColourState,
    /// Material selected in the material editor.
    pub material: usize,
    /// Thumbnails of the scene's textures (built on first view).
    pub thumbnails: Vec<Option<egui::TextureHandle>>,
    /// Topology reports of the meshes opened in the scene section.
    pub topology: std::collections::HashMap<usize, crate::mesh::TopologyReport>,
    /// The light editor and the gizmos.
    pub lights: LightsUi,
    /// Fog and ground values kept while they are off.
    pub environment: EnvironmentUi,
    /// Saving the scene file.
    pub save: SaveUi,
    /// The texture lab's image paths, errors, reads and picker.
    pub lab: textures::LabUi,
}

impl Default for Panels {
    fn default() -> Self {
        Self {
            visible: true,
            cheat_sheet: false,
            tile_grid: false,
            tile_cost: CostView::Off,
            probe: None,
            open_probe: false,
            picker: None,
            screenshot: Screenshot::default(),
            colour: ColourState::default(),
            material: 0,
            thumbnails: Vec::new(),
            topology: std::collections::HashMap::new(),
            lights: LightsUi::default(),
            environment: EnvironmentUi::default(),
            save: SaveUi::default(),
            lab: textures::LabUi::default(),
        }
    }
}

impl Panels {
    /// Forgets what belonged to the previous scene.
    pub fn on_new_scene(&mut self) {
        self.probe = None;
        self.material = 0;
        self.thumbnails.clear();
        self.topology.clear();
        self.colour = ColourState::default();
        self.lights.hovered = None;
        self.lab.on_new_scene();
    }
}

/// One row of a two-column grid: a label and a monospace value.
fn row(ui: &mut egui::Ui, key: &str, value: String) {
    ui.label(key);
    ui.monospace(value);
    ui.end_row();
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
    if s.tone != crate::render::ToneMap::Clamp {
        d += &format!(", {}", s.tone.name());
    }
    if s.output == Output::Overdraw {
        d = "overdraw".into();
    }
    d
}

/// Shading modes in the order the `M` key cycles them.
const CYCLE: [Shading; Shading::ALL.len()] = Shading::ALL;

/// Key presses (ignored while a text field has the keyboard) and dropped files.
pub fn keyboard(app: &mut ViewerApp, ui: &egui::Ui) {
    let ctx = ui.ctx().clone();
    // A dropped file opens whatever has the keyboard.
    let dropped: Option<PathBuf> =
        ctx.input(|i| i.raw.dropped_files.first().map(|f| f.path().to_owned()));
    if let Some(p) = dropped {
        app.open(p);
    }
    // Only a text field: any focused widget (a button reached with Tab) would swallow
    // every key.
    if ctx.text_edit_focused() {
        return;
    }
    let pressed: Vec<(egui::Key, egui::Modifiers)> = ctx.input(|i| {
        i.events
            .iter()
            .filter_map(|e| match e {
                egui::Event::Key {
                    key,
                    pressed: true,
                    modifiers,
                    ..
                } => Some((*key, *modifiers)),
                _ => None,
            })
            .collect()
    });
    for (key, mods) in pressed {
        if let Some(a) = keys::action_for(key, mods) {
            if key == egui::Key::Tab {
                // Tab is ours (hide / show the panels), not egui's focus traversal.
                ctx.memory_mut(|m| m.move_focus(egui::FocusDirection::None));
            }
            act(app, a);
        }
    }
}

/// Does what a key or menu entry asks.
pub fn act(app: &mut ViewerApp, a: Action) {
    let aspect = app.viewport.aspect();
    let nav = &mut app.nav;
    match a {
        Action::ViewFront => nav.set_view(Named::Front),
        Action::ViewBack => nav.set_view(Named::Back),
        Action::ViewRight => nav.set_view(Named::Right),
        Action::ViewLeft => nav.set_view(Named::Left),
        Action::ViewTop => nav.set_view(Named::Top),
        Action::ViewBottom => nav.set_view(Named::Bottom),
        Action::ViewIso => nav.set_view(Named::Isometric),
        Action::ToggleOrtho => nav.toggle_ortho(),
        Action::Reset => nav.reset(),
        Action::FrameAll => {
            let (c, r) = app.scene.bounding_sphere();
            nav.frame(c, r, aspect);
        }
        Action::UpY => nav.set_up_axis(UpAxis::Y, aspect),
        Action::UpZ => nav.set_up_axis(UpAxis::Z, aspect),
        Action::ToggleTrackball => nav.set_mode(match nav.mode() {
            Mode::Turntable => Mode::Trackball,
            Mode::Trackball => Mode::Turntable,
        }),
        Action::FovDown => nav.set_fov_degrees(nav.fov_degrees() - 5.0),
        Action::FovUp => nav.set_fov_degrees(nav.fov_degrees() + 5.0),
        Action::NextShading | Action::PrevShading => {
            let s = &mut app.settings;
            let k = s
                .shading
                .and_then(|m| CYCLE.iter().position(|c| *c == m))
                .unwrap_or(3);
            let n = CYCLE.len();
            let next = if a == Action::NextShading {
                (k + 1) % n
            } else {
                (k + n - 1) % n
            };
            s.shading = Some(CYCLE[next]);
        }
        Action::ToggleWireOverlay => {
            app.settings.wireframe_overlay = !app.settings.wireframe_overlay;
        }
        Action::ToggleOverdraw => {
            let s = &mut app.settings;
            s.output = match s.output {
                Output::Shaded => Output::Overdraw,
                Output::Overdraw => Output::Shaded,
            }
        }
        Action::ToggleTileGrid => app.panels.tile_grid = !app.panels.tile_grid,
        Action::CycleTileCost => {
            app.panels.tile_cost = match app.panels.tile_cost {
                CostView::Off => CostView::Time,
                CostView::Time => CostView::Fragments,
                CostView::Fragments => CostView::Off,
            }
        }
        Action::CycleAntialias => {
            app.max_samples = match app.max_samples {
                1 => 2,
                2 => 4,
                _ => 1,
            }
        }
        Action::ToggleMultisampling => {
            app.settings.msaa = if app.settings.msaa > 1 { 1 } else { 4 };
        }
        Action::ToggleSplit => app.split.enabled = !app.split.enabled,
        Action::ToggleLightGizmos => app.panels.lights.gizmos = !app.panels.lights.gizmos,
        Action::CheatSheet => app.panels.cheat_sheet = !app.panels.cheat_sheet,
        Action::Screenshot => screenshot::quick(app),
        Action::Open => open_picker(app),
        Action::PrevFile => app.step_file(-1),
        Action::NextFile => app.step_file(1),
        Action::Reload => app.reload(),
        Action::TogglePanels => app.panels.visible = !app.panels.visible,
        Action::TogglePlay => {
            let scene = std::sync::Arc::clone(app.scene.scene());
            if scene.animations.is_empty() {
                app.notice = Some("this scene has no animation".into());
            } else {
                let length = super::timeline::duration(&scene, app.timeline.play);
                app.timeline.toggle(length);
            }
        }
    }
}

/// Opens the file picker (drawn by egui, so it works anywhere, Xvfb included).
pub fn open_picker(app: &mut ViewerApp) {
    let filter = Box::new(|p: &std::path::Path| {
        super::files::is_model(p) || super::loader::is_scene_file(p)
    });
    let mut dialog = egui_file::FileDialog::open_file()
        .show_files_filter(filter)
        .title("Open a model (.obj, .gltf, .glb, .stl, .ply) or a scene file (.toml, .json)");
    if let Some(dir) = app.model.as_deref().and_then(std::path::Path::parent) {
        dialog = dialog.initial_path(dir);
    }
    dialog.open();
    app.panels.picker = Some(dialog);
}

/// The menu bar.
pub fn menu_bar(app: &mut ViewerApp, ui: &mut egui::Ui) {
    egui::Panel::top("menu").show(ui, |ui| {
        egui::MenuBar::new().ui(ui, |ui| {
            ui.menu_button("File", |ui| {
                if ui.button("Open...  (Ctrl+O)").clicked() {
                    open_picker(app);
                    ui.close();
                }
                ui.menu_button("Recent", |ui| {
                    let list = app.recent.list().to_vec();
                    if list.is_empty() {
                        ui.label("(none yet)");
                    }
                    for p in list {
                        if ui.button(p.display().to_string()).clicked() {
                            app.open(p);
                            ui.close();
                        }
                    }
                });
                let has = app.model.is_some();
                if ui
                    .add_enabled(has, egui::Button::new("Reload  (Up)"))
                    .clicked()
                {
                    app.reload();
                }
                if ui
                    .add_enabled(has, egui::Button::new("Previous in folder  (Left)"))
                    .clicked()
                {
                    app.step_file(-1);
                }
                if ui
                    .add_enabled(has, egui::Button::new("Next in folder  (Right)"))
                    .clicked()
                {
                    app.step_file(1);
                }
                if ui.button("Demo scene").clicked() {
                    app.open_demo();
                    ui.close();
                }
                ui.separator();
                if ui
                    .button("Save scene  (to the Scene file section's path)")
                    .clicked()
                {
                    save::save(app);
                    ui.close();
                }
                if ui.button("Screenshot...  (F12 saves at once)").clicked() {
                    app.panels.screenshot.open = true;
                    ui.close();
                }
            });
            ui.menu_button("View", |ui| {
                for (label, a) in [
                    ("Front  (1)", Action::ViewFront),
                    ("Right  (3)", Action::ViewRight),
                    ("Top  (7)", Action::ViewTop),
                    ("Isometric  (9)", Action::ViewIso),
                    ("Orthographic  (5)", Action::ToggleOrtho),
                    ("Frame all  (F)", Action::FrameAll),
                    ("Reset camera  (Enter)", Action::Reset),
                    ("+Y up  (Ctrl+Y)", Action::UpY),
                    ("+Z up  (Ctrl+Z)", Action::UpZ),
                    ("Trackball / turntable  (T)", Action::ToggleTrackball),
                ] {
                    if ui.button(label).clicked() {
                        act(app, a);
                    }
                }
            });
            if ui.button("Keys (H)").clicked() {
                app.panels.cheat_sheet = !app.panels.cheat_sheet;
            }
        });
    });
}

/// The status bar: file, load progress, quality level, timings, errors. One line whatever
/// it shows (a wrapped second line would take its height from the viewport): the file name
/// is cut in the middle, the message at its end, each whole on hover.
pub fn status_bar(app: &mut ViewerApp, ui: &mut egui::Ui) {
    egui::Panel::bottom("status").show(ui, |ui| {
        ui.horizontal(|ui| {
            let name_width = (ui.available_width() / 3.0).max(80.0);
            text::elided_middle(ui, &app.scene_name(), name_width, true);
            ui.label(format!("{} triangles", app.scene.triangle_count()));
            if let Some(t) = &app.loading {
                let (stage, fraction, secs) = t.status();
                let name = t
                    .path
                    .file_name()
                    .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
                ui.separator();
                ui.label("loading");
                text::elided_middle(ui, &name, 160.0, false);
                ui.label(format!("{} ({secs:.1} s)", stage.name()));
                ui.add(
                    egui::ProgressBar::new(fraction.unwrap_or(0.0))
                        .desired_width(120.0)
                        .show_percentage(),
                );
                if ui.button("Cancel").clicked() {
                    t.cancel();
                }
            }
            if let Some(s) = &app.shown {
                ui.separator();
                let r = &s.report_a;
                let state = if app.settled() { "" } else { " …" };
                ui.label(format!(
                    "{}x{} {}{state}: {:.1} ms",
                    s.view.width,
                    s.view.height,
                    s.level.label(),
                    r.times.total
                ));
            }
            if let Some(e) = app.error.clone() {
                ui.separator();
                if ui.small_button("dismiss").clicked() {
                    app.error = None;
                }
                text::elided_end(
                    ui,
                    egui::RichText::new(e).color(Color32::from_rgb(255, 110, 90)),
                );
            } else if let Some(n) = &app.notice {
                ui.separator();
                text::elided_end(ui, n.as_str());
            }
        });
    });
}

/// The side panels.
pub fn side_panels(app: &mut ViewerApp, ui: &mut egui::Ui) {
    egui::Panel::left("controls")
        .resizable(true)
        .default_size(320.0)
        .size_range(200.0..=420.0)
        .show(ui, |ui| {
            text::bounded("controls-scroll").show(ui, |ui| {
                egui::CollapsingHeader::new("Shading")
                    .default_open(true)
                    .show(ui, |ui| shading::show(app, ui));
                egui::CollapsingHeader::new("Split view A | B")
                    .show(ui, |ui| shading::split(app, ui));
                egui::CollapsingHeader::new("Lights").show(ui, |ui| lights::lights(app, ui));
                egui::CollapsingHeader::new("Environment, exposure, fog, tone map, shadows")
                    .id_salt("environment")
                    .show(ui, |ui| environment::show(app, ui));
                egui::CollapsingHeader::new("Materials").show(ui, |ui| materials::show(app, ui));
                egui::CollapsingHeader::new("Stats").show(ui, |ui| stats::show(app, ui));
            });
        });
    egui::Panel::right("inspect")
        .resizable(true)
        .default_size(400.0)
        .size_range(220.0..=520.0)
        .show(ui, |ui| {
            // Wide rows (the probe's light shares) scroll sideways: growing the panel would
            // shrink the viewport and re-render the frame just probed.
            text::bounded("inspect-scroll").show(ui, |ui| {
                let open = std::mem::take(&mut app.panels.open_probe).then_some(true);
                egui::CollapsingHeader::new("Pixel probe")
                    .default_open(true)
                    .open(open)
                    .show(ui, |ui| probe::show(app, ui));
                egui::CollapsingHeader::new("Scene file")
                    .default_open(true)
                    .show(ui, |ui| save::show(app, ui));
                egui::CollapsingHeader::new("Scene")
                    .default_open(true)
                    .show(ui, |ui| scene::show(app, ui));
                egui::CollapsingHeader::new("Colour (CIE 1931)")
                    .show(ui, |ui| colour::show(app, ui));
            });
        });
}

/// The floating windows.
pub fn windows(app: &mut ViewerApp, ctx: &egui::Context) {
    if app.panels.cheat_sheet {
        let mut open = true;
        egui::Window::new("Keys and mouse")
            .open(&mut open)
            .collapsible(false)
            .show(ctx, |ui| cheat_sheet(app, ui));
        app.panels.cheat_sheet &= open;
    }
    if let Some(dialog) = &mut app.panels.picker {
        if dialog.show(ctx).selected() {
            if let Some(p) = dialog.path().map(std::path::Path::to_path_buf) {
                app.panels.picker = None;
                app.open(p);
            }
        } else if !dialog.visible() {
            app.panels.picker = None;
        }
    }
    if let Some((light, dialog)) = &mut app.panels.lights.slide_picker {
        let light = *light;
        if dialog.show(ctx).selected() {
            if let Some(p) = dialog.path().map(std::path::Path::to_path_buf) {
                app.panels.lights.slide_picker = None;
                lights::read_image(app, light, p);
            }
        } else if !dialog.visible() {
            app.panels.lights.slide_picker = None;
        }
    }
    if let Some(dialog) = &mut app.panels.environment.picker {
        if dialog.show(ctx).selected() {
            if let Some(p) = dialog.path().map(std::path::Path::to_path_buf) {
                app.panels.environment.picker = None;
                environment::read_environment(app, &p);
            }
        } else if !dialog.visible() {
            app.panels.environment.picker = None;
        }
    }
    textures::after_ui(app, ctx);
    screenshot::window(app, ctx);
}

/// The `H` cheat sheet: every binding with the current state of each toggle.
fn cheat_sheet(app: &ViewerApp, ui: &mut egui::Ui) {
    let on = |b: bool| if b { "on" } else { "off" };
    let state = |a: Action| -> String {
        match a {
            Action::ToggleOrtho => (if app.nav.is_ortho() {
                "orthographic"
            } else {
                "perspective"
            })
            .into(),
            Action::UpY | Action::UpZ => format!("up: {:?}", app.nav.up_axis()),
            Action::ToggleTrackball => format!("{:?}", app.nav.mode()).to_lowercase(),
            Action::FovDown | Action::FovUp => format!("{:.0} degrees", app.nav.fov_degrees()),
            Action::NextShading | Action::PrevShading => describe(&app.settings),
            Action::ToggleWireOverlay => on(app.settings.wireframe_overlay).into(),
            Action::ToggleOverdraw => on(app.settings.output == Output::Overdraw).into(),
            Action::ToggleTileGrid => on(app.panels.tile_grid).into(),
            Action::CycleTileCost => format!("{:?}", app.panels.tile_cost).to_lowercase(),
            Action::CycleAntialias => format!("up to {0}x{0}", app.max_samples),
            Action::ToggleMultisampling => format!("{}x", app.settings.msaa),
            Action::ToggleSplit => on(app.split.enabled).into(),
            Action::ToggleLightGizmos => on(app.panels.lights.gizmos).into(),
            Action::TogglePanels => on(app.panels.visible).into(),
            Action::TogglePlay => on(app.timeline.playing).into(),
            Action::CheatSheet => on(app.panels.cheat_sheet).into(),
            // One-shot actions: nothing to show.
            Action::ViewFront
            | Action::ViewBack
            | Action::ViewRight
            | Action::ViewLeft
            | Action::ViewTop
            | Action::ViewBottom
            | Action::ViewIso
            | Action::Reset
            | Action::FrameAll
            | Action::Screenshot
            | Action::Open
            | Action::PrevFile
            | Action::NextFile
            | Action::Reload => String::new(),
        }
    };
    egui::Grid::new("keys").striped(true).show(ui, |ui| {
        for b in BINDINGS {
            ui.monospace(keys::describe(b));
            ui.label(b.what);
            ui.label(egui::RichText::new(state(b.action)).color(Color32::from_rgb(120, 200, 255)));
            ui.end_row();
        }
        for (m, what) in MOUSE {
            ui.monospace(*m);
            ui.label(*what);
            ui.label("");
            ui.end_row();
        }
    });
}

/// The overdraw colour ramp, bottom right of the viewport.
pub fn overdraw_legend(painter: &egui::Painter, rect: Rect) {
    let (w, h) = (220.0, 14.0);
    let origin = rect.right_bottom() + Vec2::new(-w - 12.0, -h - 26.0);
    let steps = 64;
    for i in 0..steps {
        let c = 16.0 * i as f32 / (steps - 1) as f32;
        let col = crate::render::overdraw_color(c);
        let enc = crate::color::srgb8;
        let x = origin.x + w * i as f32 / steps as f32;
        painter.rect_filled(
            Rect::from_min_size(Pos2::new(x, origin.y), Vec2::new(w / steps as f32 + 0.5, h)),
            0.0,
            Color32::from_rgb(enc(col.x), enc(col.y), enc(col.z)),
        );
    }
    for (v, label) in [
        (0.0, "0"),
        (1.0, "1"),
        (4.0, "4"),
        (10.0, "10"),
        (16.0, "16+"),
    ] {
        painter.text(
            Pos2::new(origin.x + w * v / 16.0, origin.y + h + 2.0),
            Align2::CENTER_TOP,
            label,
            FontId::monospace(11.0),
            Color32::WHITE,
        );
    }
    painter.text(
        origin + Vec2::new(0.0, -3.0),
        Align2::LEFT_BOTTOM,
        "fragments per pixel",
        FontId::monospace(11.0),
        Color32::WHITE,
    );
}
