//! The environment section: linear fog (colour, d_min and d_max kept `near < far`, distance
//! Euclidean or camera depth), the tone map for colours outside [0, 1], shadow-map settings
//! (size, PCF radius, constant and slope-scaled bias) and the ground plane that catches
//! shadows. Turning fog or the ground off and on again brings back the values they had.
//! The split view's B side follows A's fog, shadows and ground (its tone map is its own, in
//! the split section).

use eframe::egui;
use glam::Vec3;

use super::edit;
use crate::render::{Ground, ToneMap};
use crate::shade::{Fog, FogDistance, MAX_SHADOW_SIZE};
use crate::viewer::app::ViewerApp;

/// Shadow-map sizes offered.
pub const SHADOW_SIZES: [u32; 6] = [256, 512, 1024, 2048, 4096, 8192];
/// Largest PCF radius offered ((2r + 1)² taps).
pub const MAX_PCF: u32 = 4;

/// What the section remembers while fog or the ground is off.
#[derive(Clone, Debug, Default)]
pub struct EnvironmentUi {
    pub fog: Option<Fog>,
    pub ground: Option<Ground>,
}

/// Fog for the current view: from the front of the scene's bounding sphere to its back.
fn default_fog(app: &ViewerApp) -> Fog {
    let (c, r) = app.scene.bounding_sphere();
    let eye = app.current_view().camera.eye;
    let d = (c - eye).length();
    let d = if d.is_finite() { d } else { 2.0 * r };
    Fog {
        near: (d - r).max(0.0),
        far: (d + r).max(1e-3),
        ..Fog::default()
    }
}

/// The environment section.
pub fn show(app: &mut ViewerApp, ui: &mut egui::Ui) {
    fog(app, ui);
    ui.separator();
    tone(app, ui);
    ui.separator();
    shadows(app, ui);
    ui.separator();
    ground(app, ui);
    let (a, b) = (&app.settings, &mut app.split.b);
    if b.fog != a.fog || b.shadow != a.shadow || b.ground != a.ground {
        b.fog = a.fog;
        b.shadow = a.shadow;
        b.ground = a.ground;
    }
}

fn fog(app: &mut ViewerApp, ui: &mut egui::Ui) {
    let mut on = app.settings.fog.is_some();
    if ui
        .checkbox(
            &mut on,
            "fog (linear, the textbook's pipeline chapter, §5.1)",
        )
        .changed()
    {
        app.settings.fog = if on {
            Some(
                app.panels
                    .environment
                    .fog
                    .unwrap_or_else(|| default_fog(app)),
            )
        } else {
            None
        };
    }
    let Some(f) = &mut app.settings.fog else {
        return;
    };
    let speed = f64::from(app.scene.bounding_sphere().1 * 0.01).max(1e-4);
    egui::Grid::new("fog-grid").num_columns(2).show(ui, |ui| {
        ui.label("colour");
        edit::colour(ui, &mut f.color, "fog colour");
        ui.end_row();
        ui.label("near / far")
            .on_hover_text("no fog within near, only fog beyond far, linear between");
        let (mut near, mut far) = (f.near, f.far);
        let (cn, cf) = ui
            .horizontal(|ui| {
                (
                    edit::drag(ui, &mut near, 0.0..=f32::MAX, speed, "fog near"),
                    edit::drag(ui, &mut far, 1e-3..=f32::MAX, speed, "fog far"),
                )
            })
            .inner;
        if cn || cf {
            (f.near, f.far) = ordered(near, far, cn);
        }
        ui.end_row();
        ui.label("distance");
        ui.horizontal(|ui| {
            ui.selectable_value(&mut f.distance, FogDistance::Euclidean, "from the eye")
                .on_hover_text("spherical: the same as the camera turns");
            ui.selectable_value(&mut f.distance, FogDistance::Depth, "camera depth")
                .on_hover_text("along the line of sight: changes as the camera turns");
        });
        ui.end_row();
    });
    app.panels.environment.fog = Some(*f);
}

/// Fog distances kept `0 <= near < far`: the edited one wins, the other moves out of its
/// way.
#[must_use]
pub fn ordered(near: f32, far: f32, near_edited: bool) -> (f32, f32) {
    let near = edit::shown(near, &(0.0..=f32::MAX));
    let far = edit::shown(far, &(1e-3..=f32::MAX));
    if near < far {
        (near, far)
    } else if near_edited {
        (near, near + (near * 0.01).max(1e-3))
    } else {
        ((far - (far * 0.01).max(1e-3)).max(0.0), far)
    }
}

