//! Animation, skinning and morph targets of the Khronos samples in
//! `$REALIST_SHARED/models/gltf/khronos/` (reported as ignored when `REALIST_SHARED` is
//! unset), each checked against a direct evaluation written here from what the file says,
//! not through the loader's animation code:
//!
//! - `AnimatedTriangle`: one LINEAR rotation channel turning the triangle about +Z, a
//!   quarter turn every 0.25 s, so at time t the rest triangle is turned by 360° t.
//! - `SimpleMorph`: two morph targets whose weights are keyed (0,0) (0,1) (1,1) (1,0) (0,0)
//!   at t = 0..4; posed positions are linear in the weights: base + w0 d0 + w1 d1.
//! - `SimpleSkin`: a strip skinned to two joints; the second joint, 1 above the root, turns
//!   about +Z by 0, 45, 90, 90, 45, 0, 0, -45, -90, -90, -45, 0 degrees at t = 0, 0.5, ...,
//!   5.5. A vertex with weights (w0, w1) goes to w0 p + w1 (R(p - c) + c), c = (0, 1, 0);
//!   its joints and weights are read from the file's base64 buffers by this test.
//!
//! And golden images of them (and `RiggedSimple`, `BoxAnimated`) at several times.

mod common;

use std::path::PathBuf;

use base64::Engine;
use glam::{Quat, Vec3};
use realist::load::{load, LoadOptions};
use realist::render::{PreparedScene, Settings, Shot};
use realist::scene::{Camera, Play};

/// The Khronos sample `name` in the shared test data (for tests marked as needing it).
fn khronos(name: &str) -> PathBuf {
    realist_testkit::shared(name)
        .join("models/gltf/khronos")
        .join(name)
        .join(format!("{name}.gltf"))
}

fn prepared(path: &std::path::Path) -> PreparedScene {
    let scene = load(path, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    PreparedScene::new(scene)
}

/// Every posed position of every instance, in order.
fn positions(p: &PreparedScene) -> Vec<Vec3> {
    p.world_positions().into_iter().flatten().collect()
}

fn assert_close(got: &[Vec3], want: &[Vec3], tol: f32, what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: vertex count");
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            (*g - *w).length() < tol,
            "{what}: vertex {i} at {g}, expected {w}"
        );
    }
}

/// Accessor `i` of a glTF whose buffers are all `data:` URIs, as f32 rows (float or
/// unsigned short components).
fn accessor(json: &serde_json::Value, i: usize) -> Vec<Vec<f32>> {
    let a = &json["accessors"][i];
    let v = &json["bufferViews"][a["bufferView"].as_u64().unwrap() as usize];
    let uri = json["buffers"][v["buffer"].as_u64().unwrap() as usize]["uri"]
        .as_str()
        .unwrap();
    let bytes = base64::engine::general_purpose::STANDARD
        .decode(uri.split_once(',').unwrap().1)
        .unwrap();
    let n = match a["type"].as_str().unwrap() {
        "SCALAR" => 1,
        "VEC3" => 3,
        "VEC4" => 4,
        t => panic!("type {t}"),
    };
    let size = if a["componentType"] == 5126 { 4 } else { 2 };
    let stride = v["byteStride"].as_u64().unwrap_or((n * size) as u64) as usize;
    let base = v["byteOffset"].as_u64().unwrap_or(0) as usize
        + a["byteOffset"].as_u64().unwrap_or(0) as usize;
    (0..a["count"].as_u64().unwrap() as usize)
        .map(|k| {
            (0..n)
                .map(|c| {
                    let at = base + k * stride + c * size;
                    if size == 4 {
                        f32::from_le_bytes(bytes[at..at + 4].try_into().unwrap())
                    } else {
                        f32::from(u16::from_le_bytes(bytes[at..at + 2].try_into().unwrap()))
                    }
                })
                .collect()
        })
        .collect()
}

#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn animated_triangle_turns_a_full_circle_per_second() {
    let path = khronos("AnimatedTriangle");
    let mut p = prepared(&path);
    assert_eq!(p.scene().animations.len(), 1);
    assert_eq!(p.scene().animations[0].duration(), 1.0);
    p.pose_at(Play::One(0), 0.0, true);
    let rest = positions(&p);
    for t in [0.1f32, 0.3, 0.55, 0.9, 1.3, 7.25] {
        p.pose_at(Play::One(0), t, true);
        let turn = Quat::from_rotation_z(std::f32::consts::TAU * t.fract());
        let want: Vec<Vec3> = rest.iter().map(|&v| turn * v).collect();
        assert_close(&positions(&p), &want, 2e-3, &format!("t = {t}"));
    }
    // Not looping, time past the end holds the last key (a full turn: the rest pose).
    p.pose_at(Play::One(0), 1.3, false);
    assert_close(&positions(&p), &rest, 2e-3, "held at the end");
}

