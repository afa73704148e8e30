//! Measuring: the point a click lands on, snapped to a vertex or an edge of the triangle it
//! hits when one is within a few pixels on screen, else the surface point; and the distance
//! and angle between picked points, in the scene's units (glTF: metres).
//!
//! The hit is the pixel probe's ray cast ([`super::probe`]): exact in f64, back faces
//! skipped where the rasterizer culls them, parts cut away by section planes passed over.

use glam::{DVec3, Vec3};

use super::prepare::PreparedScene;
use super::settings::{Settings, View};

/// What a picked point is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Snap {
    /// A vertex of the mesh.
    Vertex,
    /// The nearest point of a triangle edge to the click's ray.
    Edge,
    /// The surface where the ray meets it.
    Surface,
}

impl Snap {
    /// `vertex`, `edge` or `surface`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Snap::Vertex => "vertex",
            Snap::Edge => "edge",
            Snap::Surface => "surface",
        }
    }
}

/// A point picked for measuring.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pick {
    /// World-space position.
    pub position: Vec3,
    pub snap: Snap,
    /// Index into the scene's instances, and the prepared mesh's triangle hit.
    pub instance: usize,
    pub triangle: usize,
}

/// The point under screen position (`x`, `y`) of `view` (pixels, y down, (0.5, 0.5) the
/// first pixel's centre), snapped to a vertex of the triangle hit when its image is within
/// `radius` pixels, else to an edge within `radius`, else on the surface. `None` if the
/// ray meets nothing.
#[must_use]
pub fn pick(
    scene: &PreparedScene,
    settings: &Settings,
    view: &View,
    x: f32,
    y: f32,
    radius: f32,
) -> Option<Pick> {
    let (w, h) = (f64::from(view.width.max(1)), f64::from(view.height.max(1)));
    let cam = &view.camera;
    let vp = (cam.projection(view.aspect()) * cam.view()).as_dmat4();
    let inv = vp.inverse();
    let ndc = glam::DVec2::new(f64::from(x) / w * 2.0 - 1.0, 1.0 - f64::from(y) / h * 2.0);
    // Reversed-Z: z = 1 on the near plane, 0 on the far plane.
    let near = inv.project_point3(ndc.extend(1.0));
    let far = inv.project_point3(ndc.extend(0.0));
    let hit = super::probe::cast(scene, settings, near, far, true)?;
    let inst = &scene.instances[hit.instance];
    let tri = &scene.meshes[inst.mesh].tri;
    let world = inst.placement(hit.copy).as_dmat4();
    let corners = tri.triangles[hit.triangle]
        .map(|k| world.transform_point3(tri.positions[k as usize].as_dvec3()));
    // Where a world point shows on screen, in pixels.
    let screen = |p: DVec3| {
        let c = vp * p.extend(1.0);
        (c.w > 0.0).then(|| {
            let n = c.truncate() / c.w;
            glam::DVec2::new((n.x + 1.0) * 0.5 * w, (1.0 - n.y) * 0.5 * h)
        })
    };
    let click = glam::DVec2::new(f64::from(x), f64::from(y));
    let r = f64::from(radius.max(0.0));
    let out = |position: DVec3, snap: Snap| Pick {
        position: position.as_vec3(),
        snap,
        instance: hit.instance,
        triangle: hit.triangle,
    };
    let nearest_vertex = corners
        .iter()
        .filter_map(|&c| screen(c).map(|s| ((s - click).length(), c)))
        .min_by(|a, b| a.0.total_cmp(&b.0));
    if let Some((d, c)) = nearest_vertex {
        if d <= r {
            return Some(out(c, Snap::Vertex));
        }
    }
    let dir = far - near;
    let nearest_edge = (0..3)
        .filter_map(|i| {
            let (a, b) = (corners[i], corners[(i + 1) % 3]);
            let p = closest_on_segment(near, dir, a, b);
            screen(p).map(|s| ((s - click).length(), p))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0));
    if let Some((d, p)) = nearest_edge {
        if d <= r {
            return Some(out(p, Snap::Edge));
        }
    }
    Some(out(near + dir * hit.t, Snap::Surface))
}

/// The point of segment `a..b` nearest to the line `o + t d`.
fn closest_on_segment(o: DVec3, d: DVec3, a: DVec3, b: DVec3) -> DVec3 {
    let e = b - a;
    let (dd, ee, de) = (d.dot(d), e.dot(e), d.dot(e));
    let denom = dd * ee - de * de;
    if ee <= 0.0 {
        return a;
    }
    let w = a - o;
    // Parallel lines: any point will do; take the nearer end.
    let s = if denom.abs() <= 1e-12 * dd * ee {
        0.0
    } else {
        ((d.dot(w) * de - dd * e.dot(w)) / denom).clamp(0.0, 1.0)
    };
    a + e * s
}

/// The distance from `a` to `b`.
#[must_use]
pub fn distance(a: Vec3, b: Vec3) -> f64 {
    (b.as_dvec3() - a.as_dvec3()).length()
}

/// The angle at `vertex` between the directions to `a` and `b`, in degrees (`None` when
/// either direction has no length).
#[must_use]
pub fn angle_degrees(a: Vec3, vertex: Vec3, b: Vec3) -> Option<f64> {
    let (u, v) = (
        a.as_dvec3() - vertex.as_dvec3(),
        b.as_dvec3() - vertex.as_dvec3(),
    );
    let (lu, lv) = (u.length(), v.length());
    if lu <= 0.0 || lv <= 0.0 || !(lu * lv).is_finite() {
        return None;
    }
    // atan2 of |u x v| and u.v: accurate at every angle (acos loses digits near 0 and 180).
    Some(libm::atan2(u.cross(v).length(), u.dot(v)).to_degrees())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closest_point_of_a_segment_to_a_ray() {
        // The ray along -z through (0.3, 0, 5); the segment along x at z = 0.
        let p = closest_on_segment(
            DVec3::new(0.3, 0.0, 5.0),
            DVec3::new(0.0, 0.0, -10.0),
            DVec3::new(-1.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
        );
        assert!((p - DVec3::new(0.3, 0.0, 0.0)).length() < 1e-12, "{p}");
        // Past the end: clamped.
        let p = closest_on_segment(
            DVec3::new(3.0, 0.0, 5.0),
            DVec3::new(0.0, 0.0, -10.0),
            DVec3::new(-1.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
        );
        assert_eq!(p, DVec3::new(1.0, 0.0, 0.0));
    }

    #[test]
    fn angles_and_distances() {
        let o = Vec3::ZERO;
        assert!((angle_degrees(Vec3::X, o, Vec3::Y).unwrap() - 90.0).abs() < 1e-12);
        assert!((angle_degrees(Vec3::X, o, Vec3::new(1.0, 1.0, 0.0)).unwrap() - 45.0).abs() < 1e-6);
        assert!((angle_degrees(Vec3::X, o, -Vec3::X).unwrap() - 180.0).abs() < 1e-12);
        assert_eq!(angle_degrees(o, o, Vec3::X), None);
        assert_eq!(distance(Vec3::new(1.0, 2.0, 2.0), Vec3::ZERO), 3.0);
    }
}
