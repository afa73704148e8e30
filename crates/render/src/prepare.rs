//! [`PreparedScene`]: the work on a scene that no camera, size or setting changes, done once
//! (in parallel) before the first frame: triangulation, per-instance constants (normal
//! matrix, mirroring, bounding sphere), each mesh's material resolved, the scene's bounds.
//! Flat shading's unindexed facet corners are built the first time a frame shades a mesh
//! flat (most scenes never do), then kept.
//!
//! A prepared scene owns its [`Scene`] (behind an `Arc`, so a viewer can show the scene's
//! panels while a worker renders it): the two cannot be mismatched.

use std::sync::{Arc, OnceLock};

use glam::{Mat3, Mat4, Vec3, Vec4};
use rayon::prelude::*;

use crate::mesh::{Mesh, NormalSource, Posing, TriMesh};
use crate::scene::anim::{self, Play};
use crate::scene::{Camera, Light, Material, Pose, Scene, Style};

/// A scene with its camera-independent render data.
#[derive(Clone, Debug)]
pub struct PreparedScene {
    scene: Arc<Scene>,
    pub(crate) meshes: Vec<PreparedMesh>,
    pub(crate) instances: Vec<PreparedInstance>,
    /// The scene's materials followed by [`Material::default`] (for meshes without one).
    pub(crate) materials: Vec<Material>,
    bounds: Option<(Vec3, Vec3)>,
    /// Model-space bounds of each scene mesh at rest (for bounds of a posed scene).
    rest_bounds: Vec<Option<(Vec3, Vec3)>>,
    /// Instances whose meshes skinning or morphing changes, each drawing its own copy.
    deformers: Vec<Deformer>,
    /// The pose last applied (reused, so posing allocates nothing).
    pose: Pose,
    /// Materials, lights and cameras the last pose changed (`KHR_animation_pointer`),
    /// restored to their rest values before the next pose is applied.
    animated: Vec<(crate::scene::anim::Target, usize)>,
    /// The scene's lights and cameras as posed now (those under animated nodes move).
    lights: Vec<Light>,
    cameras: Vec<Camera>,
    /// The ray-traced modes' hierarchies, built on first use ([`PreparedScene::rays`]).
    pub(crate) rays: super::rays::Rays,
    /// The radiosity solution, made on first use ([`PreparedScene::radiosity`]).
    pub(crate) radiosity: super::radiosity::Cache,
}

/// An instance whose mesh is posed per frame: `rest` is the shared rest mesh, `out` the
/// instance's own copy that [`crate::mesh::deform`] rewrites.
#[derive(Clone, Debug)]
struct Deformer {
    instance: usize,
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
    bounds: Option<(Vec3, Vec3)>,
}

/// Quads per side of the ground plane's grid.
const GROUND_CELLS: u32 = 32;

/// One mesh ready to draw.
#[derive(Clone, Debug)]
pub struct PreparedMesh {
    pub tri: TriMesh,
    flat: OnceLock<FlatMesh>,
    /// The scene mesh it was made from (`None` for the ground, whose wire is made at once).
    source: Option<usize>,
    /// Wireframe edges as render-vertex pairs, built on first use ([`PreparedScene::wire`]).
    wire: OnceLock<Vec<[u32; 2]>>,
}

/// Flat shading's form of a mesh: every triangle's corners unindexed (so each corner carries
/// its facet's colour), and per facet the area-weighted centroid and the colour of its first
/// vertex (the textbook's §9.2.2).
#[derive(Clone, Debug, Default)]
pub struct FlatMesh {
    pub corners: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
    /// Model-space centroid of each facet (zero for a facet of zero area).
    pub centroids: Vec<Vec3>,
    pub first_colors: Vec<Vec4>,
}

