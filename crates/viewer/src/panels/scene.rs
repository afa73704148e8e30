//! The scene section: instances, meshes with their topology report, materials, textures
//! with thumbnails, lights, cameras (view through a file's camera) and the load report.

use eframe::egui::{self, ColorImage, TextureOptions};

use super::{row, Cx, Dock, Installed, Panel};

use crate::mesh::{NormalSource, TopologyReport};
use crate::navigate::Navigator;
use crate::render::{Hidden, Lights};
use crate::scene::{Light, Slot};

mod nodes;

use nodes::nodes;

/// Largest thumbnail side in texels.
const THUMB: u32 = 96;
/// Rows listed before a long list is cut.
const MAX_ROWS: usize = 200;

/// The scene section, with the thumbnails and topology reports it has made.
#[derive(Default)]
pub struct ScenePanel {
    /// Thumbnails of the scene's textures (built on first view).
    thumbnails: Vec<Option<egui::TextureHandle>>,
    /// Topology reports of the meshes opened.
    topology: std::collections::HashMap<usize, TopologyReport>,
}

impl Panel for ScenePanel {
    fn dock(&self) -> Dock {
        Dock::Right
    }

    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        egui::CollapsingHeader::new("Scene")
            .default_open(true)
            .show(ui, |ui| self.show(ui, cx));
    }

    fn installed(&mut self, what: &Installed<'_>) {
        if what.fresh {
            self.thumbnails.clear();
            self.topology.clear();
        }
    }
}

