//! The viewport: the rendered frame as a texture (A | B in split view), mouse navigation,
//! picking and the probe click, and the overlays (64x64 tile grid, per-tile cost, overdraw
//! legend, split divider, light gizmos, section plane handles).
//!
//! Units: egui lays out in points; the renderer draws physical pixels (`points * pixels per
//! point`, rounded), so a frame maps one to one onto the screen. A frame of another size
//! (reduced while moving, or from before a resize) is stretched over the viewport.

use eframe::egui::{self, CursorIcon, Pos2, Rect, Sense, Vec2};

use super::navigate::Navigator;
use super::panels::Cx;
use crate::render::{Output, View};

mod overlays;
mod pointer;
mod sections;

pub use overlays::{overdraw_legend, HINT};
pub use pointer::{measure_at, pick, probe_at, read_probe};
pub use sections::{handles, Handle};

use overlays::paint;
use pointer::navigate;
use sections::section_handles;

/// Wheel travel (points) per dolly step.
const POINTS_PER_STEP: f32 = 50.0;
/// Half-width (points) of the split divider's grab area.
const DIVIDER_GRAB: f32 = 5.0;
/// Radius (points) of a section plane's handle; its grab area is a square around it.
pub const HANDLE_RADIUS: f32 = 8.0;

/// Where the viewport is on screen.
#[derive(Clone, Debug)]
pub struct ViewportState {
    /// In points.
    pub rect: Rect,
    /// Physical pixels (the render size).
    pub size_px: [u32; 2],
    pub pixels_per_point: f32,
    /// The light gizmos drawn in the last pass (empty when they are off).
    pub gizmos: Vec<super::gizmos::Gizmo>,
}

impl Default for ViewportState {
    fn default() -> Self {
        Self {
            rect: Rect::NOTHING,
            size_px: [0, 0],
            pixels_per_point: 1.0,
            gizmos: Vec::new(),
        }
    }
}

impl ViewportState {
    /// Width over height (16:10 before the first layout).
    #[must_use]
    pub fn aspect(&self) -> f32 {
        match self.size_px {
            [w, h] if w > 0 && h > 0 => w as f32 / h as f32,
            _ => 1.6,
        }
    }

    /// A point on screen in the render's physical pixels (top left 0, 0).
    #[must_use]
    pub fn to_pixels(&self, p: Pos2) -> Vec2 {
        (p - self.rect.min) * self.pixels_per_point
    }
}

/// The view of a viewport of `vp`'s size through `nav`'s camera.
#[must_use]
pub fn view_of(nav: &Navigator, vp: &ViewportState) -> View {
    let [w, h] = vp.size_px;
    View {
        camera: nav.camera(w.max(1) as f32 / h.max(1) as f32),
        width: w.max(1),
        height: h.max(1),
    }
}

/// Lays out the viewport and handles its input.
pub fn show(cx: &mut Cx<'_>, ui: &mut egui::Ui) {
    let (rect, resp) = ui.allocate_exact_size(ui.available_size(), Sense::click_and_drag());
    let ppp = ui.ctx().pixels_per_point();
    let size = (rect.size() * ppp).round();
    cx.viewport.rect = rect;
    cx.viewport.size_px = [size.x.max(1.0) as u32, size.y.max(1.0) as u32];
    cx.viewport.pixels_per_point = ppp;
    let divider = split_divider(cx, ui, rect);
    let handle = section_handles(cx, ui, rect);
    if !divider && !handle {
        navigate(cx, ui, &resp);
    }
    cx.viewport.gizmos = if cx.shared.light_gizmos && cx.settings.output == Output::Shaded {
        super::gizmos::build(cx, rect)
    } else {
        Vec::new()
    };
    paint(cx, ui, rect);
}

/// The split divider: a handle to drag. Returns true while it is being dragged.
fn split_divider(cx: &mut Cx<'_>, ui: &mut egui::Ui, rect: Rect) -> bool {
    if !cx.split.enabled {
        return false;
    }
    let x = rect.left() + rect.width() * cx.split.divider;
    let grab = Rect::from_x_y_ranges(x - DIVIDER_GRAB..=x + DIVIDER_GRAB, rect.y_range());
    let r = ui.interact(grab, ui.scope_id().with("split-divider"), Sense::drag());
    if r.hovered() || r.dragged() {
        ui.ctx().set_cursor_icon(CursorIcon::ResizeHorizontal);
    }
    if r.dragged() {
        if let Some(p) = r.interact_pointer_pos() {
            cx.split.divider = ((p.x - rect.left()) / rect.width()).clamp(0.0, 1.0);
        }
    }
    r.dragged()
}