/// One instance's constants.
#[derive(Clone, Debug)]
pub(crate) struct PreparedInstance {
    pub mesh: usize,
    pub world: Mat4,
    /// Cofactor normal matrix (see [`normal_matrix`]).
    pub normal: Mat3,
    /// The world matrix mirrors (det < 0): front faces are clockwise.
    pub mirrored: bool,
    /// Index into [`PreparedScene::materials`].
    pub material: usize,
    pub style: Style,
    /// The node that places it (posed instances follow it).
    pub node: Option<usize>,
    /// The skin ([`Scene::skins`]) that places the vertices; posed, the world matrix is
    /// then the identity.
    pub skin: Option<usize>,
    /// False if the instance can never draw (no triangles, points or lines, or a
    /// non-finite matrix); also
    /// false for the ground plane, which set-up draws only when the settings ask for it.
    pub drawable: bool,
    /// The ground plane ([`super::Ground`]), last of the instances; its world matrix is
    /// made per frame by [`PreparedScene::ground_world`].
    pub ground: bool,
    /// `EXT_mesh_gpu_instancing` ([`crate::scene::Instance::copies`]): copy `i` is placed
    /// by `world * copies.matrices[i]`.
    pub copies: Option<Copies>,
}

/// The copies of an instanced mesh and their bounding spheres, in the instance's frame
/// (before its world matrix).
#[derive(Clone, Debug)]
pub(crate) struct Copies {
    pub matrices: Arc<[Mat4]>,
    /// Per copy, the mesh's bounding sphere placed by its matrix (centre, radius scaled by
    /// the matrix's largest axis scale).
    pub spheres: Arc<[Vec4]>,
    /// A sphere around all of them (centre, radius; radius < 0 when there are none).
    pub all: (Vec3, f32),
}

impl Copies {
    fn new(matrices: &Arc<[Mat4]>, center: Vec3, radius: f32) -> Self {
        let spheres: Vec<Vec4> = matrices
            .par_iter()
            .with_min_len(4096)
            .map(|&m| {
                let (c, r) = crate::frame::world_sphere(m, center, radius);
                c.extend(r)
            })
            .collect();
        let (lo, hi) = spheres.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), s| (lo.min(s.truncate()), hi.max(s.truncate())),
        );
        let mid = (lo + hi) * 0.5;
        let all = if spheres.is_empty() || radius < 0.0 {
            (Vec3::ZERO, -1.0)
        } else {
            let r = spheres
                .iter()
                .map(|s| (s.truncate() - mid).length() + s.w)
                .fold(0.0f32, f32::max);
            (mid, r)
        };
        Self {
            matrices: Arc::clone(matrices),
            spheres: spheres.into(),
            all,
        }
    }
}

impl PreparedInstance {
    /// How many times the instance is drawn.
    pub fn copy_count(&self) -> usize {
        self.copies.as_ref().map_or(1, |c| c.matrices.len())
    }

    /// The model -> world matrix of copy `i` (the instance's own without copies).
    pub fn placement(&self, i: usize) -> Mat4 {
        match &self.copies {
            Some(c) => self.world * c.matrices[i],
            None => self.world,
        }
    }
}

