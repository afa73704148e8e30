//! The material editor: each material's Kd (diffuse) and alpha, Ks (specular) and the Phong
//! exponent n (logarithmic, 1..2000), Ka (ambient factor), Ke (emission), alpha mode
//! (opaque, mask with its cutoff, blend) and sidedness, edited as the renderer's material
//! overrides ([`crate::render::Settings::materials`]) so the frame follows; "restore the
//! file's materials" drops them.

use super::{edit, Cx, Dock, Installed, Panel};
use crate::scene::{AlphaMode, Material};
use eframe::egui;

/// The alpha modes by name, in the order the editor lists them.
const MODES: [&str; 3] = ["opaque", "mask", "blend"];

fn mode_name(m: AlphaMode) -> &'static str {
    match m {
        AlphaMode::Opaque => MODES[0],
        AlphaMode::Mask(_) => MODES[1],
        AlphaMode::Blend => MODES[2],
    }
}

/// The glTF default alpha cutoff.
const DEFAULT_CUTOFF: f32 = 0.5;

/// The material editor section: the material selected.
#[derive(Default)]
pub struct MaterialsPanel {
    material: usize,
}

impl Panel for MaterialsPanel {
    fn dock(&self) -> Dock {
        Dock::Left
    }

    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        egui::CollapsingHeader::new("Materials").show(ui, |ui| self.show(ui, cx));
    }

    fn installed(&mut self, what: &Installed<'_>) {
        if what.fresh {
            self.material = 0;
        }
    }
}

impl MaterialsPanel {
    /// The material editor section.
    fn show(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        let scene_materials = &cx.session.scene.scene().materials;
        if scene_materials.is_empty() {
            ui.label("the model has no materials: every mesh uses the default material");
            return;
        }
        let mut list: Vec<Material> = cx
            .settings
            .materials
            .clone()
            .unwrap_or_else(|| scene_materials.clone());
        let k = self.material.min(list.len() - 1);
        egui::ComboBox::from_id_salt("material")
            .selected_text(format!("{k}: {}", list[k].name))
            .show_ui(ui, |ui| {
                for (i, m) in list.iter().enumerate().take(500) {
                    ui.selectable_value(&mut self.material, i, format!("{i}: {}", m.name));
                }
            })
            .response
            .accessible_name("material");
        let changed = editor(ui, &mut list[k]);
        if changed {
            cx.settings.materials = Some(list);
        }
        if cx.settings.materials.is_some() && ui.button("restore the file's materials").clicked() {
            cx.settings.materials = None;
        }
        if cx.split.b.materials != cx.settings.materials {
            cx.split.b.materials = cx.settings.materials.clone();
        }
    }
}

