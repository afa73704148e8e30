//! Triangulation of one facet, in corner indices local to the facet (`0..len`).
//!
//! Every facet of `n` corners gives exactly `n - 2` triangles, counter-clockwise about the
//! facet normal wherever the facet allows it:
//!
//! - quads: the diagonal that keeps both triangles facing the facet normal; when both do
//!   (convex) or neither does (twisted or degenerate), the shorter diagonal;
//! - more corners, convex (every corner turns left about the normal): a fan from corner 0;
//! - more corners, concave: ear clipping in the facet's plane, in `f64`, with an `O(n^2)`
//!   ear-flag scheme (flags of the two neighbours are refreshed after each clip, all flags
//!   once when a full turn finds no ear). When even that finds no ear (self-intersecting or
//!   collinear outlines), or the facet has more than [`MAX_EAR_CLIP`] corners, or it is
//!   degenerate, the fan is used instead. Nothing here can loop forever.

use glam::{DVec2, Vec3};

/// Concave facets with more corners than this are fanned, not ear-clipped (ear clipping is
/// quadratic, cubic in pathological cases).
pub const MAX_EAR_CLIP: usize = 1024;

/// Buffers reused from facet to facet.
#[derive(Default)]
pub(super) struct Scratch {
    points: Vec<DVec2>,
    prev: Vec<u32>,
    next: Vec<u32>,
    ear: Vec<bool>,
}

/// Appends the triangles of the facet through `positions[ring[..]]` with unit normal `normal`
/// (zero if degenerate) to `out`.
pub(super) fn triangulate(
    positions: &[Vec3],
    ring: &[u32],
    normal: Vec3,
    out: &mut Vec<[u32; 3]>,
    scratch: &mut Scratch,
) {
    let p = |i: usize| positions[ring[i] as usize];
    let n = ring.len();
    match n {
        3 => out.push([0, 1, 2]),
        4 => {
            let faces = |a, b, c| (p(b) - p(a)).cross(p(c) - p(a)).dot(normal) > 0.0;
            let with_02 = faces(0, 1, 2) && faces(0, 2, 3);
            let with_13 = faces(0, 1, 3) && faces(1, 2, 3);
            let shorter_02 = p(0).distance_squared(p(2)) <= p(1).distance_squared(p(3));
            let use_02 = if with_02 != with_13 {
                with_02
            } else {
                shorter_02
            };
            if use_02 {
                out.extend([[0, 1, 2], [0, 2, 3]]);
            } else {
                out.extend([[0, 1, 3], [1, 2, 3]]);
            }
        }
        _ => {
            let convex = (0..n).all(|i| {
                let (a, b, c) = (p((i + n - 1) % n), p(i), p((i + 1) % n));
                (b - a).cross(c - b).dot(normal) >= 0.0
            });
            let start = out.len();
            let clipped = !convex
                && normal != Vec3::ZERO
                && n <= MAX_EAR_CLIP
                && ear_clip(positions, ring, normal, out, scratch);
            if !clipped {
                out.truncate(start);
                out.extend((1..n as u32 - 1).map(|i| [0, i, i + 1]));
            }
        }
    }
}

/// 2D cross product of `b - a` and `c - a`: positive when `a, b, c` turn left.
#[inline]
fn turn(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (b - a).perp_dot(c - a)
}

/// Ear clipping of the facet projected on its plane; false if no ear could be found.
fn ear_clip(
    positions: &[Vec3],
    ring: &[u32],
    normal: Vec3,
    out: &mut Vec<[u32; 3]>,
    s: &mut Scratch,
) -> bool {
    let n = ring.len();
    // Right-handed basis (u, v, normal): counter-clockwise about the normal stays
    // counter-clockwise in (u, v).
    let axis = normal.as_dvec3();
    let u = axis.any_orthonormal_vector();
    let v = axis.cross(u);
    let origin = positions[ring[0] as usize].as_dvec3();
    s.points.clear();
    s.points.extend(ring.iter().map(|&i| {
        let d = positions[i as usize].as_dvec3() - origin;
        DVec2::new(d.dot(u), d.dot(v))
    }));
    s.prev.clear();
    s.prev
        .extend((0..n as u32).map(|i| (i + n as u32 - 1) % n as u32));
    s.next.clear();
    s.next.extend((0..n as u32).map(|i| (i + 1) % n as u32));
    s.ear.clear();
    for i in 0..n as u32 {
        let ear = is_ear(s, i);
        s.ear.push(ear);
    }

    let mut remaining = n;
    let mut i = 0u32;
    let mut misses = 0;
    let mut refreshed = false;
    while remaining > 3 {
        if s.ear[i as usize] {
            let (a, c) = (s.prev[i as usize], s.next[i as usize]);
            out.push([a, i, c]);
            s.next[a as usize] = c;
            s.prev[c as usize] = a;
            remaining -= 1;
            s.ear[a as usize] = is_ear(s, a);
            s.ear[c as usize] = is_ear(s, c);
            (i, misses, refreshed) = (c, 0, false);
            continue;
        }
        i = s.next[i as usize];
        misses += 1;
        if misses >= remaining {
            // A clip can turn vertices other than its neighbours into ears: refresh them all
            // once before giving up.
            if refreshed {
                return false;
            }
            for _ in 0..remaining {
                s.ear[i as usize] = is_ear(s, i);
                i = s.next[i as usize];
            }
            (misses, refreshed) = (0, true);
        }
    }
    out.push([s.prev[i as usize], i, s.next[i as usize]]);
    true
}

/// True if the remaining polygon's corner `i` is strictly convex and no other remaining
/// corner lies inside or on the triangle it cuts off (corners coinciding with the triangle's
/// own, as where a polygon touches itself, are ignored).
fn is_ear(s: &Scratch, i: u32) -> bool {
    let (pa, pc) = (s.prev[i as usize], s.next[i as usize]);
    let (a, b, c) = (
        s.points[pa as usize],
        s.points[i as usize],
        s.points[pc as usize],
    );
    if turn(a, b, c) <= 0.0 {
        return false;
    }
    let mut j = s.next[pc as usize];
    while j != pa {
        let q = s.points[j as usize];
        let own = q == a || q == b || q == c;
        if !own && turn(a, b, q) >= 0.0 && turn(b, c, q) >= 0.0 && turn(c, a, q) >= 0.0 {
            return false;
        }
        j = s.next[j as usize];
    }
    true
}
