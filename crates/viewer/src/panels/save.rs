//! Saving the scene as a scene file: a path (the open scene file, else `scene.toml` next to
//! the model) and a button. The file records the model, the settings and the camera
//! ([`crate::scenefile::SceneFile::from_settings`]); what it cannot record is listed.

use eframe::egui;

use super::{text, Command, Cx, Dock, Installed, Panel};

/// The scene file section: where to save.
#[derive(Clone, Debug, Default)]
pub struct SavePanel {
    /// Where to save (`.toml` or `.json`).
    pub path: String,
}

impl Panel for SavePanel {
    fn dock(&self) -> Dock {
        Dock::Right
    }

    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        egui::CollapsingHeader::new("Scene file")
            .default_open(true)
            .show(ui, |ui| self.show(ui, cx));
    }

    fn file_menu(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        if ui
            .button("Save scene  (to the Scene file section's path)")
            .clicked()
        {
            self.save(cx);
            ui.close();
        }
    }

    fn installed(&mut self, what: &Installed<'_>) {
        self.path.clone_from(&what.save_path);
    }
}

impl SavePanel {
    /// Saves to the path in the field; the outcome goes to the section and the status bar.
    pub fn save(&self, cx: &mut Cx<'_>) {
        cx.ask(Command::SaveScene(std::path::PathBuf::from(
            self.path.trim(),
        )));
    }

    /// The save section.
    fn show(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        ui.horizontal(|ui| {
            ui.label("open:");
            match cx.session.scene_file {
                Some(f) => text::elided_middle(
                    ui,
                    &f.file.path.display().to_string(),
                    f32::INFINITY,
                    false,
                ),
                None => ui.label("none (a model or the demo)"),
            };
        });
        ui.horizontal(|ui| {
            ui.label("save to");
            // As wide as the room left, not as the path: the field scrolls its text.
            let width = ui.available_width();
            ui.add(egui::TextEdit::singleline(&mut self.path).desired_width(width))
                .accessible_name("scene file path");
        });
        let exists = std::path::Path::new(self.path.trim()).is_file();
        ui.horizontal(|ui| {
            if ui.button("Save scene").clicked() {
                self.save(cx);
            }
            if exists {
                ui.weak("(replaces the file)");
            }
        });
        match cx.session.saved {
            Some(Ok(msg)) => {
                ui.label(msg.as_str());
            }
            Some(Err(e)) => {
                ui.colored_label(egui::Color32::from_rgb(255, 110, 90), e.as_str());
            }
            None => {}
        }
    }
}
