//! Posing a prepared scene: node transforms, skins and morph weights applied to the
//! instances and to the deformed instances' own mesh copies, and the lights and cameras
//! moved with their nodes.

use std::sync::{Arc, OnceLock};

use glam::{Mat4, Vec3};

use super::{normal_matrix, PreparedInstance, PreparedMesh, PreparedScene};
use crate::mesh::{NormalSource, Posing};
use crate::scene::anim::{self, Play};
use crate::scene::{Pose, Scene};

/// An instance whose mesh is posed per frame: `rest` is the shared rest mesh, `out` the
/// instance's own copy that [`crate::mesh::deform`] rewrites.
#[derive(Clone, Debug)]
pub(super) struct Deformer {
    pub(super) instance: usize,
    /// The scene mesh (for its [`crate::mesh::Deform`]), which is also the prepared rest
    /// mesh.
    rest: usize,
    out: usize,
    skin: Option<usize>,
    node: Option<usize>,
    flat: bool,
    /// Joint matrices of the current pose (world x inverse bind), reused.
    joints: Vec<Mat4>,
    /// Model-space bounds of the posed mesh.
    pub(super) bounds: Option<(Vec3, Vec3)>,
}

impl PreparedScene {
    /// Poses the scene at playback time `t` (seconds) of the animations `play` chooses
    /// from [`Scene::animations`], each wrapped into its duration when `looping`. Node
    /// transforms, skins and morph weights all follow; the bounds are updated. Allocates
    /// nothing once the buffers have grown.
    pub fn pose_at(&mut self, play: Play, t: f32, looping: bool) {
        let scene = Arc::clone(&self.scene);
        if scene.graph.nodes.is_empty() {
            return;
        }
        let mut pose = std::mem::take(&mut self.pose);
        anim::pose_at(&scene.graph, &scene.animations, play, t, looping, &mut pose);
        self.apply_pose(&pose);
        self.pose = pose;
    }

    /// Applies `pose` (of this scene's [`Scene::graph`]).
    pub fn apply_pose(&mut self, pose: &Pose) {
        let scene = Arc::clone(&self.scene);
        for inst in self.instances.iter_mut().filter(|i| !i.ground) {
            let Some(node) = inst.node else { continue };
            let world = match (inst.skin.is_some(), pose.worlds.get(node)) {
                (true, _) => Mat4::IDENTITY,
                (false, Some(w)) => *w,
                (false, None) => continue,
            };
            inst.world = world;
            inst.normal = normal_matrix(world);
            inst.mirrored = world.determinant() < 0.0;
            inst.drawable = !self.meshes[inst.mesh].tri.is_empty()
                && world.is_finite()
                && inst.copy_count() > 0;
        }
        for d in &mut self.deformers {
            let Some(deform) = scene.meshes.get(d.rest).and_then(|m| m.deform.as_deref()) else {
                continue;
            };
            d.joints.clear();
            if let Some(skin) = d.skin.and_then(|s| scene.skins.get(s)) {
                d.joints.extend(
                    skin.joints.iter().zip(&skin.inverse_bind).map(|(&j, ibm)| {
                        pose.worlds.get(j).copied().unwrap_or(Mat4::IDENTITY) * *ibm
                    }),
                );
            }
            let weights = d
                .node
                .and_then(|n| pose.weights.get(n))
                .map_or(&[][..], Vec::as_slice);
            let (head, tail) = self.meshes.split_at_mut(d.out);
            let (rest, out) = (&head[d.rest], &mut tail[0]);
            let posing = Posing {
                deform,
                vertex_of: &rest.tri.vertex_of,
                weights,
                joints: d.skin.map(|_| d.joints.as_slice()),
                flat: d.flat,
            };
            d.bounds = crate::mesh::deform(&rest.tri, &mut out.tri, &posing);
            out.flat = OnceLock::new();
            let inst = &mut self.instances[d.instance];
            inst.drawable = !out.tri.is_empty() && inst.world.is_finite();
        }
        self.bounds = self.posed_bounds();
        let outs = self.deformers.iter().map(|d| d.out);
        self.rays.posed(&self.meshes, outs);
        self.pose_lights_and_cameras(pose);
        self.pose_values(pose);
    }
    /// Moves the lights and cameras of nodes to where `pose` puts those nodes (position at
    /// the node's origin, looking down its -Z with +Y up, as at load); a degenerate or
    /// non-finite transform leaves them where they were.
    fn pose_lights_and_cameras(&mut self, pose: &Pose) {
        let scene = Arc::clone(&self.scene);
        for (n, node) in scene.graph.nodes.iter().enumerate() {
            if node.lights.is_empty() && node.cameras.is_empty() {
                continue;
            }
            let Some(world) = pose.worlds.get(n).filter(|w| w.is_finite()) else {
                continue;
            };
            let origin = world.transform_point3(Vec3::ZERO);
            let forward = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
            let up = world.transform_vector3(Vec3::Y).normalize_or_zero();
            if forward == Vec3::ZERO || up == Vec3::ZERO || !origin.is_finite() {
                continue;
            }
            for &l in &node.lights {
                if let Some(light) = self.lights.get_mut(l) {
                    light.position = origin;
                    light.direction = forward;
                    light.up = up;
                }
            }
            for &c in &node.cameras {
                let (Some(cam), Some(rest)) = (self.cameras.get_mut(c), scene.cameras.get(c))
                else {
                    continue;
                };
                let reach = (rest.target - rest.eye).length();
                cam.eye = origin;
                cam.target = origin + forward * if reach > 0.0 { reach } else { 1.0 };
                cam.up = up;
            }
        }
    }
}

/// Gives every instance whose mesh skinning or morphing changes a copy of its mesh to pose
/// (appended to `meshes`), and lists them.
pub(super) fn deformers(
    scene: &Scene,
    meshes: &mut Vec<PreparedMesh>,
    instances: &mut [PreparedInstance],
) -> Vec<Deformer> {
    let mut out = Vec::new();
    for (k, inst) in instances.iter_mut().enumerate() {
        let Some(mesh) = scene.meshes.get(inst.mesh) else {
            continue;
        };
        let Some(deform) = mesh.deform.as_deref() else {
            continue;
        };
        let skin = inst.skin;
        if skin.is_none() && deform.targets.is_empty() {
            continue;
        }
        let rest = inst.mesh;
        meshes.push(PreparedMesh {
            tri: meshes[rest].tri.clone(),
            flat: OnceLock::new(),
            source: Some(rest),
            wire: OnceLock::new(),
        });
        inst.mesh = meshes.len() - 1;
        out.push(Deformer {
            instance: k,
            rest,
            out: inst.mesh,
            skin,
            node: inst.node,
            flat: matches!(mesh.normal_source, NormalSource::Flat),
            joints: Vec::new(),
            bounds: None,
        });
    }
    out
}
