//! Light gizmos: each light of the frame drawn over the 3-D view with egui's painter, so
//! what the editor changes can be seen where it is. A point light is a marker; a spot its
//! apex, axis, falloff (outer) circle and four generators, with the hotspot (inner) circle
//! fainter; a rectangular spot its pyramid, with a tick on the edge its image's top is on;
//! a directional light an arrow outside the scene's bounding sphere pointing the way the
//! light travels. Ambient light has no place and is not drawn.
//!
//! The lights are the renderer's own [`Source`]s of the frame on screen (from
//! [`frame_lights`], with the cone and pyramid angles clamped as the renderer clamps them),
//! projected with that frame's camera (`Camera::view`, `Camera::projection(aspect)`), so a
//! gizmo sits on the image it belongs to even while the camera moves and the frame lags.
//!
//! Segments are clipped in view space against a plane just in front of the eye before the
//! divide (an end behind the camera would otherwise project to the wrong side, or divide by
//! zero), then in 2-D against the viewport grown by its own size on every side (a point
//! just past that plane projects very far out; egui need not tessellate such lines).
//! Non-finite points are
//! dropped. Nothing here can produce NaN on screen.

use eframe::egui::{self, Align2, Color32, FontId, Pos2, Rect, Stroke};
use glam::{Mat4, Vec3, Vec4Swizzles};

use super::panels::Cx;
use crate::render::{frame_lights, View};
use crate::scene::LightKind;
use crate::shade::{LightSet, Source};

/// Segments around a cone's circle.
const CIRCLE_SEGMENTS: usize = 48;
/// Where gizmos are clipped: this fraction of the camera's distance to its target in
/// front of the eye.
pub const NEAR_FRACTION: f32 = 1e-3;

/// Projects world points onto a viewport for one frame's camera.
#[derive(Clone, Debug)]
pub struct Projector {
    view: Mat4,
    proj: Mat4,
    near: f32,
    rect: Rect,
}

impl Projector {
    /// For the frame `view` shown stretched over `rect` (points).
    #[must_use]
    pub fn new(view: &View, rect: Rect) -> Self {
        let cam = &view.camera;
        // Not the camera's near plane, which follows the scene's bounding sphere (a light
        // between the camera and the scene would vanish): a plane just in front of the eye.
        // Only x and y are drawn, so the projection's depth range does not matter.
        let distance = (cam.target - cam.eye).length();
        let near = NEAR_FRACTION
            * if distance.is_finite() && distance > 0.0 {
                distance
            } else {
                1.0
            };
        Self {
            view: cam.view(),
            proj: cam.projection(view.aspect()),
            near,
            rect,
        }
    }

    /// Distance in front of the camera (view-space depth) of world point `p`.
    #[must_use]
    pub fn depth(&self, p: Vec3) -> f32 {
        -self.view.transform_point3(p).z
    }

    /// A view-space point (at or beyond the near plane) on the screen, in points.
    fn screen(&self, v: Vec3) -> Option<Pos2> {
        let clip = self.proj * v.extend(1.0);
        if clip.w.is_nan() || clip.w <= 0.0 {
            return None;
        }
        let ndc = clip.xy() / clip.w;
        let p = Pos2::new(
            self.rect.left() + (ndc.x * 0.5 + 0.5) * self.rect.width(),
            self.rect.top() + (0.5 - ndc.y * 0.5) * self.rect.height(),
        );
        (p.x.is_finite() && p.y.is_finite()).then_some(p)
    }

    /// World point `p` on the screen, or `None` if it is nearer than the near plane (or
    /// behind the camera) or not finite.
    #[must_use]
    pub fn point(&self, p: Vec3) -> Option<Pos2> {
        let v = self.view.transform_point3(p);
        if !v.is_finite() || -v.z < self.near {
            return None;
        }
        self.screen(v)
    }

    /// The part of the world segment `a`-`b` in front of the near plane and near the
    /// viewport, on the screen.
    #[must_use]
    pub fn segment(&self, a: Vec3, b: Vec3) -> Option<[Pos2; 2]> {
        let (mut va, mut vb) = (self.view.transform_point3(a), self.view.transform_point3(b));
        if !va.is_finite() || !vb.is_finite() {
            return None;
        }
        // Signed distances to the near plane, positive in front of it.
        let (da, db) = (-va.z - self.near, -vb.z - self.near);
        if da < 0.0 && db < 0.0 {
            return None;
        }
        if da < 0.0 {
            va = va + (vb - va) * (da / (da - db));
            va.z = -self.near;
        } else if db < 0.0 {
            vb = vb + (va - vb) * (db / (db - da));
            vb.z = -self.near;
        }
        let (pa, pb) = (self.screen(va)?, self.screen(vb)?);
        let margin = self.rect.width().max(self.rect.height());
        clip_2d(pa, pb, self.rect.expand(margin))
    }
}

