//! The scene section: instances, meshes with their topology report, materials, textures
//! with thumbnails, lights, cameras (view through a file's camera) and the load report.

use eframe::egui::{self, ColorImage, TextureOptions};

use super::{row, Cx, Dock, Installed, Panel};

use crate::mesh::{NormalSource, TopologyReport};
use crate::navigate::Navigator;
use crate::render::{Hidden, Lights};
use crate::scene::{Light, Slot};

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

/// Nodes deeper than this are not listed (a tree that deep is a broken file).
const MAX_DEPTH: usize = 64;

/// What a node's buttons ask for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum NodeAction {
    /// Frame what it draws.
    Frame,
    /// Hide what it and its children draw.
    Hide,
    /// Show it again.
    Show,
    /// Show only what it and its children draw.
    Isolate,
}

/// The node tree as a collapsible tree: each scene of the file with its roots (the drawn one
/// marked), then the parentless nodes outside every scene (a skin's joints may live there).
/// A node that draws something can be framed, hidden (with its children) or isolated.
fn nodes(cx: &mut Cx<'_>, ui: &mut egui::Ui, scene: &crate::scene::Scene) {
    let g = &scene.graph;
    egui::CollapsingHeader::new(format!("Nodes ({})", g.nodes.len()))
        .id_salt("nodes")
        .show(ui, |ui| {
            if g.nodes.is_empty() {
                ui.label("none: this format has no node tree (the instances above can be hidden)");
                return;
            }
            let mut act = None;
            let mut listed = vec![false; g.nodes.len()];
            let hidden = &cx.settings.hidden;
            for (si, s) in g.scenes.iter().enumerate() {
                let drawn = if g.drawn == Some(si) { ", drawn" } else { "" };
                let name = if s.name.is_empty() {
                    ""
                } else {
                    s.name.as_str()
                };
                egui::CollapsingHeader::new(format!(
                    "scene {si} {name} ({} roots{drawn})",
                    s.roots.len()
                ))
                .id_salt(("graph-scene", si))
                .default_open(g.drawn == Some(si))
                .show(ui, |ui| {
                    for &r in s.roots.iter().take(MAX_ROWS) {
                        node(ui, g, hidden, r, 0, &mut act);
                    }
                    more(ui, s.roots.len());
                });
                for &r in &s.roots {
                    if let Some(l) = listed.get_mut(r) {
                        *l = true;
                    }
                }
            }
            let others: Vec<usize> = (0..g.nodes.len())
                .filter(|&n| g.nodes[n].parent.is_none() && !listed[n])
                .collect();
            if !others.is_empty() {
                let title = if g.scenes.is_empty() {
                    format!("root nodes ({})", others.len())
                } else {
                    format!("outside every scene ({})", others.len())
                };
                egui::CollapsingHeader::new(title)
                    .id_salt("graph-others")
                    .default_open(g.scenes.is_empty())
                    .show(ui, |ui| {
                        for &r in others.iter().take(MAX_ROWS) {
                            node(ui, g, hidden, r, 0, &mut act);
                        }
                        more(ui, others.len());
                    });
            }
            let Some((what, n)) = act else { return };
            let drawn = subtree_instances(g, n);
            let name = g.nodes.get(n).map_or("", |nd| nd.name.as_str());
            match what {
                NodeAction::Frame => frame_node(cx, &drawn, n, name),
                NodeAction::Hide | NodeAction::Show => {
                    for &i in &drawn {
                        cx.settings.hidden.set(i, what == NodeAction::Hide);
                    }
                    let verb = if what == NodeAction::Hide {
                        "hid"
                    } else {
                        "showed"
                    };
                    cx.notice(format!("{verb} node {n}: {name} ({} parts)", drawn.len()));
                }
                NodeAction::Isolate => {
                    cx.settings.hidden = Hidden::all_but(scene.instances.len(), drawn);
                    cx.notice(format!("showing only node {n}: {name}"));
                }
            }
        });
}

