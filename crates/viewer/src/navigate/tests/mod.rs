//! Tests of the navigator: angles, pointer invariants (the point under the cursor stays under
//! it), framing, named views; random operation sequences that must keep the camera sane are
//! in [`random`].

use super::*;
use glam::{Vec2, Vec3};

mod random;

const H: f32 = 600.0;
const W: f32 = 900.0;
const ASPECT: f32 = W / H;

/// World point -> (NDC x, NDC y, view depth) through `camera.projection(aspect) * camera.view()`.
fn project(camera: &Camera, aspect: f32, p: Vec3) -> Vec3 {
    let clip = camera.projection(aspect) * camera.view() * p.extend(1.0);
    let depth = -(camera.view() * p.extend(1.0)).z;
    Vec3::new(clip.x / clip.w, clip.y / clip.w, depth)
}

fn ndc(camera: &Camera, aspect: f32, p: Vec3) -> Vec2 {
    project(camera, aspect, p).truncate()
}

/// `n` points spread evenly over a sphere (Fibonacci lattice).
fn sphere_points(center: Vec3, radius: f32, n: usize) -> Vec<Vec3> {
    let golden = PI * (3.0 - 5f32.sqrt());
    (0..n)
        .map(|i| {
            let y = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
            let ring = (1.0 - y * y).sqrt();
            let (s, c) = libm::sincosf(golden * i as f32);
            center + Vec3::new(c * ring, y, s * ring) * radius
        })
        .collect()
}

fn assert_near(a: Vec3, b: Vec3, tol: f32, what: &str) {
    assert!((a - b).abs().max_element() < tol, "{what}: {a} vs {b}");
}

fn forward(nav: &Navigator) -> Vec3 {
    nav.camera(ASPECT).forward()
}

/// The camera's right vector (screen x) in world space.
fn right(camera: &Camera) -> Vec3 {
    camera.forward().cross(camera.up).normalize()
}

fn navigator(ortho: bool) -> Navigator {
    let mut nav = Navigator::new(Vec3::new(1.0, -2.0, 0.5), 3.0, ASPECT);
    nav.set_ortho(ortho);
    nav
}

#[test]
fn turntable_orbit_turns_180_degrees_per_viewport_height() {
    let mut nav = navigator(false);
    nav.set_view(View::Front);
    nav.orbit(H / 2.0, 0.0, H);
    // Dragging right moves the eye to its left: from +Z round to -X, looking along +X.
    assert_near(forward(&nav), Vec3::X, 1e-5, "half height");
    nav.orbit(H / 2.0, 0.0, H);
    assert_near(forward(&nav), Vec3::Z, 1e-5, "full height");
    nav.set_view(View::Front);
    nav.orbit(0.0, H * 30.0 / 180.0, H);
    // Dragging down raises the eye by 30 degrees.
    let f = forward(&nav);
    assert!(
        (libm::asinf(f.dot(-Vec3::Y)).to_degrees() - 30.0).abs() < 1e-3,
        "{f}"
    );
}

#[test]
fn trackball_orbit_turns_freely_and_rolls_the_up_vector() {
    let mut nav = navigator(false);
    nav.set_view(View::Front);
    nav.set_mode(Mode::Trackball);
    nav.orbit(0.0, H / 2.0, H);
    let cam = nav.camera(ASPECT);
    assert_near(cam.forward(), -Vec3::Y, 1e-5, "over the top");
    assert_near(cam.up, -Vec3::Z, 1e-5, "up turned with the view");
    nav.orbit(0.0, H / 2.0, H);
    let cam = nav.camera(ASPECT);
    assert_near(cam.forward(), Vec3::Z, 1e-5, "behind");
    assert_near(cam.up, -Vec3::Y, 1e-5, "upside down");
    // A diagonal drag of one viewport height turns 180 degrees about the perpendicular axis.
    nav.set_view(View::Front);
    nav.orbit(H * 0.6, H * 0.8, H);
    assert!(nav.camera(ASPECT).forward().dot(Vec3::Z) > 1.0 - 1e-5);
}

#[test]
fn turntable_pitch_is_clamped_and_named_poles_are_kept() {
    for up_axis in [UpAxis::Y, UpAxis::Z] {
        let mut nav = navigator(false);
        nav.set_up_axis(up_axis, ASPECT);
        let up = up_axis.up();
        for (dy, sign) in [(10.0 * H, -1.0), (-10.0 * H, 1.0)] {
            nav.orbit(37.0, dy, H);
            let pitch = libm::asinf(forward(&nav).dot(up) * sign).to_degrees();
            assert!((pitch - PITCH_LIMIT_DEGREES).abs() < 1e-3, "{pitch}");
        }
        nav.set_view(View::Top);
        nav.orbit(50.0, 50.0, H);
        assert_near(forward(&nav), -up, 1e-6, "top stays at the pole");
        nav.orbit(0.0, -H / 18.0, H);
        let pitch = libm::asinf(-forward(&nav).dot(up)).to_degrees();
        assert!((pitch - 80.0).abs() < 1e-2, "{pitch}");
    }
}

