//! One instance's constants (matrices, material, style, drawability) and the copies of an
//! instanced mesh with their bounding spheres.

use std::sync::Arc;

use glam::{Mat3, Mat4, Vec3, Vec4};
use rayon::prelude::*;

use crate::scene::Style;

/// One instance's constants.
#[derive(Clone, Debug)]
pub(crate) struct PreparedInstance {
    pub mesh: usize,
    pub world: Mat4,
    /// Cofactor normal matrix (see [`normal_matrix`](super::normal_matrix)).
    pub normal: Mat3,
    /// The world matrix mirrors (det < 0): front faces are clockwise.
    pub mirrored: bool,
    /// Index into [`PreparedScene::materials`](super::PreparedScene::materials).
    pub material: usize,
    pub style: Style,
    /// The node that places it (posed instances follow it).
    pub node: Option<usize>,
    /// The skin ([`Scene::skins`](crate::scene::Scene::skins)) that places the vertices;
    /// posed, the world matrix is then the identity.
    pub skin: Option<usize>,
    /// False if the instance can never draw (no triangles, points or lines, or a
    /// non-finite matrix); also
    /// false for the ground plane, which set-up draws only when the settings ask for it.
    pub drawable: bool,
    /// The ground plane ([`super::Ground`](crate::Ground)), last of the instances; its
    /// world matrix is made per frame by
    /// [`PreparedScene::ground_world`](super::PreparedScene::ground_world).
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
    pub(super) fn new(matrices: &Arc<[Mat4]>, center: Vec3, radius: f32) -> Self {
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
