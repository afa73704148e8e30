//! Edge cases against the reference: non-finite input, empty scenes and bad requests, back faces, alpha masks and blending, shared edges covered once, bands and threads.

use super::*;

#[test]
fn non_finite_input_empty_scenes_and_bad_requests() {
    let opts = black(40, 30, Some(Camera::default()));
    let background = [0.25, 0.5, 0.75];
    let opts = Shot {
        settings: Settings {
            background: Vec4::new(0.25, 0.5, 0.75, 1.0),
            ..opts.settings.clone()
        },
        ..opts
    };
    // Empty scene, with and without the default camera.
    for camera in [None, Some(Camera::default())] {
        let o = Shot {
            camera,
            ..opts.clone()
        };
        let img = reference(&Scene::default(), &o, 3, false).unwrap();
        assert!(img.rgb.iter().all(|&c| c == background));
    }
    // A triangle with a NaN corner next to a good one, an instance with a NaN matrix,
    // one with a missing mesh: only the good triangle is drawn.
    let mut scene = Scene::default();
    scene
        .materials
        .push(flat_material(Vec3::ONE, 1.0, AlphaMode::Opaque));
    scene.lights = vec![Light::ambient(Vec3::ONE)];
    let mesh = Mesh::new(
        MeshData {
            name: "nan".into(),
            positions: vec![
                Vec3::new(-1.0, -1.0, 0.0),
                Vec3::new(0.0, -1.0, 0.0),
                Vec3::new(-1.0, 1.0, 0.0),
                Vec3::new(1.0, -1.0, 0.0),
                Vec3::new(1.0, 1.0, f32::NAN),
                Vec3::new(f32::INFINITY, 0.0, 0.0),
            ],
            corners: vec![0, 1, 2, 1, 3, 4, 3, 5, 4],
            material: Some(0),
            ..MeshData::default()
        },
        NormalPolicy::default(),
    )
    .unwrap();
    place(&mut scene, mesh.clone(), Mat4::IDENTITY);
    place(
        &mut scene,
        mesh,
        Mat4::from_scale(Vec3::new(1.0, f32::NAN, 1.0)),
    );
    scene.instances.push(Instance {
        mesh: 99,
        world: Mat4::IDENTITY,
        name: "missing".into(),
        style: Style::Inherit,
        node: None,
        skin: None,
        copies: None,
    });
    let img = reference(&scene, &opts, 4, false).unwrap();
    // Camera at z = 3, 45 degrees: the plane z = 0 spans +-1.243 vertically, so the
    // good triangle's interior around (-0.7, -0.6) is at pixel (9, 22); (30, 10) is
    // where the NaN triangles would be.
    assert_eq!(img.rgb[22 * 40 + 9], [1.0; 3]);
    assert_eq!(img.rgb[10 * 40 + 30], background);
    assert!(img.rgb.iter().all(|c| c.iter().all(|v| v.is_finite())));
    let _ = raster(&scene, &opts, 2);
    // Refused requests.
    let bad = |o: &Shot, s: u32| reference(&scene, o, s, false).unwrap_err();
    assert_eq!(bad(&opts, 0), ReferenceError::Samples(0));
    assert_eq!(bad(&opts, 65), ReferenceError::Samples(65));
    let huge = Shot {
        width: 8192,
        height: 8192,
        ..opts.clone()
    };
    assert!(matches!(bad(&huge, 8), ReferenceError::TooLarge { total, .. } if total == 1 << 32));
    let empty = Shot {
        width: 0,
        ..opts.clone()
    };
    assert!(matches!(bad(&empty, 1), ReferenceError::EmptyImage { .. }));
    for camera in [
        Camera {
            near: 0.0,
            ..Camera::default()
        },
        Camera {
            far: 0.05,
            ..Camera::default()
        },
        Camera {
            eye: Vec3::ZERO,
            ..Camera::default()
        },
        Camera {
            yfov: f32::NAN,
            ..Camera::default()
        },
    ] {
        let o = Shot {
            camera: Some(camera),
            ..opts.clone()
        };
        let e = bad(&o, 1);
        assert!(matches!(e, ReferenceError::Camera { .. }), "{e}");
    }
}