#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn simple_morph_is_linear_in_its_keyed_weights() {
    let path = khronos("SimpleMorph");
    let mut p = prepared(&path);
    let mut at = |t: f32| {
        p.pose_at(Play::One(0), t, false);
        positions(&p)
    };
    let base = at(0.0); // weights (0, 0)
    let d1: Vec<Vec3> = at(1.0).iter().zip(&base).map(|(a, b)| *a - *b).collect();
    let d0: Vec<Vec3> = at(3.0).iter().zip(&base).map(|(a, b)| *a - *b).collect();
    assert!(
        d0.iter().chain(&d1).any(|d| d.length() > 0.1),
        "targets move"
    );
    for (t, w0, w1) in [
        (0.5f32, 0.0f32, 0.5f32),
        (1.5, 0.5, 1.0),
        (2.25, 1.0, 0.75),
        (3.5, 0.5, 0.0),
    ] {
        let want: Vec<Vec3> = (0..base.len())
            .map(|i| base[i] + d0[i] * w0 + d1[i] * w1)
            .collect();
        assert_close(&at(t), &want, 1e-4, &format!("t = {t}"));
    }
    // At rest the mesh's own weights (0.5, 0.5) apply.
    let mut rest = prepared(&path);
    rest.pose_at(Play::Rest, 0.0, false);
    let want: Vec<Vec3> = (0..base.len())
        .map(|i| base[i] + (d0[i] + d1[i]) * 0.5)
        .collect();
    assert_close(&positions(&rest), &want, 1e-4, "rest weights");
}

#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn simple_skin_bends_by_its_joint_rotation() {
    let path = khronos("SimpleSkin");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let attrs = &json["meshes"][0]["primitives"][0]["attributes"];
    let of = |name: &str| accessor(&json, attrs[name].as_u64().unwrap() as usize);
    let (file_pos, joints, weights) = (of("POSITION"), of("JOINTS_0"), of("WEIGHTS_0"));
    let mut p = prepared(&path);
    // The file's keys are rotations about +Z written (z, w) = (0.383, 0.924) for 45° and
    // (0.707, 0.707) for 90°: their angles 2 atan2(z, w) are used, so 45° is 45.03°.
    let (a45, a90) = (
        2.0 * libm::atan2f(0.383f32, 0.924),
        2.0 * libm::atan2f(0.707f32, 0.707),
    );
    let keys = [
        0.0, a45, a90, a90, a45, 0.0, 0.0, -a45, -a90, -a90, -a45, 0.0,
    ];
    let angle = |t: f32| {
        let k = ((t / 0.5) as usize).min(keys.len() - 2);
        let s = (t - k as f32 * 0.5) / 0.5;
        keys[k] + (keys[k + 1] - keys[k]) * s
    };
    let pivot = Vec3::Y;
    for t in [0.0f32, 0.25, 0.75, 1.25, 2.6, 3.75, 5.2] {
        p.pose_at(Play::One(0), t, false);
        let r = Quat::from_rotation_z(angle(t));
        let want: Vec<Vec3> = (0..file_pos.len())
            .map(|v| {
                let x = Vec3::from_slice(&file_pos[v]);
                let turned = r * (x - pivot) + pivot;
                let mut out = Vec3::ZERO;
                for (j, w) in joints[v].iter().zip(&weights[v]) {
                    out += *w * if *j == 1.0 { turned } else { x };
                }
                out
            })
            .collect();
        // The mesh is not welded, so its vertices are the file's, in order.
        assert_close(&positions(&p), &want, 1e-4, &format!("t = {t}"));
    }
}

/// Renders `path` at each time of all its animations together, from `elevation` degrees,
/// framed on the union of the posed bounds, and compares with
/// `tests/golden/anim-NAME-T.png`.
fn goldens(name: &str, elevation: f32, times: &[f32]) {
    let path = khronos(name);
    let mut p = prepared(&path);
    let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    for &t in times {
        p.pose_at(Play::All, t, true);
        let (a, b) = p.bounds().expect("bounds");
        (lo, hi) = (lo.min(a), hi.max(b));
    }
    let (w, h) = (160, 120);
    let opts = Shot {
        width: w,
        height: h,
        camera: Some(Camera::frame_box(
            lo,
            hi,
            w as f32 / h as f32,
            20.0,
            elevation,
        )),
        settings: Settings {
            double_sided: true,
            ..Settings::default()
        },
    };
    let view = opts.view(p.scene());
    let settings = opts.settings;
    for &t in times {
        p.pose_at(Play::All, t, true);
        let fb = common::render_prepared(&p, &settings, &view, 2).0;
        common::assert_finite(&fb, name);
        let tol = common::Tolerance {
            max_channel: 8,
            max_fraction: 0.002,
        };
        common::check_golden(&format!("anim-{name}-{t}"), &fb, tol);
    }
}

#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn khronos_animation_goldens() {
    goldens("AnimatedTriangle", 15.0, &[0.0, 0.125, 0.5]);
    goldens("SimpleMorph", 15.0, &[0.5, 2.0, 3.5]);
    goldens("SimpleSkin", 15.0, &[0.0, 1.0, 4.25]);
    goldens("RiggedSimple", 15.0, &[0.0, 1.0, 2.0]);
    goldens("BoxAnimated", 50.0, &[0.0, 1.0, 2.5]);
}
