//! realist against three.js r187 on the same view: the references in `tests/threejs/refs/`
//! are rendered by three.js in headless Chromium (`bash tests/threejs/make-refs.sh`; the
//! script and its pinned packages are in that folder), so this test needs neither.
//!
//! `models/pbr/no-material.glb` is a unit sphere without a material: the specification's
//! default, white, metallic 1, roughness 1, which three's GLTFLoader also applies. Under a
//! 1-lux directional light from the camera, without tone mapping, both renderers draw the
//! glTF BRDF and give the punctual light back the energy single scattering loses between
//! microfacets, by the same formula (each specular lobe times `1 + F0 (1/E_ss - 1)`), with
//! `E_ss` read at the same table coordinates (three.js's 16 x 16 table at texel centres:
//! roughness 1 compensates as 0.969 does, 1/0.345 head-on instead of the exact 1/0.307;
//! with the exact value realist's centre was 139 against three's 132, mean 4.4 levels).

use std::path::Path;

use glam::{Vec3, Vec4};
use realist::load::{self, LoadOptions};
use realist::render::{Environment, Lights, PreparedScene, Renderer, Settings, ToneMap, View};
use realist::scene::{Camera, Light};

const SIZE: u32 = 256;

fn reference(name: &str) -> image::RgbImage {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/threejs/refs")
        .join(name);
    image::open(&path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .into_rgb8()
}

/// realist's render of `model` from (0, 0, 3) towards the origin (45 degrees), lit by a
/// 1-lux directional light travelling along -Z, no environment, no tone map, black
/// background, as 8-bit sRGB.
fn render(model: &str, single_scatter: bool) -> image::RgbImage {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(model);
    let scene = load::load(&path, &LoadOptions::default()).expect("model loads");
    let prepared = PreparedScene::new(scene);
    let settings = Settings {
        lights: Lights::Custom {
            lights: vec![Light::directional(Vec3::NEG_Z, Vec3::ONE)],
            follow_camera: false,
        },
        environment: Environment::Off,
        tone: ToneMap::Clamp,
        background: Vec4::new(0.0, 0.0, 0.0, 1.0),
        single_scatter,
        ..Settings::default()
    };
    let view = View {
        camera: Camera {
            eye: Vec3::new(0.0, 0.0, 3.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            yfov: 45f32.to_radians(),
            near: 0.5,
            far: 10.0,
            ..Camera::default()
        },
        width: SIZE,
        height: SIZE,
    };
    let mut r = Renderer::new();
    r.render(&prepared, &settings, &view);
    let fb = r.take_target().expect("a frame").resolve();
    let enc = realist::color::srgb8;
    image::RgbImage::from_fn(SIZE, SIZE, |x, y| {
        let c = fb.color[(y * SIZE + x) as usize];
        image::Rgb([enc(c.x), enc(c.y), enc(c.z)])
    })
}

/// Per-pixel largest channel difference over the pixels both images cover with two pixels
/// of margin (the silhouettes' anti-aliasing aside): (mean, max, pixels compared).
fn compare(a: &image::RgbImage, b: &image::RgbImage) -> (f64, u8, usize) {
    let covered = |img: &image::RgbImage, x: i64, y: i64| {
        x >= 0
            && y >= 0
            && x < i64::from(SIZE)
            && y < i64::from(SIZE)
            && img.get_pixel(x as u32, y as u32).0 != [0, 0, 0]
    };
    let (mut sum, mut max, mut n) = (0u64, 0u8, 0usize);
    for y in 0..i64::from(SIZE) {
        for x in 0..i64::from(SIZE) {
            let inside = (-2..=2).all(|dy| {
                (-2..=2).all(|dx| covered(a, x + dx, y + dy) && covered(b, x + dx, y + dy))
            });
            if !inside {
                continue;
            }
            let (p, q) = (
                a.get_pixel(x as u32, y as u32).0,
                b.get_pixel(x as u32, y as u32).0,
            );
            let d = (0..3).map(|c| p[c].abs_diff(q[c])).max().unwrap_or(0);
            sum += u64::from(d);
            max = max.max(d);
            n += 1;
        }
    }
    (sum as f64 / n.max(1) as f64, max, n)
}

#[test]
fn the_default_material_under_a_head_on_light_against_three_js() {
    let three = reference("no-material-headon.png");
    // three.js's centre: the single-scattering lobe head-on, 1/(4π) = 0.0796, times its
    // compensation 1/0.3453: 0.2305, sRGB 132.
    assert_eq!(three.get_pixel(128, 128).0, [132, 132, 132]);
    let ours = render("models/pbr/no-material.glb", false);
    let (mean, max, n) = compare(&ours, &three);
    eprintln!("realist vs three.js r187, default material: mean {mean:.2}, max {max} levels over {n} pixels");
    assert!(n > 30_000, "the sphere covers both images: {n} pixels");
    // The same centre: the lobe times 1/E_ss at three's coordinates.
    assert_eq!(ours.get_pixel(128, 128).0, [132, 132, 132]);
    // The bound is 4 levels; measured: mean 0.03, max 1.
    assert!(mean < 0.5 && max <= 4, "mean {mean:.2}, max {max}");
    // Without the compensation (the specification's single-scattering BRDF) the sphere is
    // far darker than three's: what the compensation fixed.
    let single = render("models/pbr/no-material.glb", true);
    let (mean_ss, _, _) = compare(&single, &three);
    eprintln!("single scattering only: mean {mean_ss:.2} levels");
    assert_eq!(
        single.get_pixel(128, 128).0[0],
        realist::color::srgb8(0.25 / std::f32::consts::PI)
    );
    assert!(mean_ss > 30.0, "{mean_ss}");
}
