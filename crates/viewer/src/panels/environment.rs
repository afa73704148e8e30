//! The environment section: the environment that lights `pbr` surfaces (none, a built-in
//! or an `.hdr` / `.exr` file; turned, scaled, shown behind the model), the exposure,
//! linear fog (colour, d_min and d_max kept `near < far`, distance
//! Euclidean or camera depth), the tone map for colours outside [0, 1], shadow-map settings
//! (size, PCF radius, constant and slope-scaled bias) and the ground plane that catches
//! shadows. Turning fog or the ground off and on again brings back the values they had.
//! The split view's B side follows A's fog, shadows and ground (its tone map is its own, in
//! the split section).

use eframe::egui;
use glam::Vec3;

use super::edit;
use super::{file_dialog, Cx, Dock, Installed, Panel};
use crate::render::{Environment, Ground, ToneMap};
use crate::shade::{Fog, FogDistance, MAX_SHADOW_SIZE};
use crate::texture::env::{default_cache_dir, BUILTIN_NAMES, DEFAULT_ROTATION_DEG};

/// Shadow-map sizes offered.
pub const SHADOW_SIZES: [u32; 6] = [256, 512, 1024, 2048, 4096, 8192];

/// The environment section, with what it remembers while fog or the ground is off.
#[derive(Default)]
pub struct EnvironmentPanel {
    pub fog: Option<Fog>,
    pub ground: Option<Ground>,
    /// The open picker for an environment image.
    pub picker: Option<egui_file::FileDialog>,
    /// Why the last environment image could not be used.
    pub env_error: Option<String>,
}

impl Panel for EnvironmentPanel {
    fn dock(&self) -> Dock {
        Dock::Left
    }

    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        egui::CollapsingHeader::new("Environment, exposure, fog, tone map, shadows")
            .id_salt("environment")
            .show(ui, |ui| self.show(cx, ui));
    }

    fn dialogs(&mut self, ctx: &egui::Context, cx: &mut Cx<'_>) {
        if let Some(dialog) = &mut self.picker {
            if dialog.show(ctx).selected() {
                if let Some(p) = dialog.path().map(std::path::Path::to_path_buf) {
                    self.picker = None;
                    self.read_environment(cx, &p);
                }
            } else if !dialog.visible() {
                self.picker = None;
            }
        }
    }

    fn installed(&mut self, what: &Installed<'_>) {
        // A scene file's fog and ground come back when they are turned off and on again.
        if let Some(s) = what.settings {
            self.fog = s.fog;
            self.ground = s.ground;
        }
    }
}

/// Fog for the current view: from the front of the scene's bounding sphere to its back.
fn default_fog(cx: &Cx<'_>) -> Fog {
    let (c, r) = cx.session.scene.bounding_sphere();
    let eye = cx.view().camera.eye;
    let d = (c - eye).length();
    let d = if d.is_finite() { d } else { 2.0 * r };
    Fog {
        near: (d - r).max(0.0),
        far: (d + r).max(1e-3),
        ..Fog::default()
    }
}

impl EnvironmentPanel {
    /// The environment section.
    pub fn show(&mut self, cx: &mut Cx<'_>, ui: &mut egui::Ui) {
        self.image_lighting(cx, ui);
        ui.separator();
        self.fog(cx, ui);
        ui.separator();
        tone(cx, ui);
        let mut compensate = !cx.settings.single_scatter;
        if ui
            .checkbox(
                &mut compensate,
                "lights: give rough surfaces back lost energy",
            )
            .on_hover_text(
                "pbr: the punctual lights' specular lobe times 1 + F0 (1/Ess - 1), the energy \
                 single scattering loses between microfacets (as three.js). Off: the glTF \
                 specification's single-scattering BRDF. The environment is always compensated.",
            )
            .changed()
        {
            cx.settings.single_scatter = !compensate;
        }
        ui.separator();
        shadows(cx, ui);
        ui.separator();
        self.ground(cx, ui);
        let (a, b) = (&*cx.settings, &mut cx.split.b);
        if b.fog != a.fog
            || b.shadow != a.shadow
            || b.ground != a.ground
            || b.single_scatter != a.single_scatter
        {
            b.fog = a.fog;
            b.shadow = a.shadow;
            b.ground = a.ground;
            b.single_scatter = a.single_scatter;
        }
    }

