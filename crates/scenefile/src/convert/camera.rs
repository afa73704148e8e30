//! The `[camera]` table: its checks, and the camera it gives (an orbit around the scene's
//! bounds, or an eye looking at a target).

use super::*;

/// An orbit camera around `scene`'s bounds: from `azimuth` degrees around the up axis `up`
/// and `elevation` degrees above the horizon; at `distance` (scene units) if given, else at
/// the distance that frames the bounding box. `yfov` in radians (default 45 degrees).
#[must_use]
pub fn orbit_camera(
    scene: &Scene,
    aspect: f32,
    azimuth: f32,
    elevation: f32,
    distance: Option<f32>,
    yfov: Option<f32>,
    up: Up,
) -> Camera {
    let (lo, hi) = scene.bounds().unwrap_or((Vec3::splat(-1.0), Vec3::ONE));
    let yfov = clamp_fov(yfov.unwrap_or(DEFAULT_YFOV));
    // Framed in the Y-up frame, turned back (the identity for Y).
    let (lo, hi) = up.box_to_y_up(lo, hi);
    let (center, radius) = ((lo + hi) * 0.5, ((hi - lo) * 0.5).length().max(1e-6));
    let framed = Camera::frame_box_fov(lo, hi, aspect, azimuth, elevation, yfov);
    let cam = match distance {
        None => framed,
        Some(d) => {
            let mut cam = Camera::orbit(center, azimuth, elevation, d, framed.yfov);
            cam.fit(center, radius);
            cam
        }
    };
    cam.turned(up.to_y_up().inverse())
}

/// Checks a `[camera]` table without a model.
pub(crate) fn check_camera(s: &CameraSpec) -> Result<(), Bad> {
    let look = s.eye.is_some() || s.target.is_some() || s.up.is_some();
    let orbit = s.azimuth.is_some() || s.elevation.is_some() || s.distance.is_some();
    if s.gltf.is_some() && (look || orbit) {
        return Err(bad(
            "gltf",
            "a file camera takes no eye, target, up, azimuth, elevation or distance",
        ));
    }
    if look && orbit {
        return Err(bad(
            "eye",
            "give eye/target/up or azimuth/elevation/distance, not both",
        ));
    }
    if (s.target.is_some() || s.up.is_some()) && s.eye.is_none() {
        return Err(bad("eye", "target and up need an eye"));
    }
    for (k, v) in [("eye", s.eye), ("target", s.target)] {
        if let Some(v) = v {
            vec3(k, v)?;
        }
    }
    if let Some(u) = s.up {
        nonzero("up", u)?;
    }
    if let (Some(e), Some(t)) = (s.eye, s.target) {
        if e == t {
            return Err(bad("target", "is the eye"));
        }
    }
    if let Some(a) = s.azimuth {
        ranged("azimuth", a, -3600.0, 3600.0)?;
    }
    if let Some(e) = s.elevation {
        ranged("elevation", e, -90.0, 90.0)?;
    }
    if let Some(d) = s.distance {
        if ranged("distance", d, 0.0, MAX_COORD)? <= 0.0 {
            return Err(bad("distance", "must be above 0"));
        }
    }
    if let Some(f) = s.yfov {
        let f = ranged("yfov", f, 0.1, 179.0)?;
        debug_assert!(f > 0.0);
    }
    for (k, v) in [("near", s.near), ("far", s.far), ("ortho", s.ortho)] {
        if let Some(v) = v {
            if ranged(k, v, 0.0, MAX_COORD)? <= 0.0 {
                return Err(bad(k, "must be above 0"));
            }
        }
    }
    if let (Some(n), Some(f)) = (s.near, s.far) {
        if n >= f {
            return Err(bad("near", format!("{n} is not below far ({f})")));
        }
    }
    Ok(())
}

/// Resolves a checked `[camera]` against `scene` (keys without the `camera.` prefix).
pub(crate) fn camera(s: &CameraSpec, scene: &Scene, aspect: f32, up: Up) -> Result<Camera, Bad> {
    check_camera(s)?;
    let yfov = s.yfov.map(|f| (f as f32).to_radians());
    let (lo, hi) = scene.bounds().unwrap_or((Vec3::splat(-1.0), Vec3::ONE));
    let (center, radius) = ((lo + hi) * 0.5, ((hi - lo) * 0.5).length().max(1e-6));
    let mut cam = if let Some(n) = s.gltf {
        let count = scene.cameras.len();
        let file = &scene.report.file;
        let Some(c) = scene.cameras.get(n) else {
            return Err(bad(
                "gltf",
                if count == 0 {
                    format!("{file} has no cameras")
                } else {
                    format!("{file} has {count} camera(s) (0 to {}), not {n}", count - 1)
                },
            ));
        };
        let mut c = c.clone();
        if let Some(f) = yfov {
            c.yfov = f;
        }
        c
    } else if let Some(eye) = s.eye {
        let v = |a: [f64; 3]| Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32);
        let mut c = Camera {
            name: "scene file".into(),
            eye: v(eye),
            target: s.target.map_or(center, v),
            up: s.up.map_or(up.vector(), v),
            yfov: yfov.unwrap_or(DEFAULT_YFOV),
            ..Camera::default()
        };
        c.fit(center, radius);
        c
    } else {
        let mut c = orbit_camera(
            scene,
            aspect,
            s.azimuth.map_or(35.0, |a| a as f32),
            s.elevation.map_or(25.0, |e| e as f32),
            s.distance.map(|d| d as f32),
            yfov,
            up,
        );
        c.name = "scene file".into();
        c
    };
    if let Some(h) = s.ortho {
        cam.ortho = Some(h as f32);
    }
    if let Some(n) = s.near {
        cam.near = n as f32;
    }
    if let Some(f) = s.far {
        cam.far = f as f32;
    }
    if !(cam.near > 0.0 && cam.near < cam.far) {
        return Err(bad(
            if s.near.is_some() { "near" } else { "far" },
            format!("near {} must be below far {}", cam.near, cam.far),
        ));
    }
    Ok(cam)
}
