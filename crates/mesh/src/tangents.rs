//! Tangents for normal maps: MikkTSpace, the tangent space that normal maps are baked in by
//! Blender, Substance and xNormal and that glTF prescribes when a file gives none
//! (`bevy_mikktspace`, a line-by-line port of Morten Mikkelsen's reference code).
//!
//! Facets of 3 and 4 corners go to MikkTSpace as they are; a larger facet (rare where normal
//! maps are used) gets one tangent from its UV gradient, made orthogonal to each corner's
//! normal. The result is a per-corner [`Channel`] whose equal values are shared, so the
//! render vertices split only where the tangent frame really changes (UV seams, mirrored
//! UVs), as MikkTSpace requires: never averaged into the existing vertices.
//!
//! **Sign.** MikkTSpace's bitangent `sign · (N × T)` runs along +v of the UVs it is given;
//! glTF's must run along -v (v grows downwards in the image), so the handedness is negated,
//! as glTF-Transform and three.js do with raw glTF UVs.

use bevy_mikktspace::{generate_tangents, Geometry, Ops, TangentSpace};
use glam::{Vec2, Vec3, Vec4};

use super::{Channel, Mesh};

/// Why tangents could not be generated.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum TangentError {
    #[error("the mesh has no texture coordinate set {0}")]
    NoUvSet(u32),
}

/// The mesh as MikkTSpace reads it, and the per-corner results.
struct Faces<'a> {
    mesh: &'a Mesh,
    uv: &'a Channel<Vec2>,
    out: Vec<Option<Vec4>>,
}

impl Faces<'_> {
    fn corner(&self, face: usize, vert: usize) -> (usize, u32) {
        let c = self.mesh.facets()[face].first as usize + vert;
        (c, self.mesh.corners[c])
    }
}

/// MikkTSpace's math with the `libm` crate's acos (its default, `StdOps`, calls the
/// platform's libm, whose bits differ between machines): the same computation as
/// `StdOps` (acos in f64, rounded to f32), the same bits everywhere.
struct LibmOps;

impl Ops for LibmOps {
    fn sqrt(x: f32) -> f32 {
        x.sqrt()
    }

    fn acos(x: f32) -> f32 {
        libm::acos(f64::from(x)) as f32
    }
}

impl Geometry<LibmOps> for Faces<'_> {
    fn num_faces(&self) -> usize {
        self.mesh.facets().len()
    }

    fn num_vertices_of_face(&self, face: usize) -> usize {
        self.mesh.facets()[face].len as usize
    }

    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        let (_, v) = self.corner(face, vert);
        self.mesh.positions[v as usize].to_array()
    }

    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        let (c, v) = self.corner(face, vert);
        self.mesh.normals.at(c, v).to_array()
    }

    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        let (c, v) = self.corner(face, vert);
        self.uv.at(c, v).to_array()
    }

    fn set_tangent(&mut self, t: Option<TangentSpace>, face: usize, vert: usize) {
        let (c, _) = self.corner(face, vert);
        self.out[c] = t.map(|t| {
            let [x, y, z, w] = t.tangent_encoded();
            Vec4::new(x, y, z, -w)
        });
    }
}

/// Some unit vector perpendicular to unit `n` (for corners no tangent can be found for).
fn any_perpendicular(n: Vec3) -> Vec3 {
    let axis = if n.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
    (axis - n * n.dot(axis)).normalize_or(Vec3::X)
}

/// The tangent of a facet from the UV gradient of its first three corners (positions `p`,
/// UVs `t`), with glTF's handedness: `None` if the UVs are degenerate.
fn gradient_tangent(p: [Vec3; 3], t: [Vec2; 3], n: Vec3) -> Option<Vec4> {
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    let (d1, d2) = (t[1] - t[0], t[2] - t[0]);
    let det = d1.x * d2.y - d2.x * d1.y;
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let tangent = ((e1 * d2.y - e2 * d1.y) / det).normalize_or_zero();
    let along_v = (e2 * d1.x - e1 * d2.x) / det;
    if tangent == Vec3::ZERO || !along_v.is_finite() {
        return None;
    }
    // glTF's bitangent w (N × T) runs along -v.
    let w = if n.cross(tangent).dot(along_v) < 0.0 {
        1.0
    } else {
        -1.0
    };
    Some(tangent.extend(w))
}

