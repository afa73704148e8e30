//! The light editor. It edits the frame's light list (the scene's lights, or the default
//! rig when the scene has none) as the renderer's [`Lights::Custom`], so the frame follows
//! every change; "back to the scene's lights" returns to [`Lights::Auto`].
//!
//! Every [`Light`] has every field, so switching a light's kind keeps its other values
//! (a spot turned into a point light and back has its cone again). The editor shows the
//! fields the kind uses: colour and intensity; position (point, spot, rectangular);
//! direction as x, y, z and as azimuth and elevation (directional, spot, rectangular); the
//! spot's hotspot and falloff half-angles in degrees, kept `inner <= outer`; the
//! rectangular spot's half-angles, up vector and projected image; attenuation with its
//! parameters (positional kinds); shadows (the kinds that can cast them).
//!
//! With "follow the camera" the positions and directions are in camera space (x right,
//! y up, z towards the viewer); turning it on or off converts them with the current
//! camera, so the lights stay where they are.

use std::borrow::Cow;
use std::path::PathBuf;

use eframe::egui;
use glam::{Mat3, Mat4, Vec2, Vec3};

use super::edit;
use super::{file_dialog, Cx, Dock, Panel};
use crate::navigate::UpAxis;
use crate::render::{Lights, PreparedScene, Settings};
use crate::scene::{Attenuation, Light, LightKind};
use crate::shade::MAX_HALF_ANGLE;
use crate::slide::{self, SlideLoad};

mod rows;
use rows::*;

/// The light editor (the gizmos' toggle and the light under the pointer are in
/// [`super::Shared`], which the viewport reads).
#[derive(Default)]
pub struct LightsPanel {
    /// The image picker, open for this light.
    pub slide_picker: Option<(usize, egui_file::FileDialog)>,
    /// An image being decoded.
    pub slide_load: Option<SlideLoad>,
    /// The last image that could not be used, until the next success or dismissal.
    pub slide_error: Option<String>,
}

impl Panel for LightsPanel {
    fn dock(&self) -> Dock {
        Dock::Left
    }

    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        egui::CollapsingHeader::new("Lights").show(ui, |ui| self.lights(ui, cx));
    }

    fn poll(&mut self, cx: &mut Cx<'_>) {
        let done = self
            .slide_load
            .as_ref()
            .and_then(|t| t.poll().map(|o| (t.light, o)));
        if let Some((light, out)) = done {
            self.slide_load = None;
            self.install_image(cx, light, out);
        }
    }

    fn dialogs(&mut self, ctx: &egui::Context, cx: &mut Cx<'_>) {
        if let Some((light, dialog)) = &mut self.slide_picker {
            let light = *light;
            if dialog.show(ctx).selected() {
                if let Some(p) = dialog.path().map(std::path::Path::to_path_buf) {
                    self.slide_picker = None;
                    self.read_image(cx, light, p);
                }
            } else if !dialog.visible() {
                self.slide_picker = None;
            }
        }
    }
}

/// The lights the frame uses now, as an editable list, and whether they follow the camera:
/// the custom list, the scene's lights (world space, as posed now), or the default rig
/// (camera space).
/// The order is the frame's (the probe's and the gizmos' light numbers).
#[must_use]
pub fn effective(settings: &Settings, scene: &PreparedScene) -> (Vec<Light>, bool) {
    match &settings.lights {
        Lights::Custom {
            lights,
            follow_camera,
        } => (lights.clone(), *follow_camera),
        Lights::Auto if settings.default_rig(scene.scene()) => {
            (Light::default_rig(Mat3::IDENTITY), true)
        }
        Lights::Auto => (scene.lights().to_vec(), false),
    }
}

/// The names of the frame's lights, in its order.
#[must_use]
pub fn light_names(settings: &Settings, scene: &PreparedScene) -> Vec<String> {
    effective(settings, scene)
        .0
        .iter()
        .map(|l| l.name.to_string())
        .collect()
}

