//! Clipping in homogeneous clip space, before the perspective divide.
//!
//! A triangle is clipped only against the planes one of its vertices violates: the near plane
//! (so nothing behind the eye is divided by w <= 0 and nothing wraps around), the far plane,
//! and the four guard-band planes that keep snapped coordinates inside the fixed-point range.
//! Sutherland-Hodgman keeps inside vertices bit-exact; an intersection is always computed from
//! the inside vertex towards the outside one, so two triangles sharing a clipped edge get the
//! identical new vertex and stay watertight.
//!
//! Clip space (see `scene::Camera::projection`): visible points have -w <= x, y <= w and
//! 0 <= z <= w (reversed depth, z = w on the near plane).

use glam::{Vec2, Vec4};

use super::MAX_VARYINGS;

pub(crate) const NEAR: u8 = 1;
pub(crate) const FAR: u8 = 2;
pub(crate) const LEFT: u8 = 4;
pub(crate) const RIGHT: u8 = 8;
pub(crate) const BOTTOM: u8 = 16;
pub(crate) const TOP: u8 = 32;
const PLANES: [u8; 6] = [NEAR, FAR, LEFT, RIGHT, BOTTOM, TOP];

/// Signed distance-like value of `p` to a plane: >= 0 inside. `g` scales the x/y planes
/// (1 = the view frustum, > 1 = the guard band).
#[inline(always)]
fn distance(p: Vec4, plane: u8, g: Vec2) -> f32 {
    match plane {
        NEAR => p.w - p.z,
        FAR => p.z,
        LEFT => p.x + g.x * p.w,
        RIGHT => g.x * p.w - p.x,
        BOTTOM => p.y + g.y * p.w,
        _ => g.y * p.w - p.y,
    }
}

/// Bit set of the planes `p` is outside of.
#[inline(always)]
pub(crate) fn outcode(p: Vec4, g: Vec2) -> u8 {
    let mut code = 0;
    for plane in PLANES {
        if distance(p, plane, g) < 0.0 {
            code |= plane;
        }
    }
    code
}

/// A vertex being clipped: clip-space position and its varyings (the draw's first
/// `stride` floats are meaningful).
#[derive(Clone, Copy, Debug)]
pub(crate) struct ClipVertex {
    pub pos: Vec4,
    pub var: [f32; MAX_VARYINGS],
}

impl ClipVertex {
    /// A vertex with position `pos` and varyings `var` (at most [`MAX_VARYINGS`]).
    pub fn new(pos: Vec4, var: &[f32]) -> Self {
        let mut v = [0.0; MAX_VARYINGS];
        let n = var.len().min(MAX_VARYINGS);
        v[..n].copy_from_slice(&var[..n]);
        Self { pos, var: v }
    }
}

/// Most section planes a draw can carry ([`crate::Draw::sections`]).
pub const MAX_SECTIONS: usize = 3;

/// Most vertices a clipped triangle can have: each of the six frustum planes and each
/// section plane adds at most one.
pub(crate) const MAX_POLY: usize = 3 + 6 + MAX_SECTIONS;

/// Bit `k` set when `p` is on the removed side of section plane `k` (`dot(plane, p) < 0`;
/// a non-finite distance removes nothing here, the triangle is culled later).
#[inline(always)]
pub(crate) fn section_code(p: Vec4, planes: &[Vec4]) -> u8 {
    let mut code = 0;
    for (k, plane) in planes.iter().enumerate() {
        if plane.dot(p) < 0.0 {
            code |= 1 << k;
        }
    }
    code
}