/// The metallic-roughness rows of a glTF material (what the `pbr` mode reads; the Phong
/// modes draw it with `Kd = base (1 - metallic)`); true if one changed.
fn pbr_rows(ui: &mut egui::Ui, m: &mut Material) -> bool {
    let mut changed = false;
    ui.label("metallic");
    changed |= edit::slider(ui, &mut m.metallic, 0.0..=1.0, false, "material metallic");
    ui.end_row();
    ui.label("roughness")
        .on_hover_text("perceptual: the GGX α is its square");
    changed |= edit::slider(ui, &mut m.roughness, 0.0..=1.0, false, "material roughness");
    ui.end_row();
    let Some(p) = &mut m.pbr else {
        return changed;
    };
    ui.label("index of refraction").on_hover_text(
        "KHR_materials_ior: the dielectric's F0 = ((ior - 1)/(ior + 1))², 0.04 at 1.5",
    );
    changed |= edit::drag(ui, &mut p.ior, 1.0..=5.0, 0.01, "material ior");
    ui.end_row();
    ui.label("specular")
        .on_hover_text("KHR_materials_specular: F90 of the dielectric lobe and a factor on its F0");
    changed |= edit::slider(ui, &mut p.specular, 0.0..=1.0, false, "material specular");
    ui.end_row();
    ui.label("specular colour");
    changed |= edit::colour(ui, &mut p.specular_color, "material specular colour");
    ui.end_row();
    ui.label("emissive strength")
        .on_hover_text("KHR_materials_emissive_strength: multiplies Ke");
    changed |= edit::drag(
        ui,
        &mut p.emissive_strength,
        0.0..=1000.0,
        0.05,
        "material emissive strength",
    );
    ui.end_row();
    ui.label("clear coat").on_hover_text(
        "KHR_materials_clearcoat: a clear layer (IOR 1.5) over the material; 0 for none",
    );
    changed |= edit::slider(ui, &mut p.clearcoat, 0.0..=1.0, false, "material clearcoat");
    ui.end_row();
    ui.label("clear coat roughness");
    changed |= edit::slider(
        ui,
        &mut p.clearcoat_roughness,
        0.0..=1.0,
        false,
        "material clearcoat roughness",
    );
    ui.end_row();
    ui.label("sheen colour").on_hover_text(
        "KHR_materials_sheen: the colour of a cloth-like layer (Charlie distribution) over the base; black for none",
    );
    changed |= edit::colour(ui, &mut p.sheen_color, "material sheen colour");
    ui.end_row();
    ui.label("sheen roughness");
    changed |= edit::slider(
        ui,
        &mut p.sheen_roughness,
        0.0..=1.0,
        false,
        "material sheen roughness",
    );
    ui.end_row();
    ui.label("iridescence").on_hover_text(
        "KHR_materials_iridescence: a thin film on the base whose interference colours the reflection; 0 for none",
    );
    changed |= edit::slider(
        ui,
        &mut p.iridescence,
        0.0..=1.0,
        false,
        "material iridescence",
    );
    ui.end_row();
    ui.label("film IOR");
    changed |= edit::drag(
        ui,
        &mut p.iridescence_ior,
        1.0..=3.0,
        0.01,
        "material iridescence ior",
    );
    ui.end_row();
    ui.label("film thickness").on_hover_text(
        "The film's thickness: the maximum, or from the minimum to the maximum by the thickness texture's G",
    );
    ui.horizontal(|ui| {
        let [lo, hi] = &mut p.iridescence_thickness;
        changed |= edit::drag_with(
            ui,
            lo,
            0.0..=2000.0,
            1.0,
            "material iridescence thickness minimum",
            " nm",
        );
        changed |= edit::drag_with(
            ui,
            hi,
            0.0..=2000.0,
            1.0,
            "material iridescence thickness maximum",
            " nm",
        );
    });
    ui.end_row();
    ui.label("anisotropy").on_hover_text(
        "KHR_materials_anisotropy: the highlight stretched along a direction of the tangent frame; 0 for none (needs tangents)",
    );
    changed |= edit::slider(
        ui,
        &mut p.anisotropy,
        0.0..=1.0,
        false,
        "material anisotropy",
    );
    ui.end_row();
    ui.label("anisotropy direction");
    let mut degrees = p.anisotropy_rotation.to_degrees();
    if edit::drag_with(
        ui,
        &mut degrees,
        -360.0..=360.0,
        1.0,
        "material anisotropy rotation",
        "°",
    ) {
        p.anisotropy_rotation = degrees.to_radians();
        changed = true;
    }
    ui.end_row();
    ui.label("diffuse transmission").on_hover_text(
        "KHR_materials_diffuse_transmission: the share of the diffuse light that passes through (leaves, paper); 0 for none",
    );
    changed |= edit::slider(
        ui,
        &mut p.diffuse_transmission,
        0.0..=1.0,
        false,
        "material diffuse transmission",
    );
    ui.end_row();
    ui.label("diffuse transmission colour");
    changed |= edit::colour(
        ui,
        &mut p.diffuse_transmission_color,
        "material diffuse transmission colour",
    );
    ui.end_row();
    ui.label("transmission").on_hover_text(
        "KHR_materials_transmission: the share of the light that passes through (glass, water); 0 for none",
    );
    changed |= edit::slider(
        ui,
        &mut p.transmission,
        0.0..=1.0,
        false,
        "material transmission",
    );
    ui.end_row();
    ui.label("thickness").on_hover_text(
        "KHR_materials_volume: the volume's thickness under the surface, in the model's units; 0: thin-walled",
    );
    changed |= edit::drag(
        ui,
        &mut p.thickness,
        0.0..=1000.0,
        0.01,
        "material thickness",
    );
    ui.end_row();
    ui.label("attenuation distance").on_hover_text(
        "KHR_materials_volume: the distance after which white light has the attenuation colour; 0 or less: none",
    );
    let mut d = if p.attenuation_distance.is_finite() {
        p.attenuation_distance
    } else {
        0.0
    };
    if edit::drag(
        ui,
        &mut d,
        0.0..=1000.0,
        0.01,
        "material attenuation distance",
    ) {
        p.attenuation_distance = if d > 0.0 { d } else { f32::INFINITY };
        changed = true;
    }
    ui.end_row();
    ui.label("attenuation colour");
    changed |= edit::colour(ui, &mut p.attenuation_color, "material attenuation colour");
    ui.end_row();
    ui.label("dispersion")
        .on_hover_text("KHR_materials_dispersion: 20 / the Abbe number; 0 for none");
    changed |= edit::drag(
        ui,
        &mut p.dispersion,
        0.0..=100.0,
        0.05,
        "material dispersion",
    );
    ui.end_row();
    ui.label("unlit");
    changed |= ui
        .checkbox(
            &mut p.unlit,
            "the base colour as it is (KHR_materials_unlit)",
        )
        .changed();
    ui.end_row();
    changed
}

