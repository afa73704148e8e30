//! `KHR_lights_punctual`: lights from nodes, units, defaults and malformed entries.

use std::f32::consts::{FRAC_PI_2, FRAC_PI_4};

use glam::Vec3;
use serde_json::json;

use super::*;
use crate::scene::{Attenuation, LightKind};

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1e-5
}

#[test]
fn punctual_lights_are_placed_by_their_nodes() {
    let mut d = Doc::default();
    let tri = d.floats(&TRI, "VEC3");
    // Node 1: a sun rotated -90 degrees about X, so its -Z points down (-Y).
    // Node 2: a spot at (0, 2, 0) under a parent translated by (1, 0, 0), rotated to shine
    // along +X (90 degrees about Y turns -Z into -X; -90 turns it into +X).
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let text = d.finish(json!({
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensionsRequired": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "directional", "name": "sun", "color": [1.0, 0.9, 0.8], "intensity": 2.5},
            {"type": "spot", "intensity": 40, "range": 12,
             "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}},
            {"type": "point", "color": [0.5, 0.5, 1.0]}
        ]}},
        "meshes": [{"primitives": [{"attributes": {"POSITION": tri}}]}],
        "nodes": [
            {"mesh": 0},
            {"name": "sun node", "rotation": [-s, 0, 0, s],
             "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"translation": [1, 0, 0], "children": [3]},
            {"name": "spot node", "translation": [0, 2, 0], "rotation": [0, -s, 0, s],
             "extensions": {"KHR_lights_punctual": {"light": 1}}},
            {"name": "bulb", "translation": [0, 0, 3], "scale": [5, 5, 5],
             "extensions": {"KHR_lights_punctual": {"light": 2}}}
        ],
        "scenes": [{"nodes": [0, 1, 2, 4]}], "scene": 0
    }));
    let scene = load_text(&TempDir::new("gltf-lights"), &text).unwrap();
    assert!(
        scene.report.warnings.is_empty() && scene.report.skipped.is_empty(),
        "{:?} {:?}",
        scene.report.warnings,
        scene.report.skipped
    );
    let [sun, spot, bulb] = &scene.lights[..] else {
        panic!("{:?}", scene.lights)
    };
    assert_eq!(
        (sun.kind, sun.name.as_ref()),
        (LightKind::Directional, "sun")
    );
    assert!(close(sun.direction, Vec3::NEG_Y), "{}", sun.direction);
    assert_eq!((sun.color, sun.intensity), (Vec3::new(1.0, 0.9, 0.8), 2.5));
    assert_eq!(sun.attenuation, Attenuation::None);

    assert_eq!(
        (spot.kind, spot.name.as_ref()),
        (LightKind::Spot, "spot node")
    );
    assert!(
        close(spot.position, Vec3::new(1.0, 2.0, 0.0)),
        "{}",
        spot.position
    );
    assert!(close(spot.direction, Vec3::X), "{}", spot.direction);
    assert_eq!((spot.inner, spot.outer), (0.2, 0.5));
    assert_eq!((spot.intensity, spot.color), (40.0, Vec3::ONE));
    assert_eq!(spot.attenuation, Attenuation::Range(12.0));

    // Scale does not stretch the light; no range means inverse-square.
    assert_eq!(bulb.kind, LightKind::Point);
    assert!(close(bulb.position, Vec3::new(0.0, 0.0, 3.0)));
    assert!(close(bulb.direction, Vec3::NEG_Z));
    assert_eq!(
        (bulb.intensity, bulb.attenuation),
        (1.0, Attenuation::InverseSquare)
    );
}

#[test]
fn malformed_lights_are_warnings_never_failures() {
    let mut d = Doc::default();
    let tri = d.floats(&TRI, "VEC3");
    let light = |i: usize| json!({"extensions": {"KHR_lights_punctual": {"light": i}}});
    let text = d.finish(json!({
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "area"},
            {"color": [1, 1, 1]},
            {"type": "point", "color": [1, "x"], "intensity": -3, "range": 0},
            {"type": "spot", "spot": {"innerConeAngle": 2.0, "outerConeAngle": 9.0}},
            {"type": "spot"},
            "not an object"
        ]}},
        "meshes": [{"primitives": [{"attributes": {"POSITION": tri}}]}],
        "nodes": [{"mesh": 0}, light(0), light(1), light(2), light(3), light(4), light(5),
                  light(17), {"extensions": {"KHR_lights_punctual": {"light": "zero"}}},
                  {"scale": [0, 0, 0], "extensions": {"KHR_lights_punctual": {"light": 2}}}]
    }));
    let scene = load_text(&TempDir::new("gltf-bad-lights"), &text).unwrap();
    let w = scene.report.warnings.join("\n");
    for needle in [
        "light 0: unknown type 'area'; skipped",
        "light 1: has no `type`; skipped",
        "light 2: color [1,\"x\"] is not 3 non-negative numbers; white used",
        "light 2: intensity -3 is not a non-negative number; 1 used",
        "light 2: range 0 is not a positive number; inverse-square used",
        "light 3: outerConeAngle 9.0 is beyond π/2; clamped",
        "light 3: innerConeAngle 1.5707964 is not below outerConeAngle 1.5707964; clamped",
        "light 4: spot light without a `spot` object; default cone used",
        "light 5: is not an object; skipped",
        "refers to light 17, but there are only 6",
        "has no light index",
        "is under a degenerate transform",
    ] {
        assert!(w.contains(needle), "missing '{needle}' in:\n{w}");
    }
    let kinds: Vec<_> = scene.lights.iter().map(|l| l.kind).collect();
    assert_eq!(
        kinds,
        [LightKind::Point, LightKind::Spot, LightKind::Spot],
        "{:?}",
        scene.lights
    );
    let point = &scene.lights[0];
    assert_eq!(
        (point.color, point.intensity, point.attenuation),
        (Vec3::ONE, 1.0, Attenuation::InverseSquare)
    );
    // Clamped to the spec's largest cone; the missing cone is the spec's default.
    assert_eq!(
        (scene.lights[1].inner, scene.lights[1].outer),
        (FRAC_PI_2, FRAC_PI_2)
    );
    assert_eq!(
        (scene.lights[2].inner, scene.lights[2].outer),
        (0.0, FRAC_PI_4)
    );
}

