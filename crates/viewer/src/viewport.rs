//! The viewport: the rendered frame as a texture (A | B in split view), mouse navigation,
//! picking and the probe click, and the overlays (64x64 tile grid, per-tile cost, overdraw
//! legend, split divider, light gizmos, section plane handles).
//!
//! Units: egui lays out in points; the renderer draws physical pixels (`points * pixels per
//! point`, rounded), so a frame maps one to one onto the screen. A frame of another size
//! (reduced while moving, or from before a resize) is stretched over the viewport.

use eframe::egui::{
    self, Align2, Color32, CursorIcon, FontId, PointerButton, Pos2, Rect, Sense, Stroke,
    StrokeKind, Vec2,
};

use super::app::Shown;
use super::navigate::pixel_to_ndc;
use super::navigate::Navigator;
use super::panels::measure::{self, SNAP_PIXELS};
use super::panels::Cx;
use super::panels::{CostView, ProbeView, Side};
use crate::render::{self, Output, PreparedScene, Settings, View};

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
    let proj = super::gizmos::Projector::new(view, rect);
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
fn section_handles(cx: &mut Cx<'_>, ui: &mut egui::Ui, rect: Rect) -> bool {
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
fn paint_handles(cx: &Cx<'_>, painter: &egui::Painter, view: &View, rect: Rect) {
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

/// Mouse navigation, picking and probing.
fn navigate(cx: &mut Cx<'_>, ui: &mut egui::Ui, resp: &egui::Response) {
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
                .dolly(zoom.ln() / (1.0 / super::navigate::DOLLY_PER_STEP).ln());
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

/// Paints the frame, the split halves and the overlays.
fn paint(cx: &Cx<'_>, ui: &egui::Ui, rect: Rect) {
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 0.0, Color32::from_gray(12));
    let Some(s) = cx.session.shown else {
        loading(cx, &painter, rect);
        return;
    };
    let full = Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0));
    let white = Color32::WHITE;
    match (&s.tex_b, cx.split.enabled) {
        (Some(tex_b), true) => {
            let d = cx.split.divider;
            let x = rect.left() + rect.width() * d;
            let (left, right) = (
                Rect::from_min_max(rect.min, Pos2::new(x, rect.max.y)),
                Rect::from_min_max(Pos2::new(x, rect.min.y), rect.max),
            );
            let uv_l = Rect::from_min_max(Pos2::ZERO, Pos2::new(d, 1.0));
            let uv_r = Rect::from_min_max(Pos2::new(d, 0.0), Pos2::new(1.0, 1.0));
            painter.image(s.tex_a.id(), left, uv_l, white);
            let right_tex = match (&s.tex_heat, cx.split.heat) {
                (Some(h), true) => h.id(),
                _ => tex_b.id(),
            };
            painter.image(right_tex, right, uv_r, white);
            painter.line_segment(
                [Pos2::new(x, rect.top()), Pos2::new(x, rect.bottom())],
                Stroke::new(2.0, Color32::from_rgb(255, 200, 40)),
            );
            let label = |pos: Pos2, align: Align2, text: String| {
                painter.text(
                    pos,
                    align,
                    text,
                    FontId::monospace(13.0),
                    Color32::from_rgb(255, 220, 120),
                );
            };
            label(
                rect.left_top() + Vec2::new(8.0, 6.0),
                Align2::LEFT_TOP,
                "A: ".to_owned() + &super::panels::describe(&*cx.settings),
            );
            let right_text = match (s.heat, cx.split.heat) {
                (Some((mean, p95)), true) => format!("ΔE00 A vs B: mean {mean:.3}, p95 {p95:.3}"),
                _ => "B: ".to_owned() + &super::panels::describe(&cx.split.b),
            };
            label(
                rect.right_top() + Vec2::new(-8.0, 6.0),
                Align2::RIGHT_TOP,
                right_text,
            );
        }
        _ => {
            painter.image(s.tex_a.id(), rect, full, white);
        }
    }
    tiles(cx, &painter, rect);
    super::gizmos::paint(&painter, &cx.viewport.gizmos, cx.shared.hovered_light);
    if cx.settings.output == Output::Overdraw {
        overdraw_legend(&painter, rect);
    }
    measurements(cx, &painter, &s.view, rect);
    paint_handles(cx, &painter, &s.view, rect);
    if cx.shared.axes {
        axes(&painter, &s.view, rect);
    }
    if let Some(pv) = &cx.shared.probe {
        if s.view.width == pv.frame_size[0] && s.view.height == pv.frame_size[1] {
            let c = rect.min
                + Vec2::new(
                    (pv.pixel[0] as f32 + 0.5) / s.view.width as f32 * rect.width(),
                    (pv.pixel[1] as f32 + 0.5) / s.view.height as f32 * rect.height(),
                );
            let stroke = Stroke::new(1.5, Color32::from_rgb(0, 255, 200));
            painter.circle_stroke(c, 6.0, stroke);
            painter.line_segment([c - Vec2::X * 10.0, c - Vec2::X * 3.0], stroke);
            painter.line_segment([c + Vec2::X * 3.0, c + Vec2::X * 10.0], stroke);
        }
    }
    loading(cx, &painter, rect);
    if !cx.shared.moved && cx.session.error.is_none() {
        hint(&painter, rect);
    }
    if let Some(e) = cx.session.error {
        // Also in the status bar; here so it cannot be missed.
        let bar = Rect::from_min_size(
            rect.left_bottom() - Vec2::new(0.0, 30.0),
            Vec2::new(rect.width(), 30.0),
        );
        painter.rect_filled(bar, 0.0, Color32::from_rgba_unmultiplied(120, 20, 10, 220));
        painter.text(
            bar.left_center() + Vec2::new(10.0, 0.0),
            Align2::LEFT_CENTER,
            format!("could not open: {e}"),
            FontId::proportional(14.0),
            Color32::WHITE,
        );
    }
    let hovering = ui.input(|i| !i.raw.hovered_files.is_empty());
    if hovering {
        painter.rect_filled(rect, 0.0, Color32::from_black_alpha(160));
        painter.text(
            rect.center(),
            Align2::CENTER_CENTER,
            "drop a .obj, .gltf, .glb, .stl or .ply file to open it",
            FontId::proportional(22.0),
            Color32::WHITE,
        );
    }
}