/// Where things are in the space the lights are edited in (world, or camera space when they
/// follow the camera).
struct Space {
    /// The scene's bounding sphere.
    center: Vec3,
    radius: f32,
    /// The camera's up unit vector.
    up: Vec3,
    /// East, north and up for azimuth and elevation.
    compass: [Vec3; 3],
    /// Where a new lamp goes: between the camera and the scene, towards the top right of
    /// the view, so it is in sight and lights the scene from about 30 degrees.
    lamp: Vec3,
}

impl Space {
    fn new(cx: &Cx<'_>, follow: bool) -> Self {
        let (c, radius) = cx.session.scene.bounding_sphere();
        let cam = cx.view().camera;
        let view = cam.view();
        let to_world = view.inverse();
        let axis = |v: Vec3| to_world.transform_vector3(v).normalize_or(v);
        let (right, up, back) = (axis(Vec3::X), axis(Vec3::Y), axis(Vec3::Z));
        let aspect = cx.viewport.aspect();
        let distance = (cam.target - cam.eye).length();
        let depth = if distance.is_finite() && distance > 0.0 {
            0.55 * distance
        } else {
            2.0 * radius
        };
        let half = match cam.ortho {
            Some(h) => h,
            None => depth * libm::tanf(cam.yfov * 0.5),
        };
        let lamp = cam.eye - back * depth + (right * aspect + up) * 0.6 * half;
        let lamp = if lamp.is_finite() {
            lamp
        } else {
            c + up * 2.0 * radius
        };
        if follow {
            return Self {
                center: view.transform_point3(c),
                radius,
                up: Vec3::Y,
                compass: [Vec3::X, Vec3::NEG_Z, Vec3::Y],
                lamp: view.transform_point3(lamp),
            };
        }
        Self {
            center: c,
            radius,
            up,
            compass: match cx.nav.up_axis() {
                UpAxis::Y => [Vec3::X, Vec3::NEG_Z, Vec3::Y],
                UpAxis::Z => [Vec3::X, Vec3::Y, Vec3::Z],
            },
            lamp,
        }
    }

    /// Drag speed for positions.
    fn speed(&self) -> f64 {
        f64::from(self.radius * 0.01).max(1e-4)
    }
}

/// Something a light's buttons ask for, done after the list is drawn.
enum Request {
    Remove(usize),
    Duplicate(usize),
    PickImage(usize),
}

/// The largest cone or pyramid half-angle, in degrees (what the renderer accepts).
fn max_degrees() -> f32 {
    MAX_HALF_ANGLE.to_degrees()
}

/// "0: key (directional)".
fn header(i: usize, l: &Light) -> String {
    if l.name.is_empty() || l.name == l.kind.name() {
        format!("{i}: {}", l.kind.name())
    } else {
        format!("{i}: {} ({})", l.name, l.kind.name())
    }
}

/// A new light of `kind`, numbered `n`, placed to show off on the scene: at the lamp
/// position of `s`, aimed at the scene's centre; a spot's pool of light covers about half
/// the scene, so its edge shows on it.
fn new_light(kind: LightKind, s: &Space, n: usize) -> Light {
    let to_center = s.center - s.lamp;
    let aim = to_center.normalize_or(-s.up);
    let d = to_center.length();
    // Half the half-angle the bounding sphere subtends.
    let cone = if d > s.radius {
        (libm::asinf(s.radius / d) * 0.5).min(40f32.to_radians())
    } else {
        30f32.to_radians()
    };
    let lamp = Vec3::splat(0.8);
    let light = match kind {
        LightKind::Ambient => Light::ambient(Vec3::splat(0.1)),
        LightKind::Directional => Light::directional(aim, lamp),
        LightKind::Point => Light::point(s.lamp, lamp),
        LightKind::Spot => Light::spot(s.lamp, aim, lamp, 0.6 * cone, cone),
        LightKind::Rect => Light::rect(s.lamp, aim, s.up, Vec2::new(cone, 0.75 * cone), lamp),
    };
    light.with_name(format!("{} {n}", kind.name()))
}

