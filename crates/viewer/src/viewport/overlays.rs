//! Painting the frame (A | B in split view) and what is drawn over it: labels, tile grid
//! and cost, measurements, axes, the hint, load progress and errors, the overdraw legend.

use eframe::egui::{self, Align2, Color32, FontId, Pos2, Rect, Stroke, StrokeKind, Vec2};

use super::sections::paint_handles;
use crate::panels::measure;
use crate::panels::{CostView, Cx};
use crate::render::{Output, View};

/// Paints the frame, the split halves and the overlays.
pub(super) fn paint(cx: &Cx<'_>, ui: &egui::Ui, rect: Rect) {
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
                "A: ".to_owned() + &crate::panels::describe(&*cx.settings),
            );
            let right_text = match (s.heat, cx.split.heat) {
                (Some((mean, p95)), true) => format!("ΔE00 A vs B: mean {mean:.3}, p95 {p95:.3}"),
                _ => "B: ".to_owned() + &crate::panels::describe(&cx.split.b),
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
    crate::gizmos::paint(&painter, &cx.viewport.gizmos, cx.shared.hovered_light);
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
    let proj = crate::gizmos::Projector::new(view, rect);
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