/// The part of segment `a`-`b` inside `r` (Liang-Barsky, [`crate::geom::clip_segment`]).
#[must_use]
pub fn clip_2d(a: Pos2, b: Pos2, r: Rect) -> Option<[Pos2; 2]> {
    let (lo, hi) = ([r.left(), r.top()], [r.right(), r.bottom()]);
    let (t0, t1) = crate::geom::clip_segment([a.x, a.y], [b.x, b.y], lo, hi)?;
    let d = b - a;
    Some([a + d * t0, a + d * t1])
}

/// One light's gizmo, on the screen.
#[derive(Clone, Debug, PartialEq)]
pub struct Gizmo {
    /// Position in the frame's light list (as in the probe and the editor).
    pub index: usize,
    pub kind: LightKind,
    /// Where the light is (positional kinds, when in front of the camera).
    pub anchor: Option<Pos2>,
    /// Outline segments: cone or pyramid edges, the arrow.
    pub lines: Vec<[Pos2; 2]>,
    /// Fainter segments: the spot's hotspot circle, the axis.
    pub faint: Vec<[Pos2; 2]>,
    pub color: Color32,
    pub label: String,
    /// Where the label goes.
    pub label_at: Option<Pos2>,
}

/// Unit vectors perpendicular to unit `axis` and to each other.
fn perpendiculars(axis: Vec3) -> (Vec3, Vec3) {
    let u = axis.any_orthonormal_vector();
    (u, axis.cross(u))
}

/// The world segments of a circle about `axis` through `centre` with `radius`.
fn circle(centre: Vec3, axis: Vec3, radius: f32) -> Vec<(Vec3, Vec3)> {
    let (u, v) = perpendiculars(axis);
    let at = |k: usize| {
        let t = k as f32 / CIRCLE_SEGMENTS as f32 * std::f32::consts::TAU;
        centre + (u * libm::cosf(t) + v * libm::sinf(t)) * radius
    };
    (0..CIRCLE_SEGMENTS).map(|k| (at(k), at(k + 1))).collect()
}

/// A display colour for a light's radiance: its hue at full brightness, kept away from
/// black so a dim or black light still shows.
fn display_color(radiance: Vec3) -> Color32 {
    let m = radiance.max_element();
    let c = if m > 0.0 && m.is_finite() {
        radiance / m
    } else {
        Vec3::ONE
    };
    let c = c * 0.7 + Vec3::splat(0.3);
    let e = crate::color::srgb8;
    Color32::from_rgb(e(c.x), e(c.y), e(c.z))
}

