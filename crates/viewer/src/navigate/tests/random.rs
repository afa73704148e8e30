//! Random sequences of user actions: the camera must stay finite with 0 < near < far, the
//! scene sphere inside near..far whenever it is wholly in front of the eye (always, when
//! orthographic), and turntable orbits must never roll.

use glam::{Vec2, Vec3, Vec4};
use proptest::prelude::*;

use super::{sphere_points, H};
use crate::navigate::{Mode, Navigator, UpAxis, View};

/// One random user action.
#[derive(Clone, Debug)]
enum Op {
    Orbit(f32, f32),
    Pan(f32, f32),
    Dolly(f32),
    DollyAt(f32, Vec2),
    CenterOn(Vec3),
    Frame(f32),
    View(usize),
    UpAxis(bool),
    Mode(bool),
    Ortho,
    Fov(f32),
    Reset,
    SetHome,
}

fn op() -> impl Strategy<Value = Op> {
    let px = -3000.0f32..3000.0;
    let ndc = (-1.2f32..1.2, -1.2f32..1.2).prop_map(|(x, y)| Vec2::new(x, y));
    let point =
        (-50.0f32..50.0, -50.0f32..50.0, -50.0f32..50.0).prop_map(|(x, y, z)| Vec3::new(x, y, z));
    prop_oneof![
        (px.clone(), px.clone()).prop_map(|(x, y)| Op::Orbit(x, y)),
        (px.clone(), px).prop_map(|(x, y)| Op::Pan(x, y)),
        (-40.0f32..40.0).prop_map(Op::Dolly),
        (-40.0f32..40.0, ndc).prop_map(|(s, c)| Op::DollyAt(s, c)),
        point.prop_map(Op::CenterOn),
        (0.1f32..4.0).prop_map(Op::Frame),
        (0..View::ALL.len()).prop_map(Op::View),
        any::<bool>().prop_map(Op::UpAxis),
        any::<bool>().prop_map(Op::Mode),
        Just(Op::Ortho),
        (-10.0f32..200.0).prop_map(Op::Fov),
        Just(Op::Reset),
        Just(Op::SetHome),
    ]
}

proptest! {
    /// Any sequence of actions leaves a finite camera whose near/far enclose the scene
    /// sphere whenever it is wholly in front of the eye, with 0 < near < far; turntable
    /// orbits never roll.
    #[test]
    fn random_operations_keep_the_camera_sane(ops in prop::collection::vec(op(), 1..40), aspect in 0.3f32..3.0) {
        let (center, radius) = (Vec3::new(2.0, -1.0, 3.0), 1.5);
        let mut nav = Navigator::new(center, radius, aspect);
        for op in ops {
            match op.clone() {
                Op::Orbit(x, y) => nav.orbit(x, y, H),
                Op::Pan(x, y) => nav.pan(x, y, H),
                Op::Dolly(s) => nav.dolly(s),
                Op::DollyAt(s, c) => nav.dolly_at(s, c, aspect),
                Op::CenterOn(p) => nav.center_on(p),
                Op::Frame(scale) => nav.frame(center, radius * scale, aspect),
                Op::View(i) => nav.set_view(View::ALL[i]),
                Op::UpAxis(z) => nav.set_up_axis(if z { UpAxis::Z } else { UpAxis::Y }, aspect),
                Op::Mode(t) => nav.set_mode(if t { Mode::Turntable } else { Mode::Trackball }),
                Op::Ortho => nav.toggle_ortho(),
                Op::Fov(f) => nav.set_fov_degrees(f),
                Op::Reset => nav.reset(),
                Op::SetHome => nav.set_home(),
            }
            let cam = nav.camera(aspect);
            prop_assert!(cam.eye.is_finite() && cam.target.is_finite() && cam.up.is_finite(), "{cam:?}");
            prop_assert!(cam.near > 0.0 && cam.near < cam.far && cam.far.is_finite(), "{cam:?}");
            let m = cam.projection(aspect) * cam.view();
            prop_assert!(m.is_finite(), "{cam:?}");
            let (c, r) = nav.scene();
            let nearest = (c - cam.eye).dot(cam.forward()) - r;
            // An orthographic eye is free to stand back: nothing is ever behind it.
            prop_assert!(nearest > 0.0 || cam.ortho.is_none(), "ortho eye inside {cam:?}");
            for p in sphere_points(c, r, 64) {
                let depth = -(cam.view() * Vec4::from((p, 1.0))).z;
                prop_assert!(depth <= cam.far, "depth {depth} beyond far {}", cam.far);
                if nearest > 0.0 {
                    prop_assert!(depth >= cam.near, "depth {depth} before near {}", cam.near);
                }
            }
            if nav.mode() == Mode::Turntable && matches!(op, Op::Orbit(..)) {
                // The orientation itself, not `eye - target`: at the minimum distance far from
                // the origin that difference has only a few significant bits of direction.
                let right = nav.pose.rotation * Vec3::X;
                prop_assert!(right.dot(nav.up_axis().up()).abs() < 1e-5, "roll {cam:?}");
            }
        }
    }
}
