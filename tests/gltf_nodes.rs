//! glTF node transforms end to end: a parent-child hierarchy composes TRS and matrix
//! transforms, and a mirroring (negative-scale) node flips winding so back-face culling still
//! shows the outside of the mesh.

mod common;

use glam::{Mat4, Quat, Vec3};
use realist::load::{load, LoadOptions};
use realist::scene::Camera;
use realist::shade::Shading;

#[test]
fn parent_child_transforms_compose() {
    let dir = common::temp_dir("compose");
    let path = common::write_gltf(
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
    let dir = common::temp_dir("mirror");
    let plain = load(
        &common::write_gltf(&dir, r#""name": "root""#, r#""name": "child""#),
        &LoadOptions::default(),
    )
    .expect("load");
    let mirrored = load(
        &common::write_gltf(&dir, r#""scale": [-1, 1, 1]"#, r#""name": "child""#),
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
    // Flat shading lights each triangle at its centroid, and the mirrored triangulation
    // moves the centroids: with a highlight, whole triangles would differ. Without one
    // (and the rig's lights directional) a face's colour does not depend on the point.
    let matte = |s: &realist::scene::Scene| {
        let mut s = s.clone();
        s.materials.push(realist::scene::Material {
            specular: Vec3::ZERO,
            ..Default::default()
        });
        let matte = s.materials.len() - 1;
        s.meshes.iter_mut().for_each(|m| m.material = Some(matte));
        s
    };
    let (plain_matte, mirrored_matte) = (matte(&plain), matte(&mirrored));
    for mode in [Shading::Phong, Shading::Normals, Shading::Flat] {
        let (p, m) = if mode == Shading::Flat {
            (&plain_matte, &mirrored_matte)
        } else {
            (&plain, &mirrored)
        };
        let a = common::render(p, 96, 96, Some(mode), Some(cam.clone()));
        let b = common::render(m, 96, 96, Some(mode), Some(cam.clone()));
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
