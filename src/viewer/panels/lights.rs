//! The light and material editors: what exists today (ambient, directional and point lights:
//! add, remove, direction or position, colour, intensity; Kd, Ks, shininess, alpha), edited
//! as the renderer's [`Lights::Custom`] and material overrides, so the frame updates live.

use eframe::egui;
use glam::{Mat3, Vec3};

use crate::render::Lights;
use crate::scene::{AlphaMode, Light, Material};
use crate::viewer::app::ViewerApp;

/// The lights the frame uses now, as an editable list: the scene's (world space) or the
/// default rig (camera space, following the camera).
fn effective(app: &ViewerApp) -> (Vec<Light>, bool) {
    match &app.settings.lights {
        Lights::Custom {
            lights,
            follow_camera,
        } => (lights.clone(), *follow_camera),
        Lights::Auto if app.scene.scene().lights.is_empty() => {
            (Light::default_rig(Mat3::IDENTITY), true)
        }
        Lights::Auto => (app.scene.scene().lights.clone(), false),
    }
}

/// Splits a light colour into a unit-maximum colour and an intensity.
fn split_intensity(c: Vec3) -> ([f32; 3], f32) {
    let i = c.max_element();
    if i > 0.0 && i.is_finite() {
        ((c / i).to_array(), i)
    } else {
        ([1.0; 3], 0.0)
    }
}

fn colour_intensity(ui: &mut egui::Ui, color: &mut Vec3) -> bool {
    let (mut rgb, mut i) = split_intensity(*color);
    let mut changed = ui.color_edit_button_rgb(&mut rgb).changed();
    changed |= ui
        .add(
            egui::DragValue::new(&mut i)
                .speed(0.01)
                .range(0.0..=100.0)
                .prefix("intensity "),
        )
        .changed();
    if changed {
        *color = Vec3::from_array(rgb) * i;
    }
    changed
}

fn vec3_edit(ui: &mut egui::Ui, v: &mut Vec3, speed: f64) -> bool {
    let mut changed = false;
    for (c, name) in [(&mut v.x, "x "), (&mut v.y, "y "), (&mut v.z, "z ")] {
        changed |= ui
            .add(egui::DragValue::new(c).speed(speed).prefix(name))
            .changed();
    }
    changed
}

/// The light editor.
pub fn lights(app: &mut ViewerApp, ui: &mut egui::Ui) {
    let (mut list, mut follow) = effective(app);
    let mut changed = false;
    changed |= ui
        .checkbox(
            &mut follow,
            "positions and directions in camera space (follow the camera)",
        )
        .changed();
    let mut remove = None;
    for (i, l) in list.iter_mut().enumerate() {
        ui.push_id(i, |ui| {
            ui.horizontal(|ui| {
                ui.label(format!("{i} {}", l.kind()));
                if ui.small_button("remove").clicked() {
                    remove = Some(i);
                }
            });
            ui.horizontal(|ui| {
                changed |= colour_intensity(ui, &mut l.color);
                if l.kind.positional() {
                    ui.label("at");
                    changed |= vec3_edit(ui, &mut l.position, 0.05);
                }
                if l.kind.directed() {
                    ui.label("along");
                    changed |= vec3_edit(ui, &mut l.direction, 0.01);
                }
            });
        });
    }
    if let Some(i) = remove {
        list.remove(i);
        changed = true;
    }
    ui.horizontal(|ui| {
        ui.label("add");
        let (c, r) = app.scene.bounding_sphere();
        if ui.button("ambient").clicked() {
            list.push(Light::ambient(Vec3::splat(0.1)));
            changed = true;
        }
        if ui.button("directional").clicked() {
            list.push(Light::directional(
                Vec3::new(-0.3, -1.0, -0.5).normalize(),
                Vec3::splat(0.8),
            ));
            changed = true;
        }
        if ui.button("point").clicked() {
            let position = if follow {
                Vec3::new(0.0, r, r)
            } else {
                c + Vec3::new(r, 2.0 * r, 2.0 * r)
            };
            list.push(Light::point(position, Vec3::splat(0.8)));
            changed = true;
        }
    });
    if changed {
        app.settings.lights = Lights::Custom {
            lights: list,
            follow_camera: follow,
        };
    }
    if app.settings.lights != Lights::Auto
        && ui
            .button("back to the scene's lights (or the default rig)")
            .clicked()
    {
        app.settings.lights = Lights::Auto;
    }
    if app.split.b.lights != app.settings.lights {
        app.split.b.lights = app.settings.lights.clone();
    }
}

/// The material editor.
pub fn materials(app: &mut ViewerApp, ui: &mut egui::Ui) {
    let scene_materials = &app.scene.scene().materials;
    if scene_materials.is_empty() {
        ui.label("the model has no materials: every mesh uses the default (grey, Ks 0.2, n 32)");
        return;
    }
    let mut list: Vec<Material> = app
        .settings
        .materials
        .clone()
        .unwrap_or_else(|| scene_materials.clone());
    let k = app.panels.material.min(list.len() - 1);
    egui::ComboBox::from_id_salt("material")
        .selected_text(format!("{k}: {}", list[k].name))
        .show_ui(ui, |ui| {
            for (i, m) in list.iter().enumerate().take(500) {
                ui.selectable_value(&mut app.panels.material, i, format!("{i}: {}", m.name));
            }
        });
    let m = &mut list[k];
    let mut changed = false;
    egui::Grid::new("material-grid")
        .num_columns(2)
        .show(ui, |ui| {
            ui.label("Kd (diffuse)");
            let mut kd = m.base_color.truncate().to_array();
            if ui.color_edit_button_rgb(&mut kd).changed() {
                m.base_color = Vec3::from_array(kd).extend(m.base_color.w);
                changed = true;
            }
            ui.end_row();
            ui.label("alpha");
            changed |= ui
                .add(egui::Slider::new(&mut m.base_color.w, 0.0..=1.0))
                .changed();
            ui.end_row();
            ui.label("Ks (specular)");
            let mut ks = m.specular.to_array();
            if ui.color_edit_button_rgb(&mut ks).changed() {
                m.specular = Vec3::from_array(ks);
                changed = true;
            }
            ui.end_row();
            ui.label("shininess n");
            changed |= ui
                .add(egui::Slider::new(&mut m.shininess, 1.0..=2000.0).logarithmic(true))
                .changed();
            ui.end_row();
            ui.label("Ka (ambient factor)");
            let mut ka = m.ambient.to_array();
            if ui.color_edit_button_rgb(&mut ka).changed() {
                m.ambient = Vec3::from_array(ka);
                changed = true;
            }
            ui.end_row();
            ui.label("alpha mode");
            ui.horizontal(|ui| {
                for (mode, name) in [
                    (AlphaMode::Opaque, "opaque"),
                    (AlphaMode::Mask(0.5), "mask 0.5"),
                    (AlphaMode::Blend, "blend"),
                ] {
                    changed |= ui.selectable_value(&mut m.alpha_mode, mode, name).changed();
                }
            });
            ui.end_row();
            ui.label("double-sided");
            changed |= ui.checkbox(&mut m.double_sided, "").changed();
            ui.end_row();
        });
    if changed {
        app.settings.materials = Some(list);
    }
    if app.settings.materials.is_some() && ui.button("restore the file's materials").clicked() {
        app.settings.materials = None;
    }
    if app.split.b.materials != app.settings.materials {
        app.split.b.materials = app.settings.materials.clone();
    }
}