/// The measured points, the segments between them with their lengths, and the angle.
fn measurements(cx: &Cx<'_>, painter: &egui::Painter, view: &View, rect: Rect) {
    let m = &cx.shared.measure;
    if m.points.is_empty() {
        return;
    }
    let proj = super::gizmos::Projector::new(view, rect);
    let colour = Color32::from_rgb(255, 230, 60);
    let stroke = Stroke::new(2.0, colour);
    let label = |at: Pos2, text: String| {
        let galley = painter.layout_no_wrap(text, FontId::monospace(13.0), Color32::BLACK);
        let back = Rect::from_center_size(at, galley.size() + Vec2::splat(6.0));
        painter.rect_filled(back, 3.0, colour);
        painter.galley(back.min + Vec2::splat(3.0), galley, Color32::BLACK);
    };
    let distances = m.distances();
    for (i, w) in m.points.windows(2).enumerate() {
        if let Some([a, b]) = proj.segment(w[0].position, w[1].position) {
            painter.line_segment([a, b], stroke);
            label(
                a + (b - a) * 0.5 + Vec2::new(0.0, -14.0),
                measure::number(distances[i]),
            );
        }
    }
    for (i, p) in m.points.iter().enumerate() {
        if let Some(at) = proj.point(p.position) {
            painter.circle_filled(at, 4.0, colour);
            painter.circle_stroke(at, 6.0, Stroke::new(1.0, Color32::BLACK));
            let text = match (i, m.angle()) {
                (1, Some(a)) => format!("B {}°", measure::number(a)),
                _ => measure::name(i).to_string(),
            };
            label(at + Vec2::new(14.0, 12.0), text);
        }
    }
}

