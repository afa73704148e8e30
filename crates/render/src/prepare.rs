//! [`PreparedScene`]: the work on a scene that no camera, size or setting changes, done once
//! (in parallel) before the first frame: triangulation, per-instance constants (normal
//! matrix, mirroring, bounding sphere), each mesh's material resolved, the scene's bounds.
//! Flat shading's unindexed facet corners are built the first time a frame shades a mesh
//! flat (most scenes never do), then kept.
//!
//! A prepared scene owns its [`Scene`] (behind an `Arc`, so a viewer can show the scene's
//! panels while a worker renders it): the two cannot be mismatched.

use std::sync::{Arc, OnceLock};

use glam::{Mat3, Mat4, Vec3};
use rayon::prelude::*;

use crate::mesh::{Mesh, TriMesh};
use crate::scene::anim::Play;
use crate::scene::{Camera, Light, Material, Pose, Scene, Style};

mod animated;
mod flat;
mod instances;
mod pose;

pub use flat::FlatMesh;
pub(crate) use instances::PreparedInstance;

use instances::Copies;
use pose::{deformers, Deformer};

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

/// The edges of `mesh` ([`Mesh::edges`], smaller vertex first) as render-vertex pairs:
/// render vertex `v` is mesh vertex `v` for every mesh vertex (see [`TriMesh`]), so the
/// pair is the same, and a vertex split at a seam has the same position in every copy.
fn wire_edges(mesh: &Mesh) -> Vec<[u32; 2]> {
    mesh.edges().iter().map(|e| e.vertices).collect()
}

/// Transforms normals of a model -> world matrix: the normal matrix of its 3x3 part
/// ([`crate::mesh::cofactor`]).
pub(crate) fn normal_matrix(world: Mat4) -> Mat3 {
    crate::mesh::cofactor(Mat3::from_mat4(world))
}