impl PreparedScene {
    /// Prepares `scene` (in parallel on the current rayon pool).
    #[must_use]
    pub fn new(scene: impl Into<Arc<Scene>>) -> Self {
        let scene: Arc<Scene> = scene.into();
        let meshes: Vec<PreparedMesh> = scene
            .meshes
            .par_iter()
            .enumerate()
            .map(|(k, m)| PreparedMesh {
                tri: m.triangulate(),
                flat: OnceLock::new(),
                source: Some(k),
                wire: OnceLock::new(),
            })
            .collect();
        let mut materials = scene.materials.clone();
        materials.push(Material::default());
        let default_material = materials.len() - 1;
        let instances = scene
            .instances
            .iter()
            .filter_map(|inst| {
                let mesh = scene.meshes.get(inst.mesh)?;
                let tri = &meshes[inst.mesh].tri;
                let material = mesh
                    .material
                    .filter(|&m| m < default_material)
                    .unwrap_or(default_material);
                Some(PreparedInstance {
                    mesh: inst.mesh,
                    world: inst.world,
                    normal: normal_matrix(inst.world),
                    mirrored: inst.world.determinant() < 0.0,
                    material,
                    style: inst.style,
                    node: inst.node,
                    skin: inst.skin,
                    drawable: !tri.is_empty()
                        && inst.world.is_finite()
                        && inst.copies.as_ref().is_none_or(|c| !c.is_empty()),
                    ground: false,
                    copies: inst
                        .copies
                        .as_ref()
                        .map(|c| Copies::new(c, tri.center, tri.radius)),
                })
            })
            .collect::<Vec<_>>();
        let bounds = scene.bounds();
        let mut meshes = meshes;
        let mut instances = instances;
        let deformers = deformers(&scene, &mut meshes, &mut instances);
        let rest_bounds = if scene.graph.nodes.is_empty() {
            Vec::new()
        } else {
            scene.meshes.par_iter().map(|m| m.bounds()).collect()
        };
        // The ground plane: a unit grid (cut so per-vertex lighting shows pools of light),
        // with a material of its own after the default one.
        let ground = crate::mesh::Mesh::grid(1.0, 1.0, GROUND_CELLS, GROUND_CELLS)
            .expect("the ground grid's parameters are valid");
        meshes.push(PreparedMesh {
            tri: ground.triangulate(),
            flat: OnceLock::new(),
            source: None,
            wire: OnceLock::from(wire_edges(&ground)),
        });
        materials.push(Material {
            name: "ground".into(),
            specular: Vec3::splat(0.03),
            shininess: 8.0,
            ..Material::default()
        });
        instances.push(PreparedInstance {
            mesh: meshes.len() - 1,
            world: Mat4::IDENTITY,
            normal: Mat3::IDENTITY,
            mirrored: false,
            material: materials.len() - 1,
            style: Style::Inherit,
            node: None,
            skin: None,
            drawable: false,
            ground: true,
            copies: None,
        });
        let (lights, cameras) = (scene.lights.clone(), scene.cameras.clone());
        let mut prepared = Self {
            scene,
            meshes,
            instances,
            materials,
            bounds,
            rest_bounds,
            deformers,
            pose: Pose::default(),
            animated: Vec::new(),
            lights,
            cameras,
            rays: super::rays::Rays::default(),
            radiosity: super::radiosity::Cache::default(),
        };
        if !prepared.deformers.is_empty() {
            // Skinned meshes are drawn by their joints even at rest.
            prepared.pose_at(Play::Rest, 0.0, false);
        }
        prepared
    }

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

