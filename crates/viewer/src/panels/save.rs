//! Saving the scene as a scene file: a path (the open scene file, else `scene.toml` next to
//! the model) and a button. The file records the model, the settings and the camera
//! ([`crate::scenefile::SceneFile::from_settings`]); what it cannot record is listed.

use eframe::egui;

use super::text;
use crate::app::ViewerApp;

/// The save section's state.
#[derive(Clone, Debug, Default)]
pub struct SaveUi {
    /// Where to save (`.toml` or `.json`).
    pub path: String,
    /// The last save's outcome: the message shown under the button.
    pub result: Option<Result<String, String>>,
}

/// Saves to the path in the field; the outcome goes to the section and the status bar.
pub fn save(app: &mut ViewerApp) {
    let path = std::path::PathBuf::from(app.panels.save.path.trim());
    let result = if path.as_os_str().is_empty() {
        Err("no path to save the scene file to".to_owned())
    } else {
        app.save_scene(&path).map(|notes| {
            let shown = std::path::absolute(&path).unwrap_or_else(|_| path.clone());
            let mut msg = format!("saved scene file {}", shown.display());
            if !notes.is_empty() {
                msg += &format!(" (left out: {})", notes.join("; "));
            }
            msg
        })
    };
    match &result {
        Ok(msg) => {
            app.notice = Some(msg.clone());
            app.error = None;
        }
        Err(e) => app.error = Some(e.clone()),
    }
    app.panels.save.result = Some(result);
}

/// The save section.
pub fn show(app: &mut ViewerApp, ui: &mut egui::Ui) {
    ui.horizontal(|ui| {
        ui.label("open:");
        match &app.scene_file {
            Some(f) => {
                text::elided_middle(ui, &f.file.path.display().to_string(), f32::INFINITY, false)
            }
            None => ui.label("none (a model or the demo)"),
        };
    });
    ui.horizontal(|ui| {
        ui.label("save to");
        // As wide as the room left, not as the path: the field scrolls its text.
        let width = ui.available_width();
        ui.add(egui::TextEdit::singleline(&mut app.panels.save.path).desired_width(width))
            .accessible_name("scene file path");
    });
    let exists = std::path::Path::new(app.panels.save.path.trim()).is_file();
    ui.horizontal(|ui| {
        if ui.button("Save scene").clicked() {
            save(app);
        }
        if exists {
            ui.weak("(replaces the file)");
        }
    });
    match &app.panels.save.result {
        Some(Ok(msg)) => {
            ui.label(msg.as_str());
        }
        Some(Err(e)) => {
            ui.colored_label(egui::Color32::from_rgb(255, 110, 90), e.as_str());
        }
        None => {}
    }
}