#[test]
fn back_faces_culled_or_lit_from_behind() {
    // A square facing +Z seen from behind (camera at z = -3), lit along +Z from the
    // camera's side: only its back can be lit, with N.L = 1.
    let mut scene = Scene::default();
    let mut mat = flat_material(Vec3::splat(0.5), 1.0, AlphaMode::Opaque);
    scene.materials.push(mat.clone());
    place(&mut scene, square(0.0, 1.0, None, 0), Mat4::IDENTITY);
    scene.lights = vec![
        Light::directional(Vec3::Z, Vec3::splat(0.8)),
        Light::ambient(Vec3::splat(0.1)),
    ];
    let camera = Camera {
        eye: Vec3::new(0.0, 0.0, -3.0),
        ..Camera::default()
    };
    let opts = black(32, 32, Some(camera));
    let centre =
        |scene: &Scene, opts: &Shot| reference(scene, opts, 2, false).unwrap().rgb[16 * 32 + 16];
    assert_eq!(centre(&scene, &opts), [0.0; 3], "culled");
    let want = [0.1 * 0.5 + 0.8 * 0.5; 3];
    let both = Shot {
        settings: Settings {
            double_sided: true,
            ..opts.clone().settings
        },
        ..opts.clone()
    };
    assert!(close(centre(&scene, &both), want));
    mat.double_sided = true;
    scene.materials[0] = mat;
    assert!(close(centre(&scene, &opts), want));
    // A mirroring world matrix makes the same square front-facing from behind.
    scene.materials[0].double_sided = false;
    scene.instances[0].world = Mat4::from_scale(Vec3::new(1.0, 1.0, -1.0));
    assert!(close(centre(&scene, &opts), want));
    let m = de(
        &raster(&scene, &opts, 2),
        &reference(&scene, &opts, 2, false).unwrap(),
    );
    assert!(m.mean_de2000 < 1e-3, "{m:?}");
}

#[test]
fn alpha_mask_discards_and_blending_follows_depth() {
    // Head-on: camera at z = 3. Back: an opaque red square at z = -1. Front: a masked
    // white square whose vertex alpha runs 0 -> 1 from left to right (cutoff 0.5), so
    // its left half is cut away and shows the red one behind it. Ambient light 1.
    let mut scene = Scene {
        lights: vec![Light::ambient(Vec3::ONE)],
        materials: vec![
            flat_material(Vec3::X, 1.0, AlphaMode::Opaque),
            flat_material(Vec3::splat(0.5), 1.0, AlphaMode::Mask(0.5)),
        ],
        ..Scene::default()
    };
    let ramp = [0.0, 1.0, 1.0, 0.0].map(|a| Vec4::new(1.0, 1.0, 1.0, a));
    place(&mut scene, square(-1.0, 10.0, None, 0), Mat4::IDENTITY);
    place(&mut scene, square(0.0, 5.0, Some(ramp), 1), Mat4::IDENTITY);
    let (w, h) = (40u32, 20u32);
    let opts = black(w, h, Some(Camera::default()));
    let img = reference(&scene, &opts, 4, false).unwrap();
    for y in 0..h {
        for x in 0..w {
            let c = img.rgb[(y * w + x) as usize];
            if x < w / 2 - 1 {
                assert_eq!(c, [1.0, 0.0, 0.0], "({x}, {y})");
            } else if x > w / 2 {
                assert!(close(c, [0.5; 3]), "({x}, {y}) {c:?}");
            }
        }
    }
    let m = de(
        &raster(&scene, &opts, 4),
        &reference(&scene, &opts, 4, false).unwrap(),
    );
    assert!(m.mean_de2000 < 1e-3, "{m:?}");

    // Blend: green at z = 0 and blue at z = -0.5, both alpha 0.5, over the red square,
    // listed near first. Per sample: red, then blue, then green over it.
    scene.materials = vec![
        flat_material(Vec3::X, 1.0, AlphaMode::Opaque),
        flat_material(Vec3::Y, 0.5, AlphaMode::Blend),
        flat_material(Vec3::Z, 0.5, AlphaMode::Blend),
    ];
    scene.meshes.truncate(1);
    scene.instances.truncate(1);
    place(&mut scene, square(0.0, 5.0, None, 1), Mat4::IDENTITY);
    place(&mut scene, square(-0.5, 5.0, None, 2), Mat4::IDENTITY);
    let img = reference(&scene, &opts, 2, false).unwrap();
    assert!(close(img.rgb[10 * w as usize + 20], [0.25, 0.5, 0.25]));
    let m = de(&raster(&scene, &opts, 2), &img);
    assert!(m.mean_de2000 < 1e-3, "{m:?}");
}