/// The instances node `n` and its descendants draw (each node once, at most
/// [`MAX_DEPTH`] deep).
fn subtree_instances(g: &crate::scene::Graph, n: usize) -> Vec<usize> {
    let mut drawn = Vec::new();
    let mut stack = vec![(n, 0)];
    let mut seen = vec![false; g.nodes.len()];
    while let Some((k, depth)) = stack.pop() {
        let Some(nd) = g.nodes.get(k) else { continue };
        if std::mem::replace(&mut seen[k], true) || depth > MAX_DEPTH {
            continue;
        }
        drawn.extend(nd.instances.iter().copied());
        stack.extend(nd.children.iter().map(|&c| (c, depth + 1)));
    }
    drawn.sort_unstable();
    drawn.dedup();
    drawn
}

/// One node of the tree and (when opened) its children, with buttons to frame, hide or
/// show, and isolate what it draws.
fn node(
    ui: &mut egui::Ui,
    g: &crate::scene::Graph,
    hidden: &Hidden,
    n: usize,
    depth: usize,
    act: &mut Option<(NodeAction, usize)>,
) {
    let Some(nd) = g.nodes.get(n) else { return };
    let mut what = Vec::new();
    if !nd.instances.is_empty() {
        what.push(format!("{} primitives", nd.instances.len()));
    }
    if let Some(s) = nd.skin {
        what.push(format!("skin {s}"));
    }
    if !nd.weights.is_empty() {
        what.push(format!("{} morph targets", nd.weights.len()));
    }
    if matches!(nd.local, crate::scene::Local::Matrix(_)) {
        what.push("matrix".into());
    }
    let drawn = subtree_instances(g, n);
    let off = !drawn.is_empty() && drawn.iter().all(|&i| hidden.contains(i));
    if off {
        what.push("hidden".into());
    }
    let label = if what.is_empty() {
        format!("{n}: {}", nd.name)
    } else {
        format!("{n}: {} ({})", nd.name, what.join(", "))
    };
    let buttons = |ui: &mut egui::Ui, act: &mut Option<(NodeAction, usize)>| {
        if drawn.is_empty() {
            return;
        }
        if ui
            .small_button("frame")
            .on_hover_text("frame what this node and its children draw")
            .clicked()
        {
            *act = Some((NodeAction::Frame, n));
        }
        let (text, tip, a) = if off {
            (
                "show",
                "show this node and its children again",
                NodeAction::Show,
            )
        } else {
            ("hide", "hide this node and its children", NodeAction::Hide)
        };
        if ui.small_button(text).on_hover_text(tip).clicked() {
            *act = Some((a, n));
        }
        if ui
            .small_button("isolate")
            .on_hover_text("show only this node and its children")
            .clicked()
        {
            *act = Some((NodeAction::Isolate, n));
        }
    };
    if nd.children.is_empty() || depth >= MAX_DEPTH {
        // The buttons first: a long name is cut at the panel's edge, they are not.
        ui.horizontal(|ui| {
            buttons(ui, act);
            ui.label(label);
        });
        return;
    }
    let id = ui.make_persistent_id(("graph-node", n));
    let mut clicked = false;
    let mut header =
        egui::collapsing_header::CollapsingState::load_with_default_open(ui.ctx(), id, false)
            .show_header(ui, |ui| {
                buttons(ui, act);
                // The name opens and closes the node, as a collapsing header's does.
                let name = ui.add(egui::Label::new(label).sense(egui::Sense::click()));
                clicked = name.clicked();
            });
    if clicked {
        header.toggle();
    }
    header.body(|ui| {
        for &c in nd.children.iter().take(MAX_ROWS) {
            node(ui, g, hidden, c, depth + 1, act);
        }
        more(ui, nd.children.len());
    });
}

/// Frames the camera on `drawn`, the instances of node `n` (called `name`) and its
/// descendants, as posed now.
fn frame_node(cx: &mut Cx<'_>, drawn: &[usize], n: usize, name: &str) {
    match cx
        .session
        .scene
        .instance_bounds(|i| drawn.binary_search(&i).is_ok())
    {
        Some((lo, hi)) => {
            let aspect = cx.viewport.aspect();
            let radius = ((hi - lo).length() * 0.5).max(1e-6);
            cx.nav.frame((lo + hi) * 0.5, radius, aspect);
            cx.notice(format!("framed node {n}: {name}"));
        }
        None => cx.notice(format!("node {n} draws nothing")),
    }
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