impl ScenePanel {
    /// The scene section.
    fn show(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        let scene = std::sync::Arc::clone(cx.session.scene.scene());
        let r = &scene.report;
        ui.label(format!(
            "{} ({}): {} meshes, {} instances{}, {} triangles",
            cx.session.name(),
            if r.format.is_empty() {
                "?"
            } else {
                r.format.as_str()
            },
            scene.meshes.len(),
            scene.instances.len(),
            match scene
                .instances
                .iter()
                .map(|i| i.copy_count())
                .sum::<usize>()
            {
                n if n != scene.instances.len() => format!(" ({n} copies drawn)"),
                _ => String::new(),
            },
            cx.session.scene.triangle_count()
        ));
        variant_choice(cx, ui, &scene.variants);
        egui::CollapsingHeader::new(format!(
            "Load report ({} warnings, {} skipped, {} generated)",
            r.warnings.len(),
            r.skipped.len(),
            r.generated.len()
        ))
        .id_salt("load-report")
        .show(ui, |ui| {
            for (what, list) in [
                ("warning", &r.warnings),
                ("skipped", &r.skipped),
                ("generated", &r.generated),
            ] {
                for line in list.iter().take(MAX_ROWS) {
                    ui.label(format!("{what}: {line}"));
                }
            }
            if r.warnings.is_empty() && r.skipped.is_empty() && r.generated.is_empty() {
                ui.label("nothing to report");
            }
        });
        egui::CollapsingHeader::new(format!("Instances ({})", scene.instances.len()))
            .id_salt("instances")
            .show(ui, |ui| {
                let mut isolate = None;
                for (i, inst) in scene.instances.iter().enumerate().take(MAX_ROWS) {
                    let tris = cx
                        .session
                        .scene
                        .meshes()
                        .get(inst.mesh)
                        .map_or(0, |m| m.tri.triangles.len());
                    ui.horizontal(|ui| {
                        // The button first: a long name is cut at the panel's edge.
                        if ui
                            .small_button("isolate")
                            .on_hover_text("show only this part")
                            .clicked()
                        {
                            isolate = Some(i);
                        }
                        let mut shown = !cx.settings.hidden.contains(i);
                        if ui
                            .checkbox(
                                &mut shown,
                                match inst.copies.as_ref().map(|c| c.len()) {
                                    None => format!(
                                        "{i}: {} (mesh {}, {tris} triangles, {:?})",
                                        inst.name, inst.mesh, inst.style
                                    ),
                                    Some(n) => format!(
                                        "{i}: {} (mesh {}, {tris} triangles, {n} copies, {:?})",
                                        inst.name, inst.mesh, inst.style
                                    ),
                                },
                            )
                            .on_hover_text("shown; untick to hide this part")
                            .changed()
                        {
                            cx.settings.hidden.set(i, !shown);
                        }
                    });
                }
                more(ui, scene.instances.len());
                if let Some(i) = isolate {
                    cx.settings.hidden = Hidden::all_but(scene.instances.len(), [i]);
                }
            });
        nodes(cx, ui, &scene);
        let hidden = cx.settings.hidden.count();
        if hidden > 0 {
            ui.horizontal(|ui| {
                ui.label(format!("{hidden} of {} parts hidden", scene.instances.len()));
                if ui
                    .button("show all")
                    .on_hover_text("show every part again (hidden or isolated in the node tree or the instances)")
                    .clicked()
                {
                    cx.settings.hidden = Hidden::default();
                }
            });
        }
        let (a, b) = (&*cx.settings, &mut cx.split.b);
        if b.hidden != a.hidden {
            b.hidden = a.hidden.clone();
        }
        egui::CollapsingHeader::new(format!("Meshes ({})", scene.meshes.len()))
            .id_salt("meshes")
            .show(ui, |ui| {
                for (i, m) in scene.meshes.iter().enumerate().take(MAX_ROWS) {
                    egui::CollapsingHeader::new(format!(
                        "{i}: {} ({} vertices, {} facets)",
                        m.name,
                        m.positions.len(),
                        m.facet_count()
                    ))
                    .id_salt(("mesh", i))
                    .show(ui, |ui| {
                        let normals = match m.normal_source {
                            NormalSource::File => "from the file".to_owned(),
                            NormalSource::Averaged(o) => format!(
                                "averaged ({:?} weights, crease {})",
                                o.weighting,
                                o.crease_degrees.map_or("off".into(), |d| format!("{d}°"))
                            )
                            .to_lowercase(),
                            NormalSource::Flat => "flat (one per facet)".into(),
                            NormalSource::Analytic => "exact (primitive)".into(),
                        };
                        let yes = |b: bool| if b { "yes" } else { "no" };
                        ui.label(format!(
                            "normals {normals}; UV sets {}; colours {}; tangents {}",
                            m.uvs.len(),
                            yes(m.colors.is_some()),
                            yes(m.tangents.is_some())
                        ));
                        // The topology report walks the whole mesh: computed when opened, then kept.
                        let report = self.topology.entry(i).or_insert_with(|| m.topology());
                        topology(ui, i, report);
                    });
                }
                more(ui, scene.meshes.len());
            });
        egui::CollapsingHeader::new(format!("Materials ({})", scene.materials.len()))
            .id_salt("materials")
            .show(ui, |ui| {
                for (i, m) in scene.materials.iter().enumerate().take(MAX_ROWS) {
                    let c = m.base_color;
                    ui.label(format!(
                        "{i}: {}: Kd ({:.2} {:.2} {:.2}) a {:.2}, Ks {:.2}, n {:.0}, {:?}{}{}",
                        m.name,
                        c.x,
                        c.y,
                        c.z,
                        c.w,
                        m.specular.max_element(),
                        m.shininess,
                        m.alpha_mode,
                        if m.double_sided { ", double-sided" } else { "" },
                        if m.base_color_texture.is_some() {
                            ", textured"
                        } else {
                            ""
                        },
                    ));
                    for slot in Slot::ALL {
                        if let Some(t) = m.slot(slot) {
                            ui.label(format!("    {} map: {}", slot.name(), t.describe()));
                        }
                    }
                }
                more(ui, scene.materials.len());
            });
        egui::CollapsingHeader::new(format!("Textures ({})", scene.textures.len()))
            .id_salt("textures")
            .show(ui, |ui| {
                if self.thumbnails.len() != scene.textures.len() {
                    self.thumbnails = vec![None; scene.textures.len()];
                }
                for (i, t) in scene.textures.iter().enumerate().take(MAX_ROWS) {
                    ui.horizontal(|ui| {
                        let thumb = self.thumbnails[i].get_or_insert_with(|| {
                            ui.ctx().load_texture(
                                format!("thumb-{i}"),
                                thumbnail(t),
                                TextureOptions::LINEAR,
                            )
                        });
                        ui.image((thumb.id(), thumb.size_vec2()));
                        ui.label(format!(
                            "{i}: {}\n{}x{}, {}",
                            t.name,
                            t.width,
                            t.height,
                            t.texels.format_name()
                        ));
                    });
                }
            });
        egui::CollapsingHeader::new(format!("Lights ({})", scene.lights.len()))
            .id_salt("scene-lights")
            .show(ui, |ui| {
                if scene.lights.is_empty() {
                    ui.label("none: the default rig (ambient, key and fill) follows the camera");
                }
                for (i, l) in scene.lights.iter().enumerate() {
                    ui.label(format!("{i}: {}", describe_light(l)));
                }
                if cx.settings.lights != Lights::Auto
                    && ui.button("use the scene's lights").clicked()
                {
                    cx.settings.lights = Lights::Auto;
                }
            });
        egui::CollapsingHeader::new(format!("Cameras ({})", scene.cameras.len()))
            .id_salt("cameras")
            .show(ui, |ui| {
                if scene.cameras.is_empty() {
                    ui.label("none in the file");
                }
                // As posed now: a camera under an animated node is where the animation put it.
                let cameras = cx.session.scene.cameras().to_vec();
                for (i, c) in cameras.iter().enumerate() {
                    let kind = match c.ortho {
                        Some(h) => format!("orthographic, half height {h:.3}"),
                        None => format!("{:.1}° field of view", c.yfov.to_degrees()),
                    };
                    if ui
                        .button(format!("{i}: view through '{}' ({kind})", c.name))
                        .clicked()
                    {
                        let (center, radius) = cx.session.scene.bounding_sphere();
                        *cx.nav = Navigator::from_camera(c, center, radius, cx.nav.up_axis());
                    }
                }
            });
    }
}

