//! The node tree of a file (glTF's nodes; other formats have none) and poses of it.
//!
//! A [`Graph`] keeps every node with its parent, children, name and local transform (TRS,
//! or a matrix, which glTF forbids animating), the file's scenes and which one is drawn, and
//! an evaluation order in which every parent comes before its children. A [`Pose`] holds
//! what animation changes (each node's TRS and morph weights) and the world matrices
//! [`Graph::update_worlds`] computes from them, so instances, skins, the viewer's scene
//! panel and picking all read the same nodes.
//!
//! The order is built once at load, iteratively: the drawn scene's roots first, then every
//! other node without a parent (a skin's joints may live outside the drawn scene). A node
//! reached a second time (a cycle, or a child listed by two parents, both invalid glTF) is
//! not visited again, and nodes only reachable through a cycle are left out of the order;
//! their world matrix stays the identity and the loader names them in its report.

use glam::{Mat4, Quat, Vec3};

/// Translation, rotation (unit quaternion) and scale: `T * R * S`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trs {
    pub translation: Vec3,
    pub rotation: Quat,
    pub scale: Vec3,
}

impl Trs {
    pub const IDENTITY: Self = Self {
        translation: Vec3::ZERO,
        rotation: Quat::IDENTITY,
        scale: Vec3::ONE,
    };

    #[must_use]
    pub fn matrix(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }
}

impl Default for Trs {
    fn default() -> Self {
        Self::IDENTITY
    }
}

/// A node's transform relative to its parent.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Local {
    /// A matrix (glTF `matrix`); animation channels cannot target it.
    Matrix(Mat4),
    Trs(Trs),
}

impl Local {
    #[must_use]
    pub fn matrix(&self) -> Mat4 {
        match self {
            Local::Matrix(m) => *m,
            Local::Trs(t) => t.matrix(),
        }
    }
}

/// One node of the tree.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// The file's name, else "node N".
    pub name: String,
    pub parent: Option<usize>,
    pub children: Vec<usize>,
    /// The rest transform (what the file says, before any animation).
    pub local: Local,
    /// Index into [`crate::Scene::skins`] of the skin of this node's mesh.
    pub skin: Option<usize>,
    /// The rest morph target weights of this node's mesh (the node's `weights`, else the
    /// mesh's; empty without morph targets).
    pub weights: Vec<f32>,
    /// Instances drawn for this node (indices into [`crate::Scene::instances`]).
    pub instances: Vec<usize>,
    /// Cameras this node places (indices into [`crate::Scene::cameras`]).
    pub cameras: Vec<usize>,
    /// Lights this node places (indices into [`crate::Scene::lights`]).
    pub lights: Vec<usize>,
}

/// One scene of the file: a name and its root nodes.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneRoots {
    pub name: String,
    pub roots: Vec<usize>,
}

/// The node tree.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Graph {
    pub nodes: Vec<Node>,
    /// Every scene of the file, in file order.
    pub scenes: Vec<SceneRoots>,
    /// Index into `scenes` of the one drawn (`None` when the file has no scenes and every
    /// parentless node is drawn).
    pub drawn: Option<usize>,
    /// Nodes in evaluation order: every node after its parent.
    pub order: Vec<usize>,
}

/// What changes over time: local transforms and morph weights per node, and the world
/// matrices computed from them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Pose {
    pub locals: Vec<Local>,
    /// Morph target weights per node (the length of the node's rest weights).
    pub weights: Vec<Vec<f32>>,
    /// World matrices, by node (the identity for nodes outside [`Graph::order`]).
    pub worlds: Vec<Mat4>,
    /// Material, light and camera properties the animations set (`KHR_animation_pointer`):
    /// the object (an index into `Scene::materials`, `lights` or `cameras`, as
    /// [`crate::anim::Property::target`] says), the property and its value (the first 1, 3
    /// or 4 numbers). What is not listed keeps its rest value.
    pub values: Vec<(usize, crate::anim::Property, [f32; 4])>,
}

impl Graph {
    /// The rest pose, with its world matrices.
    #[must_use]
    pub fn rest_pose(&self) -> Pose {
        let mut pose = Pose {
            locals: self.nodes.iter().map(|n| n.local).collect(),
            weights: self.nodes.iter().map(|n| n.weights.clone()).collect(),
            worlds: vec![Mat4::IDENTITY; self.nodes.len()],
            values: Vec::new(),
        };
        self.update_worlds(&mut pose);
        pose
    }

    /// Resets `pose` to the rest pose without allocating (when it came from
    /// [`Self::rest_pose`] of this graph) and without computing world matrices.
    pub fn reset(&self, pose: &mut Pose) {
        pose.locals.clear();
        pose.locals.extend(self.nodes.iter().map(|n| n.local));
        pose.weights.resize_with(self.nodes.len(), Vec::new);
        for (w, n) in pose.weights.iter_mut().zip(&self.nodes) {
            w.clear();
            w.extend_from_slice(&n.weights);
        }
        pose.worlds.resize(self.nodes.len(), Mat4::IDENTITY);
        pose.values.clear();
    }

    /// Computes `pose.worlds` from `pose.locals`, parents first.
    pub fn update_worlds(&self, pose: &mut Pose) {
        pose.worlds.resize(self.nodes.len(), Mat4::IDENTITY);
        for &n in &self.order {
            let local = pose.locals.get(n).map_or(Mat4::IDENTITY, Local::matrix);
            let parent = self.nodes[n]
                .parent
                .and_then(|p| pose.worlds.get(p).copied())
                .unwrap_or(Mat4::IDENTITY);
            pose.worlds[n] = parent * local;
        }
    }

    /// The node's path from its root, for reports ("Armature / Hips / Spine").
    #[must_use]
    pub fn path(&self, node: usize) -> String {
        let mut names = Vec::new();
        let mut at = Some(node);
        while let Some(n) = at.filter(|_| names.len() <= self.nodes.len()) {
            let Some(node) = self.nodes.get(n) else { break };
            names.push(node.name.as_str());
            at = node.parent;
        }
        names.reverse();
        names.join(" / ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn node(name: &str, parent: Option<usize>, local: Local) -> Node {
        Node {
            name: name.into(),
            parent,
            children: Vec::new(),
            local,
            skin: None,
            weights: Vec::new(),
            instances: Vec::new(),
            cameras: Vec::new(),
            lights: Vec::new(),
        }
    }

    #[test]
    fn worlds_compose_parent_then_child() {
        let t = |x: f32| {
            Local::Trs(Trs {
                translation: Vec3::new(x, 0.0, 0.0),
                ..Trs::IDENTITY
            })
        };
        let mut g = Graph {
            nodes: vec![
                node("child", Some(1), t(1.0)),
                node(
                    "root",
                    None,
                    Local::Matrix(Mat4::from_scale(Vec3::splat(2.0))),
                ),
            ],
            order: vec![1, 0],
            ..Graph::default()
        };
        g.nodes[1].children.push(0);
        let pose = g.rest_pose();
        let p = pose.worlds[0].transform_point3(Vec3::ZERO);
        assert!((p - Vec3::new(2.0, 0.0, 0.0)).length() < 1e-6, "{p}");
        assert_eq!(g.path(0), "root / child");
        let mut again = pose.clone();
        again.locals[0] = t(5.0);
        g.reset(&mut again);
        g.update_worlds(&mut again);
        assert_eq!(again, pose);
    }
}
