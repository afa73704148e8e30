//! The shading section (mode, wireframe overlay, overdraw, background, texture filter,
//! multisampling, anti-aliasing, rasterizer overlays) and the split view's section (what B shows, the
//! ΔE00 map).

use eframe::egui;

use super::textures::LabUi;
use super::{CostView, Cx, Dock, Installed, Panel, Side, UvView};
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
        // Every mode in view at once, no scrolling (about 20 rows).
        .height(640.0)
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
    // What the rasterizer does, for whoever studies it: one level down.
    egui::CollapsingHeader::new("rasterizer")
        .id_salt((id, "rasterizer"))
        .show(ui, |ui| rasterizer_controls(s, ui));
}

/// The rasterizer's own controls of a side: overdraw view, vertex snap, multisampling.
/// The traced modes' depth limit (`whitted`, `path`).
fn ray_depth(s: &mut Settings, ui: &mut egui::Ui) {
    if matches!(
        s.rays(),
        crate::shade::mode::Rays::Whitted | crate::shade::mode::Rays::Path
    ) {
        ui.horizontal(|ui| {
            let label = ui.label("ray depth").on_hover_text(
                "traced rays: the most surfaces a ray meets after the first (Whitted's \
             depth, the path tracer's bounces; 0 is the direct light alone; the \
             textbook's §9.6.1 depth limit)",
            );
            ui.add(egui::Slider::new(
                &mut s.ray_depth,
                super::edit::whole_range_of("ray_depth"),
            ))
            .labelled_by(label.id);
        });
    }
}

fn rasterizer_controls(s: &mut Settings, ui: &mut egui::Ui) {
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
        let label = ui.label("sub-pixel bits").on_hover_text(
            "fixed-point precision of the vertex snap: 8 (the default) is 1/256 pixel",
        );
        let bits = super::edit::whole_range_of("subpixel_bits");
        let bits = *bits.start() as u8..=*bits.end() as u8;
        ui.add(egui::Slider::new(&mut s.subpixel_bits, bits))
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

/// The shading section and the split view's, and the texture lab's state (in both).
#[derive(Default)]
pub struct ShadingPanel {
    /// The texture lab's image paths, errors, reads and picker.
    pub lab: LabUi,
}

impl Panel for ShadingPanel {
    fn dock(&self) -> Dock {
        Dock::Left
    }

    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        egui::CollapsingHeader::new("Shading")
            .default_open(true)
            .show(ui, |ui| self.show(ui, cx));
        egui::CollapsingHeader::new("Split view A | B").show(ui, |ui| self.split(ui, cx));
    }

    fn poll(&mut self, cx: &mut Cx<'_>) {
        self.lab.poll_images(cx);
    }

    fn dialogs(&mut self, ctx: &egui::Context, cx: &mut Cx<'_>) {
        self.lab.after_ui(ctx, cx);
    }

    fn installed(&mut self, what: &Installed<'_>) {
        if what.fresh {
            self.lab.on_new_scene();
        }
    }
}

impl ShadingPanel {
    /// The shading section.
    fn show(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        let uv = cx.session.uv;
        settings_controls(cx.settings, &mut self.lab, uv, ui, Side::A);
        ui.horizontal(|ui| {
            ui.label("background");
            let mut c = cx.settings.background.truncate().to_array();
            // The picker edits linear RGB, as the renderer clears with it.
            if ui.color_edit_button_rgb(&mut c).changed() {
                cx.settings.background = glam::Vec3::from_array(c).extend(1.0);
                cx.split.b.background = cx.settings.background;
            }
        });
        ui.horizontal(|ui| {
            ui.label("anti-aliasing when still (A)");
            for n in [1, 2, 4] {
                ui.selectable_value(
                    &mut *cx.max_samples,
                    n,
                    if n == 1 {
                        "off".into()
                    } else {
                        format!("{n}x{n}")
                    },
                );
            }
        });
        ray_depth(cx.settings, ui);
        if cx.settings.rays() == crate::shade::mode::Rays::Path {
            ui.label(format!(
                "path: while still, paths are added up to {} per pixel (one when off)",
                crate::worker::PATH_CAP
            ));
        }
        egui::CollapsingHeader::new("rasterizer views")
            .id_salt("rasterizer-views")
            .show(ui, |ui| {
                ui.checkbox(&mut cx.shared.tile_grid, "64x64 tile grid (G)");
                ui.horizontal(|ui| {
                    ui.label("tile cost (K)");
                    ui.selectable_value(&mut cx.shared.tile_cost, CostView::Off, "off");
                    ui.selectable_value(&mut cx.shared.tile_cost, CostView::Time, "time");
                    ui.selectable_value(&mut cx.shared.tile_cost, CostView::Fragments, "fragments");
                });
            });
    }

    /// The split view section.
    fn split(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        let mut on = cx.split.enabled;
        if ui
            .checkbox(&mut on, "split the view (S): A left, B right")
            .changed()
        {
            cx.split.set_enabled(on, cx.settings);
        }
        ui.add_enabled_ui(cx.split.enabled, |ui| {
            ui.label("A is the shading section above; B:");
            let uv = cx.session.uv;
            settings_controls(&mut cx.split.b, &mut self.lab, uv, ui, Side::B);
            super::environment::tone_map(ui, &mut cx.split.b.tone, "b");
            ui.horizontal(|ui| {
                ui.label("divider");
                ui.add(egui::Slider::new(&mut cx.split.divider, 0.0..=1.0));
            });
            ui.checkbox(
                &mut cx.split.heat,
                "right half shows the ΔE00 difference A vs B",
            );
            if let Some((mean, p95)) = cx.session.shown.and_then(|s| s.heat) {
                ui.label(format!(
                    "ΔE00 over the model's pixels: mean {mean:.4}, 95th percentile {p95:.4}"
                ));
                ui.label("black 0, red, yellow, white at 5 and above");
            }
            if ui.button("swap A and B").clicked() {
                std::mem::swap(cx.settings, &mut cx.split.b);
            }
        });
    }
}