/// The gizmo of one light source of a scene with bounding sphere (`center`, `radius`).
#[must_use]
pub fn gizmo(
    s: &Source,
    name: &str,
    p: &Projector,
    center: Vec3,
    radius: f32,
    forward: Vec3,
) -> Gizmo {
    let mut lines = Vec::new();
    let mut faint = Vec::new();
    let add = |list: &mut Vec<[Pos2; 2]>, a: Vec3, b: Vec3| {
        if let Some(seg) = p.segment(a, b) {
            list.push(seg);
        }
    };
    let axis = s.axis;
    // How far a cone or pyramid is drawn: to the scene's centre (along the axis), or the
    // scene's radius when it points away from the scene.
    let along = (center - s.position).dot(axis);
    let reach = if along > 0.1 * radius && along.is_finite() {
        along
    } else {
        radius
    };
    let mut label_at = None;
    let anchor = s.kind.positional().then(|| p.point(s.position)).flatten();
    match s.kind {
        LightKind::Ambient | LightKind::Point => {}
        LightKind::Directional => {
            let (start, end) = (center - axis * 1.6 * radius, center - axis * 1.1 * radius);
            add(&mut lines, start, end);
            let side = axis
                .cross(forward)
                .try_normalize()
                .unwrap_or_else(|| axis.any_orthonormal_vector());
            let back = end - axis * 0.14 * radius;
            add(&mut lines, end, back + side * 0.07 * radius);
            add(&mut lines, end, back - side * 0.07 * radius);
            // The tail's end when in view, else the head's.
            label_at = lines
                .first()
                .and_then(|[a, b]| [*a, *b].into_iter().find(|q| p.rect.contains(*q)));
        }
        LightKind::Spot => {
            let end = s.position + axis * reach;
            add(&mut faint, s.position, end);
            let outer = libm::acosf(s.cos_outer.clamp(-1.0, 1.0));
            let inner = libm::acosf(s.cos_inner.clamp(-1.0, 1.0));
            let r_out = reach * libm::tanf(outer);
            for (a, b) in circle(end, axis, r_out) {
                add(&mut lines, a, b);
            }
            for (a, b) in circle(end, axis, reach * libm::tanf(inner)) {
                add(&mut faint, a, b);
            }
            let (u, v) = perpendiculars(axis);
            for d in [u, v, -u, -v] {
                add(&mut lines, s.position, end + d * r_out);
            }
        }
        LightKind::Rect => {
            let end = s.position + axis * reach;
            let (rx, uy) = (s.right * s.tan.x * reach, s.up * s.tan.y * reach);
            let corners = [end - rx + uy, end + rx + uy, end + rx - uy, end - rx - uy];
            for k in 0..4 {
                add(&mut lines, s.position, corners[k]);
                add(&mut lines, corners[k], corners[(k + 1) % 4]);
            }
            // The image's top edge: a tick pointing up from its middle.
            let top = end + uy;
            add(&mut lines, top, top + uy * 0.25);
            add(&mut faint, s.position, end);
        }
    }
    Gizmo {
        index: s.index,
        kind: s.kind,
        anchor,
        lines,
        faint,
        color: display_color(s.radiance),
        label: if name.is_empty() {
            format!("{} {}", s.index, s.kind.name())
        } else {
            format!("{} {name}", s.index)
        },
        label_at: label_at.or(anchor),
    }
}

/// The gizmos of every light of the frame on screen (or of the current view before the
/// first frame), for the viewport `rect`.
#[must_use]
pub fn build(cx: &Cx<'_>, rect: Rect) -> Vec<Gizmo> {
    let view = cx
        .session
        .shown
        .map_or_else(|| cx.view(), |s| s.view.clone());
    let cam = &view.camera;
    let cam_to_world = cam.view().inverse();
    let mut set = LightSet::default();
    let scene = cx.session.scene.scene();
    let rig = cx.settings.default_rig(scene);
    frame_lights(
        &scene.lights,
        &cx.settings.lights,
        rig,
        cam_to_world,
        &mut set,
    );
    let names = super::panels::light_names(cx.settings, cx.session.scene);
    let p = Projector::new(&view, rect);
    let (center, radius) = cx.session.scene.bounding_sphere();
    set.sources
        .iter()
        .map(|s| {
            let name = names.get(s.index).map_or("", String::as_str);
            gizmo(s, name, &p, center, radius, cam.forward())
        })
        .collect()
}

/// Paints gizmos; the light numbered `highlight` wider.
pub fn paint(painter: &egui::Painter, gizmos: &[Gizmo], highlight: Option<usize>) {
    for g in gizmos {
        let wide = highlight == Some(g.index);
        let width = if wide { 2.5 } else { 1.25 };
        let shadow = Stroke::new(width + 1.5, Color32::from_black_alpha(140));
        let stroke = Stroke::new(width, g.color);
        let faint = Stroke::new(1.0, g.color.gamma_multiply(0.55));
        for seg in &g.lines {
            painter.line_segment(*seg, shadow);
        }
        for seg in &g.lines {
            painter.line_segment(*seg, stroke);
        }
        for seg in &g.faint {
            painter.line_segment(*seg, faint);
        }
        if let Some(a) = g.anchor {
            painter.circle(a, if wide { 6.0 } else { 4.5 }, g.color, shadow);
            if g.kind == LightKind::Point {
                // Rays, so a point light reads as a lamp.
                for k in 0..8 {
                    let t = k as f32 * std::f32::consts::FRAC_PI_4;
                    let d = egui::vec2(libm::cosf(t), libm::sinf(t));
                    painter.line_segment([a + d * 7.0, a + d * 11.0], stroke);
                }
            }
        }
        if let Some(at) = g.label_at {
            painter.text(
                at + egui::vec2(9.0, -9.0),
                Align2::LEFT_BOTTOM,
                &g.label,
                FontId::proportional(12.0),
                g.color,
            );
        }
    }
}
