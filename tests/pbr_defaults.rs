//! The default look of glTF files, as the Khronos glTF Sample Viewer shows them: PBR
//! Neutral tone mapping, the environment alone when the file has no lights (no default
//! rig on top), the background colour shown as it is. Measured on files written by
//! glTF-Transform (`models/pbr/`, `tests/pbr-models/make.mjs`).

use std::path::Path;

use glam::{Vec3, Vec4};
use realist::load::{self, LoadOptions};
use realist::render::{PreparedScene, Renderer, Settings, Shot, ToneMap};

fn scene(name: &str) -> realist::scene::Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("models/pbr")
        .join(name);
    load::load(&path, &LoadOptions::default()).expect("model loads")
}

/// `scene` at `w` x `h` from its default camera with `settings`, as 8-bit sRGB, and the view.
fn render(
    scene: &realist::scene::Scene,
    settings: &Settings,
    w: u32,
    h: u32,
) -> (Vec<[u8; 3]>, realist::render::View) {
    let shot = Shot {
        settings: settings.clone(),
        width: w,
        height: h,
        camera: None,
    };
    let view = shot.view(scene);
    let prepared = PreparedScene::new(scene.clone());
    let mut r = Renderer::new();
    r.render(&prepared, settings, &view);
    let fb = r.take_target().expect("a frame").resolve();
    let enc = realist::color::srgb8;
    let px = fb
        .color
        .iter()
        .map(|c| [enc(c.x), enc(c.y), enc(c.z)])
        .collect();
    (px, view)
}

/// Fraction of the pixels with a channel at 255.
fn clipped(px: &[[u8; 3]]) -> f64 {
    px.iter().filter(|p| p.contains(&255)).count() as f64 / px.len() as f64
}

#[test]
fn a_file_with_its_own_lights_clips_under_two_percent_by_default() {
    let scene = scene("lights-punctual.glb");
    assert_eq!(scene.lights.len(), 3, "point, spot and sun");
    let (px, _) = render(&scene, &Settings::default(), 480, 360);
    let by_default = clipped(&px);
    let clamp = Settings {
        tone: ToneMap::Clamp,
        ..Settings::default()
    };
    let (px, _) = render(&scene, &clamp, 480, 360);
    let clamped = clipped(&px);
    eprintln!(
        "lights-punctual.glb: {:.2}% of pixels clip by default, {:.2}% with the clamp",
        100.0 * by_default,
        100.0 * clamped
    );
    assert!(by_default < 0.02, "{by_default}");
    assert!(
        clamped > 2.0 * by_default,
        "the tone map is what keeps them: {clamped}"
    );
}

/// Hue (degrees) and saturation (HSV) of an 8-bit colour.
fn hue_sat(c: [u8; 3]) -> (f64, f64) {
    let [r, g, b] = c.map(f64::from);
    let (max, min) = (r.max(g).max(b), r.min(g).min(b));
    if max <= 0.0 || max == min {
        return (0.0, 0.0);
    }
    let d = max - min;
    let h = if max == r {
        60.0 * ((g - b) / d).rem_euclid(6.0)
    } else if max == g {
        60.0 * ((b - r) / d + 2.0)
    } else {
        60.0 * ((r - g) / d + 4.0)
    };
    (h, d / max)
}

/// For each sphere of the grid (node k = 5 j + i at (i - 2, 2 - j, 0), radius 0.4), the
/// fraction of its pixels (within 0.85 of its image's radius) whose colour has lost the base
/// colour's hue: more than 10 degrees off `hue`, or saturation under half of `sat`.
fn off_hue(px: &[[u8; 3]], view: &realist::render::View, hue: f64, sat: f64) -> Vec<f64> {
    let vp = view.camera.projection(view.aspect()) * view.camera.view();
    let (w, h) = (view.width as i64, view.height as i64);
    let screen = |p: Vec3| {
        let c = vp * p.extend(1.0);
        (
            (c.x / c.w + 1.0) * 0.5 * w as f32,
            (1.0 - c.y / c.w) * 0.5 * h as f32,
        )
    };
    let right = view.camera.view().inverse().transform_vector3(Vec3::X);
    let mut out = Vec::new();
    for j in 0..5 {
        for i in 0..5 {
            let centre = Vec3::new(i as f32 - 2.0, 2.0 - j as f32, 0.0);
            let (cx, cy) = screen(centre);
            let (ex, ey) = screen(centre + right * 0.4);
            let r = 0.85 * ((ex - cx).powi(2) + (ey - cy).powi(2)).sqrt();
            let (mut n, mut off) = (0usize, 0usize);
            for y in (cy - r) as i64..=(cy + r) as i64 {
                for x in (cx - r) as i64..=(cx + r) as i64 {
                    let d2 = (x as f32 + 0.5 - cx).powi(2) + (y as f32 + 0.5 - cy).powi(2);
                    if d2 > r * r || x < 0 || y < 0 || x >= w || y >= h {
                        continue;
                    }
                    let (hh, ss) = hue_sat(px[(y * w + x) as usize]);
                    n += 1;
                    if (hh - hue).abs() > 10.0 || ss < 0.5 * sat {
                        off += 1;
                    }
                }
            }
            out.push(off as f64 / n.max(1) as f64);
        }
    }
    out
}