    /// Sets the material, light and camera properties `pose` animates (clamped to their
    /// ranges; a non-finite value leaves the rest value), after returning those the last
    /// pose changed to rest. Field by field, so posing allocates nothing.
    fn pose_values(&mut self, pose: &Pose) {
        use crate::scene::anim::{Property as P, Target};
        let rest = Arc::clone(&self.scene);
        for (kind, k) in self.animated.drain(..) {
            match kind {
                Target::Material => {
                    if let (Some(m), Some(r)) = (self.materials.get_mut(k), rest.materials.get(k)) {
                        m.base_color = r.base_color;
                        m.emissive = r.emissive;
                        m.metallic = r.metallic;
                        m.roughness = r.roughness;
                        if let (Some(p), Some(q)) = (&mut m.pbr, &r.pbr) {
                            p.emissive_strength = q.emissive_strength;
                            p.clearcoat = q.clearcoat;
                            p.clearcoat_roughness = q.clearcoat_roughness;
                            p.sheen_color = q.sheen_color;
                            p.sheen_roughness = q.sheen_roughness;
                        }
                        for slot in crate::scene::Slot::ALL {
                            if let (Some(t), Some(q)) = (m.slot_mut(slot).as_mut(), r.slot(slot)) {
                                t.transform = q.transform;
                            }
                        }
                    }
                }
                Target::Light => {
                    if let (Some(l), Some(r)) = (self.lights.get_mut(k), rest.lights.get(k)) {
                        l.color = r.color;
                        l.intensity = r.intensity;
                        l.inner = r.inner;
                        l.outer = r.outer;
                    }
                }
                Target::Camera => {
                    if let (Some(c), Some(r)) = (self.cameras.get_mut(k), rest.cameras.get(k)) {
                        c.yfov = r.yfov;
                    }
                }
                Target::Node => {}
            }
        }
        let finite = |x: f32| x.is_finite().then_some(x);
        let rgb = |v: [f32; 4]| Some(Vec3::new(v[0], v[1], v[2])).filter(|c| c.is_finite());
        let half_pi = std::f32::consts::FRAC_PI_2;
        for &(k, property, v) in &pose.values {
            let kind = property.target();
            match kind {
                // Only the scene's own materials (not the default or the ground after them).
                Target::Material if k < rest.materials.len() => {
                    let Some(m) = self.materials.get_mut(k) else {
                        continue;
                    };
                    match property {
                        P::BaseColor => {
                            if v.iter().all(|x| x.is_finite()) {
                                m.base_color = Vec4::from_array(v).clamp(Vec4::ZERO, Vec4::ONE);
                            }
                        }
                        P::Emissive => {
                            if let Some(e) = rgb(v) {
                                m.emissive = e.max(Vec3::ZERO);
                            }
                        }
                        P::Metallic => {
                            m.metallic = finite(v[0]).map_or(m.metallic, |x| x.clamp(0.0, 1.0));
                        }
                        P::Roughness => {
                            m.roughness = finite(v[0]).map_or(m.roughness, |x| x.clamp(0.0, 1.0));
                        }
                        P::EmissiveStrength => {
                            if let (Some(p), Some(x)) = (&mut m.pbr, finite(v[0])) {
                                p.emissive_strength = x.max(0.0);
                            }
                        }
                        P::ClearcoatFactor
                        | P::ClearcoatRoughness
                        | P::SheenColor
                        | P::SheenRoughness => {
                            let Some(p) = &mut m.pbr else { continue };
                            let unit = |x: f32| finite(x).map(|x| x.clamp(0.0, 1.0));
                            match property {
                                P::ClearcoatFactor => {
                                    p.clearcoat = unit(v[0]).unwrap_or(p.clearcoat);
                                }
                                P::ClearcoatRoughness => {
                                    p.clearcoat_roughness =
                                        unit(v[0]).unwrap_or(p.clearcoat_roughness);
                                }
                                P::SheenRoughness => {
                                    p.sheen_roughness = unit(v[0]).unwrap_or(p.sheen_roughness);
                                }
                                _ => {
                                    if let Some(c) = rgb(v) {
                                        p.sheen_color = c.clamp(Vec3::ZERO, Vec3::ONE);
                                    }
                                }
                            }
                        }
                        P::IridescenceFactor
                        | P::IridescenceIor
                        | P::IridescenceThicknessMin
                        | P::IridescenceThicknessMax => {
                            let (Some(p), Some(x)) = (&mut m.pbr, finite(v[0])) else {
                                continue;
                            };
                            match property {
                                P::IridescenceFactor => p.iridescence = x.clamp(0.0, 1.0),
                                P::IridescenceIor => p.iridescence_ior = x.max(1.0),
                                P::IridescenceThicknessMin => {
                                    p.iridescence_thickness[0] = x.max(0.0);
                                }
                                _ => p.iridescence_thickness[1] = x.max(0.0),
                            }
                        }
                        P::TransmissionFactor
                        | P::ThicknessFactor
                        | P::AttenuationDistance
                        | P::Dispersion => {
                            let (Some(p), Some(x)) = (&mut m.pbr, finite(v[0])) else {
                                continue;
                            };
                            match property {
                                P::TransmissionFactor => p.transmission = x.clamp(0.0, 1.0),
                                P::ThicknessFactor => p.thickness = x.max(0.0),
                                P::AttenuationDistance if x > 0.0 => p.attenuation_distance = x,
                                P::Dispersion => p.dispersion = x.max(0.0),
                                _ => {}
                            }
                        }
                        P::AttenuationColor => {
                            if let (Some(p), Some(c)) = (&mut m.pbr, rgb(v)) {
                                p.attenuation_color = c.clamp(Vec3::ZERO, Vec3::ONE);
                            }
                        }
                        P::DiffuseTransmission => {
                            if let (Some(p), Some(x)) = (&mut m.pbr, finite(v[0])) {
                                p.diffuse_transmission = x.clamp(0.0, 1.0);
                            }
                        }
                        P::DiffuseTransmissionColor => {
                            if let (Some(p), Some(c)) = (&mut m.pbr, rgb(v)) {
                                p.diffuse_transmission_color = c.clamp(Vec3::ZERO, Vec3::ONE);
                            }
                        }
                        P::AnisotropyStrength | P::AnisotropyRotation => {
                            let (Some(p), Some(x)) = (&mut m.pbr, finite(v[0])) else {
                                continue;
                            };
                            if property == P::AnisotropyStrength {
                                p.anisotropy = x.clamp(0.0, 1.0);
                            } else {
                                p.anisotropy_rotation = x;
                            }
                        }
                        P::TexOffset(slot) | P::TexRotation(slot) | P::TexScale(slot) => {
                            let Some(t) = m.slot_mut(slot).as_mut() else {
                                continue;
                            };
                            let pair = glam::Vec2::new(v[0], v[1]);
                            match property {
                                P::TexOffset(_) if pair.is_finite() => t.transform.offset = pair,
                                P::TexScale(_) if pair.is_finite() => t.transform.scale = pair,
                                P::TexRotation(_) if v[0].is_finite() => {
                                    t.transform.rotation = v[0];
                                }
                                _ => {}
                            }
                        }
                        _ => continue,
                    }
                }
                Target::Light => {
                    let Some(l) = self.lights.get_mut(k) else {
                        continue;
                    };
                    match property {
                        P::LightColor => {
                            if let Some(c) = rgb(v) {
                                l.color = c.max(Vec3::ZERO);
                            }
                        }
                        P::LightIntensity => {
                            l.intensity = finite(v[0]).map_or(l.intensity, |x| x.max(0.0));
                        }
                        // The cone: outer in (0, π/2], inner in [0, outer].
                        P::SpotOuter => {
                            if let Some(x) = finite(v[0]).filter(|x| *x > 0.0) {
                                l.outer = x.min(half_pi);
                                l.inner = l.inner.min(l.outer);
                            }
                        }
                        P::SpotInner => {
                            if let Some(x) = finite(v[0]) {
                                l.inner = x.clamp(0.0, l.outer);
                            }
                        }
                        _ => continue,
                    }
                }
                Target::Camera => {
                    let Some(c) = self.cameras.get_mut(k) else {
                        continue;
                    };
                    if let (P::CameraYfov, Some(x)) = (property, finite(v[0])) {
                        c.yfov = x.clamp(1e-3, std::f32::consts::PI - 1e-3);
                    } else {
                        continue;
                    }
                }
                Target::Material | Target::Node => continue,
            }
            self.animated.push((kind, k));
        }
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

    /// The scene's lights as posed now ([`Scene::lights`] moved with their nodes).
    #[must_use]
    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    /// The scene's cameras as posed now ([`Scene::cameras`] moved with their nodes).
    #[must_use]
    pub fn cameras(&self) -> &[Camera] {
        &self.cameras
    }

    /// The world-space positions of every instance's mesh vertices (in the order of
    /// [`crate::mesh::Mesh::positions`]) as posed now, the ground plane left out: one list
    /// per instance, in scene order (an instanced mesh's copies one after another).
    #[must_use]
    pub fn world_positions(&self) -> Vec<Vec<Vec3>> {
        self.instances
            .iter()
            .filter(|i| !i.ground)
            .map(|i| {
                let tri = &self.meshes[i.mesh].tri;
                let count = if tri.vertex_of.is_empty() {
                    tri.positions.len()
                } else {
                    tri.vertex_of.iter().max().map_or(0, |&v| v as usize + 1)
                };
                let mut out = vec![Vec3::ZERO; count * i.copy_count()];
                for (c, part) in out.chunks_exact_mut(count.max(1)).enumerate() {
                    let placed = i.placement(c);
                    let world = |p: Vec3| placed.transform_point3(p);
                    if tri.vertex_of.is_empty() {
                        for (o, &p) in part.iter_mut().zip(&tri.positions) {
                            *o = world(p);
                        }
                    } else {
                        for (&v, &p) in tri.vertex_of.iter().zip(&tri.positions) {
                            part[v as usize] = world(p);
                        }
                    }
                }
                out
            })
            .collect()
    }

    /// World bounds of the instances as posed now.
    fn posed_bounds(&self) -> Option<(Vec3, Vec3)> {
        self.instance_bounds(|_| true)
    }

    /// World-space bounds of the instances (indices into [`Scene::instances`]) that `which`
    /// accepts, as posed now (the ground plane left out).
    #[must_use]
    pub fn instance_bounds(&self, which: impl Fn(usize) -> bool) -> Option<(Vec3, Vec3)> {
        let placed = self
            .instances
            .iter()
            .enumerate()
            .filter(|(k, i)| !i.ground && which(*k));
        crate::scene::world_bounds(
            placed
                .filter_map(|(k, inst)| {
                    let b = match self.deformers.iter().find(|d| d.instance == k) {
                        Some(d) => d.bounds,
                        None => self.rest_bounds.get(inst.mesh).copied().flatten(),
                    };
                    let b = b?;
                    Some((0..inst.copy_count()).map(move |c| (inst.placement(c), b)))
                })
                .flatten(),
        )
    }

    /// Material `k` of the scene as posed now (`KHR_animation_pointer` changes factors; the
    /// rest values are in [`Scene::materials`]).
    #[must_use]
    pub fn material(&self, k: usize) -> Option<&Material> {
        self.materials
            .get(k)
            .filter(|_| k < self.scene.materials.len())
    }

    /// The scene mesh `inst` draws (for a skinned or morphed instance, the rest mesh its
    /// posed copy was made from; `None` for the ground).
    pub(crate) fn scene_mesh(
        &self,
        inst: &PreparedInstance,
    ) -> Option<(usize, &crate::mesh::Mesh)> {
        let source = self.meshes.get(inst.mesh)?.source?;
        Some((source, self.scene.meshes.get(source)?))
    }

    /// The index into `materials` of `inst`'s material under material variant `variant`
    /// ([`crate::mesh::Mesh::material_in`]; the instance's own for `None`, a mesh without
    /// a mapping for it, or a mapping to a material that does not exist).
    pub(crate) fn material_of(&self, inst: &PreparedInstance, variant: Option<usize>) -> usize {
        variant
            .and_then(|v| {
                let k = self.scene_mesh(inst)?.1.variant_material(v)?;
                (k < self.scene.materials.len()).then_some(k)
            })
            .unwrap_or(inst.material)
    }

    /// The scene this was prepared from.
    #[must_use]
    pub fn scene(&self) -> &Arc<Scene> {
        &self.scene
    }

    /// The triangulated meshes, in the order of [`Scene::meshes`].
    #[must_use]
    pub fn meshes(&self) -> &[PreparedMesh] {
        &self.meshes
    }

    /// World-space bounds of the scene (see [`Scene::bounds`]).
    #[must_use]
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        self.bounds
    }

