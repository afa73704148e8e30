//! The section planes' handles: where they are on screen, dragging them along their
//! normals, and painting them.

use eframe::egui::{self, Align2, Color32, CursorIcon, FontId, Pos2, Rect, Sense, Stroke, Vec2};

use super::HANDLE_RADIUS;
use crate::panels::Cx;
use crate::render::{PreparedScene, Settings, View};

/// A section plane's handle on screen: the point of the plane nearest the model's centre,
/// and how far (points) the plane moves on screen per world unit along its normal.
#[derive(Clone, Copy, Debug)]
pub struct Handle {
    pub plane: usize,
    pub at: Pos2,
    pub along: Vec2,
}

/// The handles of the section planes for the frame `view` over `rect` (none for a plane
/// whose handle is behind the camera).
#[must_use]
pub fn handles(settings: &Settings, scene: &PreparedScene, view: &View, rect: Rect) -> Vec<Handle> {
    let planes = &settings.sections.planes;
    if planes.is_empty() {
        return Vec::new();
    }
    let (c, r) = scene.bounding_sphere();
    let proj = crate::gizmos::Projector::new(view, rect);
    let step = r.max(1e-6) * 0.1;
    planes
        .iter()
        .enumerate()
        .filter_map(|(plane, p)| {
            let n = p.truncate();
            let anchor = c - n * (n.dot(c) + p.w);
            let at = proj.point(anchor)?;
            let tip = proj.point(anchor + n * step)?;
            Some(Handle {
                plane,
                at,
                along: (tip - at) / step,
            })
        })
        .collect()
}

/// Drags of the section planes' handles: each moves its plane along its normal (within
/// the model's bounding sphere), side B following. Returns true while one is dragged.
pub(super) fn section_handles(cx: &mut Cx<'_>, ui: &mut egui::Ui, rect: Rect) -> bool {
    let Some(view) = cx.session.shown.map(|s| s.view.clone()) else {
        return false;
    };
    let (c, radius) = cx.session.scene.bounding_sphere();
    let mut dragging = false;
    for h in handles(cx.settings, cx.session.scene, &view, rect) {
        let grab = Rect::from_center_size(h.at, Vec2::splat(2.0 * HANDLE_RADIUS + 4.0));
        let id = ui.scope_id().with(("section-handle", h.plane));
        let r = ui.interact(grab, id, Sense::drag()).on_hover_text(format!(
            "drag to move section plane {} along its normal",
            h.plane + 1
        ));
        if r.hovered() || r.dragged() {
            ui.ctx().set_cursor_icon(CursorIcon::Grab);
        }
        if !r.dragged() {
            continue;
        }
        dragging = true;
        let delta = r.drag_delta();
        let len2 = h.along.length_sq();
        // A normal that points at the camera barely moves on screen: then the vertical
        // motion moves the plane, the viewport's height for the sphere's diameter.
        let dt = if len2 * radius * radius > 100.0 {
            delta.dot(h.along) / len2
        } else {
            -delta.y / rect.height().max(1.0) * 2.0 * radius
        };
        if let Some(p) = cx.settings.sections.planes.get_mut(h.plane) {
            let n = p.truncate();
            let off = (n.dot(c) + p.w - dt).clamp(-1.05 * radius, 1.05 * radius);
            p.w = off - n.dot(c);
        }
    }
    if dragging {
        let (a, b) = (&*cx.settings, &mut cx.split.b);
        b.sections.clone_from(&a.sections);
    }
    dragging
}

/// The section planes' handles: a disc with an arrow along the side the plane keeps.
pub(super) fn paint_handles(cx: &Cx<'_>, painter: &egui::Painter, view: &View, rect: Rect) {
    let colour = Color32::from_rgb(255, 140, 120);
    for h in handles(cx.settings, cx.session.scene, view, rect) {
        let dir = if h.along.length() > 1e-3 {
            h.along.normalized()
        } else {
            Vec2::new(0.0, -1.0)
        };
        let tip = h.at + dir * 36.0;
        painter.line_segment([h.at, tip], Stroke::new(3.0, Color32::BLACK));
        painter.line_segment([h.at, tip], Stroke::new(2.0, colour));
        let side = Vec2::new(-dir.y, dir.x) * 5.0;
        painter.add(egui::Shape::convex_polygon(
            vec![tip + dir * 8.0, tip + side, tip - side],
            colour,
            Stroke::new(1.0, Color32::BLACK),
        ));
        painter.circle_filled(h.at, HANDLE_RADIUS, colour);
        painter.circle_stroke(h.at, HANDLE_RADIUS, Stroke::new(1.5, Color32::BLACK));
        painter.text(
            h.at,
            Align2::CENTER_CENTER,
            format!("{}", h.plane + 1),
            FontId::proportional(11.0),
            Color32::BLACK,
        );
    }
}
