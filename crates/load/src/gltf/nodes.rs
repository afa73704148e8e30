//! The node tree ([`crate::scene::Graph`]): every node with its parent, children, name and
//! TRS or matrix, the file's scenes and which is drawn (the one
//! [`crate::LoadOptions::scene`] asks for, else the file's default, else the first), and an evaluation order; then, at
//! the rest pose, instances for the drawn nodes with meshes (each knowing its node and
//! skin), cameras for nodes with cameras, and `KHR_lights_punctual` lights for nodes that
//! carry one.
//!
//! The walk uses an explicit stack and visits every node at most once, so a cycle or a
//! node listed under two parents (both invalid glTF) cannot loop or blow up the instance
//! count; such a node is reported and skipped the second time. The drawn scene's roots are
//! walked first, then the other parentless nodes (not drawn, but a skin's joints may be
//! there). Nodes deeper than [`MAX_DEPTH`] and subtrees under a non-finite transform are
//! skipped with a warning. Cameras and lights stay where the rest pose puts them.

use glam::{Mat4, Quat, Vec3};
use gltf::json;

use super::{instancing, Builder, GltfError};
use crate::scene::graph::SceneRoots;
use crate::scene::{Camera, Graph, Instance, Local, Node, Style, Trs, DEFAULT_YFOV};
use crate::LoadError;

/// Deepest node level walked (the root nodes of a scene are at depth 0).
pub const MAX_DEPTH: usize = 1024;