impl LightsPanel {
    /// The light editor section.
    fn lights(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        let (mut list, mut follow) = effective(cx.settings, cx.session.scene);
        let mut changed = false;
        ui.checkbox(
            &mut cx.shared.light_gizmos,
            "show the lights and their cones in the view (L)",
        );
        let mut f = follow;
        if ui
            .checkbox(
                &mut f,
                "follow the camera (positions and directions in camera space)",
            )
            .changed()
        {
            let view = cx.view().camera.view();
            let m: Mat4 = if f { view } else { view.inverse() };
            for l in &mut list {
                *l = l.transformed(m);
            }
            follow = f;
            changed = true;
        }
        let space = Space::new(cx, follow);
        let mut requests = Vec::new();
        let mut hovered = None;
        let loading = self.slide_load.as_ref().map(|s| s.light);
        for (i, l) in list.iter_mut().enumerate() {
            let r = egui::CollapsingHeader::new(header(i, l))
                .id_salt(("light", i))
                .show(ui, |ui| {
                    changed |= light_editor(ui, i, l, &space, loading == Some(i), &mut requests);
                });
            let body = r
                .body_response
                .as_ref()
                .is_some_and(egui::Response::contains_pointer);
            if body || r.header_response.contains_pointer() {
                hovered = Some(i);
            }
        }
        cx.shared.hovered_light = hovered;
        for q in requests {
            match q {
                Request::Remove(i) if i < list.len() => {
                    list.remove(i);
                    changed = true;
                }
                Request::Duplicate(i) if i < list.len() => {
                    let mut copy = list[i].clone();
                    copy.name = Cow::Owned(format!("{} copy", copy.name));
                    list.insert(i + 1, copy);
                    changed = true;
                }
                Request::PickImage(i) => self.open_image_picker(cx, i),
                _ => {}
            }
        }
        ui.horizontal_wrapped(|ui| {
            ui.label("add");
            for kind in LightKind::ALL {
                if ui
                    .button(format!("+ {}", kind.name()))
                    .on_hover_text(format!("add a {} light", kind.name()))
                    .clicked()
                {
                    list.push(new_light(kind, &space, list.len()));
                    changed = true;
                }
            }
        });
        if let Some(e) = self.slide_error.clone() {
            ui.horizontal_wrapped(|ui| {
                ui.colored_label(egui::Color32::from_rgb(255, 110, 90), e);
                if ui.small_button("dismiss").clicked() {
                    self.slide_error = None;
                }
            });
        }
        if changed {
            cx.settings.lights = Lights::Custom {
                lights: list,
                follow_camera: follow,
            };
        }
        if cx.settings.lights != Lights::Auto
            && ui
                .button("back to the scene's lights (or the default rig)")
                .clicked()
        {
            cx.settings.lights = Lights::Auto;
        }
        if cx.split.b.lights != cx.settings.lights {
            cx.split.b.lights = cx.settings.lights.clone();
        }
    }
}

