//! Flat shading's form of a mesh: unindexed facet corners, facet centroids and first
//! colours, built the first time a frame shades the mesh flat.

use glam::{Vec3, Vec4};

use super::PreparedMesh;
use crate::mesh::TriMesh;

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
