//! The stats section: milliseconds per stage, the pipeline's counters, frame rate and the
//! quality level of the frame on screen.

use eframe::egui;

use super::{row, Cx, Dock, Panel};

use crate::render::FrameReport;

fn report_grid(ui: &mut egui::Ui, id: &str, r: &FrameReport) {
    let t = &r.times;
    let s = &r.stats;
    egui::Grid::new(id)
        .striped(true)
        .num_columns(2)
        .show(ui, |ui| {
            row(
                ui,
                "size",
                format!(
                    "{}x{}, {2}x{2} samples, msaa {3}x",
                    r.width, r.height, r.samples, r.msaa
                ),
            );
            row(ui, "frame", format!("{:.2} ms", t.total));
            row(ui, "  set-up", format!("{:.2} ms", t.setup));
            row(ui, "  vertex", format!("{:.2} ms", t.vertex));
            row(ui, "  clip, set-up, bin", format!("{:.2} ms", t.raster));
            row(ui, "  fill + shade", format!("{:.2} ms", t.fill));
            row(ui, "  resolve samples", format!("{:.2} ms", t.resolve));
            row(ui, "triangles in", s.triangles_in.to_string());
            row(ui, "  objects culled", s.objects_culled.to_string());
            row(ui, "  frustum culled", s.culled_frustum.to_string());
            row(ui, "  back faces", s.culled_backface.to_string());
            row(ui, "  degenerate", s.culled_degenerate.to_string());
            if s.too_wide > 0 {
                // Never expected: a layout wider than the rasterizer's varyings.
                row(ui, "  too many varyings", s.too_wide.to_string());
            }
            row(ui, "  clipped", s.clipped.to_string());
            row(ui, "  drawn (set up)", s.drawn.to_string());
            row(ui, "tiles filled", s.tiles.to_string());
            row(ui, "pixels shaded", s.pixels_shaded.to_string());
            row(ui, "depth rejected", s.depth_rejected.to_string());
            row(ui, "lines", s.lines_drawn.to_string());
        });
}

/// The stats section.
pub struct StatsPanel;

impl Panel for StatsPanel {
    fn dock(&self) -> Dock {
        Dock::Left
    }

    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        egui::CollapsingHeader::new("Stats").show(ui, |ui| show(ui, cx));
    }
}

/// The stats section's body.
fn show(ui: &mut egui::Ui, cx: &Cx<'_>) {
    let Some(s) = cx.session.shown else {
        ui.label("no frame yet");
        return;
    };
    ui.label(format!("on screen: {}", s.level.label()));
    if let Some(ms) = s.interval.filter(|ms| *ms < 2000.0) {
        ui.label(format!(
            "frames arrive every {ms:.1} ms ({:.0} per second)",
            1e3 / ms.max(1e-3)
        ));
    }
    if let Some(l) = cx.session.load_millis {
        ui.label(format!("model loaded and prepared in {l:.0} ms"));
    }
    ui.label("counters are summed over the supersampling passes");
    report_grid(ui, "stats-a", &s.report_a);
    if let Some(b) = &s.report_b {
        ui.separator();
        ui.label("B");
        report_grid(ui, "stats-b", b);
    }
}