/// The controls of one material; true if it changed.
fn editor(ui: &mut egui::Ui, m: &mut Material) -> bool {
    let mut changed = false;
    egui::Grid::new("material-grid")
        .num_columns(2)
        .show(ui, |ui| {
            ui.label(if m.pbr.is_some() {
                "base colour (Kd)"
            } else {
                "Kd (diffuse)"
            });
            let mut kd = m.base_color.truncate();
            if edit::colour(ui, &mut kd, "material Kd") {
                m.base_color = kd.extend(m.base_color.w);
                changed = true;
            }
            ui.end_row();
            ui.label("alpha");
            changed |= edit::slider(ui, &mut m.base_color.w, 0.0..=1.0, false, "material alpha");
            ui.end_row();
            if m.pbr.is_some() {
                changed |= pbr_rows(ui, m);
            }
            ui.label("Ks (specular)");
            changed |= edit::colour(ui, &mut m.specular, "material Ks");
            ui.end_row();
            ui.label("shininess n");
            changed |= edit::slider(
                ui,
                &mut m.shininess,
                1.0..=2000.0,
                true,
                "material shininess",
            );
            ui.end_row();
            ui.label("Ka (ambient factor)");
            changed |= edit::colour(ui, &mut m.ambient, "material Ka");
            ui.end_row();
            ui.label("Ke (emission)");
            changed |= edit::colour(ui, &mut m.emissive, "material Ke");
            ui.end_row();
            ui.label("alpha mode");
            ui.horizontal(|ui| {
                let now = mode_name(m.alpha_mode);
                for name in MODES {
                    let r = ui
                        .selectable_label(now == name, name)
                        .accessible_name(format!("alpha mode {name}"));
                    if r.clicked() && now != name {
                        m.alpha_mode = match name {
                            "mask" => AlphaMode::Mask(DEFAULT_CUTOFF),
                            "blend" => AlphaMode::Blend,
                            _ => AlphaMode::Opaque,
                        };
                        changed = true;
                    }
                }
            });
            ui.end_row();
            if let AlphaMode::Mask(cutoff) = &mut m.alpha_mode {
                ui.label("alpha cutoff");
                changed |= edit::slider(ui, cutoff, 0.0..=1.0, false, "material alpha cutoff");
                ui.end_row();
            }
            ui.label("double-sided");
            changed |= ui
                .checkbox(&mut m.double_sided, "lit on both sides, not culled")
                .changed();
            ui.end_row();
            for slot in crate::scene::Slot::ALL {
                if let Some(t) = m.slot(slot) {
                    ui.label(format!("{} map", slot.name()));
                    ui.label(t.describe());
                    ui.end_row();
                }
            }
        });
    changed
}