#[test]
fn turntable_keeps_the_horizon_level_and_mode_switches_keep_the_view() {
    for up_axis in [UpAxis::Y, UpAxis::Z] {
        let up = up_axis.up();
        let mut nav = navigator(false);
        nav.set_up_axis(up_axis, ASPECT);
        for i in 0..50 {
            nav.orbit(
                libm::sinf(i as f32 * 1.7) * 80.0,
                libm::cosf(i as f32 * 0.9) * 60.0,
                H,
            );
            let cam = nav.camera(ASPECT);
            assert!(right(&cam).dot(up).abs() < 1e-5, "roll at step {i}");
            assert!(cam.up.dot(up) >= 0.0, "upside down at step {i}");
        }
        nav.set_mode(Mode::Trackball);
        nav.orbit(120.0, -70.0, H);
        nav.orbit(-30.0, 200.0, H);
        let rolled = nav.camera(ASPECT);
        assert!(right(&rolled).dot(up).abs() > 0.05, "trackball should roll");
        nav.set_mode(Mode::Trackball);
        assert_eq!(nav.camera(ASPECT), rolled, "same mode is a no-op");
        nav.set_mode(Mode::Turntable);
        let level = nav.camera(ASPECT);
        assert_near(level.eye, rolled.eye, 1e-4, "eye kept");
        assert_near(level.forward(), rolled.forward(), 1e-5, "view kept");
        assert!(right(&level).dot(up).abs() < 1e-5);
    }
}

#[test]
fn pan_keeps_the_point_under_the_cursor() {
    for ortho in [false, true] {
        let mut nav = navigator(ortho);
        nav.orbit(40.0, 25.0, H);
        let cam = nav.camera(ASPECT);
        let half = nav.half_height();
        // A point at the target's depth, up and to the right of the centre.
        let p = cam.target + (right(&cam) * 0.7 * ASPECT + cam.up * 0.4) * half;
        let before = ndc(&cam, ASPECT, p);
        let (dx, dy) = (-73.0, 41.0);
        nav.pan(dx, dy, H);
        let after = ndc(&nav.camera(ASPECT), ASPECT, p);
        let expected = before + Vec2::new(2.0 * dx / W, -2.0 * dy / H);
        assert!(
            (after - expected).abs().max_element() < 1e-4,
            "ortho {ortho}: {after} vs {expected}"
        );
    }
}

#[test]
fn dolly_at_keeps_the_point_under_the_cursor() {
    for ortho in [false, true] {
        for steps in [3.0, -2.5, 0.4] {
            let mut nav = navigator(ortho);
            nav.orbit(-90.0, 30.0, H);
            let cam = nav.camera(ASPECT);
            let cursor = Vec2::new(0.6, -0.35);
            let half = nav.half_height();
            let p = cam.target + (right(&cam) * cursor.x * ASPECT + cam.up * cursor.y) * half;
            assert!((ndc(&cam, ASPECT, p) - cursor).abs().max_element() < 1e-4);
            // A second point on the cursor's ray, nearer the eye (perspective) or behind
            // (orthographic): it stays put as well.
            let q = if ortho {
                p + cam.forward() * 2.0
            } else {
                cam.eye + (p - cam.eye) * 0.6
            };
            let distance = nav.distance();
            nav.dolly_at(steps, cursor, ASPECT);
            let expected = distance * libm::powf(DOLLY_PER_STEP, steps);
            assert!((nav.distance() / expected - 1.0).abs() < 1e-5);
            let cam = nav.camera(ASPECT);
            for (point, what) in [(p, "target plane"), (q, "on the ray")] {
                let after = ndc(&cam, ASPECT, point);
                assert!(
                    (after - cursor).abs().max_element() < 1e-4,
                    "ortho {ortho}, steps {steps}, {what}: {after}"
                );
            }
            // The target stays on the line of sight at the new distance.
            assert!(((cam.target - cam.eye).length() / nav.distance() - 1.0).abs() < 1e-4 || ortho);
        }
    }
}