/// The material variant drawn (`KHR_materials_variants`; only for a file that has some).
fn variant_choice(cx: &mut Cx<'_>, ui: &mut egui::Ui, variants: &[String]) {
    if variants.is_empty() {
        return;
    }
    const DEFAULT: &str = "file's default";
    ui.horizontal(|ui| {
        let shown = cx.settings.variant.clone();
        let r = egui::ComboBox::from_label("material variant")
            .selected_text(shown.as_deref().unwrap_or(DEFAULT))
            .show_ui(ui, |ui| {
                ui.selectable_value(&mut cx.settings.variant, None, DEFAULT);
                for v in variants {
                    ui.selectable_value(&mut cx.settings.variant, Some(v.clone()), v);
                }
            });
        r.response
            .on_hover_text(
                "The file's material variants (KHR_materials_variants): each part takes the \
                 material the variant gives it, the others keep theirs (as --variant NAME).",
            )
            .accessible_name("material variant");
    });
}

fn more(ui: &mut egui::Ui, n: usize) {
    if n > MAX_ROWS {
        ui.label(format!("... and {} more", n - MAX_ROWS));
    }
}

fn topology(ui: &mut egui::Ui, i: usize, t: &TopologyReport) {
    egui::Grid::new(("topology", i))
        .num_columns(2)
        .show(ui, |ui| {
            row(
                ui,
                "vertices / edges / facets",
                format!("{} / {} / {}", t.vertices, t.edges, t.facets),
            );
            row(ui, "triangles", t.triangles.to_string());
            row(
                ui,
                "boundary edges (loops)",
                format!("{} ({})", t.boundary_edges, t.boundary_loops),
            );
            row(ui, "non-manifold edges", t.non_manifold_edges.to_string());
            row(ui, "degenerate facets", t.degenerate_facets.to_string());
            row(ui, "isolated vertices", t.isolated_vertices.to_string());
            row(ui, "components", t.components.to_string());
            row(
                ui,
                "V - E + F",
                format!(
                    "{} (used vertices: {})",
                    t.euler_characteristic, t.euler_characteristic_used
                ),
            );
            row(
                ui,
                "genus",
                t.genus.map_or("not defined".into(), |g| g.to_string()),
            );
        });
}

/// A one-line description of a light.
#[must_use]
pub fn describe_light(l: &Light) -> String {
    let c = |v: glam::Vec3| format!("({:.2} {:.2} {:.2})", v.x, v.y, v.z);
    let deg = |r: f32| r.to_degrees();
    let mut out = if l.name.is_empty() {
        l.kind().to_string()
    } else {
        format!("{} '{}'", l.kind(), l.name)
    };
    if l.kind.positional() {
        out += &format!(" at {}", c(l.position));
    }
    if l.kind.directed() {
        out += &format!(" along {}", c(l.direction));
    }
    match l.kind {
        crate::scene::LightKind::Spot => {
            out += &format!(" cone {:.0}/{:.0} deg", deg(l.inner), deg(l.outer));
        }
        crate::scene::LightKind::Rect => {
            out += &format!(" pyramid {:.0}x{:.0} deg", deg(l.rect.x), deg(l.rect.y));
        }
        crate::scene::LightKind::Ambient
        | crate::scene::LightKind::Directional
        | crate::scene::LightKind::Point => {}
    }
    out += &format!(" colour {} x {:.2}", c(l.color), l.intensity);
    if l.attenuation != crate::scene::Attenuation::None {
        out += &format!(", {} attenuation", l.attenuation.name());
    }
    if l.shadow {
        out += ", shadows";
    }
    out
}

/// A texture scaled down (nearest texel) to at most [`THUMB`] texels a side.
fn thumbnail(t: &crate::texture::Texture) -> ColorImage {
    let (w, h) = (t.width.max(1), t.height.max(1));
    let scale = (THUMB as f32 / w.max(h) as f32).min(1.0);
    let (tw, th) = (
        ((w as f32 * scale) as u32).max(1),
        ((h as f32 * scale) as u32).max(1),
    );
    let texels = t.to_srgb8();
    let mut px = Vec::with_capacity((tw * th) as usize);
    for y in 0..th {
        for x in 0..tw {
            let (sx, sy) = (x * w / tw, y * h / th);
            let [r, g, b, a] = texels
                .get((sy * w + sx) as usize)
                .copied()
                .unwrap_or([0; 4]);
            px.push(egui::Color32::from_rgba_unmultiplied(r, g, b, a));
        }
    }
    ColorImage::new([tw as usize, th as usize], px)
}