/// The controls of light `i`; true if it changed.
fn light_editor(
    ui: &mut egui::Ui,
    i: usize,
    l: &mut Light,
    s: &Space,
    loading: bool,
    requests: &mut Vec<Request>,
) -> bool {
    let id = |what: &str| format!("light {i} {what}");
    let mut changed = false;
    egui::Grid::new(("light-grid", i))
        .num_columns(2)
        .show(ui, |ui| {
            ui.label("kind");
            egui::ComboBox::from_id_salt(("light-kind", i))
                .selected_text(l.kind.name())
                .show_ui(ui, |ui| {
                    for k in LightKind::ALL {
                        changed |= ui.selectable_value(&mut l.kind, k, k.name()).changed();
                    }
                })
                .response
                .accessible_name(id("kind"));
            ui.end_row();
            ui.label("name");
            let mut name = l.name.to_string();
            if ui
                .add(egui::TextEdit::singleline(&mut name).desired_width(140.0))
                .accessible_name(id("name"))
                .changed()
            {
                l.name = Cow::Owned(name);
                changed = true;
            }
            ui.end_row();
            ui.label("colour");
            ui.horizontal(|ui| {
                changed |= edit::colour(ui, &mut l.color, &id("colour"));
                changed |= edit::drag(ui, &mut l.intensity, 0.0..=1e6, 0.01, &id("intensity"));
            });
            ui.end_row();
            if l.kind.positional() {
                ui.label("position");
                ui.horizontal(|ui| {
                    changed |= edit::vec3(ui, &mut l.position, s.speed(), &id("position"))
                });
                ui.end_row();
            }
            if l.kind.directed() {
                changed |= direction_rows(ui, &id(""), l, s);
            }
            match l.kind {
                LightKind::Spot => changed |= cone_rows(ui, &id(""), l),
                LightKind::Rect => changed |= pyramid_rows(ui, &id(""), l, loading, i, requests),
                _ => {}
            }
            if l.kind.positional() {
                changed |= attenuation_rows(ui, &id(""), i, l, s);
            }
            if l.kind.can_shadow() {
                ui.label("shadows");
                changed |= ui
                    .checkbox(&mut l.shadow, "cast")
                    .accessible_name(id("shadows"))
                    .changed();
                ui.end_row();
            }
        });
    ui.horizontal_wrapped(|ui| {
        if ui
            .small_button("duplicate")
            .accessible_name(id("duplicate"))
            .clicked()
        {
            requests.push(Request::Duplicate(i));
        }
        if ui
            .small_button("remove")
            .accessible_name(id("remove"))
            .clicked()
        {
            requests.push(Request::Remove(i));
        }
        if l.kind.positional()
            && l.kind.directed()
            && ui
                .small_button("aim at the centre")
                .on_hover_text("point it at the centre of the scene's bounding sphere")
                .clicked()
        {
            l.direction = (s.center - l.position).normalize_or(l.direction);
            changed = true;
        }
    });
    changed
}

impl LightsPanel {
    /// Opens the image picker for light `light`.
    fn open_image_picker(&mut self, cx: &Cx<'_>, light: usize) {
        let filter = Box::new(|p: &std::path::Path| {
            p.extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| slide::EXTENSIONS.contains(&e.to_ascii_lowercase().as_str()))
        });
        let dialog = file_dialog(
            cx,
            "Image for the rectangular spotlight (.png, .jpg)",
            filter,
        );
        self.slide_picker = Some((light, dialog));
    }

    /// Reads `path` as the image of light `light`: now in synchronous mode (tests), else on a
    /// thread of its own ([`Panel::poll`] installs it).
    pub fn read_image(&mut self, cx: &mut Cx<'_>, light: usize, path: PathBuf) {
        if cx.session.synchronous {
            let out = slide::decode(&path).map(std::sync::Arc::new);
            self.install_image(cx, light, out);
        } else {
            self.slide_load = Some(SlideLoad::start(
                light,
                path,
                std::sync::Arc::clone(cx.session.repaint),
            ));
        }
    }

    /// Gives light `light` a decoded image, or shows why there is none.
    fn install_image(&mut self, cx: &mut Cx<'_>, light: usize, out: slide::Outcome) {
        let texture = match out {
            Ok(t) => t,
            Err(e) => {
                // Also in the status bar: the editor may be scrolled away or shut.
                cx.notice(e.clone());
                self.slide_error = Some(e);
                return;
            }
        };
        let (mut list, follow_camera) = effective(cx.settings, cx.session.scene);
        let Some(l) = list.get_mut(light) else {
            self.slide_error = Some(format!("{}: light {light} no longer exists", texture.name));
            return;
        };
        l.image = Some(texture);
        self.slide_error = None;
        cx.settings.lights = Lights::Custom {
            lights: list,
            follow_camera,
        };
    }
}