impl Mesh {
    /// Generates MikkTSpace tangents from UV set `set` into [`Mesh::tangents`] (see the
    /// module docs), replacing any the mesh had. Every tangent is finite, unit in `xyz` and
    /// orthogonal to its corner's normal, with `w = ±1`.
    ///
    /// # Errors
    ///
    /// [`TangentError::NoUvSet`] if the mesh has no UV set `set`.
    pub fn generate_tangents(&mut self, set: u32) -> Result<(), TangentError> {
        let uv = self
            .uvs
            .get(set as usize)
            .ok_or(TangentError::NoUvSet(set))?;
        let mut faces = Faces {
            mesh: self,
            uv,
            out: vec![None; self.corners.len()],
        };
        // Errors only for meshes above MikkTSpace's index range: every corner then takes
        // the fallback below.
        let _ = generate_tangents(&mut faces);
        let mut per_corner = faces.out;
        for f in self.facets() {
            let range = f.corners();
            let missing = per_corner[range.clone()].iter().any(Option::is_none);
            if !missing {
                continue;
            }
            let c0 = range.start;
            let p = [0, 1, 2].map(|k| self.positions[self.corners[c0 + k] as usize]);
            let t = [0, 1, 2].map(|k| uv.at(c0 + k, self.corners[c0 + k]));
            let facet = gradient_tangent(p, t, f.normal);
            for c in range {
                if per_corner[c].is_some() {
                    continue;
                }
                let n = self.normals.at(c, self.corners[c]);
                let (dir, w) = match facet {
                    Some(t) => (t.truncate(), t.w),
                    None => (any_perpendicular(n), 1.0),
                };
                let d = (dir - n * n.dot(dir)).normalize_or_zero();
                let d = if d == Vec3::ZERO {
                    any_perpendicular(n)
                } else {
                    d
                };
                per_corner[c] = Some(d.extend(w));
            }
        }
        // Equal tangents share one value (bitwise), so render vertices split only where
        // the frame changes.
        let mut values: Vec<Vec4> = Vec::new();
        let mut seen = std::collections::HashMap::new();
        let indices = per_corner
            .into_iter()
            .enumerate()
            .map(|(c, t)| {
                let n = self.normals.at(c, self.corners[c]);
                let t = t
                    .filter(|t| t.is_finite() && t.truncate() != Vec3::ZERO)
                    .unwrap_or_else(|| any_perpendicular(n).extend(1.0));
                let w = if t.w < 0.0 { -1.0 } else { 1.0 };
                let t = t.truncate().normalize_or(Vec3::X).extend(w);
                let key = t.to_array().map(f32::to_bits);
                *seen.entry(key).or_insert_with(|| {
                    values.push(t);
                    (values.len() - 1) as u32
                })
            })
            .collect();
        self.tangents = Some(Channel {
            values,
            indices: Some(indices),
        });
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tangent frame at every corner: unit, orthogonal to the normal, `w = ±1`.
    fn check_frame(m: &Mesh) {
        let t = m.tangents.as_ref().expect("tangents");
        for (c, &v) in m.corners.iter().enumerate() {
            let tc = t.at(c, v);
            let n = m.normals.at(c, v);
            assert!((tc.truncate().length() - 1.0).abs() < 1e-5, "{tc}");
            assert!(tc.truncate().dot(n).abs() < 1e-4, "{tc} vs {n}");
            assert!(tc.w == 1.0 || tc.w == -1.0, "{tc}");
        }
    }

    #[test]
    fn a_plane_gets_its_u_axis_and_a_bitangent_towards_the_image_top() {
        // The grid faces +Y with u along +x and v along +z: the image's top (v = 0) is at
        // -z, so glTF's bitangent w (N × T) must point along -z: T = +x, w = +1
        // (Y × X = -Z).
        let mut m = Mesh::grid(1.0, 1.0, 2, 2).expect("a grid");
        m.generate_tangents(0).expect("UV set 0");
        check_frame(&m);
        let t = m.tangents.as_ref().unwrap();
        assert_eq!(
            t.values.len(),
            1,
            "one frame for the flat grid: {:?}",
            t.values
        );
        let t = t.values[0];
        assert!(
            (t.truncate() - Vec3::X).length() < 1e-5 && t.w == 1.0,
            "{t}"
        );
        let b = Vec3::Y.cross(t.truncate()) * t.w;
        assert!((b + Vec3::Z).length() < 1e-5, "{b}");
        // The per-facet gradient agrees.
        let g = gradient_tangent(
            [Vec3::ZERO, Vec3::X, Vec3::Z],
            [Vec2::ZERO, Vec2::X, Vec2::Y],
            Vec3::Y,
        );
        assert_eq!(g, Some(Vec4::new(1.0, 0.0, 0.0, 1.0)));
    }

    #[test]
    fn mirrored_uvs_flip_the_handedness() {
        let mut m = Mesh::grid(1.0, 1.0, 1, 1).expect("a grid");
        for uv in &mut m.uvs[0].values {
            uv.x = 1.0 - uv.x;
        }
        m.generate_tangents(0).unwrap();
        let t = m.tangents.as_ref().unwrap().values[0];
        // u now runs along -x: T = -x, and B must still point along -z: w = -1.
        assert!(
            (t.truncate() + Vec3::X).length() < 1e-5 && t.w == -1.0,
            "{t}"
        );
    }

    #[test]
    fn primitives_and_degenerate_uvs_get_finite_orthogonal_frames() {
        for mut m in [
            Mesh::sphere(1.0, 16, 8).unwrap(),
            Mesh::torus(1.0, 0.3, 16, 8).unwrap(),
            Mesh::cylinder(0.5, 2.0, 12, true).unwrap(),
            Mesh::cube(1.0).unwrap(),
        ] {
            m.generate_tangents(0).unwrap();
            check_frame(&m);
            // All UVs equal: no gradient anywhere, still a frame.
            for uv in &mut m.uvs[0].values {
                *uv = Vec2::splat(0.5);
            }
            m.generate_tangents(0).unwrap();
            check_frame(&m);
        }
        let mut m = Mesh::grid(1.0, 1.0, 1, 1).unwrap();
        assert_eq!(m.generate_tangents(1), Err(TangentError::NoUvSet(1)));
    }
}