#[test]
fn shared_edges_are_covered_exactly_once() {
    // Two blended triangles of a square, alpha 0.5 over black, head-on into a square
    // image: their shared diagonal projects to x = y exactly, through the samples with
    // i = j of the diagonal pixels, where both edge functions are exactly 0. Covered
    // once, every sample is 0.5; twice, 0.75; never, 0.
    let r = 2.0;
    let mut scene = Scene {
        lights: vec![Light::ambient(Vec3::ONE)],
        materials: vec![flat_material(Vec3::ONE, 0.5, AlphaMode::Blend)],
        ..Scene::default()
    };
    let mesh = Mesh::new(
        MeshData {
            name: "two triangles".into(),
            positions: vec![
                Vec3::new(-r, -r, 0.0),
                Vec3::new(r, -r, 0.0),
                Vec3::new(r, r, 0.0),
                Vec3::new(-r, r, 0.0),
            ],
            corners: vec![0, 1, 3, 1, 2, 3],
            material: Some(0),
            ..MeshData::default()
        },
        NormalPolicy::default(),
    )
    .unwrap();
    place(&mut scene, mesh, Mat4::IDENTITY);
    let opts = black(24, 24, Some(Camera::default()));
    let img = reference(&scene, &opts, 4, false).unwrap();
    assert!(
        img.rgb.iter().all(|&c| close(c, [0.5; 3])),
        "{:?}",
        img.rgb[0]
    );
    let ras = raster(&scene, &opts, 4);
    assert!(
        ras.rgb.iter().all(|&c| close(c, [0.5; 3])),
        "the rasterizer too"
    );
}

#[test]
fn bands_and_threads_do_not_change_the_image() {
    let (mut scene, opts) = textured();
    // Add a masked and a blended square in front of everything.
    scene
        .materials
        .push(flat_material(Vec3::Y, 0.4, AlphaMode::Blend));
    scene
        .materials
        .push(flat_material(Vec3::X, 1.0, AlphaMode::Mask(0.5)));
    let ramp = [0.0, 1.0, 1.0, 0.0].map(|a| Vec4::new(1.0, 1.0, 1.0, a));
    place(&mut scene, square(0.8, 0.9, None, 2), Mat4::IDENTITY);
    place(
        &mut scene,
        square(0.5, 0.6, Some(ramp), 3),
        Mat4::from_translation(Vec3::X),
    );
    let opts = Shot {
        width: 61,
        height: 37,
        ..opts
    };
    let s = 3;
    let base = render(&scene, &opts, s, true, BAND_SAMPLES, ENV_SAMPLES).unwrap();
    // Sanity: both extras show.
    let m = de(&raster(&scene, &opts, 3), &base);
    assert!(m.mean_de2000 < 2e-3, "{m:?}");
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    assert_eq!(
        one.install(|| reference(&scene, &opts, s, true)).unwrap(),
        base
    );
    // One pixel per band, five pixels, part of a row, seven rows.
    for band in [1, 9 * 5, 9 * 50, 9 * 61 * 7] {
        assert_eq!(
            render(&scene, &opts, s, true, band, ENV_SAMPLES).unwrap(),
            base,
            "band {band}"
        );
    }
}