    /// The environment, its rotation and intensity, the background and the exposure.
    fn image_lighting(&mut self, cx: &mut Cx<'_>, ui: &mut egui::Ui) {
        ui.label("image-based lighting of pbr surfaces (the split sum)");
        let s = &mut cx.settings;
        let mut pick = None;
        ui.horizontal(|ui| {
            ui.label("environment");
            egui::ComboBox::from_id_salt("environment")
            .selected_text(env_label(&s.environment))
            .show_ui(ui, |ui| {
                if ui
                    .selectable_label(s.environment == Environment::Off, "none")
                    .clicked()
                {
                    pick = Some("none");
                }
                for name in BUILTIN_NAMES {
                    let on = matches!(&s.environment, Environment::On(v) if v.env.name() == name)
                        || (name == "studio" && s.environment == Environment::Auto);
                    let what = match name {
                        "studio" => "a neutral photo studio: three soft boxes over a dim room",
                        "sky" => "a clear blue sky with a sun, over a dark ground",
                        _ => "radiance 1 from every direction: the white furnace",
                    };
                    if ui.selectable_label(on, name).on_hover_text(what).clicked() {
                        pick = Some(name);
                    }
                }
                if ui.selectable_label(false, "file (.hdr, .exr)...").clicked() {
                    pick = Some("file");
                }
            })
            .response
            .accessible_name("environment");
        });
        match pick {
            Some("file") => self.open_env_picker(cx),
            Some(name) => {
                let old = cx.settings.environment.view();
                match Environment::named(name, |n: &str| n.into(), None) {
                    Ok((env, _)) => {
                        cx.settings.environment = keep_turn(env, old);
                        self.env_error = None;
                    }
                    Err(e) => self.env_error = Some(e),
                }
            }
            None => {}
        }
        let s = &mut cx.settings;
        if let Some(mut view) = s.environment.view() {
            let mut changed = false;
            egui::Grid::new("env-grid").num_columns(2).show(ui, |ui| {
                ui.label("rotation about +Y").on_hover_text(format!(
                "{DEFAULT_ROTATION_DEG}° puts the image centre at +Z, as the Khronos sample viewer"
            ));
                changed |= edit::drag_with(
                    ui,
                    &mut view.rotation_deg,
                    edit::range_of("env_rotate"),
                    1.0,
                    "environment rotation",
                    "°",
                );
                ui.end_row();
                ui.label("intensity");
                changed |= edit::slider(
                    ui,
                    &mut view.intensity,
                    edit::range_of("env_intensity"),
                    true,
                    "environment intensity",
                );
                ui.end_row();
            });
            if changed {
                s.environment = Environment::On(view);
            }
            let mut shown = s.env_background.is_some();
            if ui
                .checkbox(&mut shown, "shown behind the model")
                .on_hover_text("the environment instead of the background colour, blurred")
                .changed()
            {
                s.env_background = shown.then_some(0.0);
            }
            if let Some(blur) = &mut s.env_background {
                ui.horizontal(|ui| {
                    ui.label("blur (roughness)");
                    edit::slider(
                        ui,
                        blur,
                        edit::range_of("env_background"),
                        false,
                        "environment background blur",
                    );
                });
            }
        }
        if let Some(e) = &self.env_error {
            ui.colored_label(ui.visuals().error_fg_color, e);
        }
        ui.horizontal(|ui| {
            ui.label("exposure").on_hover_text(
                "stops: colours are multiplied by 2^EV before the tone map (lights are in lux: \
             a sunlit glTF scene wants about -15)",
            );
            edit::drag_with(
                ui,
                &mut cx.settings.exposure,
                edit::range_of("exposure"),
                0.05,
                "exposure in stops",
                " EV",
            );
        });
    }

