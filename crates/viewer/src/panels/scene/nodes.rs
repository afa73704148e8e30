//! The scene section's node tree: each scene of the file with its roots, and the buttons
//! that frame, hide, show or isolate what a node and its children draw.

use eframe::egui;

use super::{more, MAX_ROWS};
use crate::panels::Cx;
use crate::render::Hidden;

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
pub(super) fn nodes(cx: &mut Cx<'_>, ui: &mut egui::Ui, scene: &crate::scene::Scene) {
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