/// Clips a convex polygon against the section planes whose bits are set in `need`, keeping
/// the side where `dot(plane, p) >= 0`. Like the frustum planes, an intersection is computed
/// in f64 from the inside vertex towards the outside one, so two triangles sharing a cut
/// edge get the identical new vertex.
pub(crate) fn clip_sections(poly: Poly, planes: &[Vec4], need: u8) -> Poly {
    let mut poly = poly;
    let mut out = poly;
    for (k, plane) in planes.iter().enumerate() {
        if need & (1 << k) == 0 {
            continue;
        }
        let stride = poly.stride;
        let l = plane.as_dvec4();
        let kept = clip_by(
            &mut poly,
            &mut out,
            |v| plane.dot(v.pos) >= 0.0,
            |i, o| {
                let (pi, po) = (i.pos.as_dvec4(), o.pos.as_dvec4());
                let t = crate::geom::crossing(l.dot(pi), l.dot(po));
                lerp(i, o, pi, po, t, stride)
            },
        );
        if !kept {
            break;
        }
    }
    poly
}

/// Clips `poly` against one plane: `inside` tells the vertices kept, `cut` makes the vertex
/// where an edge from an inside vertex to an outside one crosses the plane; `out` is
/// scratch. Returns false, with `poly` emptied, when fewer than three vertices remain.
#[inline(always)]
fn clip_by(
    poly: &mut Poly,
    out: &mut Poly,
    inside: impl Fn(&ClipVertex) -> bool,
    cut: impl Fn(&ClipVertex, &ClipVertex) -> ClipVertex,
) -> bool {
    out.n = 0;
    crate::geom::clip_polygon(poly.as_slice(), inside, cut, out);
    std::mem::swap(poly, out);
    if poly.n < 3 {
        poly.n = 0;
        return false;
    }
    true
}

/// A convex polygon of at most [`MAX_POLY`] vertices, on the stack: clipping allocates
/// nothing, so a frame that clips triangles allocates nothing either.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Poly {
    v: [ClipVertex; MAX_POLY],
    /// Varyings per vertex to interpolate.
    stride: usize,
    n: usize,
}

impl Extend<ClipVertex> for Poly {
    #[inline]
    fn extend<I: IntoIterator<Item = ClipVertex>>(&mut self, iter: I) {
        for p in iter {
            self.push(p);
        }
    }
}

impl Poly {
    /// A polygon with the vertices of `tri`, whose first `stride` varyings are interpolated.
    pub fn triangle(tri: [ClipVertex; 3], stride: usize) -> Self {
        let mut v = [tri[0]; MAX_POLY];
        v[..3].copy_from_slice(&tri);
        Self {
            v,
            stride: stride.min(MAX_VARYINGS),
            n: 3,
        }
    }

    #[inline]
    fn push(&mut self, p: ClipVertex) {
        // Cannot overflow: a plane adds at most one vertex to a convex polygon.
        if self.n < MAX_POLY {
            self.v[self.n] = p;
            self.n += 1;
        }
    }

    /// The vertices, in winding order.
    #[must_use]
    pub fn as_slice(&self) -> &[ClipVertex] {
        &self.v[..self.n]
    }
}

/// Clips a convex polygon against every plane in `planes`; returns the clipped polygon
/// (possibly empty) in the same winding.
pub(crate) fn clip_polygon(poly: Poly, planes: u8, g: Vec2) -> Poly {
    let mut poly = poly;
    let mut out = poly;
    for plane in PLANES {
        if planes & plane == 0 {
            continue;
        }
        let stride = poly.stride;
        let kept = clip_by(
            &mut poly,
            &mut out,
            |v| distance(v.pos, plane, g) >= 0.0,
            |i, o| intersect(i, o, plane, g, stride),
        );
        if !kept {
            break;
        }
    }
    poly
}

/// The point where the segment from inside vertex `i` to outside vertex `o` meets `plane`.
///
/// Computed in f64 from the f64 distances: with the outside vertex near w = 0 (a triangle
/// grazing the eye) t is within 1e-7 of 1 and `i + (o - i) t` cancels almost completely, so
/// in f32 the new vertex's small coordinates carried errors of order ulp(|i|), which turned
/// the clipped edge by up to 1e-3 rad (found by `tests/stability.rs`). In f64 the result
/// is correct to f32 rounding. Still computed from the inside vertex, so two triangles
/// sharing the edge get the identical vertex.
#[inline]
fn intersect(i: &ClipVertex, o: &ClipVertex, plane: u8, g: Vec2, stride: usize) -> ClipVertex {
    let (pi, po) = (i.pos.as_dvec4(), o.pos.as_dvec4());
    let (di, d_o) = (distance64(pi, plane, g), distance64(po, plane, g));
    lerp(i, o, pi, po, crate::geom::crossing(di, d_o), stride)
}