    /// Opens the picker for an environment image.
    fn open_env_picker(&mut self, cx: &mut Cx<'_>) {
        let filter = Box::new(|p: &std::path::Path| {
            p.extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| matches!(e.to_ascii_lowercase().as_str(), "hdr" | "exr"))
        });
        self.picker = Some(file_dialog(
            cx,
            "Environment (equirectangular .hdr or .exr)",
            filter,
        ));
    }

    /// Lights the scene with the equirectangular image at `path`, prefiltered once and cached
    /// by content (a second open is instant), or shows why it cannot (in the section and the
    /// status bar); the scene and the other settings stay as they were.
    pub fn read_environment(&mut self, cx: &mut Cx<'_>, path: &std::path::Path) {
        let old = cx.settings.environment.view();
        let cache = default_cache_dir();
        match Environment::named(
            &path.display().to_string(),
            |n: &str| n.into(),
            cache.as_deref(),
        ) {
            Ok((env, note)) => {
                cx.settings.environment = keep_turn(env, old);
                self.env_error = None;
                if let Some(n) = note {
                    cx.notice(format!("{}: {n}", path.display()));
                }
            }
            Err(e) => {
                let e = format!("{}: {e}", path.display());
                cx.notice(e.clone());
                self.env_error = Some(e);
            }
        }
    }

    fn fog(&mut self, cx: &mut Cx<'_>, ui: &mut egui::Ui) {
        let mut on = cx.settings.fog.is_some();
        if ui
            .checkbox(
                &mut on,
                "fog (linear, the textbook's pipeline chapter, §5.1)",
            )
            .changed()
        {
            let fog = on.then(|| self.fog.unwrap_or_else(|| default_fog(cx)));
            cx.settings.fog = fog;
        }
        let Some(f) = &mut cx.settings.fog else {
            return;
        };
        let speed = f64::from(cx.session.scene.bounding_sphere().1 * 0.01).max(1e-4);
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
                        edit::drag(ui, &mut near, edit::range_of("fog.near"), speed, "fog near"),
                        edit::drag(ui, &mut far, edit::range_of("fog.far"), speed, "fog far"),
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
        self.fog = Some(*f);
    }

    fn ground(&mut self, cx: &mut Cx<'_>, ui: &mut egui::Ui) {
        let mut on = cx.settings.ground.is_some();
        if ui
            .checkbox(&mut on, "ground plane under the scene (catches shadows)")
            .changed()
        {
            cx.settings.ground = on.then(|| self.ground.unwrap_or_default());
        }
        let Some(g) = &mut cx.settings.ground else {
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
                edit::drag(
                    ui,
                    &mut g.extent,
                    edit::range_of("ground.extent"),
                    0.05,
                    "ground extent",
                );
                ui.end_row();
            });
        self.ground = Some(*g);
    }
}

/// What the environment is called in the picker.
fn env_label(e: &Environment) -> String {
    match e {
        Environment::Auto => "studio (default)".into(),
        Environment::Off => "none".into(),
        Environment::On(v) => v.env.name().to_owned(),
    }
}

/// `env` with the rotation and intensity of `old` (the user's), if both are on.
fn keep_turn(env: Environment, old: Option<crate::texture::env::EnvView>) -> Environment {
    match (env, old) {
        (Environment::On(mut v), Some(o)) => {
            v.rotation_deg = o.rotation_deg;
            v.intensity = o.intensity;
            Environment::On(v)
        }
        (env, _) => env,
    }
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

fn tone(cx: &mut Cx<'_>, ui: &mut egui::Ui) {
    tone_map(ui, &mut cx.settings.tone, "a");
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
                        ToneMap::Auto => {
                            "PBR Neutral for a glTF model's own look (as the Khronos sample \
                             viewer), clamp for the textbook's shading modes"
                        }
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

fn shadows(cx: &mut Cx<'_>, ui: &mut egui::Ui) {
    let casting: Vec<String> = super::lights::effective(cx.settings, cx.session.scene)
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
    let s = &mut cx.settings.shadow;
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
            let pcf_range = edit::whole_range_of("shadow.pcf");
            let mut pcf = s.pcf.min(*pcf_range.end());
            if ui
                .add(egui::Slider::new(&mut pcf, pcf_range))
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
                let bias = edit::range_of("shadow.bias");
                edit::drag(ui, &mut s.bias, bias, 0.05, "shadow bias");
                let slope = edit::range_of("shadow.slope");
                edit::drag(ui, &mut s.slope, slope, 0.05, "shadow slope bias");
            });
            ui.end_row();
        });
}