fn tone(app: &mut ViewerApp, ui: &mut egui::Ui) {
    tone_map(ui, &mut app.settings.tone, "a");
}

/// The tone map selector of one side of the split (`id` "a" or "b").
pub fn tone_map(ui: &mut egui::Ui, tone: &mut ToneMap, id: &str) {
    ui.horizontal(|ui| {
        ui.label("colours above 1");
        egui::ComboBox::from_id_salt(("tone", id))
            .selected_text(tone.name())
            .show_ui(ui, |ui| {
                for t in ToneMap::ALL {
                    let what = match t {
                        ToneMap::Clamp => "clamp each channel: (1, 2, 1) turns white",
                        ToneMap::ScaleMax => "divide by the largest: (1, 2, 1) stays light green",
                        ToneMap::Reinhard => {
                            "Reinhard L / (1 + L): everything fits, a little darker"
                        }
                        ToneMap::PbrNeutral => {
                            "Khronos PBR Neutral: base colours kept (minus 0.04), highlights \
                             rolled off to white"
                        }
                        ToneMap::AcesNarkowicz => "ACES filmic (Narkowicz's fit): 1 becomes 0.8",
                        ToneMap::AcesHill => {
                            "ACES filmic (Hill's RRT + ODT fit): 1 becomes 0.62, contrasty"
                        }
                    };
                    ui.selectable_value(tone, t, t.name()).on_hover_text(what);
                }
            })
            .response
            .accessible_name(format!("tone map {}", id.to_uppercase()));
    });
}

fn shadows(app: &mut ViewerApp, ui: &mut egui::Ui) {
    let casting: Vec<String> = super::lights::effective(app)
        .0
        .iter()
        .enumerate()
        .filter(|(_, l)| l.shadow && l.kind.can_shadow())
        .map(|(i, l)| {
            if l.name.is_empty() {
                i.to_string()
            } else {
                format!("{i} {}", l.name)
            }
        })
        .collect();
    ui.label(if casting.is_empty() {
        "Shadows: no light casts any (tick a directional, spot or rect light's \"cast\")".to_owned()
    } else {
        format!("Shadows cast by: {}", casting.join(", "))
    });
    let s = &mut app.settings.shadow;
    egui::Grid::new("shadow-grid")
        .num_columns(2)
        .show(ui, |ui| {
            ui.label("map size");
            egui::ComboBox::from_id_salt("shadow-size")
                .selected_text(format!("{0}x{0}", s.size))
                .show_ui(ui, |ui| {
                    for n in SHADOW_SIZES.into_iter().filter(|n| *n <= MAX_SHADOW_SIZE) {
                        ui.selectable_value(&mut s.size, n, format!("{n}x{n}"));
                    }
                })
                .response
                .accessible_name("shadow map size");
            ui.end_row();
            ui.label("PCF radius");
            let mut pcf = s.pcf.min(MAX_PCF);
            if ui
                .add(egui::Slider::new(&mut pcf, 0..=MAX_PCF))
                .on_hover_text("(2r + 1)² filtered taps; 0 = one bilinear tap, the hardest edge")
                .accessible_name("shadow PCF radius")
                .changed()
            {
                s.pcf = pcf;
            }
            ui.end_row();
            ui.label("bias / slope")
                .on_hover_text("constant and slope-scaled depth bias, in texels");
            ui.horizontal(|ui| {
                edit::drag(ui, &mut s.bias, 0.0..=50.0, 0.05, "shadow bias");
                edit::drag(ui, &mut s.slope, 0.0..=50.0, 0.05, "shadow slope bias");
            });
            ui.end_row();
        });
}

fn ground(app: &mut ViewerApp, ui: &mut egui::Ui) {
    let mut on = app.settings.ground.is_some();
    if ui
        .checkbox(&mut on, "ground plane under the scene (catches shadows)")
        .changed()
    {
        app.settings.ground = on.then(|| app.panels.environment.ground.unwrap_or_default());
    }
    let Some(g) = &mut app.settings.ground else {
        return;
    };
    egui::Grid::new("ground-grid")
        .num_columns(2)
        .show(ui, |ui| {
            ui.label("colour");
            let mut c: Vec3 = g.color;
            if edit::colour(ui, &mut c, "ground colour") {
                g.color = c;
            }
            ui.end_row();
            ui.label("half-size").on_hover_text("in scene radii");
            edit::drag(ui, &mut g.extent, 0.1..=100.0, 0.05, "ground extent");
            ui.end_row();
        });
    app.panels.environment.ground = Some(*g);
}