/// The world axes as the camera sees them, in the bottom-right corner: x red, y green,
/// z blue, the nearer drawn last.
fn axes(painter: &egui::Painter, view: &View, rect: Rect) {
    const LENGTH: f32 = 28.0;
    let origin = rect.right_bottom() + Vec2::new(-LENGTH - 16.0, -LENGTH - 16.0);
    let v = view.camera.view();
    let mut arms: Vec<(f32, Vec2, Color32, &str)> = [
        (glam::Vec3::X, Color32::from_rgb(235, 70, 60), "x"),
        (glam::Vec3::Y, Color32::from_rgb(90, 210, 80), "y"),
        (glam::Vec3::Z, Color32::from_rgb(70, 130, 255), "z"),
    ]
    .into_iter()
    .filter_map(|(axis, colour, name)| {
        let d = v.transform_vector3(axis);
        d.is_finite()
            .then(|| (d.z, Vec2::new(d.x, -d.y) * LENGTH, colour, name))
    })
    .collect();
    // Farthest first (view space looks down -z).
    arms.sort_by(|a, b| a.0.total_cmp(&b.0));
    painter.circle_filled(origin, LENGTH + 10.0, Color32::from_black_alpha(90));
    for (_, d, colour, name) in arms {
        painter.line_segment([origin, origin + d], Stroke::new(2.5, colour));
        // An arm pointing at the camera has no direction on screen: its label beside it.
        let off = if d.length() > 0.5 {
            d.normalized() * 8.0
        } else {
            Vec2::new(7.0, -7.0)
        };
        let at = origin + d + off;
        painter.text(
            at,
            Align2::CENTER_CENTER,
            name,
            FontId::proportional(13.0),
            colour,
        );
    }
}

/// How to move the camera, one line at the bottom of the viewport until it first moves.
pub const HINT: &str =
    "drag: orbit    shift+drag: pan    wheel: zoom    click: probe a pixel    H: every key";

fn hint(painter: &egui::Painter, rect: Rect) {
    let galley = painter.layout_no_wrap(HINT.into(), FontId::proportional(13.0), Color32::WHITE);
    let at = rect.left_bottom() + Vec2::new(10.0, -10.0 - galley.size().y);
    let back = Rect::from_min_size(at - Vec2::splat(4.0), galley.size() + Vec2::splat(8.0));
    painter.rect_filled(back, 4.0, Color32::from_black_alpha(150));
    painter.galley(at, galley, Color32::WHITE);
}

/// "Loading NAME: stage, percent" in the middle of the viewport while a load runs.
fn loading(cx: &Cx<'_>, painter: &egui::Painter, rect: Rect) {
    let Some(t) = cx.session.loading else {
        return;
    };
    let (stage, fraction, _) = t.status();
    let name = t
        .path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let pct = fraction.map_or(String::new(), |f| format!(" {:.0}%", f * 100.0));
    painter.text(
        rect.center(),
        Align2::CENTER_CENTER,
        format!("loading {name}: {}{pct}", stage.name()),
        FontId::proportional(18.0),
        Color32::from_gray(200),
    );
}

