//! The rows of a light's editor that depend on its kind: direction, cone, pyramid and image, attenuation.

use super::*;

/// Direction as x, y, z and as azimuth and elevation.
pub(super) fn direction_rows(ui: &mut egui::Ui, id: &str, l: &mut Light, s: &Space) -> bool {
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
pub(super) fn cone_rows(ui: &mut egui::Ui, id: &str, l: &mut Light) -> bool {
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
pub(super) fn pyramid_rows(
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
pub(super) fn attenuation_rows(
    ui: &mut egui::Ui,
    id: &str,
    i: usize,
    l: &mut Light,
    s: &Space,
) -> bool {
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