#[test]
fn dolly_is_exponential_and_clamped() {
    let mut nav = navigator(false);
    let d = nav.distance();
    nav.dolly(1.0);
    assert!((nav.distance() / d - 0.9).abs() < 1e-6);
    nav.dolly(-1.0);
    assert!((nav.distance() / d - 1.0).abs() < 1e-6);
    let (_, r) = nav.scene();
    for (steps, bound) in [(1e9, DISTANCE_RANGE.0), (-1e9, DISTANCE_RANGE.1)] {
        nav.dolly(steps);
        assert!((nav.distance() / (bound * r) - 1.0).abs() < 1e-5, "{steps}");
        let cam = nav.camera(ASPECT);
        assert!(cam.near > 0.0 && cam.near < cam.far && cam.far.is_finite());
    }
    let before = nav.clone();
    nav.dolly(f32::NAN);
    nav.dolly_at(f32::INFINITY, Vec2::ZERO, ASPECT);
    nav.dolly_at(1.0, Vec2::NAN, ASPECT);
    nav.orbit(f32::NAN, 1.0, H);
    nav.pan(1.0, 1.0, 0.0);
    nav.center_on(Vec3::INFINITY);
    assert_eq!(nav, before, "non-finite input is ignored");
}

#[test]
fn framing_fits_the_sphere_with_ten_percent_margin() {
    let (center, radius) = (Vec3::new(5.0, 1.0, -3.0), 2.0);
    let points = sphere_points(center, radius, 4000);
    for ortho in [false, true] {
        for aspect in [0.5, 1.0, 2.5] {
            for fov in [20.0f32, 45.0, 90.0] {
                let mut nav = navigator(ortho);
                nav.set_fov_degrees(fov);
                nav.orbit(123.0, -45.0, H);
                nav.frame(center, radius, aspect);
                let cam = nav.camera(aspect);
                let mut extent = Vec2::ZERO;
                for &p in &points {
                    let q = project(&cam, aspect, p);
                    assert!(
                        q.z > cam.near && q.z < cam.far,
                        "depth {} in {}..{}",
                        q.z,
                        cam.near,
                        cam.far
                    );
                    extent = extent.max(q.truncate().abs());
                }
                let half_v = fov.to_radians() / 2.0;
                let half_h = libm::atanf(libm::tanf(half_v) * aspect);
                // Silhouette of the sphere on the tighter axis, in NDC.
                let expected = if ortho {
                    1.0 / FRAME_PADDING
                } else {
                    let half = half_v.min(half_h);
                    libm::tanf(libm::asinf(libm::sinf(half) / FRAME_PADDING)) / libm::tanf(half)
                };
                let tight = if half_h < half_v { extent.x } else { extent.y };
                let what = format!("ortho {ortho} aspect {aspect} fov {fov}: {extent}");
                assert!(extent.max_element() <= 1.0, "{what}");
                assert!(
                    (tight - expected).abs() < 5e-3,
                    "{what}, expected {expected}"
                );
                assert!(expected > 0.8, "{what}");
            }
        }
    }
}

#[test]
fn named_views_look_along_the_documented_axes() {
    let s = 1.0 / 3f32.sqrt();
    // (view, looking along with Y up, with Z up)
    let table = [
        (View::Front, Vec3::NEG_Z, Vec3::Y),
        (View::Back, Vec3::Z, Vec3::NEG_Y),
        (View::Right, Vec3::NEG_X, Vec3::NEG_X),
        (View::Left, Vec3::X, Vec3::X),
        (View::Top, Vec3::NEG_Y, Vec3::NEG_Z),
        (View::Bottom, Vec3::Y, Vec3::Z),
        (View::Isometric, Vec3::new(-s, -s, -s), Vec3::new(-s, s, -s)),
    ];
    for (up_axis, column) in [(UpAxis::Y, 0), (UpAxis::Z, 1)] {
        let mut nav = navigator(false);
        nav.set_up_axis(up_axis, ASPECT);
        for (view, along_y, along_z) in table {
            nav.set_view(view);
            let along = if column == 0 { along_y } else { along_z };
            let cam = nav.camera(ASPECT);
            assert_near(cam.forward(), along, 1e-6, &format!("{view:?} {up_axis:?}"));
            let up = up_axis.up();
            match view {
                // Top: screen up points away from the front viewer; bottom: towards them.
                View::Top => assert_near(cam.up, -nav_front_eye(up_axis), 1e-6, "top up"),
                View::Bottom => assert_near(cam.up, nav_front_eye(up_axis), 1e-6, "bottom up"),
                _ => assert!(right(&cam).dot(up).abs() < 1e-6 && cam.up.dot(up) > 0.0),
            }
            assert!(cam.view().is_finite());
        }
    }
}

