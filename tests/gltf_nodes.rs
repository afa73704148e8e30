//! glTF node transforms end to end: a parent-child hierarchy composes TRS and matrix
//! transforms, and a mirroring (negative-scale) node flips winding so back-face culling still
//! shows the outside of the mesh.

mod common;

use base64::Engine as _;
use glam::{Mat4, Quat, Vec3};
use realist::load::{load, LoadOptions};
use realist::scene::Camera;
use realist::shade::Shading;

/// A unit cube (24 vertices with normals, 36 u16 indices) as a buffer.
fn cube_buffer() -> (Vec<u8>, usize, usize) {
    let mut pos = Vec::new();
    let mut nrm = Vec::new();
    let mut idx: Vec<u16> = Vec::new();
    let faces = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
    for n in faces {
        let u = if n.y.abs() > 0.5 { Vec3::X } else { Vec3::Y };
        let v = n.cross(u);
        let base = pos.len() as u16;
        for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            pos.push(n * 0.5 + u * (0.5 * a) + v * (0.5 * b));
            nrm.push(n);
        }
        // (u, v, n) is right-handed, so counter-clockwise in (u, v) faces +n.
        idx.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    let mut bytes = Vec::new();
    for p in pos.iter().chain(&nrm) {
        for c in p.to_array() {
            bytes.extend(c.to_le_bytes());
        }
    }
    let idx_offset = bytes.len();
    for i in &idx {
        bytes.extend(i.to_le_bytes());
    }
    (bytes, idx_offset, idx.len())
}

/// A glTF whose scene has `root` with `child` below it, the child drawing the cube.
fn write_gltf(dir: &std::path::Path, root: &str, child: &str) -> std::path::PathBuf {
    let (bytes, idx_offset, idx_count) = cube_buffer();
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&bytes)
    );
    let json = format!(
        r#"{{
  "asset": {{"version": "2.0"}},
  "scene": 0,
  "scenes": [{{"nodes": [0]}}],
  "nodes": [{{"children": [1], {root}}}, {{"mesh": 0, {child}}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "NORMAL": 1}}, "indices": 2}}]}}],
  "buffers": [{{"byteLength": {len}, "uri": "{uri}"}}],
  "bufferViews": [
    {{"buffer": 0, "byteOffset": 0, "byteLength": 576}},
    {{"buffer": 0, "byteOffset": {idx_offset}, "byteLength": {idx_len}}}
  ],
  "accessors": [
    {{"bufferView": 0, "byteOffset": 0, "componentType": 5126, "count": 24, "type": "VEC3", "min": [-0.5, -0.5, -0.5], "max": [0.5, 0.5, 0.5]}},
    {{"bufferView": 0, "byteOffset": 288, "componentType": 5126, "count": 24, "type": "VEC3"}},
    {{"bufferView": 1, "componentType": 5123, "count": {idx_count}, "type": "SCALAR"}}
  ]
}}"#,
        len = bytes.len(),
        idx_len = idx_count * 2,
    );
    let path = dir.join("nodes.gltf");
    std::fs::write(&path, json).expect("write gltf");
    path
}

fn temp_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("realist-test-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

#[test]
fn parent_child_transforms_compose() {
    let dir = temp_dir("compose");
    let path = write_gltf(
        &dir,
        r#""translation": [2, 0, 0], "rotation": [0, 0.7071068, 0, 0.7071068]"#,
        r#""matrix": [2,0,0,0, 0,2,0,0, 0,0,2,0, 0,1,0,1]"#,
    );
    let scene = load(&path, &LoadOptions::default()).expect("load");
    assert_eq!(scene.instances.len(), 1);
    let parent = Mat4::from_rotation_translation(
        Quat::from_rotation_y(std::f32::consts::FRAC_PI_2),
        Vec3::new(2.0, 0.0, 0.0),
    );
    let child = Mat4::from_scale_rotation_translation(Vec3::splat(2.0), Quat::IDENTITY, Vec3::Y);
    let want = parent * child;
    let got = scene.instances[0].world;
    assert!(
        got.abs_diff_eq(want, 1e-5),
        "world matrix\n{got}\nexpected\n{want}"
    );
    // The cube's corner (0.5, 0.5, 0.5) lands where parent * child puts it.
    let (lo, hi) = scene.bounds().expect("bounds");
    assert!(
        (lo - Vec3::new(1.0, 0.0, -1.0)).abs().max_element() < 1e-4,
        "{lo}"
    );
    assert!(
        (hi - Vec3::new(3.0, 2.0, 1.0)).abs().max_element() < 1e-4,
        "{hi}"
    );
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn mirrored_node_shows_the_outside_of_the_cube() {
    let dir = temp_dir("mirror");
    let plain = load(
        &write_gltf(&dir, r#""name": "root""#, r#""name": "child""#),
        &LoadOptions::default(),
    )
    .expect("load");
    let mirrored = load(
        &write_gltf(&dir, r#""scale": [-1, 1, 1]"#, r#""name": "child""#),
        &LoadOptions::default(),
    )
    .expect("load");
    assert!(mirrored.instances[0].world.determinant() < 0.0);
    let mut cam = Camera {
        eye: Vec3::new(1.6, 1.3, 2.2),
        ..Camera::default()
    };
    cam.fit(Vec3::ZERO, 0.9);
    // The cube is symmetric under x -> -x, so a correctly mirrored cube looks the same.
    // Wrong winding would cull the outside and show the inside faces instead.
    for mode in [Shading::Phong, Shading::Normals, Shading::Flat] {
        let a = common::render(&plain, 96, 96, Some(mode), Some(cam.clone()));
        let b = common::render(&mirrored, 96, 96, Some(mode), Some(cam.clone()));
        assert!(common::covered(&a) > 2000);
        let (sa, sb) = (a.to_srgb8(), b.to_srgb8());
        let differing = sa
            .chunks(3)
            .zip(sb.chunks(3))
            .filter(|(x, y)| x.iter().zip(*y).any(|(p, q)| p.abs_diff(*q) > 2))
            .count();
        // Only pixels along the faces' diagonals may differ (mirrored triangulation).
        assert!(
            differing < 40,
            "{mode}: {differing} pixels differ between the cube and its mirror image"
        );
    }
    let _ = std::fs::remove_dir_all(dir);
}
