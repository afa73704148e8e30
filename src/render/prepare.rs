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

use crate::mesh::TriMesh;
use crate::scene::{Material, Scene, Style};

/// A scene with its camera-independent render data.
#[derive(Debug)]
pub struct PreparedScene {
    scene: Arc<Scene>,
    pub(crate) meshes: Vec<PreparedMesh>,
    pub(crate) instances: Vec<PreparedInstance>,
    /// The scene's materials followed by [`Material::default`] (for meshes without one).
    pub(crate) materials: Vec<Material>,
    bounds: Option<(Vec3, Vec3)>,
}

/// Quads per side of the ground plane's grid.
const GROUND_CELLS: u32 = 32;

/// One mesh ready to draw.
#[derive(Debug)]
pub struct PreparedMesh {
    pub tri: TriMesh,
    flat: OnceLock<FlatMesh>,
}

/// Flat shading's form of a mesh: every triangle's corners unindexed (so each corner carries
/// its facet's colour), and per facet the area-weighted centroid and the colour of its first
/// vertex (the textbook's §9.2.2).
#[derive(Debug, Default)]
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
    /// False if the instance can never draw (no triangles or a non-finite matrix); also
    /// false for the ground plane, which set-up draws only when the settings ask for it.
    pub drawable: bool,
    /// The ground plane ([`super::Ground`]), last of the instances; its world matrix is
    /// made per frame by [`PreparedScene::ground_world`].
    pub ground: bool,
}

impl PreparedScene {
    /// Prepares `scene` (in parallel on the current rayon pool).
    #[must_use]
    pub fn new(scene: impl Into<Arc<Scene>>) -> Self {
        let scene: Arc<Scene> = scene.into();
        let meshes: Vec<PreparedMesh> = scene
            .meshes
            .par_iter()
            .map(|m| PreparedMesh {
                tri: m.triangulate(),
                flat: OnceLock::new(),
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
                    drawable: !tri.triangles.is_empty() && inst.world.is_finite(),
                    ground: false,
                })
            })
            .collect::<Vec<_>>();
        let bounds = scene.bounds();
        // The ground plane: a unit grid (cut so per-vertex lighting shows pools of light),
        // with a material of its own after the default one.
        let mut meshes = meshes;
        let mut instances = instances;
        let ground = crate::mesh::Mesh::grid(1.0, 1.0, GROUND_CELLS, GROUND_CELLS)
            .expect("the ground grid's parameters are valid");
        meshes.push(PreparedMesh {
            tri: ground.triangulate(),
            flat: OnceLock::new(),
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
            drawable: false,
            ground: true,
        });
        Self {
            scene,
            meshes,
            instances,
            materials,
            bounds,
        }
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

    /// Total triangles over the instances (the ground plane not included).
    #[must_use]
    pub fn triangle_count(&self) -> u64 {
        self.instances
            .iter()
            .filter(|i| !i.ground)
            .map(|i| self.meshes[i.mesh].tri.triangles.len() as u64)
            .sum()
    }
}

impl PreparedMesh {
    /// The mesh's flat-shading form, built on first use.
    pub fn flat(&self) -> &FlatMesh {
        self.flat.get_or_init(|| FlatMesh::new(&self.tri))
    }
}

impl FlatMesh {
    fn new(tri: &TriMesh) -> Self {
        let nf = tri.facet_normals.len();
        let mut centroids = vec![Vec3::ZERO; nf];
        let mut area = vec![0.0f32; nf];
        for (t, f) in tri.triangles.iter().zip(&tri.triangle_facets) {
            let [a, b, c] = t.map(|k| tri.positions[k as usize]);
            let (f, ar) = (*f as usize, (b - a).cross(c - a).length());
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
            for (t, f) in tri
                .triangles
                .iter()
                .rev()
                .zip(tri.triangle_facets.iter().rev())
            {
                if let Some(slot) = first_colors.get_mut(*f as usize) {
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

/// Transforms normals of a model -> world matrix: the cofactor matrix of its 3x3 part, which
/// equals det * (M^-1)^T and stays defined for singular matrices (a flattened mesh keeps the
/// normal of its plane); the sign of the determinant keeps mirrored normals outward.
pub(crate) fn normal_matrix(world: Mat4) -> Mat3 {
    let m = Mat3::from_mat4(world);
    let cof = Mat3::from_cols(
        m.y_axis.cross(m.z_axis),
        m.z_axis.cross(m.x_axis),
        m.x_axis.cross(m.y_axis),
    );
    if m.determinant() < 0.0 {
        -cof
    } else {
        cof
    }
}