/// The direction from the target to the eye in the front view.
fn nav_front_eye(up_axis: UpAxis) -> Vec3 {
    match up_axis {
        UpAxis::Y => Vec3::Z,
        UpAxis::Z => Vec3::NEG_Y,
    }
}

#[test]
fn ortho_toggle_and_fov_keep_the_apparent_size_at_the_target() {
    let mut nav = navigator(false);
    nav.orbit(10.0, 20.0, H);
    let cam = nav.camera(ASPECT);
    let p = cam.target + right(&cam) * 0.8 + cam.up * 0.5;
    let before = ndc(&cam, ASPECT, p);
    nav.toggle_ortho();
    let ortho = nav.camera(ASPECT);
    assert!(nav.is_ortho());
    assert!(
        (ortho.ortho.unwrap_or(0.0) - nav.distance() * libm::tanf(ortho.yfov / 2.0)).abs() < 1e-5
    );
    assert!((ndc(&ortho, ASPECT, p) - before).abs().max_element() < 1e-5);
    nav.set_fov_degrees(20.0);
    assert!(
        (ndc(&nav.camera(ASPECT), ASPECT, p) - before)
            .abs()
            .max_element()
            < 1e-5
    );
    nav.toggle_ortho();
    nav.set_fov_degrees(70.0);
    assert!((nav.fov_degrees() - 70.0).abs() < 1e-4);
    assert!(
        (ndc(&nav.camera(ASPECT), ASPECT, p) - before)
            .abs()
            .max_element()
            < 1e-5
    );
    nav.set_fov_degrees(500.0);
    assert!((nav.fov_degrees() - FOV_RANGE_DEGREES.1).abs() < 1e-4);
    nav.set_fov_degrees(-3.0);
    assert!((nav.fov_degrees() - FOV_RANGE_DEGREES.0).abs() < 1e-4);
}

#[test]
fn center_on_moves_the_target_keeping_direction_and_distance() {
    let mut nav = navigator(false);
    nav.orbit(33.0, -12.0, H);
    let before = nav.camera(ASPECT);
    let d = nav.distance();
    let point = before.target + Vec3::new(0.4, 0.9, -0.3);
    nav.center_on(point);
    let after = nav.camera(ASPECT);
    assert_eq!(nav.target(), point);
    assert!((nav.distance() - d).abs() < 1e-6);
    assert_near(after.forward(), before.forward(), 1e-6, "direction");
    assert_near(after.up, before.up, 1e-6, "roll");
    assert!(ndc(&after, ASPECT, point).abs().max_element() < 1e-5);
}

#[test]
fn reset_up_axis_and_file_cameras() {
    let mut nav = navigator(false);
    let home = nav.camera(ASPECT);
    nav.orbit(100.0, 50.0, H);
    nav.pan(20.0, 5.0, H);
    nav.dolly_at(2.0, Vec2::new(0.3, 0.3), ASPECT);
    nav.set_fov_degrees(30.0);
    nav.reset();
    assert_eq!(nav.camera(ASPECT), home);

    // Z up: the default view is from above the XY plane, in front (-Y side) and to the right.
    nav.set_up_axis(UpAxis::Z, ASPECT);
    let cam = nav.camera(ASPECT);
    let eye = cam.eye - cam.target;
    assert!(eye.z > 0.0 && eye.y < 0.0 && eye.x > 0.0, "{eye}");
    assert_eq!(cam.target, nav.scene().0);
    assert_eq!(nav.up_axis(), UpAxis::Z);

    // A file camera round-trips, perspective and orthographic.
    for ortho in [false, true] {
        let mut nav = navigator(ortho);
        nav.set_mode(Mode::Trackball);
        nav.orbit(77.0, 140.0, H);
        let cam = nav.camera(ASPECT);
        let (center, radius) = nav.scene();
        let from = Navigator::from_camera(&cam, center, radius, UpAxis::Y);
        let again = from.camera(ASPECT);
        assert_near(again.eye, cam.eye, 1e-4, "eye");
        assert_near(again.up, cam.up, 1e-5, "up");
        assert_eq!(again.ortho.is_some(), ortho);
        assert!((again.ortho.unwrap_or(0.0) - cam.ortho.unwrap_or(0.0)).abs() < 1e-4);
    }
}

#[test]
fn pixels_map_to_ndc_with_y_up() {
    let size = Vec2::new(W, H);
    assert_eq!(pixel_to_ndc(Vec2::ZERO, size), Vec2::new(-1.0, 1.0));
    assert_eq!(pixel_to_ndc(size, size), Vec2::new(1.0, -1.0));
    assert_eq!(pixel_to_ndc(size / 2.0, size), Vec2::ZERO);
}