#[test]
fn a_required_unknown_extension_is_still_refused() {
    let text = json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual", "EXT_magic"],
        "extensionsRequired": ["KHR_lights_punctual", "EXT_magic"]
    })
    .to_string();
    let err = load_text(&TempDir::new("gltf-ext"), &text).unwrap_err();
    assert!(
        err.to_string().contains("requires extension EXT_magic"),
        "{err}"
    );
}

#[test]
fn lights_and_cameras_under_animated_nodes_move_with_them() {
    let mut d = Doc::default();
    let tri = d.floats(&TRI, "VEC3");
    // Node 1 carries node 2 (a spot light and a camera at (0, 2, 0)); an animation moves
    // node 1 from the origin to (4, 0, 0) over one second and turns it 90 degrees about Y.
    let times = d.floats(&[0.0, 1.0], "SCALAR");
    let moves = d.floats(&[0.0, 0.0, 0.0, 4.0, 0.0, 0.0], "VEC3");
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let turns = d.floats(&[0.0, 0.0, 0.0, 1.0, 0.0, s, 0.0, s], "VEC4");
    let text = d.finish(json!({
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "spot", "spot": {}}]}},
        "meshes": [{"primitives": [{"attributes": {"POSITION": tri}}]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}],
        "nodes": [
            {"mesh": 0},
            {"name": "rig", "children": [2]},
            {"name": "head", "translation": [0, 2, 0], "camera": 0,
             "extensions": {"KHR_lights_punctual": {"light": 0}}}
        ],
        "animations": [{"channels": [
            {"sampler": 0, "target": {"node": 1, "path": "translation"}},
            {"sampler": 1, "target": {"node": 1, "path": "rotation"}}
        ], "samplers": [
            {"input": times, "output": moves},
            {"input": times, "output": turns}
        ]}],
        "scenes": [{"nodes": [0, 1]}], "scene": 0
    }));
    let scene = load_text(&TempDir::new("gltf-moving-lights"), &text).unwrap();
    assert!(
        scene.report.warnings.is_empty() && scene.report.skipped.is_empty(),
        "{:?} {:?}",
        scene.report.warnings,
        scene.report.skipped
    );
    assert_eq!(scene.animations.len(), 1);
    assert_eq!(scene.graph.nodes[2].lights, [0]);
    assert_eq!(scene.graph.nodes[2].cameras, [0]);
    let mut p = realist_render::PreparedScene::new(scene);
    assert!(close(p.lights()[0].position, Vec3::new(0.0, 2.0, 0.0)));
    p.pose_at(crate::scene::Play::All, 1.0, false);
    // At one second: at (4, 2, 0), and -Z turned 90 degrees about Y points along -X.
    let (light, cam) = (&p.lights()[0], &p.cameras()[0]);
    assert!(
        close(light.position, Vec3::new(4.0, 2.0, 0.0)),
        "{}",
        light.position
    );
    assert!(close(light.direction, Vec3::NEG_X), "{}", light.direction);
    assert!(close(cam.eye, Vec3::new(4.0, 2.0, 0.0)), "{}", cam.eye);
    assert!(close((cam.target - cam.eye).normalize(), Vec3::NEG_X));
    assert!(close(cam.up, Vec3::Y));
    // The scene as loaded keeps the rest pose.
    assert!(close(
        p.scene().lights[0].position,
        Vec3::new(0.0, 2.0, 0.0)
    ));
    p.pose_at(crate::scene::Play::Rest, 0.0, false);
    assert!(close(p.cameras()[0].eye, Vec3::new(0.0, 2.0, 0.0)));
}
