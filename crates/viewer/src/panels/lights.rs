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
        Lights::Auto if scene.lights().is_empty() => (Light::default_rig(Mat3::IDENTITY), true),
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
            None => depth * (cam.yfov * 0.5).tan(),
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
        ((s.radius / d).asin() * 0.5).min(40f32.to_radians())
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

/// Direction as x, y, z and as azimuth and elevation.
fn direction_rows(ui: &mut egui::Ui, id: &str, l: &mut Light, s: &Space) -> bool {
    let mut changed = false;
    ui.label("direction");
    ui.horizontal(|ui| {
        changed |= edit::vec3(ui, &mut l.direction, 0.01, &format!("{id}direction"))
    });
    ui.end_row();
    ui.label("az / el");
    ui.horizontal(|ui| {
        let (mut az, mut el) = edit::azimuth_elevation(l.direction, s.compass).unwrap_or((0.0, -90.0));
        let a = edit::drag_with(ui, &mut az, -180.0..=180.0, 0.5, &format!("{id}azimuth"), "°");
        let e = edit::drag_with(ui, &mut el, -90.0..=90.0, 0.5, &format!("{id}elevation"), "°");
        if a || e {
            let len = l.direction.length();
            let len = if len.is_finite() && len > 0.0 { len } else { 1.0 };
            l.direction = edit::from_azimuth_elevation(az, el, s.compass) * len;
            changed = true;
        }
    })
    .response
    .on_hover_text("azimuth 0 points away from the front view, 90 to the right; elevation -90 points straight down");
    ui.end_row();
    changed
}

/// The spot's hotspot and falloff half-angles, kept `inner <= outer`.
fn cone_rows(ui: &mut egui::Ui, id: &str, l: &mut Light) -> bool {
    let max = max_degrees();
    let (mut inner, mut outer) = (l.inner, l.outer);
    ui.label("hotspot")
        .on_hover_text("inner half-angle: full strength inside");
    let ci = edit::degrees(ui, &mut inner, 0.0..=max, &format!("{id}inner"));
    ui.end_row();
    ui.label("falloff")
        .on_hover_text("outer half-angle: no light outside, a smooth fall between");
    let co = edit::degrees(ui, &mut outer, 0.1..=max, &format!("{id}outer"));
    ui.end_row();
    if !(ci || co) {
        return false;
    }
    let (lo, hi) = (0.0, max.to_radians());
    let mut inner = edit::shown(inner, &(lo..=hi));
    let mut outer = edit::shown(outer, &(0.1f32.to_radians()..=hi));
    if inner > outer {
        if ci {
            outer = inner.max(0.1f32.to_radians());
        } else {
            inner = outer;
        }
    }
    l.inner = inner.min(outer);
    l.outer = outer;
    true
}

/// The rectangular spot's half-angles, up vector and image.
fn pyramid_rows(
    ui: &mut egui::Ui,
    id: &str,
    l: &mut Light,
    loading: bool,
    i: usize,
    requests: &mut Vec<Request>,
) -> bool {
    let max = max_degrees();
    let mut changed = false;
    ui.label("half-angles");
    ui.horizontal(|ui| {
        changed |= edit::degrees(
            ui,
            &mut l.rect.x,
            0.1..=max,
            &format!("{id}horizontal half-angle"),
        );
        changed |= edit::degrees(
            ui,
            &mut l.rect.y,
            0.1..=max,
            &format!("{id}vertical half-angle"),
        );
    });
    ui.end_row();
    ui.label("up")
        .on_hover_text("the projected image's up direction");
    ui.horizontal(|ui| changed |= edit::vec3(ui, &mut l.up, 0.01, &format!("{id}up")));
    ui.end_row();
    ui.label("image");
    match &l.image {
        Some(t) => ui.label(format!("{} ({}x{})", t.name, t.width, t.height)),
        None => ui.label("none (plain colour)"),
    };
    ui.end_row();
    ui.label("");
    ui.horizontal(|ui| {
        if ui
            .small_button("choose…")
            .accessible_name(format!("{id}choose image"))
            .clicked()
        {
            requests.push(Request::PickImage(i));
        }
        if l.image.is_some()
            && ui
                .small_button("clear")
                .accessible_name(format!("{id}clear image"))
                .clicked()
        {
            l.image = None;
            changed = true;
        }
        if loading {
            ui.label("reading…");
        }
    });
    ui.end_row();
    changed
}

/// Attenuation mode and parameters, and what arrives at the scene's centre.
fn attenuation_rows(ui: &mut egui::Ui, id: &str, i: usize, l: &mut Light, s: &Space) -> bool {
    let mut changed = false;
    let d = (s.center - l.position).length();
    let d = if d.is_finite() && d > 1e-6 {
        d
    } else {
        s.radius
    };
    let current = l.attenuation;
    ui.label("attenuation");
    egui::ComboBox::from_id_salt(("light-attenuation", i))
        .selected_text(current.name())
        .show_ui(ui, |ui| {
            // A new mode's numbers span the scene as seen from the light.
            for a in [
                Attenuation::None,
                Attenuation::Linear {
                    near: (d - s.radius).max(0.0),
                    far: d + s.radius,
                },
                Attenuation::InverseSquare,
                Attenuation::Range(d + s.radius),
            ] {
                let on = current.name() == a.name();
                if ui.selectable_label(on, a.name()).clicked() && !on {
                    l.attenuation = a;
                    changed = true;
                }
            }
        })
        .response
        .accessible_name(format!("{id}attenuation"));
    ui.end_row();
    let speed = s.speed();
    match &mut l.attenuation {
        Attenuation::Linear { near, far } => {
            let (mut n, mut f) = (*near, *far);
            ui.label("near / far")
                .on_hover_text("full strength within near, none beyond far, linear between");
            let (cn, cf) = ui
                .horizontal(|ui| {
                    let cn = edit::drag(ui, &mut n, 0.0..=f32::MAX, speed, &format!("{id}near"));
                    let cf = edit::drag(ui, &mut f, 1e-3..=f32::MAX, speed, &format!("{id}far"));
                    (cn, cf)
                })
                .inner;
            ui.end_row();
            if cn || cf {
                let n0 = edit::shown(n, &(0.0..=f32::MAX));
                let f0 = edit::shown(f, &(1e-3..=f32::MAX));
                (*near, *far) = match (n0 > f0, cn) {
                    (true, true) => (n0, n0),
                    (true, false) => (f0, f0),
                    _ => (n0, f0),
                };
                changed = true;
            }
        }
        Attenuation::Range(r) => {
            ui.label("range");
            changed |= edit::drag(ui, r, 1e-3..=f32::MAX, speed, &format!("{id}range"));
            ui.end_row();
        }
        Attenuation::None | Attenuation::InverseSquare => {}
    }
    let factor = l.attenuation.factor(f64::from(d)) as f32;
    ui.label("at centre")
        .on_hover_text("distance from the light to the scene's centre, and the attenuation there");
    ui.horizontal(|ui| {
        ui.label(format!("d {d:.2}: x {factor:.3}"));
        if factor > 0.0
            && factor.is_finite()
            && (factor - 1.0).abs() > 1e-6
            && ui
                .small_button("set x 1")
                .on_hover_text(
                    "sets the intensity so the light arrives at the centre at its colour",
                )
                .clicked()
        {
            l.intensity = 1.0 / factor;
            changed = true;
        }
    });
    ui.end_row();
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