    /// The bounding sphere (centre, radius) of [`PreparedScene::bounds`]: the unit sphere
    /// for an empty scene, radius at least 1e-6.
    #[must_use]
    pub fn bounding_sphere(&self) -> (Vec3, f32) {
        match self.bounds {
            Some((lo, hi)) => ((lo + hi) * 0.5, ((hi - lo) * 0.5).length().max(1e-6)),
            None => (Vec3::ZERO, 1.0),
        }
    }

    /// Where the ground plane goes: just under the scene's bounds (y up), centred under
    /// them, `extent` times the bounding radius in each direction.
    #[must_use]
    pub fn ground_world(&self, ground: &super::Ground) -> Mat4 {
        let (c, r) = self.bounding_sphere();
        let floor = self.bounds.map_or(c.y - r, |(lo, _)| lo.y);
        let extent = if ground.extent.is_finite() {
            ground.extent.clamp(0.01, 1e4)
        } else {
            4.0
        };
        let half = r * extent;
        Mat4::from_translation(Vec3::new(c.x, floor - r * 1e-4, c.z))
            * Mat4::from_scale(Vec3::new(half, 1.0, half))
    }

    /// A copy with about `target` triangles in all, its large meshes clustered
    /// ([`crate::mesh::cluster_triangles`]; every vertex and attribute kept), to draw while
    /// the camera moves over a scene too large to redraw in time. `None` when the scene has
    /// no more than `target` triangles, or changes with a pose (skins, morph targets or
    /// animations).
    #[must_use]
    pub fn simplified(&self, target: u64) -> Option<PreparedScene> {
        let total = self.triangle_count();
        if total <= target || !self.deformers.is_empty() || !self.scene.animations.is_empty() {
            return None;
        }
        let share = target as f64 / total as f64;
        let mut out = self.clone();
        let mut changed = false;
        for m in &mut out.meshes {
            let n = m.tri.triangles.len();
            let want = ((n as f64 * share) as usize).max(64);
            if let Some((tris, from)) =
                crate::mesh::cluster_triangles(&m.tri.positions, &m.tri.triangles, want)
            {
                if !m.tri.triangle_facets.is_empty() {
                    m.tri.triangle_facets = from
                        .iter()
                        .map(|&t| m.tri.triangle_facets[t as usize])
                        .collect();
                }
                m.tri.triangles = tris;
                m.flat = OnceLock::new();
                changed = true;
            }
        }
        changed.then_some(out)
    }

