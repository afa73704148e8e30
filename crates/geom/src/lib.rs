//! Geometry written once for every layer that needs it: the Sutherland-Hodgman polygon
//! clipper (the rasterizer's near-plane and guard-band clipping, the f64 reference's
//! near/far clipping, the chromaticity diagram's gamut intersections, the plane reference's
//! pixel coverage), the Liang-Barsky segment clipper (the rasterizer's lines in clip space
//! and on the screen, the viewer's gizmos) and the normal matrix (mesh skinning, the renderer, the f64 reference).
//!
//! Each is generic in what it clips: the caller says what is inside and how to cut an edge,
//! so the rasterizer keeps its f32 inside test and its f64 intersections, and every caller
//! cuts an edge from its inside vertex (two polygons sharing an edge get the same new
//! vertex, which keeps a clipped mesh watertight).

use glam::{DMat3, Mat3};

/// One Sutherland-Hodgman pass: the convex (or any simple) polygon `input` clipped to one
/// boundary, appended to `out` in the same winding. `inside` says which side a vertex is on;
/// `cut(i, o)` is the point where the edge from inside vertex `i` to outside vertex `o`
/// crosses the boundary (always called inside-first).
pub fn clip_polygon<P: Copy>(
    input: &[P],
    inside: impl Fn(&P) -> bool,
    cut: impl Fn(&P, &P) -> P,
    out: &mut impl Extend<P>,
) {
    let n = input.len();
    for k in 0..n {
        let (a, b) = (&input[k], &input[(k + 1) % n]);
        let (a_in, b_in) = (inside(a), inside(b));
        if a_in {
            out.extend(Some(*a));
        }
        if a_in != b_in {
            out.extend(Some(if a_in { cut(a, b) } else { cut(b, a) }));
        }
    }
}

/// Where the edge from `di` (the inside vertex's signed distance, >= 0) to `d_o` (the
/// outside one's, < 0) crosses 0, as a fraction of the edge from the inside vertex, in
/// [0, 1].
#[must_use]
pub fn crossing(di: f64, d_o: f64) -> f64 {
    (di / (di - d_o)).clamp(0.0, 1.0)
}

/// Liang-Barsky: the parameters `(t0, t1)`, `0 <= t0 <= t1 <= 1`, of the part of a segment
/// on the inner side of every boundary, given each boundary's signed distances `(da, db)` of
/// the segment's two ends (inside where >= 0, linear along the segment: a plane in 2D, 3D or
/// homogeneous clip space), or `None` when none of it is.
#[must_use]
pub fn clip_interval(distances: impl IntoIterator<Item = (f32, f32)>) -> Option<(f32, f32)> {
    let (mut t0, mut t1) = (0.0f32, 1.0f32);
    for (da, db) in distances {
        if da < 0.0 && db < 0.0 {
            return None;
        }
        if da < 0.0 {
            t0 = t0.max(da / (da - db));
        } else if db < 0.0 {
            t1 = t1.min(da / (da - db));
        }
    }
    (t0 <= t1).then_some((t0, t1))
}

/// [`clip_interval`] for the 2D segment from `a` to `b` and the box `lo..=hi`.
#[must_use]
pub fn clip_segment(a: [f32; 2], b: [f32; 2], lo: [f32; 2], hi: [f32; 2]) -> Option<(f32, f32)> {
    clip_interval([
        (a[0] - lo[0], b[0] - lo[0]),
        (hi[0] - a[0], hi[0] - b[0]),
        (a[1] - lo[1], b[1] - lo[1]),
        (hi[1] - a[1], hi[1] - b[1]),
    ])
}

macro_rules! cofactor {
    ($name:ident, $m:ty) => {
        /// The normal matrix of `m`: its cofactor matrix (`det(m) * m^-T`), which stays
        /// defined for singular matrices (a flattened mesh keeps the normal of its plane),
        /// negated when `m` mirrors so normals stay outward. Normals it transforms need
        /// normalising.
        #[must_use]
        pub fn $name(m: $m) -> $m {
            let c = <$m>::from_cols(
                m.y_axis.cross(m.z_axis),
                m.z_axis.cross(m.x_axis),
                m.x_axis.cross(m.y_axis),
            );
            if m.determinant() < 0.0 {
                -c
            } else {
                c
            }
        }
    };
}

cofactor!(normal_matrix, Mat3);
cofactor!(normal_matrix_f64, DMat3);

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec3, Vec3};

    #[test]
    fn a_triangle_clipped_by_a_half_plane_keeps_its_winding_and_cuts_from_inside() {
        let tri = [[0.0f64, 0.0], [2.0, 0.0], [0.0, 2.0]];
        let mut out: Vec<[f64; 2]> = Vec::new();
        let cuts = std::cell::RefCell::new(Vec::new());
        clip_polygon(
            &tri,
            |p| p[0] <= 1.0,
            |i, o| {
                cuts.borrow_mut().push((*i, *o));
                let t = crossing(1.0 - i[0], 1.0 - o[0]);
                [i[0] + (o[0] - i[0]) * t, i[1] + (o[1] - i[1]) * t]
            },
            &mut out,
        );
        assert_eq!(out, [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 2.0]]);
        assert!(
            cuts.borrow().iter().all(|(i, _)| i[0] <= 1.0),
            "inside first"
        );
        let mut none: Vec<[f64; 2]> = Vec::new();
        clip_polygon(&tri, |p| p[0] > 5.0, |i, _| *i, &mut none);
        assert!(none.is_empty());
    }

    #[test]
    fn segments_are_clipped_to_the_box() {
        let b = ([0.0, 0.0], [10.0, 10.0]);
        assert_eq!(
            clip_segment([-5.0, 5.0], [15.0, 5.0], b.0, b.1),
            Some((0.25, 0.75))
        );
        assert_eq!(
            clip_segment([1.0, 1.0], [2.0, 2.0], b.0, b.1),
            Some((0.0, 1.0))
        );
        assert_eq!(clip_segment([-5.0, -1.0], [15.0, -1.0], b.0, b.1), None);
        assert_eq!(
            clip_segment([-5.0, 20.0], [20.0, -5.0], b.0, b.1).map(|t| t.0),
            Some(0.4)
        );
    }

    #[test]
    fn the_normal_matrix_keeps_normals_perpendicular_and_outward() {
        let m = Mat3::from_cols(Vec3::new(2.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::Z);
        let (t, n) = (Vec3::new(1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0));
        assert!(t.dot(n).abs() < 1e-6);
        assert!(
            (m * t).dot(normal_matrix(m) * n).abs() < 1e-5,
            "stays perpendicular"
        );
        let mirror = Mat3::from_diagonal(Vec3::new(-1.0, 1.0, 1.0));
        assert_eq!(
            normal_matrix(mirror) * Vec3::X,
            -Vec3::X,
            "a mirrored normal stays outward"
        );
        let flat = Mat3::from_diagonal(Vec3::new(1.0, 1.0, 0.0));
        assert_eq!(
            normal_matrix(flat) * Vec3::Z,
            Vec3::Z,
            "a flattened mesh keeps its plane's normal"
        );
        let d = normal_matrix_f64(DMat3::from_diagonal(DVec3::new(2.0, 3.0, 4.0)));
        assert_eq!(d * DVec3::X, DVec3::new(12.0, 0.0, 0.0));
    }
}
