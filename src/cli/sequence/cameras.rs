//! The cameras of a sequence: a turntable's views around the scene, and each framing it
//! from every direction (or every pose) so that the framing stays fixed.

use glam::{Mat3, Vec3};

use realist::render::PreparedScene;
use realist::scene::{Camera, Up};

use super::SeqFrame;

/// For an animated sequence whose camera was framed on the scene (`framed`): every
/// camera moved to frame the union of the posed bounds at all the frames' times, at the
/// largest distance any frame's direction needs, so the framing stays fixed.
pub(crate) fn frame_animation(
    frames: &mut [SeqFrame],
    scene: &mut PreparedScene,
    aspect: f32,
    framed: bool,
) {
    if !framed || frames.iter().all(|f| f.time.is_none()) {
        return;
    }
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for f in frames.iter() {
        scene.pose_at(f.play, f.time.unwrap_or(0.0), false);
        if let Some((a, b)) = scene.bounds() {
            (lo, hi) = (lo.min(a), hi.max(b));
        }
    }
    if lo.x > hi.x {
        return;
    }
    let center = (lo + hi) * 0.5;
    let framed: Vec<(Vec3, f32)> = frames
        .iter()
        .map(|f| {
            let (az, el, _) = orbit_of(f.camera.eye, f.camera.target);
            let c = Camera::frame_box_fov(lo, hi, aspect, az, el, f.camera.yfov);
            let d = c.eye - c.target;
            (d.normalize_or_zero(), d.length())
        })
        .collect();
    let far = framed
        .iter()
        .map(|x| x.1)
        .filter(|d| d.is_finite())
        .fold(0.0, f32::max);
    if far <= 0.0 {
        return;
    }
    for (f, (dir, _)) in frames.iter_mut().zip(framed) {
        f.camera.eye = center + dir * far;
        f.camera.target = center;
        f.camera.fit(center, ((hi - lo) * 0.5).length().max(1e-6));
    }
}

/// `n` cameras: `base` turned by 360°·i/n around the vertical axis through `pivot` (eye,
/// target and up turn together; the first is `base`).
pub(crate) fn turntable(base: &Camera, pivot: Vec3, n: u32, up: Up) -> Vec<Camera> {
    (0..n)
        .map(|i| {
            let angle = std::f32::consts::TAU * i as f32 / n as f32;
            let turn = match up {
                Up::Y => Mat3::from_rotation_y(angle),
                Up::Z => Mat3::from_rotation_z(angle),
            };
            Camera {
                eye: pivot + turn * (base.eye - pivot),
                target: pivot + turn * (base.target - pivot),
                up: turn * base.up,
                ..base.clone()
            }
        })
        .collect()
}

/// Azimuth (degrees around +Y, 0 = on +Z), elevation (degrees) and distance of `eye` seen
/// from `pivot`.
pub(crate) fn orbit_of(eye: Vec3, pivot: Vec3) -> (f32, f32, f32) {
    let d = eye - pivot;
    let dist = d.length();
    let az = libm::atan2f(d.x, d.z).to_degrees();
    let el = if dist > 0.0 {
        libm::asinf((d.y / dist).clamp(-1.0, 1.0)).to_degrees()
    } else {
        0.0
    };
    (az, el, dist)
}

/// `base` (framing the box `lo..hi` from its direction) moved back along its line of sight
/// to the largest of the distances that frame the box from the `n` turntable directions.
pub(super) fn frame_every_azimuth(
    base: &Camera,
    lo: Vec3,
    hi: Vec3,
    aspect: f32,
    n: u32,
    up: Up,
) -> Camera {
    if up != Up::Y {
        // In the Y-up frame, and turned back.
        let q = up.to_y_up();
        let (lo, hi) = up.box_to_y_up(lo, hi);
        let c = frame_every_azimuth(&base.clone().turned(q), lo, hi, aspect, n, Up::Y);
        return c.turned(q.inverse());
    }
    let center = (lo + hi) * 0.5;
    let (az, el, dist) = orbit_of(base.eye, center);
    let far = (0..n)
        .map(|i| {
            let a = az + 360.0 * i as f32 / n as f32;
            let c = Camera::frame_box_fov(lo, hi, aspect, a, el, base.yfov);
            (c.eye - c.target).length()
        })
        .filter(|d| d.is_finite())
        .fold(dist, f32::max);
    let mut cam = base.clone();
    if far > dist && dist > 0.0 {
        cam.eye = center + (base.eye - center) * (far / dist);
        cam.fit(center, ((hi - lo) * 0.5).length().max(1e-6));
    }
    cam
}
