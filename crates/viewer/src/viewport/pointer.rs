//! The mouse over the viewport: navigation (orbit, pan, dolly), picking the point to
//! centre on, and the clicks that measure or probe.

use eframe::egui::{self, PointerButton, Pos2, Vec2};

use super::{ViewportState, POINTS_PER_STEP};
use crate::app::Shown;
use crate::navigate::pixel_to_ndc;
use crate::panels::measure::SNAP_PIXELS;
use crate::panels::{Cx, ProbeView, Side};
use crate::render::{self, PreparedScene, Settings};

/// Mouse navigation, picking and probing.
pub(super) fn navigate(cx: &mut Cx<'_>, ui: &mut egui::Ui, resp: &egui::Response) {
    let vp = cx.viewport.clone();
    let height = vp.size_px[1] as f32;
    let aspect = vp.aspect();
    let shift = ui.input(|i| i.modifiers.shift);
    let delta = resp.drag_delta() * vp.pixels_per_point;
    let mut moved = false;
    if delta != Vec2::ZERO {
        if resp.dragged_by(PointerButton::Middle)
            || (resp.dragged_by(PointerButton::Primary) && shift)
        {
            cx.nav.pan(delta.x, delta.y, height);
            moved = true;
        } else if resp.dragged_by(PointerButton::Primary) {
            cx.nav.orbit(delta.x, delta.y, height);
            moved = true;
        } else if resp.dragged_by(PointerButton::Secondary) {
            cx.nav.dolly(-delta.y / POINTS_PER_STEP);
            moved = true;
        }
    }
    if resp.hovered() {
        let (scroll, zoom, hover) = ui.input(|i| {
            (
                i.smooth_scroll_delta.y,
                i.zoom_delta(),
                i.pointer.hover_pos(),
            )
        });
        if scroll != 0.0 {
            let steps = scroll / POINTS_PER_STEP;
            match hover {
                Some(p) => {
                    let px = vp.to_pixels(p);
                    let ndc =
                        pixel_to_ndc(glam::Vec2::new(px.x, px.y), glam::Vec2::from(size(&vp)));
                    cx.nav.dolly_at(steps, ndc, aspect);
                }
                None => cx.nav.dolly(steps),
            }
            moved = true;
        }
        if zoom != 1.0 && zoom.is_finite() && zoom > 0.0 {
            // Ctrl + wheel (or a pinch): dolly towards the centre.
            cx.nav
                .dolly(libm::logf(zoom) / libm::logf(1.0 / crate::navigate::DOLLY_PER_STEP));
            moved = true;
        }
    }
    let pos = resp.interact_pointer_pos();
    if resp.double_clicked() || resp.clicked_by(PointerButton::Middle) {
        if let Some(p) = pos.and_then(|p| pick(cx, p)) {
            cx.nav.center_on(p);
            moved = true;
        }
    } else if resp.clicked() {
        if let Some(p) = pos {
            if cx.shared.measure.on {
                measure_at(cx, p);
            } else {
                probe_at(cx, p);
            }
        }
    }
    *cx.interacting |= moved;
    cx.shared.moved |= moved;
}

fn size(vp: &ViewportState) -> [f32; 2] {
    [vp.size_px[0] as f32, vp.size_px[1] as f32]
}

/// The frame pixel under a screen point, and the frame's size.
fn frame_pixel(cx: &Cx<'_>, p: Pos2) -> Option<(u32, u32)> {
    let s = cx.session.shown?;
    let r = cx.viewport.rect;
    let u = (p - r.min) / r.size();
    if !(0.0..1.0).contains(&u.x) || !(0.0..1.0).contains(&u.y) {
        return None;
    }
    let x = (u.x * s.view.width as f32) as u32;
    let y = (u.y * s.view.height as f32) as u32;
    Some((x.min(s.view.width - 1), y.min(s.view.height - 1)))
}

/// The world point under a screen point, from the shown frame's depth buffer.
#[must_use]
pub fn pick(cx: &Cx<'_>, p: Pos2) -> Option<glam::Vec3> {
    let s = cx.session.shown?;
    let (x, y) = frame_pixel(cx, p)?;
    let depth = *s.depth.get((y * s.view.width + x) as usize)?;
    render::unproject(&s.view, x as f32 + 0.5, y as f32 + 0.5, depth)
}

/// Picks the point under a screen point for measuring (side A's settings: its section
/// planes), snapped to a vertex or an edge within [`SNAP_PIXELS`] frame pixels.
pub fn measure_at(cx: &mut Cx<'_>, p: Pos2) {
    let Some(s) = cx.session.shown else {
        return;
    };
    let r = cx.viewport.rect;
    let u = (p - r.min) / r.size();
    if !(0.0..1.0).contains(&u.x) || !(0.0..1.0).contains(&u.y) {
        return;
    }
    let (x, y) = (u.x * s.view.width as f32, u.y * s.view.height as f32);
    // The snap radius in frame pixels, however large the frame is shown.
    let scale = s.view.width as f32 / r.width().max(1.0);
    let radius = SNAP_PIXELS * scale.max(1.0);
    if let Some(pick) = render::measure::pick(cx.session.scene, cx.settings, &s.view, x, y, radius)
    {
        cx.shared.measure.add(pick);
    }
}

/// Probes the pixel under a screen point with the settings of the half it is in.
pub fn probe_at(cx: &mut Cx<'_>, p: Pos2) {
    let Some(s) = cx.session.shown else {
        return;
    };
    let Some((x, y)) = frame_pixel(cx, p) else {
        return;
    };
    let r = cx.viewport.rect;
    let side = if cx.split.enabled && p.x > r.left() + r.width() * cx.split.divider {
        Side::B
    } else {
        Side::A
    };
    let settings = match side {
        Side::A => &*cx.settings,
        Side::B => &cx.split.b,
    };
    cx.shared.probe = Some(read_probe(s, cx.session.scene, settings, [x, y], side, p));
    cx.shared.open_probe = true;
}

/// The probe of frame pixel `pixel` of `s` (on `side`, drawn with `settings`), clicked at
/// `at`.
#[must_use]
pub fn read_probe(
    s: &Shown,
    scene: &PreparedScene,
    settings: &Settings,
    [x, y]: [u32; 2],
    side: Side,
    at: Pos2,
) -> ProbeView {
    let shown_rgb = match side {
        Side::A => {
            s.a.pixels
                .get((y * s.view.width + x) as usize)
                .map(|c| [c.r(), c.g(), c.b()])
        }
        Side::B => None,
    };
    let probe = render::probe(scene, settings, &s.view, x, y);
    let depth = s.depth.get((y * s.view.width + x) as usize).copied();
    ProbeView {
        pixel: [x, y],
        frame_size: [s.view.width, s.view.height],
        at,
        side,
        probe,
        shown_rgb,
        buffer_depth: depth.filter(|d| *d > 0.0),
        settings: Box::new(settings.clone()),
    }
}
