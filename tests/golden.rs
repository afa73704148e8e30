//! Golden images of every shading mode on small scenes, with named tolerances.
//! A failure writes the render and a diff to `target/golden-diff/`; `REPLACE=1` regenerates.

mod common;

use common::{check_golden, checker_cube, render, scene_of, EXACT, SHADED};
use glam::{Vec3, Vec4};
use realist::mesh::Mesh;
use realist::scene::{self, Camera, Material};
use realist::shade::Shading;

fn sphere_scene() -> scene::Scene {
    let material = Material {
        base_color: Vec4::new(0.8, 0.3, 0.2, 1.0),
        specular: Vec3::splat(0.5),
        shininess: 30.0,
        ..Material::default()
    };
    scene_of(Mesh::sphere(1.0, 16, 10).expect("sphere"), material)
}

fn camera() -> Camera {
    let mut cam = Camera {
        eye: Vec3::new(1.5, 1.2, 3.2),
        ..Camera::default()
    };
    cam.fit(Vec3::ZERO, 1.8);
    cam
}

#[test]
fn sphere_in_every_mode() {
    let scene = sphere_scene();
    for mode in Shading::ALL {
        let fb = render(&scene, 128, 96, Some(mode), Some(camera()));
        common::assert_finite(&fb, mode.name());
        let tol = if mode == Shading::Wireframe {
            EXACT
        } else {
            SHADED
        };
        check_golden(&format!("sphere-{}", mode.name()), &fb, tol);
    }
}

#[test]
fn textured_checker_cube() {
    let fb = render(
        &checker_cube(),
        128,
        96,
        Some(Shading::Textured),
        Some(camera()),
    );
    check_golden("cube-textured", &fb, SHADED);
    let fb = render(&checker_cube(), 128, 96, Some(Shading::Uv), Some(camera()));
    check_golden("cube-uv", &fb, SHADED);
}

#[test]
fn demo_scene() {
    let demo = scene::demo();
    let fb = render(&demo, 320, 180, None, demo.cameras.first().cloned());
    check_golden("demo", &fb, SHADED);
}

/// `realist render --compare` (issue 39): identical bytes pass, every kernel's image of the
/// demo passes against the portable kernel's, a changed pixel fails with its count and a
/// heat map, and a tolerance lets it through.
#[test]
fn render_compare_against_a_reference() {
    use realist::simd::KernelKind;
    use std::process::Command;
    let dir = realist_testkit::TempDir::new("compare");
    let reference = dir.0.join("reference.png");
    let realist = |kernel: KernelKind, args: &[&std::ffi::OsStr]| {
        let out = Command::new(env!("CARGO_BIN_EXE_realist"))
            .env("REALIST_KERNEL", kernel.name())
            .args(["render", "--demo", "--size", "96x64", "--shading", "pbr"])
            .args(args)
            .current_dir(&dir.0)
            .output()
            .expect("run realist");
        let text = String::from_utf8_lossy(&out.stdout).into_owned()
            + &String::from_utf8_lossy(&out.stderr);
        (out.status.code(), text)
    };
    let os = |s: &str| std::ffi::OsString::from(s);
    let (code, text) = realist(KernelKind::Portable, &[&os("-o"), reference.as_os_str()]);
    assert_eq!(code, Some(0), "{text}");
    for kernel in KernelKind::available_kinds() {
        let (code, text) = realist(
            kernel,
            &[
                &os("-o"),
                &os("got.png"),
                &os("--compare"),
                reference.as_os_str(),
            ],
        );
        assert_eq!(code, Some(0), "{kernel:?}: {text}");
        assert!(text.contains("compare: identical to"), "{text}");
        assert!(!dir.0.join("got.diff.png").exists());
    }
    // Two pixels changed in the reference: one by 1 level, one by 40.
    let mut img = image::open(&reference).expect("reference").to_rgb8();
    img.get_pixel_mut(10, 10).0[0] ^= 1;
    let p = img.get_pixel_mut(50, 30);
    p.0[1] = p.0[1].wrapping_add(40);
    let changed = dir.0.join("changed.png");
    img.save(&changed).expect("write the changed reference");
    let compare = [
        os("-o"),
        os("got.png"),
        os("--compare"),
        changed.into_os_string(),
    ];
    let args: Vec<&std::ffi::OsStr> = compare.iter().map(|s| s.as_os_str()).collect();
    let (code, text) = realist(KernelKind::best(), &args);
    assert_eq!(code, Some(1), "{text}");
    assert!(
        text.contains("2 of 6144 pixels differ") && text.contains("worst 40 levels"),
        "{text}"
    );
    let heat = image::open(dir.0.join("got.diff.png"))
        .expect("a heat map")
        .to_rgb8();
    assert_eq!(heat.get_pixel(50, 30).0, [255, 0, 0], "40 levels: red");
    assert_eq!(
        heat.get_pixel(10, 10).0[0],
        255,
        "1 level, beyond 0: yellow to red"
    );
    // One level per channel and one pixel beyond it are allowed: passes.
    let (flag, tol) = (os("--tolerance"), os("1,1"));
    let mut more = args.clone();
    more.extend([flag.as_os_str(), tol.as_os_str()]);
    let (code, text) = realist(KernelKind::best(), &more);
    assert_eq!(code, Some(0), "{text}");
    assert!(text.contains("1 by more than 1 (allowed 1)"), "{text}");
    // A render may not be written over its own reference (it would always pass), nor its
    // heat map: an error before anything is written.
    let before = std::fs::read(&reference).expect("reference");
    let (code, text) = realist(
        KernelKind::best(),
        &[
            &os("-o"),
            reference.as_os_str(),
            &os("--compare"),
            reference.as_os_str(),
        ],
    );
    assert_eq!(code, Some(1), "{text}");
    assert!(
        text.contains("would be written over the reference"),
        "{text}"
    );
    let diff_named = dir.0.join("x.diff.png");
    std::fs::copy(&reference, &diff_named).expect("copy");
    let (code, text) = realist(
        KernelKind::best(),
        &[
            &os("-o"),
            &os("x.png"),
            &os("--compare"),
            diff_named.as_os_str(),
        ],
    );
    assert_eq!(code, Some(1), "{text}");
    assert!(
        text.contains("the heat map would be written over"),
        "{text}"
    );
    assert_eq!(std::fs::read(&reference).expect("reference"), before);
    assert!(!dir.0.join("x.png").exists(), "nothing rendered");
    // A reference of another size is an error naming both sizes.
    let small = dir.0.join("small.png");
    image::RgbImage::new(8, 8).save(&small).expect("write");
    let (code, text) = realist(
        KernelKind::best(),
        &[
            &os("-o"),
            &os("got.png"),
            &os("--compare"),
            small.as_os_str(),
        ],
    );
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("is 8x8, the render 96x64"), "{text}");
}