#[test]
fn the_default_render_of_the_sphere_grid_keeps_its_base_colours_hue() {
    let scene = scene("sphere-grid.glb");
    // The base colour (0.9, 0.55, 0.2) as sRGB: hue 36.3 degrees, saturation 0.49.
    let base = Vec3::new(0.9, 0.55, 0.2)
        .to_array()
        .map(realist::color::srgb8);
    let (hue, sat) = hue_sat(base);
    let (px, view) = render(&scene, &Settings::default(), 600, 600);
    let now = off_hue(&px, &view, hue, sat);
    // The look before: the clamp, with the default rig on top of the environment.
    let before = Settings {
        tone: ToneMap::Clamp,
        lights: realist::render::Lights::Custom {
            lights: realist::scene::Light::default_rig(glam::Mat3::IDENTITY),
            follow_camera: true,
        },
        ..Settings::default()
    };
    let (px, view) = render(&scene, &before, 600, 600);
    let then = off_hue(&px, &view, hue, sat);
    for k in 0..25 {
        eprintln!(
            "sphere {k} (metallic {}, roughness {}): {:.1}% of its pixels off the hue now, {:.1}% with the clamp and the rig",
            (k % 5) as f32 / 4.0,
            (k / 5) as f32 / 4.0,
            100.0 * now[k],
            100.0 * then[k]
        );
    }
    let worst = now.iter().copied().fold(0.0, f64::max);
    let worst_then = then.iter().copied().fold(0.0, f64::max);
    eprintln!(
        "worst sphere: {:.1}% now, {:.1}% before",
        100.0 * worst,
        100.0 * worst_then
    );
    assert!(worst < 0.1, "{worst}");
    assert!(
        worst_then > 2.0 * worst,
        "the test tells the looks apart: {worst_then}"
    );
}

#[test]
fn the_background_colour_is_neither_exposed_nor_tone_mapped() {
    let scene = scene("no-material.glb");
    let bg = Vec4::new(0.2, 0.3, 0.4, 1.0);
    let want = [0.2f32, 0.3, 0.4].map(realist::color::srgb8);
    for (tone, exposure, samples, msaa) in [
        (ToneMap::Auto, 0.0, 1, 1),
        (ToneMap::PbrNeutral, 2.0, 3, 1),
        (ToneMap::AcesHill, -1.0, 1, 4),
    ] {
        let s = Settings {
            background: bg,
            tone,
            exposure,
            samples,
            msaa,
            ..Settings::default()
        };
        let (px, _) = render(&scene, &s, 64, 48);
        assert_eq!(
            px[0], want,
            "{tone:?}, {exposure} EV, {samples}x{samples}, msaa {msaa}"
        );
        assert_eq!(px[64 * 48 - 1], want);
        // The sphere itself is tone mapped.
        assert_ne!(px[24 * 64 + 32], want);
    }
}

#[test]
fn a_primitive_without_a_material_gets_the_specification_default_and_the_pbr_look() {
    let scene = scene("no-material.glb");
    assert_eq!(scene.materials.len(), 1);
    let m = &scene.materials[0];
    assert_eq!(
        (m.base_color, m.metallic, m.roughness, m.pbr.is_some()),
        (Vec4::ONE, 1.0, 1.0, true),
        "{m:?}"
    );
    let s = Settings::default();
    assert!(s.pbr_look(&scene), "drawn in the pbr mode");
    assert_eq!(s.tone_for(&scene), ToneMap::PbrNeutral);
    assert!(!s.default_rig(&scene), "lit by the environment alone");
    // An OBJ keeps the textbook's look: Phong, the clamp, the rig.
    let obj = load::load(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("models/torus.obj"),
        &LoadOptions::default(),
    )
    .expect("torus");
    assert!(!s.pbr_look(&obj));
    assert_eq!(s.tone_for(&obj), ToneMap::Clamp);
    assert!(s.default_rig(&obj));
}
