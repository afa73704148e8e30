//! The watertight ray-triangle test of Woop, Benthin and Wald ("Watertight Ray/Triangle
//! Intersection", JCGT 2(1), 2013): the ray is sheared so that it runs along +z through the
//! origin, and the triangle's 2D edge functions are evaluated at the origin. Two triangles
//! sharing an edge compute that edge's function from the same two sheared vertices with the
//! same operations (up to sign), so a ray through the edge is inside one of them or both:
//! no ray slips through a shared edge or vertex. Where an edge function rounds to exactly
//! zero it is recomputed in f64, as the paper does.

use glam::Vec3;

/// A ray prepared for the watertight test: the axis of its largest direction component
/// (`kz`) and the two others (`kx`, `ky`, swapped to keep the winding when `d[kz] < 0`),
/// and the shear.
#[derive(Clone, Copy, Debug)]
pub struct Sheared {
    pub origin: Vec3,
    pub kx: usize,
    pub ky: usize,
    pub kz: usize,
    pub sx: f32,
    pub sy: f32,
    pub sz: f32,
}

impl Sheared {
    /// `None` for a zero or non-finite direction.
    #[must_use]
    pub fn new(origin: Vec3, dir: Vec3) -> Option<Self> {
        if !(origin.is_finite() && dir.is_finite()) || dir == Vec3::ZERO {
            return None;
        }
        let a = dir.abs();
        let kz = if a.x > a.y && a.x > a.z {
            0
        } else if a.y > a.z {
            1
        } else {
            2
        };
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        if dir[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        Some(Self {
            origin,
            kx,
            ky,
            kz,
            sx: dir[kx] / dir[kz],
            sy: dir[ky] / dir[kz],
            sz: 1.0 / dir[kz],
        })
    }

    /// The hit of triangle `(a, b, c)` within `(tmin, tmax)` (in units of the ray's
    /// direction): `t` and the barycentric weights of `a`, `b`, `c`. Both sides are hit.
    #[inline(always)]
    #[must_use]
    pub fn hit(&self, a: Vec3, b: Vec3, c: Vec3, tmin: f32, tmax: f32) -> Option<(f32, [f32; 3])> {
        self.hit_sided(a, b, c, tmin, tmax).map(|(t, w, _)| (t, w))
    }

    /// [`Sheared::hit`], and whether the ray met the front (counter-clockwise) side.
    #[inline(always)]
    #[must_use]
    pub fn hit_sided(
        &self,
        a: Vec3,
        b: Vec3,
        c: Vec3,
        tmin: f32,
        tmax: f32,
    ) -> Option<(f32, [f32; 3], bool)> {
        let (kx, ky, kz) = (self.kx, self.ky, self.kz);
        let (a, b, c) = (
            (a - self.origin).to_array(),
            (b - self.origin).to_array(),
            (c - self.origin).to_array(),
        );
        let ax = a[kx] - self.sx * a[kz];
        let ay = a[ky] - self.sy * a[kz];
        let bx = b[kx] - self.sx * b[kz];
        let by = b[ky] - self.sy * b[kz];
        let cx = c[kx] - self.sx * c[kz];
        let cy = c[ky] - self.sy * c[kz];
        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        if u == 0.0 || v == 0.0 || w == 0.0 {
            let d = |p: f32, q: f32, r: f32, s: f32| {
                (f64::from(p) * f64::from(q) - f64::from(r) * f64::from(s)) as f32
            };
            u = d(cx, by, cy, bx);
            v = d(ax, cy, ay, cx);
            w = d(bx, ay, by, ax);
        }
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let t = (u * (self.sz * a[kz]) + v * (self.sz * b[kz]) + w * (self.sz * c[kz])) / det;
        if t > tmin && t < tmax {
            Some((t, [u / det, v / det, w / det], det > 0.0))
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn barycentric_weights_rebuild_the_point() {
        let (a, b, c) = (
            Vec3::new(-1.0, -1.0, 2.0),
            Vec3::new(2.0, -0.5, 3.0),
            Vec3::new(0.0, 1.5, 2.5),
        );
        let o = Vec3::new(0.1, 0.2, -1.0);
        let p = a * 0.2 + b * 0.3 + c * 0.5;
        let d = (p - o) * 0.5;
        let s = Sheared::new(o, d).unwrap();
        let (t, w) = s.hit(a, b, c, 0.0, f32::INFINITY).unwrap();
        assert!((t - 2.0).abs() < 1e-5, "{t}");
        for (got, want) in w.iter().zip([0.2, 0.3, 0.5]) {
            assert!((got - want).abs() < 1e-5, "{w:?}");
        }
        // Behind the origin, or beyond tmax: no hit.
        assert!(Sheared::new(o, -d)
            .unwrap()
            .hit(a, b, c, 0.0, 1e9)
            .is_none());
        assert!(s.hit(a, b, c, 0.0, 1.9).is_none());
        // A zero direction is refused up front.
        assert!(Sheared::new(o, Vec3::ZERO).is_none());
        assert!(Sheared::new(Vec3::NAN, d).is_none());
    }

    #[test]
    fn a_ray_through_a_shared_edge_hits_one_of_the_two_triangles() {
        // Two triangles sharing the edge (p, q), rays aimed at points along it.
        let p = Vec3::new(0.3, -0.7, 1.1);
        let q = Vec3::new(-0.2, 0.9, 0.8);
        let r = Vec3::new(1.4, 0.5, 1.3);
        let s = Vec3::new(-1.3, -0.4, 0.9);
        let o = Vec3::new(0.013, 0.021, -2.0);
        for k in 0..=1000 {
            let at = p.lerp(q, k as f32 / 1000.0);
            let ray = Sheared::new(o, at - o).unwrap();
            let one = ray.hit(p, q, r, 0.0, 2.0).is_some();
            let two = ray.hit(q, p, s, 0.0, 2.0).is_some();
            assert!(one || two, "ray {k} slipped through the shared edge");
        }
    }
}

#[cfg(test)]
mod side {
    use super::*;

    /// Which sign of the determinant is the counter-clockwise (front) side, for rays along
    /// every axis both ways and oblique ones.
    #[test]
    fn det_sign_tells_the_front_side() {
        let (a, b, c) = (
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        );
        let n = (b - a).cross(c - a);
        for d in [
            Vec3::Z,
            -Vec3::Z,
            Vec3::new(0.2, 0.1, -1.0),
            Vec3::new(-0.3, 0.2, 1.0),
        ] {
            for (p, q, r) in [(a, b, c), (b, c, a), (a, c, b)] {
                let n = (q - p).cross(r - p);
                let s = Sheared::new(-d * 5.0, d).unwrap();
                let h = s.hit_sided(p, q, r, 0.0, 100.0).unwrap();
                assert_eq!(h.2, d.dot(n) < 0.0, "{d} {n}");
            }
        }
        let _ = n;
    }
}
