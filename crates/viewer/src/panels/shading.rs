//! The shading section (mode, wireframe overlay, overdraw, background, texture filter,
//! multisampling, anti-aliasing, rasterizer overlays) and the split view's section (what B shows, the
//! ΔE00 map).

use eframe::egui;

use super::textures::{LabUi, UvView};
use super::{CostView, Side};
use crate::app::ViewerApp;
use crate::render::{Output, Settings};
use crate::shade::Shading;
use crate::texture::Filter;

/// The controls every side of a split shares: mode, overlay, filter, sides.
fn settings_controls(s: &mut Settings, lab: &mut LabUi, uv: UvView, ui: &mut egui::Ui, side: Side) {
    let id = match side {
        Side::A => "a",
        Side::B => "b",
    };
    egui::ComboBox::from_id_salt((id, "mode"))
        .selected_text(s.shading.map_or("per model", |m| m.name()))
        .show_ui(ui, |ui| {
            ui.selectable_value(
                &mut s.shading,
                None,
                "per model (textured if it has a texture, else Phong)",
            );
            for m in Shading::ALL {
                ui.selectable_value(&mut s.shading, Some(m), m.name());
            }
        })
        .response
        .accessible_name(format!("shading mode {}", id.to_uppercase()));
    ui.checkbox(&mut s.wireframe_overlay, "wireframe over shaded (E)");
    let mut overdraw = s.output == Output::Overdraw;
    if ui
        .checkbox(&mut overdraw, "overdraw: fragments per pixel (O)")
        .changed()
    {
        s.output = if overdraw {
            Output::Overdraw
        } else {
            Output::Shaded
        };
    }
    ui.horizontal(|ui| {
        let label = ui.label("texture filter");
        egui::ComboBox::from_id_salt((id, "filter"))
            .selected_text(s.filter.map_or("model's", |f| f.name()))
            .show_ui(ui, |ui| {
                ui.selectable_value(&mut s.filter, None, "the model's sampler");
                for f in Filter::COMMON {
                    ui.selectable_value(&mut s.filter, Some(f), f.name());
                }
            })
            .response
            .labelled_by(label.id);
    });
    super::textures::controls(s, lab, uv, ui, side);
    ui.checkbox(&mut s.double_sided, "every material double-sided");
    ui.horizontal(|ui| {
        let label = ui.label("sub-pixel bits");
        ui.add(egui::Slider::new(&mut s.subpixel_bits, 0..=8))
            .labelled_by(label.id);
    });
    ui.horizontal(|ui| {
        ui.label("multisampling (Shift+A)");
        for n in crate::raster::SAMPLE_COUNTS {
            let name = if n == 1 {
                "off".to_owned()
            } else {
                format!("{n}x")
            };
            ui.selectable_value(&mut s.msaa, n, name)
                .on_hover_text("coverage and depth samples per pixel, shaded once per pixel");
        }
    });
}

/// The shading section.
pub fn show(app: &mut ViewerApp, ui: &mut egui::Ui) {
    let uv = UvView::of(app);
    settings_controls(&mut app.settings, &mut app.panels.lab, uv, ui, Side::A);
    ui.horizontal(|ui| {
        ui.label("background");
        let mut c = app.settings.background.truncate().to_array();
        // The picker edits linear RGB, as the renderer clears with it.
        if ui.color_edit_button_rgb(&mut c).changed() {
            app.settings.background = glam::Vec3::from_array(c).extend(1.0);
            app.split.b.background = app.settings.background;
        }
    });
    ui.horizontal(|ui| {
        ui.label("anti-aliasing when still (A)");
        for n in [1, 2, 4] {
            ui.selectable_value(
                &mut app.max_samples,
                n,
                if n == 1 {
                    "off".into()
                } else {
                    format!("{n}x{n}")
                },
            );
        }
    });
    ui.separator();
    ui.label("Rasterizer views");
    ui.checkbox(&mut app.panels.tile_grid, "64x64 tile grid (G)");
    ui.horizontal(|ui| {
        ui.label("tile cost (K)");
        ui.selectable_value(&mut app.panels.tile_cost, CostView::Off, "off");
        ui.selectable_value(&mut app.panels.tile_cost, CostView::Time, "time");
        ui.selectable_value(&mut app.panels.tile_cost, CostView::Fragments, "fragments");
    });
}

/// The split view section.
pub fn split(app: &mut ViewerApp, ui: &mut egui::Ui) {
    ui.checkbox(
        &mut app.split.enabled,
        "split the view (S): A left, B right",
    );
    ui.add_enabled_ui(app.split.enabled, |ui| {
        ui.label("A is the shading section above; B:");
        let uv = UvView::of(app);
        settings_controls(&mut app.split.b, &mut app.panels.lab, uv, ui, Side::B);
        super::environment::tone_map(ui, &mut app.split.b.tone, "b");
        ui.horizontal(|ui| {
            ui.label("divider");
            ui.add(egui::Slider::new(&mut app.split.divider, 0.0..=1.0));
        });
        ui.checkbox(
            &mut app.split.heat,
            "right half shows the ΔE00 difference A vs B",
        );
        if let Some((mean, p95)) = app.shown.as_ref().and_then(|s| s.heat) {
            ui.label(format!("ΔE00: mean {mean:.4}, 95th percentile {p95:.4}"));
            ui.label("black 0, red, yellow, white at 5 and above");
        }
        if ui.button("swap A and B").clicked() {
            std::mem::swap(&mut app.settings, &mut app.split.b);
        }
    });
}