impl Builder<'_> {
    /// Builds the node tree ([`Scene::graph`]) and walks the chosen scene, filling
    /// instances, cameras and lights at the rest pose; then reads skins and animations.
    pub fn walk(&mut self) -> Result<(), LoadError> {
        let roots = self.roots()?;
        let count = self.doc.json.nodes.len();
        let mut graph = Graph {
            nodes: self
                .doc
                .json
                .nodes
                .iter()
                .enumerate()
                .map(|(i, n)| node(i, n))
                .collect(),
            ..Graph::default()
        };
        graph.scenes = self
            .doc
            .json
            .scenes
            .iter()
            .enumerate()
            .map(|(i, sc)| SceneRoots {
                name: sc.name.clone().unwrap_or_else(|| format!("scene {i}")),
                roots: sc
                    .nodes
                    .iter()
                    .map(|n| n.value())
                    .filter(|&n| n < count)
                    .collect(),
            })
            .collect();
        graph.drawn = match (self.chosen_scene, self.doc.json.scene) {
            (Some(s), _) => Some(s),
            (None, Some(s)) => Some(s.value()),
            (None, None) => (!graph.scenes.is_empty()).then_some(0),
        };
        // Parentless nodes outside the drawn scene are walked too (not drawn), so a skin's
        // joints there still get world matrices.
        let mut has_parent = vec![false; count];
        for c in self
            .doc
            .json
            .nodes
            .iter()
            .flat_map(|n| n.children.iter().flatten())
        {
            if let Some(flag) = has_parent.get_mut(c.value()) {
                *flag = true;
            }
        }
        let others: Vec<usize> = (0..count)
            .filter(|&n| !has_parent[n] && !roots.contains(&n))
            .collect();
        let mut visited = vec![false; count];
        let mut drawn = vec![false; count];
        // (node, parent, depth, drawn)
        let mut stack: Vec<(usize, Option<usize>, usize, bool)> = others
            .into_iter()
            .rev()
            .map(|n| (n, None, 0, false))
            .chain(roots.into_iter().rev().map(|n| (n, None, 0, true)))
            .collect();
        while let Some((n, parent, depth, draw)) = stack.pop() {
            let Some(seen) = visited.get_mut(n) else {
                continue;
            };
            if std::mem::replace(seen, true) {
                self.scene.report.warnings.push(format!("node {n} is reached twice (a cycle or a shared child); ignored the second time"));
                continue;
            }
            if depth > MAX_DEPTH {
                self.scene.report.warnings.push(format!(
                    "node {n} is deeper than {MAX_DEPTH} levels; skipped with its children"
                ));
                continue;
            }
            graph.nodes[n].parent = parent;
            graph.order.push(n);
            drawn[n] = draw;
            let children = self.doc.json.nodes[n].children.clone().unwrap_or_default();
            for &c in children.iter().rev() {
                if c.value() >= count {
                    return Err(self.doc.missing(
                        format!("node {n} children"),
                        "node",
                        c.value(),
                        count,
                    ));
                }
                graph.nodes[n].children.push(c.value());
                stack.push((c.value(), Some(n), depth + 1, draw));
            }
            graph.nodes[n].children.reverse();
        }
        // Children a node lists but does not own (reached first elsewhere) are not its.
        for n in 0..count {
            let mut kids = std::mem::take(&mut graph.nodes[n].children);
            kids.retain(|&c| graph.nodes[c].parent == Some(n));
            kids.dedup();
            graph.nodes[n].children = kids;
        }
        let unreached = (0..count).filter(|&n| !visited[n]).count();
        if unreached > 0 {
            self.scene.report.warnings.push(format!(
                "{unreached} node(s) are only reachable through a cycle; they are not drawn"
            ));
        }
        self.morph_weights(&mut graph);
        let rest = graph.rest_pose();
        let mut skipped = vec![false; count];
        for &n in &graph.order {
            let parent_skipped = graph.nodes[n].parent.is_some_and(|p| skipped[p]);
            if !drawn[n] || parent_skipped {
                skipped[n] = parent_skipped;
                continue;
            }
            let world = rest.worlds[n];
            if !world.is_finite() {
                self.scene.report.warnings.push(format!(
                    "node {n} has a non-finite transform; skipped with its children"
                ));
                skipped[n] = true;
                continue;
            }
            let first = self.scene.instances.len();
            let (cameras, lights) = (self.scene.cameras.len(), self.scene.lights.len());
            self.node_contents(n, world)?;
            let node = &mut graph.nodes[n];
            node.instances = (first..self.scene.instances.len()).collect();
            node.cameras = (cameras..self.scene.cameras.len()).collect();
            node.lights = (lights..self.scene.lights.len()).collect();
        }
        self.scene.graph = graph;
        self.fit_camera_far_planes();
        let skins = std::mem::take(&mut self.doc.json.skins);
        self.skins(&skins)?;
        let animations = std::mem::take(&mut self.doc.json.animations);
        self.animations(&animations)?;
        Ok(())
    }

    /// Root nodes of the scene asked for ([`Builder::chosen_scene`], which must exist), else
    /// of the default scene, else scene 0, else every node that is nobody's child.
    fn roots(&mut self) -> Result<Vec<usize>, LoadError> {
        let json = &self.doc.json;
        let count = json.nodes.len();
        if let Some(index) = self.chosen_scene {
            if index >= json.scenes.len() {
                return Err(LoadError::Scene {
                    path: self.doc.path.to_owned(),
                    index,
                    count: json.scenes.len(),
                });
            }
        }
        let chosen = match (self.chosen_scene, json.scene) {
            (Some(k), _) => json.scenes.get(k),
            (None, Some(s)) => Some(json.scenes.get(s.value()).ok_or_else(|| {
                self.doc
                    .missing("the default scene", "scene", s.value(), json.scenes.len())
            })?),
            (None, None) => json.scenes.first(),
        };
        let roots: Vec<usize> = match chosen {
            Some(scene) => scene.nodes.iter().map(|n| n.value()).collect(),
            None => {
                let mut child = vec![false; count];
                for c in json.nodes.iter().flat_map(|n| n.children.iter().flatten()) {
                    if let Some(flag) = child.get_mut(c.value()) {
                        *flag = true;
                    }
                }
                (0..count)
                    .filter(|&i| !child.get(i).copied().unwrap_or(true))
                    .collect()
            }
        };
        if let Some(&bad) = roots.iter().find(|&&n| n >= count) {
            return Err(self.doc.missing("scene nodes", "node", bad, count));
        }
        if json.scenes.len() > 1 {
            let which = self
                .chosen_scene
                .unwrap_or_else(|| json.scene.map_or(0, |s| s.value()));
            self.scene.report.skipped.push(format!(
                "{} scenes in the file; scene {which} is drawn (choose with --scene N)",
                json.scenes.len()
            ));
        }
        Ok(roots)
    }

    /// Instances for node `n`'s mesh primitives and a camera for its camera.
    fn node_contents(&mut self, n: usize, world: Mat4) -> Result<(), LoadError> {
        let Some(node) = self.doc.json.nodes.get(n) else {
            return Ok(());
        };
        let name = node.name.clone().unwrap_or_else(|| format!("node {n}"));
        let (mesh, camera, skin) = (
            node.mesh.map(|m| m.value()),
            node.camera.map(|c| c.value()),
            node.skin.map(|s| s.value()),
        );
        if let Some(m) = mesh {
            let meshes = self.doc.json.meshes.len();
            let primitives = self
                .doc
                .json
                .meshes
                .get(m)
                .ok_or_else(|| self.doc.missing(format!("node {n}"), "mesh", m, meshes))?
                .primitives
                .len();
            let copies = match self.node_copies(n, &name)? {
                instancing::Copies::Once => None,
                instancing::Copies::Many(c) if skin.is_some() => {
                    self.scene.report.warnings.push(format!(
                        "node '{name}': {} with a skin is not supported; drawn once ({} copies ignored)",
                        instancing::EXTENSION,
                        c.len()
                    ));
                    None
                }
                instancing::Copies::Many(c) => Some(c),
            };
            for p in 0..primitives {
                let mesh = match self.primitive_mesh(m, p) {
                    Err(LoadError::Gltf(GltfError::NoData { buffer, .. })) => {
                        self.scene.report.skipped.push(format!(
                            "mesh {m} primitive {p}: buffer {buffer} has no data (no uri, no GLB chunk)"
                        ));
                        None
                    }
                    other => other?,
                };
                if let Some(mesh) = mesh {
                    self.scene.instances.push(Instance {
                        mesh,
                        world,
                        name: name.clone(),
                        style: Style::Inherit,
                        node: Some(n),
                        skin: skin.filter(|_| {
                            self.scene.meshes[mesh]
                                .deform
                                .as_ref()
                                .is_some_and(|d| d.influences > 0)
                        }),
                        copies: copies.clone(),
                    });
                }
            }
        }
        if let Some(c) = camera {
            self.camera(c, world, &name);
        }
        self.node_light(n, world, &name);
        Ok(())
    }

    /// A scene camera for glTF camera `c` placed by `world` (looking down its local -Z,
    /// +Y up; the target is one unit ahead). `zfar` absent (infinite) is marked with
    /// `far = INFINITY` until [`Self::fit_camera_far_planes`].
    fn camera(&mut self, c: usize, world: Mat4, node: &str) {
        let warn = |this: &mut Self, why: String| {
            this.scene
                .report
                .skipped
                .push(format!("camera {c} (node '{node}'): {why}"))
        };
        let Some(cam) = self.doc.json.cameras.get(c) else {
            return warn(self, "does not exist".into());
        };
        let name = cam.name.clone().unwrap_or_else(|| node.to_owned());
        // (vertical fov, half height if orthographic, znear, zfar, aspect)
        let (yfov, ortho, znear, zfar, aspect) = match (&cam.perspective, &cam.orthographic) {
            (Some(p), _) => {
                let ok = p.yfov > 0.0 && p.yfov < std::f32::consts::PI;
                if !(ok && p.znear > 0.0 && p.znear.is_finite()) {
                    let why = format!("invalid yfov {} or znear {}", p.yfov, p.znear);
                    return warn(self, why);
                }
                (p.yfov, None, p.znear, p.zfar, p.aspect_ratio)
            }
            (None, Some(o)) => {
                let (x, y) = (o.xmag, o.ymag);
                let mags = x.is_finite() && y.is_finite() && x != 0.0 && y != 0.0;
                if !(mags && o.znear >= 0.0 && o.znear.is_finite()) {
                    let why = format!("invalid xmag {x}, ymag {y} or znear {}", o.znear);
                    return warn(self, why);
                }
                let aspect = Some(x.abs() / y.abs());
                (DEFAULT_YFOV, Some(y.abs()), o.znear, Some(o.zfar), aspect)
            }
            (None, None) => return warn(self, "neither perspective nor orthographic".into()),
        };
        let eye = world.transform_point3(Vec3::ZERO);
        let forward = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
        let up = world.transform_vector3(Vec3::Y).normalize_or_zero();
        if forward == Vec3::ZERO || up == Vec3::ZERO {
            return warn(self, "degenerate node transform".into());
        }
        let far = match zfar {
            Some(f) if f.is_finite() && f > znear => f,
            Some(f) => {
                self.scene.report.warnings.push(format!(
                    "camera {c} (node '{node}'): zfar {f} is not beyond znear {znear}; far plane fitted to the scene"
                ));
                f32::INFINITY
            }
            None => f32::INFINITY,
        };
        let aspect = aspect.filter(|a| a.is_finite() && *a > 0.0);
        self.scene.cameras.push(Camera {
            name,
            eye,
            target: eye + forward,
            up,
            yfov,
            near: znear,
            far,
            aspect,
            ortho,
            lens: Default::default(),
        });
        self.placed_cameras.push((c, self.scene.cameras.len() - 1));
    }

    /// Gives cameras without a finite far plane one just behind the scene's bounds (or
    /// 10^4 times their near plane when the scene has no bounds).
    fn fit_camera_far_planes(&mut self) {
        let bounds = self.scene.bounds();
        for cam in self.scene.cameras.iter_mut().filter(|c| !c.far.is_finite()) {
            let reach = bounds.map(|(lo, hi)| {
                let centre = (lo + hi) * 0.5;
                (centre - cam.eye).length() + (hi - lo).length() * 0.5
            });
            cam.far = reach
                .filter(|r| r.is_finite())
                .map_or(cam.near * 1e4, |r| r * 1.01)
                .max(cam.near * 2.0);
        }
    }
}

/// Node `i` of the file as a graph node: its name and local transform (`matrix` if given,
/// else T * R * S with the rotation normalised); parents, children and instances are set
/// by the walk.
fn node(i: usize, n: &json::scene::Node) -> Node {
    let local = match n.matrix {
        Some(m) => Local::Matrix(Mat4::from_cols_array(&m)),
        None => Local::Trs(Trs {
            translation: Vec3::from_array(n.translation.unwrap_or([0.0; 3])),
            rotation: Quat::from_array(n.rotation.as_ref().map_or([0.0, 0.0, 0.0, 1.0], |q| q.0))
                .normalize(),
            scale: Vec3::from_array(n.scale.unwrap_or([1.0; 3])),
        }),
    };
    Node {
        name: n.name.clone().unwrap_or_else(|| format!("node {i}")),
        parent: None,
        children: Vec::new(),
        local,
        skin: n.skin.map(|s| s.value()),
        weights: Vec::new(),
        instances: Vec::new(),
        cameras: Vec::new(),
        lights: Vec::new(),
    }
}