/// The vertex at `t` from `i` (at `pi`) towards `o` (at `po`).
#[inline]
fn lerp(
    i: &ClipVertex,
    o: &ClipVertex,
    pi: glam::DVec4,
    po: glam::DVec4,
    t: f64,
    stride: usize,
) -> ClipVertex {
    let tf = t as f32;
    let mut var = i.var;
    for (v, w) in var[..stride].iter_mut().zip(&o.var[..stride]) {
        *v += (w - *v) * tf;
    }
    ClipVertex {
        pos: (pi + (po - pi) * t).as_vec4(),
        var,
    }
}

/// [`distance`] in f64.
#[inline]
fn distance64(p: glam::DVec4, plane: u8, g: Vec2) -> f64 {
    let (gx, gy) = (f64::from(g.x), f64::from(g.y));
    match plane {
        NEAR => p.w - p.z,
        FAR => p.z,
        LEFT => p.x + gx * p.w,
        RIGHT => gx * p.w - p.x,
        BOTTOM => p.y + gy * p.w,
        _ => gy * p.w - p.y,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f32, y: f32, z: f32, w: f32) -> ClipVertex {
        ClipVertex::new(Vec4::new(x, y, z, w), &[w])
    }

    #[test]
    fn near_clip_of_triangle_through_eye_plane() {
        // One vertex behind the eye (w < 0): the result must have all w > 0.
        let tri = Poly::triangle(
            [
                v(0.0, 0.0, 0.5, 1.0),
                v(1.0, 0.0, 0.5, 1.0),
                v(0.0, 1.0, 2.0, -1.0),
            ],
            1,
        );
        let out = clip_polygon(tri, NEAR, Vec2::ONE);
        let out = out.as_slice();
        assert_eq!(out.len(), 4);
        for p in out {
            assert!(p.pos.w > 0.0 && p.pos.z <= p.pos.w + 1e-6, "{:?}", p.pos);
        }
        // Inside vertices kept bit-exact.
        assert_eq!(out[0].pos, Vec4::new(0.0, 0.0, 0.5, 1.0));
    }

    #[test]
    fn shared_edge_intersection_is_identical() {
        let a = v(0.3, 0.1, 0.2, 1.0);
        let b = v(-0.7, 0.4, 3.0, -2.0);
        let t1 = clip_polygon(
            Poly::triangle([a, b, v(0.5, 0.5, 0.1, 1.0)], 1),
            NEAR,
            Vec2::ONE,
        );
        let t2 = clip_polygon(
            Poly::triangle([b, a, v(-0.5, 0.5, 0.1, 1.0)], 1),
            NEAR,
            Vec2::ONE,
        );
        let new1: Vec<_> = t1
            .as_slice()
            .iter()
            .map(|p| p.pos)
            .filter(|p| *p != a.pos && p.w != 1.0)
            .collect();
        let new2: Vec<_> = t2
            .as_slice()
            .iter()
            .map(|p| p.pos)
            .filter(|p| *p != a.pos && p.w != 1.0)
            .collect();
        assert!(new1.iter().any(|p| new2.contains(p)), "{new1:?} {new2:?}");
    }

    #[test]
    fn fully_outside_is_empty() {
        let tri = Poly::triangle(
            [
                v(0.0, 0.0, 2.0, 1.0),
                v(1.0, 0.0, 2.0, 1.0),
                v(0.0, 1.0, 2.0, 1.0),
            ],
            1,
        );
        assert!(clip_polygon(tri, NEAR, Vec2::ONE).as_slice().is_empty());
    }
}