/// The 64x64 tile grid and the per-tile cost heat map of the shown frame.
fn tiles(cx: &Cx<'_>, painter: &egui::Painter, rect: Rect) {
    let Some(s) = cx.session.shown else {
        return;
    };
    let (fw, fh) = (s.view.width as f32, s.view.height as f32);
    let tile = crate::raster::TILE as f32;
    let (sx, sy) = (rect.width() / fw, rect.height() / fh);
    if cx.shared.tile_cost != CostView::Off && !s.tile_costs.is_empty() {
        let value = |c: &crate::raster::TileCost| match cx.shared.tile_cost {
            CostView::Time => c.nanos as f32,
            _ => c.fragments as f32,
        };
        let max = s.tile_costs.iter().map(value).fold(0.0, f32::max);
        for (i, c) in s.tile_costs.iter().enumerate() {
            let t = if max > 0.0 { value(c) / max } else { 0.0 };
            if t <= 0.0 {
                continue;
            }
            let (tx, ty) = ((i as u32 % s.tiles_x) as f32, (i as u32 / s.tiles_x) as f32);
            let r = Rect::from_min_max(
                rect.min + Vec2::new(tx * tile * sx, ty * tile * sy),
                rect.min
                    + Vec2::new(
                        ((tx + 1.0) * tile).min(fw) * sx,
                        ((ty + 1.0) * tile).min(fh) * sy,
                    ),
            );
            let [cr, cg, cb] = crate::quality::metrics::heat_color(
                f64::from(t) * crate::quality::metrics::HEAT_MAP_MAX_DE,
            );
            painter.rect_filled(r, 0.0, Color32::from_rgba_unmultiplied(cr, cg, cb, 150));
        }
        let what = match cx.shared.tile_cost {
            CostView::Time => format!("tile fill time, max {:.2} ms", max * 1e-6),
            _ => format!("fragments per tile, max {max:.0}"),
        };
        painter.text(
            rect.left_bottom() + Vec2::new(8.0, -8.0),
            Align2::LEFT_BOTTOM,
            what,
            FontId::monospace(13.0),
            Color32::WHITE,
        );
    }
    if cx.shared.tile_grid || cx.shared.tile_cost != CostView::Off {
        let stroke = Stroke::new(1.0, Color32::from_rgba_unmultiplied(255, 255, 255, 70));
        let mut x = tile;
        while x < fw {
            let px = rect.left() + x * sx;
            painter.line_segment(
                [Pos2::new(px, rect.top()), Pos2::new(px, rect.bottom())],
                stroke,
            );
            x += tile;
        }
        let mut y = tile;
        while y < fh {
            let py = rect.top() + y * sy;
            painter.line_segment(
                [Pos2::new(rect.left(), py), Pos2::new(rect.right(), py)],
                stroke,
            );
            y += tile;
        }
        painter.rect_stroke(rect, 0.0, stroke, StrokeKind::Inside);
    }
}

/// The overdraw colour ramp, bottom right of the viewport.
pub fn overdraw_legend(painter: &egui::Painter, rect: Rect) {
    let (w, h) = (220.0, 14.0);
    let origin = rect.right_bottom() + Vec2::new(-w - 12.0, -h - 26.0);
    let steps = 64;
    for i in 0..steps {
        let c = 16.0 * i as f32 / (steps - 1) as f32;
        let col = crate::render::overdraw_color(c);
        let enc = crate::color::srgb8;
        let x = origin.x + w * i as f32 / steps as f32;
        painter.rect_filled(
            Rect::from_min_size(Pos2::new(x, origin.y), Vec2::new(w / steps as f32 + 0.5, h)),
            0.0,
            Color32::from_rgb(enc(col.x), enc(col.y), enc(col.z)),
        );
    }
    for (v, label) in [
        (0.0, "0"),
        (1.0, "1"),
        (4.0, "4"),
        (10.0, "10"),
        (16.0, "16+"),
    ] {
        painter.text(
            Pos2::new(origin.x + w * v / 16.0, origin.y + h + 2.0),
            Align2::CENTER_TOP,
            label,
            FontId::monospace(11.0),
            Color32::WHITE,
        );
    }
    painter.text(
        origin + Vec2::new(0.0, -3.0),
        Align2::LEFT_BOTTOM,
        "fragments per pixel",
        FontId::monospace(11.0),
        Color32::WHITE,
    );
}
