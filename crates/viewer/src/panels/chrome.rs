//! What surrounds the panels: the keyboard and dropped files, the menu bar and the status
//! bar.

use std::path::PathBuf;

use eframe::egui::{self, Color32};

use super::{text, Command, Cx, Panels};
use crate::keys::{self, Action};

impl Panels {
    /// Key presses (ignored while a text field has the keyboard) and dropped files.
    pub fn keyboard(&mut self, ui: &egui::Ui, cx: &mut Cx<'_>) {
        let ctx = ui.ctx().clone();
        // A dropped file opens whatever has the keyboard.
        let dropped: Option<PathBuf> =
            ctx.input(|i| i.raw.dropped_files.first().map(|f| f.path().to_owned()));
        if let Some(p) = dropped {
            cx.ask(Command::Open(p));
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
                self.act(a, cx);
            }
        }
    }

    /// The menu bar.
    pub fn menu_bar(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        egui::Panel::top("menu").show(ui, |ui| {
            egui::MenuBar::new().ui(ui, |ui| {
                ui.menu_button("File", |ui| self.file_menu(ui, cx));
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
                            self.act(a, cx);
                        }
                    }
                });
                if ui.button("Keys (H)").clicked() {
                    self.act(Action::CheatSheet, cx);
                }
            });
        });
    }

    /// The File menu: opening files, then each panel's entries.
    fn file_menu(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        if ui.button("Open...  (Ctrl+O)").clicked() {
            self.open_picker(cx);
            ui.close();
        }
        ui.menu_button("Recent", |ui| {
            if cx.session.recent.is_empty() {
                ui.label("(none yet)");
            }
            for p in cx.session.recent {
                if ui.button(p.display().to_string()).clicked() {
                    cx.commands.push(Command::Open(p.clone()));
                    ui.close();
                }
            }
        });
        let has = cx.session.model.is_some();
        if ui
            .add_enabled(has, egui::Button::new("Reload  (Up)"))
            .clicked()
        {
            cx.ask(Command::Reload);
        }
        if ui
            .add_enabled(has, egui::Button::new("Previous in folder  (Left)"))
            .clicked()
        {
            cx.ask(Command::StepFile(-1));
        }
        if ui
            .add_enabled(has, egui::Button::new("Next in folder  (Right)"))
            .clicked()
        {
            cx.ask(Command::StepFile(1));
        }
        if ui.button("Demo scene").clicked() {
            cx.ask(Command::OpenDemo);
            ui.close();
        }
        ui.separator();
        for p in &mut self.list {
            p.file_menu(ui, cx);
        }
    }

    /// The status bar: file, load progress, quality level, timings, errors. One line
    /// whatever it shows (a wrapped second line would take its height from the viewport):
    /// the file name is cut in the middle, the message at its end, each whole on hover.
    pub fn status_bar(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        egui::Panel::bottom("status").show(ui, |ui| {
            ui.horizontal(|ui| {
                let s = &cx.session;
                // Started on a file still loading: nothing is open yet (not the demo).
                if !s.nothing_open() {
                    let name_width = (ui.available_width() / 3.0).max(80.0);
                    text::elided_middle(ui, &s.name(), name_width, true);
                    ui.label(format!("{} triangles", s.scene.triangle_count()));
                }
                if let Some(t) = s.loading {
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
                if let Some(f) = s.shown {
                    ui.separator();
                    let r = &f.report_a;
                    let state = if s.settled { "" } else { " …" };
                    ui.label(format!(
                        "{}x{} {}{state}: {:.1} ms",
                        f.view.width,
                        f.view.height,
                        f.level.label(),
                        r.times.total
                    ));
                }
                if let Some(e) = s.error {
                    ui.separator();
                    let dismiss = ui.small_button("dismiss").clicked();
                    text::elided_end(
                        ui,
                        egui::RichText::new(e).color(Color32::from_rgb(255, 110, 90)),
                    );
                    if dismiss {
                        cx.ask(Command::DismissError);
                    }
                } else if let Some(n) = s.notice {
                    ui.separator();
                    text::elided_end(ui, n);
                }
            });
        });
    }
}