    /// Total triangles over the instances (the ground plane not included).
    #[must_use]
    pub fn triangle_count(&self) -> u64 {
        self.instances
            .iter()
            .filter(|i| !i.ground)
            .map(|i| self.meshes[i.mesh].tri.triangles.len() as u64 * i.copy_count() as u64)
            .sum()
    }
}

impl PreparedScene {
    /// The wireframe edges of prepared mesh `k` as render-vertex pairs, built from its
    /// scene mesh's edge table on first use (most frames never draw a wireframe).
    pub(crate) fn wire(&self, k: usize) -> &[[u32; 2]] {
        let m = &self.meshes[k];
        m.wire
            .get_or_init(|| match m.source.and_then(|s| self.scene.meshes.get(s)) {
                Some(mesh) => wire_edges(mesh),
                None => Vec::new(),
            })
    }
}

/// Gives every instance whose mesh skinning or morphing changes a copy of its mesh to pose
/// (appended to `meshes`), and lists them.
fn deformers(
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

/// The edges of `mesh` ([`Mesh::edges`], smaller vertex first) as render-vertex pairs:
/// render vertex `v` is mesh vertex `v` for every mesh vertex (see [`TriMesh`]), so the
/// pair is the same, and a vertex split at a seam has the same position in every copy.
fn wire_edges(mesh: &Mesh) -> Vec<[u32; 2]> {
    mesh.edges().iter().map(|e| e.vertices).collect()
}

impl PreparedMesh {
    /// The mesh's flat-shading form, built on first use.
    pub fn flat(&self) -> &FlatMesh {
        self.flat.get_or_init(|| FlatMesh::new(&self.tri))
    }
}

impl FlatMesh {
    fn new(tri: &TriMesh) -> Self {
        let nf = tri.facet_count();
        let mut centroids = vec![Vec3::ZERO; nf];
        let mut area = vec![0.0f32; nf];
        for (k, t) in tri.triangles.iter().enumerate() {
            let [a, b, c] = t.map(|k| tri.positions[k as usize]);
            let (f, ar) = (tri.facet_of(k), (b - a).cross(c - a).length());
            if f < nf && ar.is_finite() {
                centroids[f] += (a + b + c) * (ar / 3.0);
                area[f] += ar;
            }
        }
        for (c, a) in centroids.iter_mut().zip(&area) {
            *c = if *a > 0.0 { *c / *a } else { Vec3::ZERO };
        }
        // The textbook's §9.2.2: the facet takes the colour of its first vertex.
        let mut first_colors = vec![Vec4::ONE; nf];
        if let Some(c) = &tri.colors {
            for (k, t) in tri.triangles.iter().enumerate().rev() {
                if let Some(slot) = first_colors.get_mut(tri.facet_of(k)) {
                    *slot = c[t[0] as usize];
                }
            }
        }
        let corners = tri
            .triangles
            .iter()
            .flat_map(|t| t.map(|k| tri.positions[k as usize]))
            .collect();
        let triangles = (0..tri.triangles.len() as u32)
            .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
            .collect();
        Self {
            corners,
            triangles,
            centroids,
            first_colors,
        }
    }
}

/// Transforms normals of a model -> world matrix: the normal matrix of its 3x3 part
/// ([`crate::mesh::cofactor`]).
pub(crate) fn normal_matrix(world: Mat4) -> Mat3 {
    crate::mesh::cofactor(Mat3::from_mat4(world))
}
