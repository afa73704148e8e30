//! Section planes: up to three planes that cut the model open, each along an axis with a
//! slider across the model's bounds (or free: any normal and offset), and the caps that
//! fill the cut where a solid's inside shows. What it edits is `Settings::sections`, the
//! same planes as `--section` and a scene file's `[section]`.

use eframe::egui;
use glam::{Vec3, Vec4};

use super::{edit, Cx, Dock, Panel};
use crate::render::Sections;

/// The section planes panel (left).
#[derive(Default)]
pub struct SectionPanel {
    /// Plane `i` is edited as a normal and an offset even when it lies along an axis.
    free: [bool; Sections::MAX],
}

impl Panel for SectionPanel {
    fn dock(&self) -> Dock {
        Dock::Left
    }

    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        egui::CollapsingHeader::new("Section planes")
            .id_salt("section")
            .show(ui, |ui| self.show(ui, cx));
    }
}

/// An axis-aligned plane's axis and the side it keeps, or `None` for a free plane.
fn axis_of(p: Vec4) -> Option<(usize, f32)> {
    let n = p.truncate();
    (0..3).find_map(|a| {
        let s = n[a];
        (s.abs() == 1.0 && n.length_squared() == 1.0).then_some((a, s.signum()))
    })
}

const AXES: [&str; 3] = ["x", "y", "z"];

impl SectionPanel {
    fn show(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        ui.label("cut the model open: what lies on a plane's far side is removed")
            .on_hover_text(
                "The same planes as the command line's --section NX,NY,NZ,D and a scene \
             file's [section]; at most three.",
            );
        let (lo, hi) = cx
            .scene()
            .bounds()
            .unwrap_or((Vec3::splat(-1.0), Vec3::ONE));
        let s = &mut cx.settings.sections;
        let mut remove = None;
        for (i, plane) in s.planes.iter_mut().enumerate() {
            ui.push_id(("section-plane", i), |ui| {
                ui.horizontal(|ui| {
                    ui.label(format!("plane {}", i + 1));
                    let free = &mut self.free[i];
                    let axis = axis_of(*plane).filter(|_| !*free);
                    let label = axis.map_or("free", |(a, _)| AXES[a]);
                    egui::ComboBox::from_id_salt("axis")
                        .width(56.0)
                        .selected_text(label)
                        .show_ui(ui, |ui| {
                            for (a, name) in AXES.iter().enumerate() {
                                if ui
                                    .selectable_label(axis.map(|x| x.0) == Some(a), *name)
                                    .clicked()
                                {
                                    // Through the middle of the model, keeping the + side.
                                    let mid = (lo[a] + hi[a]) * 0.5;
                                    *plane = Vec3::AXES[a].extend(-mid);
                                    *free = false;
                                }
                            }
                            if ui.selectable_label(axis.is_none(), "free").clicked() {
                                // Stays where it is; now edited as a normal and an offset.
                                *free = true;
                            }
                        })
                        .response
                        .accessible_name(format!("plane {} axis", i + 1));
                    if ui
                        .button("flip")
                        .on_hover_text("keep the other side")
                        .clicked()
                    {
                        *plane = -*plane;
                    }
                    if ui.button("remove plane").clicked() {
                        remove = Some(i);
                    }
                });
                match axis_of(*plane).filter(|_| !self.free[i]) {
                    Some((a, sign)) => {
                        // n·p + d = 0 with n = sign·e_a: the plane is at p_a = -d·sign.
                        let mut at = -plane.w * sign;
                        let (l, h) = (lo[a].min(hi[a]), hi[a].max(lo[a]));
                        let pad = (h - l).max(1e-6) * 0.05;
                        let r = ui.add(egui::Slider::new(&mut at, (l - pad)..=(h + pad)).text(
                            format!(
                                "{} at (keeps {}{})",
                                AXES[a],
                                if sign > 0.0 { "+" } else { "-" },
                                AXES[a]
                            ),
                        ));
                        if r.changed() && at.is_finite() {
                            plane.w = -at * sign;
                        }
                    }
                    None => {
                        ui.horizontal(|ui| {
                            ui.label("normal");
                            let mut n = plane.truncate();
                            if edit::vec3(ui, &mut n, 0.01, "section normal") {
                                if let Ok(p) = Sections::plane(n, plane.w) {
                                    *plane = p;
                                }
                            }
                        });
                        ui.horizontal(|ui| {
                            ui.label("offset");
                            let span = (hi - lo).length().max(1e-6);
                            edit::drag(
                                ui,
                                &mut plane.w,
                                -span * 2.0..=span * 2.0,
                                f64::from(span) * 0.002,
                                "section offset",
                            );
                        });
                    }
                }
            });
        }
        if let Some(i) = remove {
            s.planes.remove(i);
            self.free.copy_within(i + 1.., i);
            self.free[Sections::MAX - 1] = false;
        }
        ui.horizontal(|ui| {
            let full = s.planes.len() >= Sections::MAX;
            if ui
                .add_enabled(!full, egui::Button::new("add a plane"))
                .on_hover_text("along x through the middle of the model")
                .clicked()
            {
                let mid = (lo.x + hi.x) * 0.5;
                let n = s.planes.len();
                if s.push(Vec4::new(1.0, 0.0, 0.0, -mid)).is_ok() {
                    self.free[n] = false;
                }
            }
        });
        let mut caps = s.cap.is_some();
        ui.horizontal(|ui| {
            if ui
                .checkbox(&mut caps, "fill the cut (caps)")
                .on_hover_text(
                    "Where a closed mesh's inside shows through a cut, draw it in this colour \
                 (an open surface seen from behind gets it too).",
                )
                .changed()
            {
                s.cap = caps.then_some(Sections::CAP);
            }
            if let Some(c) = &mut s.cap {
                edit::colour(ui, c, "cap colour");
            }
        });
        let (a, b) = (&*cx.settings, &mut cx.split.b);
        if b.sections != a.sections {
            b.sections = a.sections.clone();
        }
    }
}
