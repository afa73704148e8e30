//! Small editing widgets shared by the light, material and environment editors.
//!
//! The values they edit come from files and may be anything: NaN, infinities, a cone wider
//! than the renderer accepts. Each widget shows such a value clamped into its range (NaN as
//! the range's value nearest 0) but writes nothing back until the user drags, types or picks:
//! merely looking at a panel never changes the settings (egui's own widgets would report the
//! clamp of an out-of-range value as a change, turning the scene's lights into an override
//! and re-rendering the frame). Every widget carries an accessible name, which is what the UI
//! tests find it by.

use std::ops::RangeInclusive;

use eframe::egui;
use glam::Vec3;

/// The range of the numeric setting `key` for a widget: the one range the command line and
/// the scene files check ([`crate::render::NUMERIC`]).
#[must_use]
pub fn range_of(key: &str) -> RangeInclusive<f32> {
    let (lo, hi) = crate::render::numeric(key).bounds();
    lo as f32..=hi as f32
}

/// [`range_of`] for a setting that is a whole number.
#[must_use]
pub fn whole_range_of(key: &str) -> RangeInclusive<u32> {
    let (lo, hi) = crate::render::numeric(key).bounds();
    lo as u32..=hi as u32
}

/// `v` as a widget shows it: clamped into `range`, a non-finite value as 0 clamped.
#[must_use]
pub fn shown(v: f32, range: &RangeInclusive<f32>) -> f32 {
    let v = if v.is_finite() { v } else { 0.0 };
    v.clamp(*range.start(), *range.end())
}

/// A drag value for `v` within `range`; true (and `v` written) only when the user changed it.
pub fn drag(
    ui: &mut egui::Ui,
    v: &mut f32,
    range: RangeInclusive<f32>,
    speed: f64,
    name: &str,
) -> bool {
    drag_with(ui, v, range, speed, name, "")
}

/// [`drag`] with a unit after the number ("°", " px").
pub fn drag_with(
    ui: &mut egui::Ui,
    v: &mut f32,
    range: RangeInclusive<f32>,
    speed: f64,
    name: &str,
    suffix: &str,
) -> bool {
    let mut x = shown(*v, &range);
    let r = ui
        .add(
            egui::DragValue::new(&mut x)
                .range(range)
                .speed(speed)
                .max_decimals(3)
                .suffix(suffix),
        )
        .accessible_name(name);
    if r.changed() && x.is_finite() {
        *v = x;
        true
    } else {
        false
    }
}

/// An angle stored in radians, edited in degrees within `range` (degrees).
pub fn degrees(
    ui: &mut egui::Ui,
    radians: &mut f32,
    range: RangeInclusive<f32>,
    name: &str,
) -> bool {
    let mut d = radians.to_degrees();
    if drag_with(ui, &mut d, range, 0.2, name, "°") {
        *radians = d.to_radians();
        true
    } else {
        false
    }
}

/// Three drag values (x, y, z), named "`name` x" and so on.
pub fn vec3(ui: &mut egui::Ui, v: &mut Vec3, speed: f64, name: &str) -> bool {
    let all = f32::NEG_INFINITY..=f32::INFINITY;
    let mut changed = false;
    for (axis, c) in ["x", "y", "z"]
        .into_iter()
        .zip([&mut v.x, &mut v.y, &mut v.z])
    {
        changed |= drag(ui, c, all.clone(), speed, &format!("{name} {axis}"));
    }
    changed
}

/// A colour button for a linear RGB colour (non-finite channels shown as 0, values above 1
/// as 1); writes back only what the picker changed.
pub fn colour(ui: &mut egui::Ui, c: &mut Vec3, name: &str) -> bool {
    let unit = 0.0..=1.0;
    let mut rgb = c.to_array().map(|v| shown(v, &unit));
    let r = ui.color_edit_button_rgb(&mut rgb).accessible_name(name);
    if r.changed() {
        *c = Vec3::from_array(rgb);
        true
    } else {
        false
    }
}

/// A label followed by a widget, the label naming the widget for screen readers.
pub fn labelled<R>(
    ui: &mut egui::Ui,
    label: &str,
    add: impl FnOnce(&mut egui::Ui) -> R,
) -> egui::InnerResponse<R> {
    ui.horizontal(|ui| {
        ui.label(label);
        add(ui)
    })
}

/// The azimuth and elevation, in degrees, of direction `d` in a frame whose horizontal
/// axes are `east` and `north` and whose vertical is `up` (all unit and orthogonal):
/// azimuth 0 points north, 90 east; elevation -90 points straight down. `None` for a zero
/// or non-finite direction.
#[must_use]
pub fn azimuth_elevation(d: Vec3, [east, north, up]: [Vec3; 3]) -> Option<(f32, f32)> {
    let n = d.normalize_or_zero();
    if n == Vec3::ZERO || !n.is_finite() {
        return None;
    }
    let az = libm::atan2f(n.dot(east), n.dot(north)).to_degrees();
    let el = libm::asinf(n.dot(up).clamp(-1.0, 1.0)).to_degrees();
    Some((az, el))
}

/// The unit direction with this azimuth and elevation (degrees) in the frame of
/// [`azimuth_elevation`].
#[must_use]
pub fn from_azimuth_elevation(az: f32, el: f32, [east, north, up]: [Vec3; 3]) -> Vec3 {
    let (az, el) = (az.to_radians(), el.to_radians());
    (libm::cosf(el) * (libm::sinf(az) * east + libm::cosf(az) * north) + libm::sinf(el) * up)
        .normalize_or(north)
}

/// A slider for `v` within `range` (logarithmic if asked); true (and `v` written) only when
/// the user moved it.
pub fn slider(
    ui: &mut egui::Ui,
    v: &mut f32,
    range: RangeInclusive<f32>,
    logarithmic: bool,
    name: &str,
) -> bool {
    let mut x = shown(*v, &range);
    let r = ui
        .add(egui::Slider::new(&mut x, range).logarithmic(logarithmic))
        .accessible_name(name);
    if r.changed() && x.is_finite() {
        *v = x;
        true
    } else {
        false
    }
}
